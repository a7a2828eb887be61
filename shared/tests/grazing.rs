//! A guard crest between two substep ends is found (docs/numerics.md, "Crests inside a
//! substep").
//!
//! The scenes are built to graze: a state is placed, through `set_state`, so that a guard of
//! its regime reaches a crest a tiny amount above zero at t_c = 5 us and is below zero at every
//! substep end, for every step size from 1e-5 s to 1e-3 s (t_c is 5 us from the start of the
//! first substep, and at least 5 us from its end). A stepper that only tests the guards at the
//! substep ends never sees it (the stepper before this test existed missed all of them).
//!
//! Each graze runs on the thesis model's `ExactStepper` and on model 2's stepper in the same
//! model (composition `Coulomb`), both as it steps (a substep with one quiet chunk takes its
//! short path, `short_substep`) and on its general path only.
//!
//! The reference is independent of the stepper's tables: the state at the crest is chosen in
//! closed form (guard rate zero, guard value +eps), carried back to t = 0 with expm(-A t_c)
//! in f64, and the first crossing time is found by bisection on g(expm(A t) z(0)) in f64,
//! with the regime matrix A of the model (`system_matrix`) and `linalg::expm`.

use stickslip_model::linalg::{self, Mat};
use stickslip_model::propagator::system_matrix;
use stickslip_model::stickslip::Guard;
use stickslip_model::model2::{Coulomb, Model2Stepper, Model2Observer, Model2Transition};
use stickslip_model::{Coefficients, ExactStepper, Real, Regime, Scene, State, DEFAULT_SCENE};

/// Time of the crest from the start of the run [s].
const T_CREST: f64 = 5e-6;

/// The step sizes tried: 1e-5 s to 1e-3 s, with the rig's rate and some in between.
const DTS: [f64; 8] = [1e-5, 2e-5, 1.0 / 25600.0, 5e-5, 1e-4, 2.5e-4, 5e-4, 1e-3];

fn flow(a: &Mat, z: &[f64; 4], t: f64) -> [f64; 4] {
    let e = linalg::expm(&linalg::scale(a, t));
    let za = [z[0], z[1], z[2], z[3], 1.0];
    let mut out = [0.0; 4];
    for (r, o) in out.iter_mut().enumerate() {
        *o = (0..5).map(|c| e[r][c] * za[c]).sum();
    }
    out
}

fn value(c: &[f64; 5], z: &[f64; 4]) -> f64 {
    c[0] * z[0] + c[1] * z[1] + c[2] * z[2] + c[3] * z[3] + c[4]
}

/// c . A: the guard's rate as a linear function of [z; 1].
fn rate_coefficients(c: &[f64; 5], a: &Mat) -> [f64; 5] {
    let mut d = [0.0; 5];
    for (col, dc) in d.iter_mut().enumerate() {
        *dc = (0..5).map(|r| c[r] * a[r][col]).sum();
    }
    d
}

#[derive(Clone, Copy)]
/// A grazing set-up: the state at t = 0, the guard, the first crossing time and the crest.
struct Graze {
    scene: Scene,
    regime: Regime,
    /// Guard coefficients (f64) and the regime matrix.
    c: [f64; 5],
    a: Mat,
    z0: [f64; 4],
    /// First time the guard reaches zero [s] (bisection to 1e-15 s).
    t_cross: f64,
    /// The guard's value at its crest [guard units].
    eps: f64,
}

impl Graze {
    /// `z_crest` without the components the guard condition fixes; `solve` makes the guard's
    /// rate zero and its value `eps` at the crest by adjusting them.
    fn new(scene: Scene, regime: Regime, c: [f64; 5], z_crest: [f64; 4], eps: f64) -> Graze {
        let co = Coefficients::of(&scene);
        let a = system_matrix(&scene, &co, regime);
        let z0 = flow(&a, &z_crest, -T_CREST);
        Graze { scene, regime, c, a, z0, t_cross: 0.0, eps }.with_crossing()
    }

    /// Finds the first crossing by bisection: g < 0 at 0, >= 0 at the crest, rising between.
    fn with_crossing(mut self) -> Graze {
        assert!(self.g(0.0) < 0.0, "the guard must start below zero");
        let (mut lo, mut hi) = (0.0, T_CREST);
        assert!(self.g(hi) >= 0.0);
        while hi - lo > 1e-15 {
            let mid = 0.5 * (lo + hi);
            if self.g(mid) < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        self.t_cross = hi;
        self
    }

    /// The same set-up from the initial state rounded to T (what `set_state` is given).
    fn rounded<T: Real>(&self) -> Graze {
        let r = |v: f64| T::from_f64(v).to_f64();
        let z0 = [r(self.z0[0]), r(self.z0[1]), r(self.z0[2]), r(self.z0[3])];
        Graze { z0, ..*self }.with_crossing()
    }

    /// The time resolution of a crossing in T: the guard's round-off (a few units of its
    /// terms' size) over its rate there.
    fn resolution<T: Real>(&self) -> f64 {
        let (rate, size) = self.rate_and_size(self.t_cross);
        let u = libm_ldexp(T::DYADIC_LEVELS);
        4.0 * u * size / rate
    }

    /// The guard's value at time t [s] (f64 reference).
    fn g(&self, t: f64) -> f64 {
        value(&self.c, &flow(&self.a, &self.z0, t))
    }

    /// The guard's rate at time t [s] and the size of its terms sum |c_i z_i| (f64 reference).
    fn rate_and_size(&self, t: f64) -> (f64, f64) {
        let z = flow(&self.a, &self.z0, t);
        let d = rate_coefficients(&self.c, &self.a);
        let size = (0..4).map(|i| (self.c[i] * z[i]).abs()).sum::<f64>() + self.c[4].abs();
        (value(&d, &z), size)
    }

    /// Checks the set-up grazes at step `dt`: below zero at both ends of the substep that
    /// holds the crest and at every substep end before it, and the crest eps above zero.
    fn check_grazes(&self, dt: f64, n_sub: u32) {
        let h = dt / n_sub as f64;
        let k_end = (T_CREST / h).floor() as u32 + 1;
        assert!(k_end <= n_sub);
        for k in 0..=k_end {
            let g = self.g(k as f64 * h);
            assert!(g < -0.5 * self.eps, "dt {dt}: guard {g} at substep end {k} is not clearly below zero");
        }
        // a fine sampling (1 ns) confirms the crest value and that it is the only one
        let mut max = f64::NEG_INFINITY;
        let mut t_max = 0.0;
        let n = (2.0 * T_CREST / 1e-9) as usize;
        for i in 0..=n {
            let t = i as f64 * 1e-9;
            let g = self.g(t);
            if g > max {
                max = g;
                t_max = t;
            }
        }
        // (from the initial state rounded to f32, the crest moves by a few ns and a few %)
        assert!((t_max - T_CREST).abs() <= 0.01 * T_CREST, "crest at {t_max}, built at {T_CREST}");
        assert!(max > 0.0 && (max - self.eps).abs() <= 0.05 * self.eps, "crest value {max}, built {}", self.eps);
    }

    /// Runs one step at `dt` in precision T on `stepper` and returns the transitions' (time,
    /// from, to).
    fn run<T: Real>(&self, dt: f64, stepper: Stepper) -> (u32, Vec<(f64, Regime, Regime)>) {
        let mut s = self.scene;
        s.dt = dt;
        let t = T::from_f64;
        if stepper != Stepper::Exact {
            // model 2's stepper in the thesis model's composition (`Coulomb`), from the same state
            let mut st = Model2Stepper::<T, Coulomb>::new(&s).unwrap();
            let z = [t(self.z0[0]), t(self.z0[1]), t(self.z0[2]), t(self.z0[3]), T::zero(), T::zero(), T::zero(), T::zero()];
            st.set_state(z, self.regime);
            let mut trs = Transitions(Vec::new());
            if stepper == Stepper::Model2 {
                st.step_observed(&mut trs).unwrap();
            } else {
                st.step_observed_general(&mut trs).unwrap();
            }
            return (st.substeps(), trs.0);
        }
        let mut st = ExactStepper::<T>::new(&s).unwrap();
        st.set_state(
            State { x: t(self.z0[0]), xdot: t(self.z0[1]), phi: t(self.z0[2]), phidot: t(self.z0[3]) },
            self.regime,
        );
        st.step().unwrap();
        let n_sub = st.propagator().n_sub;
        (n_sub, st.transitions().iter().map(|tr| (tr.t, tr.from, tr.to)).collect())
    }
}

/// The stepper a graze runs on.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Stepper {
    /// The thesis model's `ExactStepper`.
    Exact,
    /// Model 2's stepper (composition `Coulomb`), as it steps: a substep whose one chunk
    /// neither fires nor crests a guard on its short path.
    Model2,
    /// The same on its general path only (`step_observed_general`).
    Model2General,
}

/// Collects a model-2 stepper's transitions.
struct Transitions(Vec<(f64, Regime, Regime)>);

impl<T: Real> Model2Observer<T> for Transitions {
    const DERIVATIVES: bool = false;
    fn transition(&mut self, tr: &Model2Transition<T>) {
        self.0.push((tr.t, tr.from, tr.to));
    }
}

/// The push scene with its rotation ringing: the breakaway guard F_req - mu_s N of stick has a
/// crest eps above zero at t_c, where phi' = k_g V / (mu_s c_N).
fn stick_graze(eps_rel: f64) -> Graze {
    let scene = DEFAULT_SCENE;
    assert!(scene.rotation);
    let co = Coefficients::of(&scene);
    let a = system_matrix(&scene, &co, Regime::Stick);
    let c = [scene.k_g, 0.0, -scene.mu_s * co.c_n, 0.0, scene.c_x * scene.v];
    let d = rate_coefficients(&c, &a);
    // at the crest: x' = V, phi = phi0 (the static deflection), phi' from rate = 0, x from g = eps
    let phi = co.phi0;
    let phid = -(d[0] * 0.0 + d[1] * scene.v + d[2] * phi + d[4]) / d[3];
    let limit = scene.mu_s * co.c_n * phi;
    let eps = eps_rel * limit;
    let x = (eps - c[1] * scene.v - c[2] * phi - c[3] * phid - c[4]) / c[0];
    let z = [x, scene.v, phi, phid];
    let (rate, g) = (value(&d, &z), value(&c, &z));
    assert!(rate.abs() <= 1e-12 * limit && (g - eps).abs() <= 1e-14 * limit, "crest set-up: rate {rate}, g {g}");
    Graze::new(scene, Regime::Stick, c, z, eps)
}

/// The same scene in slip, pad slower: x' - V has a crest eps above zero at t_c (x'' = 0
/// there): the pad catches up with the band for a moment and falls back, unseen at the ends.
fn slip_graze(eps_rel: f64) -> Graze {
    let scene = DEFAULT_SCENE;
    let co = Coefficients::of(&scene);
    let a = system_matrix(&scene, &co, Regime::SlipSlower);
    let c = [0.0, 1.0, 0.0, 0.0, -scene.v];
    let d = rate_coefficients(&c, &a);
    // at the crest: x' = V (1 + eps_rel), phi = phi0, phi' = 0, x from x'' = 0
    let eps = eps_rel * scene.v;
    let (xd, phi, phid) = (scene.v + eps, co.phi0, 0.0);
    let x = -(d[1] * xd + d[2] * phi + d[3] * phid + d[4]) / d[0];
    let z = [x, xd, phi, phid];
    let rate = value(&d, &z);
    assert!(rate.abs() <= 1e-9 * d[0].abs() * x.abs().max(1e-6), "crest set-up: rate {rate}");
    Graze::new(scene, Regime::SlipSlower, c, z, eps)
}

/// 2^-levels.
fn libm_ldexp(levels: usize) -> f64 {
    (0.5f64).powi(levels as i32)
}

/// The crest is found in the first step at every dt, at the reference crossing time (from the
/// T-rounded initial state) within T's resolution of a crossing, and the state machine leaves
/// the regime.
fn assert_found<T: Real>(gr: &Graze) {
    for stepper in [Stepper::Exact, Stepper::Model2, Stepper::Model2General] {
        assert_found_on::<T>(gr, stepper);
    }
}

fn assert_found_on<T: Real>(gr: &Graze, stepper: Stepper) {
    let gr = &gr.rounded::<T>();
    let tol = gr.resolution::<T>();
    for dt in DTS {
        let (n_sub, trs) = gr.run::<T>(dt, stepper);
        gr.check_grazes(dt, n_sub);
        let first = trs.first().unwrap_or_else(|| {
            panic!("{} {stepper:?} dt {dt} (n_sub {n_sub}): crest at {T_CREST} s not found (guard +{:e} there)", T::NAME, gr.eps)
        });
        assert_eq!(first.1, gr.regime, "{} {stepper:?} dt {dt}", T::NAME);
        eprintln!(
            "{} {stepper:?} {:?} dt {dt:e} n_sub {n_sub}: crossing at {:.12e} s, reference {:.12e} s, difference {:+.2e} (tolerance {tol:.1e})",
            T::NAME,
            gr.regime,
            first.0,
            gr.t_cross,
            first.0 - gr.t_cross
        );
        assert!(
            (first.0 - gr.t_cross).abs() <= tol,
            "{} {stepper:?} dt {dt}: transition at {:.15e} s, reference crossing {:.15e} s (difference {:e}, tolerance {tol:e})",
            T::NAME,
            first.0,
            gr.t_cross,
            first.0 - gr.t_cross
        );
    }
}

#[test]
fn the_stick_breakaway_crest_is_found_at_every_step_f64() {
    // crest 1e-9 of mu_s N above zero (the guard is ~1e-8 of mu_s N below zero at t = 0)
    let gr = stick_graze(1e-9);
    // about 0.4 us before the crest
    assert!(gr.t_cross > 0.0 && gr.t_cross < T_CREST);
    assert_found::<f64>(&gr);
}

#[test]
fn the_stick_breakaway_crest_is_found_at_every_step_f32() {
    // f32 resolves mu_s N to 6e-8: a crest 1e-6 above zero is well above its round-off, and
    // still invisible at the substep ends
    let gr = stick_graze(1e-6);
    assert_found::<f32>(&gr);
}

#[test]
fn the_slip_velocity_crest_is_found_at_every_step_f64() {
    let gr = slip_graze(1e-9);
    assert_found::<f64>(&gr);
}

#[test]
fn the_slip_velocity_crest_is_found_at_every_step_f32() {
    let gr = slip_graze(1e-6);
    assert_found::<f32>(&gr);
}

/// The guard's own value in the stepper's precision agrees with the reference's coefficients
/// (the test's guard is the model's).
#[test]
fn the_reference_guards_are_the_models() {
    let scene = DEFAULT_SCENE;
    let co = Coefficients::of(&scene);
    let st = ExactStepper::<f64>::new(&scene).unwrap();
    let g: &Guard<f64> = &st.guards().stick_behind;
    let c = [scene.k_g, 0.0, -scene.mu_s * co.c_n, 0.0, scene.c_x * scene.v];
    for (i, (got, want)) in g.c.iter().zip(c).enumerate() {
        assert!((got - want).abs() <= 1e-12 * want.abs().max(1.0), "stick guard coefficient {i}");
    }
    let g = &st.guards().slower_caught_up;
    assert_eq!(g.c, [0.0, 1.0, 0.0, 0.0, -scene.v]);
}

/// The crests of the thesis set that the end-of-substep test missed (and the re-pinned
/// digests of shared/tests/thesis_anchor.rs now include): run in f64 to the step holding the
/// transition, then sample the guard over that step at 1 ns with expm from the state at its
/// start: it is below zero at every substep end and above zero inside.
fn assert_real_crest(scene: Scene, t_transition: f64, from: Regime, to: Regime) {
    let mut st = ExactStepper::<f64>::new(&scene).unwrap();
    let co = Coefficients::of(&scene);
    let a = system_matrix(&scene, &co, from);
    let guards = *st.guards();
    let (gs, n) = guards.of(from);
    loop {
        let (z0, r0, t0) = (st.state().to_array(), st.regime(), st.time());
        st.step().unwrap();
        let Some(tr) = st.transitions().iter().find(|tr| (tr.t - t_transition).abs() < 1e-9) else {
            assert!(st.time() < t_transition + 1.0, "no transition near {t_transition}");
            continue;
        };
        assert_eq!((r0, tr.from, tr.to), (from, from, to));
        assert!(st.transitions()[0].t == tr.t, "the transition is the step's first");
        let n_sub = st.propagator().n_sub;
        let h = scene.dt / n_sub as f64;
        let k = ((tr.t - t0) / h).floor() as u32; // the substep that holds it
        let g_max = |t: f64| (0..n).map(|w| value(&gs[w].c, &flow(&a, &z0, t))).fold(f64::NEG_INFINITY, f64::max);
        for j in 0..=k + 1 {
            assert!(g_max(j as f64 * h) < 0.0, "guard fired at substep end {j}: not a crest");
        }
        let samples = (h / 1e-9) as u32;
        let crest = (0..=samples).map(|i| g_max(k as f64 * h + i as f64 * 1e-9)).fold(f64::NEG_INFINITY, f64::max);
        assert!(crest > 0.0, "no crest above zero in substep {k}");
        eprintln!("{from:?} -> {to:?} at {:.13} s: substep {k} of {n_sub}, guard crest +{crest:.3e}", tr.t);
        return;
    }
}

#[test]
fn the_thesis_set_crests_found_since_are_real() {
    // push_lead at 1 ms: the breakaway at 0.4707663 s (found at 1/25600 s too), which the
    // end-of-substep test saw only 2.0 ms later, at 0.4727659 s
    let mut s = Scene::case(stickslip_model::Caliper::Push, stickslip_model::catalogue::CASE_BETAS[2].1);
    s.dt = 1e-3;
    assert_real_crest(s, 0.4707662509329, Regime::Stick, Regime::SlipSlower);
    // thesis-mu (mu_k = mu_s) at 1/25600 s: the slip that touches V_r = 0 at 0.2022945 s (re-stick
    // for 2.7 us), found at 1 ms too
    let mut s = DEFAULT_SCENE;
    s.mu_k = s.mu_s;
    assert_real_crest(s, 0.2022945008218, Regime::SlipSlower, Regime::Stick);
}
