//! A guard crest between two substep ends is found on the floating pad too (model 2, part 2:
//! face kinematics, k_pivot = 0, Coulomb friction; `Model2Stepper<T, FloatFace>`), as in
//! `grazing.rs` for the hinged pad.
//!
//! The set-up is built to graze: in slip with the pad slower, the face's sliding velocity
//! v = x' + s w phi' - V reaches a crest eps above zero at t_c = 5 us (the face catches up
//! with the band for a moment and falls back), and is below zero at every substep end, for
//! every step from 1e-5 s to 1e-3 s. The reference is independent of the stepper's dyadic
//! tables and of its guard location: the state at the crest is chosen in closed form (v = eps,
//! v' = 0 by the choice of x), carried back to t = 0 with expm(-A t_c) in f64 on the regime's
//! matrix (`System::of`, the floating pad's 9 x 9 augmented matrix), and the first crossing is
//! found by bisection on v(expm(A t) z(0)) in f64.

use stickslip_model::linalg::{self, MatN};
use stickslip_model::model2::{FloatFace, Model2Stepper, Model2Observer, System, Model2Transition, NA, NS, Y};
use stickslip_model::{Caliper, Coefficients, Real, Regime, Scene};

const T_CREST: f64 = 5e-6;
const DTS: [f64; 8] = [1e-5, 2e-5, 1.0 / 25600.0, 5e-5, 1e-4, 2.5e-4, 5e-4, 1e-3];

fn scene() -> Scene {
    let mut s = Scene::case(Caliper::Push, 0.040);
    s.face = true;
    s.k_pivot = 0.0;
    s.c_y = 30.0;
    s.c_phi = 0.03;
    // a stiff guide (x mode 1.3 kHz) makes the crest sharp enough to sit above f32's
    // round-off of v at 5 us: v'' = -k_g (V + eps) / m there
    s.k_g = 2e7;
    s
}

fn flow(a: &MatN<NA>, z: &[f64; NS], t: f64) -> [f64; NS] {
    let e = linalg::expm(&linalg::scale(a, t));
    let mut za = [0.0; NA];
    za[..NS].copy_from_slice(z);
    za[NA - 1] = 1.0;
    core::array::from_fn(|r| (0..NA).map(|c| e[r][c] * za[c]).sum())
}

fn dot(r: &[f64; NA], z: &[f64; NS]) -> f64 {
    (0..NS).map(|c| r[c] * z[c]).sum::<f64>() + r[NA - 1]
}

struct Graze {
    a: MatN<NA>,
    r_v: [f64; NA],
    z0: [f64; NS],
    t_cross: f64,
    eps: f64,
}

impl Graze {
    fn new(eps_rel: f64) -> Graze {
        let s = scene();
        let co = Coefficients::of(&s);
        let sys = System::of(&s, &co);
        let a = sys.a[Regime::SlipSlower.index()];
        let r_v = sys.r_v;
        // (in slip the rotation and y do not depend on x or x': N is (k_L + k_T) y + c_N phi)
        assert!(a[3][0] == 0.0 && a[3][1] == 0.0 && a[Y + 1][0] == 0.0 && a[Y + 1][1] == 0.0);
        // v's rate as a row: r_v . A
        let d: [f64; NA] = core::array::from_fn(|c| (0..NA).map(|r| r_v[r] * a[r][c]).sum());
        // at the crest: (phi, y) at rest under the load and the slip's friction moment
        // (phi'' = y'' = 0 with phi' = y' = 0), x' = V + eps (v = eps), x from v' = 0; then
        // v'' = -k_g (V + eps) / m < 0: a crest
        let eps = eps_rel * s.v;
        let (p, q) = (3, Y + 1);
        let det = a[p][2] * a[q][Y] - a[p][Y] * a[q][2];
        let (bp, bq) = (-a[p][NA - 1], -a[q][NA - 1]);
        let mut z = [0.0; NS];
        z[2] = (bp * a[q][Y] - a[p][Y] * bq) / det;
        z[Y] = (a[p][2] * bq - bp * a[q][2]) / det;
        z[1] = s.v + eps;
        let rest = dot(&d, &z); // with x = 0
        z[0] = -rest / d[0];
        let (g, rate) = (dot(&r_v, &z), dot(&d, &z));
        assert!((g - eps).abs() <= 1e-12 * s.v && rate.abs() <= 1e-9 * d[0].abs() * z[0].abs().max(1e-6), "crest set-up: v {g}, v' {rate}");
        let z0 = flow(&a, &z, -T_CREST);
        let mut gr = Graze { a, r_v, z0, t_cross: 0.0, eps };
        gr.find_crossing();
        gr
    }

    fn g(&self, t: f64) -> f64 {
        dot(&self.r_v, &flow(&self.a, &self.z0, t))
    }

    fn find_crossing(&mut self) {
        assert!(self.g(0.0) < 0.0 && self.g(T_CREST) >= 0.0);
        let (mut lo, mut hi) = (0.0, T_CREST);
        while hi - lo > 1e-15 {
            let mid = 0.5 * (lo + hi);
            if self.g(mid) < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        self.t_cross = hi;
    }

    /// The same set-up from the initial state rounded to T.
    fn rounded<T: Real>(&self) -> Graze {
        let z0 = self.z0.map(|v| T::from_f64(v).to_f64());
        let mut gr = Graze { z0, ..*self };
        gr.find_crossing();
        gr
    }

    /// Below zero at every substep end up to the one after the crest.
    fn check_grazes(&self, dt: f64, n_sub: u32) {
        let h = dt / n_sub as f64;
        let k_end = (T_CREST / h).floor() as u32 + 1;
        for k in 0..=k_end.min(n_sub) {
            let g = self.g(k as f64 * h);
            assert!(g < -0.5 * self.eps, "dt {dt}: v = {g} at substep end {k} is not clearly below zero");
        }
    }
}

impl Clone for Graze {
    fn clone(&self) -> Self {
        Graze { a: self.a, r_v: self.r_v, z0: self.z0, t_cross: self.t_cross, eps: self.eps }
    }
}
impl Copy for Graze {}

struct Transitions(Vec<(f64, Regime, Regime)>);

impl<T: Real> Model2Observer<T> for Transitions {
    const DERIVATIVES: bool = false;
    fn transition(&mut self, tr: &Model2Transition<T>) {
        self.0.push((tr.t, tr.from, tr.to));
    }
}

fn found<T: Real>(base: &Graze, general: bool) {
    let gr = base.rounded::<T>();
    // the crossing's time resolution in T: the sliding velocity's round-off (a few units of V)
    // over its rate at the crossing
    let (rate, _) = {
        let z = flow(&gr.a, &gr.z0, gr.t_cross);
        let d: [f64; NA] = core::array::from_fn(|c| (0..NA).map(|r| gr.r_v[r] * gr.a[r][c]).sum());
        (dot(&d, &z), ())
    };
    let s0 = scene();
    let tol = 8.0 * 0.5f64.powi(T::DYADIC_LEVELS as i32 - 8) * s0.v / rate.abs() + 1e-9 * T_CREST;
    for dt in DTS {
        let mut s = scene();
        s.dt = dt;
        let mut st = Model2Stepper::<T, FloatFace>::new(&s).unwrap();
        st.set_state(gr.z0.map(T::from_f64), Regime::SlipSlower);
        gr.check_grazes(dt, st.substeps());
        let mut trs = Transitions(Vec::new());
        if general {
            st.step_observed_general(&mut trs).unwrap();
        } else {
            st.step_observed(&mut trs).unwrap();
        }
        let first = trs.0.first().copied();
        let Some((t, from, _to)) = first else {
            panic!("{} dt {dt} (general: {general}): the crest at {T_CREST} s was missed", std::any::type_name::<T>());
        };
        assert_eq!(from, Regime::SlipSlower);
        assert!(
            (t - gr.t_cross).abs() <= tol,
            "{} dt {dt}: crossing at {t}, reference {} (tol {tol:e})",
            std::any::type_name::<T>(),
            gr.t_cross
        );
    }
}

#[test]
fn a_sliding_velocity_crest_on_the_floating_pad_is_found() {
    // eps = 5e-7 and 2e-6 m/s above zero at the crest; v falls 4.2e-6 m/s in the 5 us to t = 0
    for eps_rel in [1e-4, 4e-4] {
        let gr = Graze::new(eps_rel);
        for general in [false, true] {
            found::<f64>(&gr, general);
            found::<f32>(&gr, general);
        }
    }
}
