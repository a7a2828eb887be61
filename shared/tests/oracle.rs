//! The exact stepper against the closed form of the mass on a moving belt (phi held fixed),
//! docs/model.md "Oracles". The reference values are computed here from the formulas, not by
//! the code under test.

use stickslip_model::stats::StatsObserver;
use stickslip_model::{ExactStepper, Observer, Real, Regime, Scene, Transition};

/// The closed-form check values of model.md: m = 1, k = 100, N = 10, V = 0.05, 0.6 / 0.4.
fn oracle_scene(dt: f64) -> Scene {
    let mut s = Scene::oracle_1dof();
    s.dt = dt;
    s
}

struct Closed {
    t_stick: f64,
    t_slip: f64,
    x_max: f64,
    x_min: f64,
    v_min: f64,
}

fn closed_form() -> Closed {
    let (m, k, n, v, mu_s, mu_k) = (1.0f64, 100.0f64, 10.0f64, 0.05f64, 0.6f64, 0.4f64);
    let omega = (k / m).sqrt();
    let delta = (mu_s - mu_k) * n / k;
    let x_k = mu_k * n / k;
    let r = (delta * delta + (v / omega).powi(2)).sqrt();
    Closed {
        t_stick: 2.0 * delta / v,
        t_slip: (2.0 * std::f64::consts::PI - 2.0 * (omega * delta / v).atan()) / omega,
        x_max: x_k + r,
        x_min: x_k - r,
        v_min: -((omega * delta).powi(2) + v * v).sqrt(),
    }
}

#[derive(Default)]
struct Log<T> {
    tr: Vec<(f64, Regime, Regime)>,
    _p: core::marker::PhantomData<T>,
}
impl<T: Real> Observer<T> for Log<T> {
    fn transition(&mut self, t: &Transition<T>) {
        self.tr.push((t.t, t.from, t.to));
    }
}

struct Both<'a, T: Real>(&'a mut Log<T>, &'a mut StatsObserver<T>);
impl<T: Real> Observer<T> for Both<'_, T> {
    fn segment(&mut self, s: &stickslip_model::Segment<T>, p: &stickslip_model::propagator::Propagator<T>) {
        self.1.segment(s, p)
    }
    fn transition(&mut self, t: &Transition<T>) {
        self.0.transition(t);
        self.1.transition(t)
    }
}

fn run<T: Real>(dt: f64) -> (Vec<(f64, Regime, Regime)>, stickslip_model::stats::RunStats) {
    let scene = oracle_scene(dt);
    let mut st = ExactStepper::<T>::new(&scene).unwrap();
    let mut log = Log::<T>::default();
    let mut stats = StatsObserver::<T>::new(scene.stats_from, scene.dt);
    let n = (scene.duration / scene.dt).round() as u64;
    for _ in 0..n {
        st.step_observed(&mut Both(&mut log, &mut stats)).unwrap();
    }
    (log.tr, stats.finish())
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

fn check<T: Real>(dt: f64, tol: f64) {
    let c = closed_form();
    let (tr, stats) = run::<T>(dt);
    // first slip from rest at x_s / V = 1.2 s
    assert_eq!(tr[0].1, Regime::Stick);
    assert_eq!(tr[0].2, Regime::SlipSlower);
    assert!(rel(tr[0].0, 1.2) < tol, "first slip {} vs 1.2", tr[0].0);
    let mut n_cycles = 0;
    for w in tr.windows(2) {
        let dur = w[1].0 - w[0].0;
        match (w[0].2, w[1].2) {
            (Regime::SlipSlower, Regime::Stick) => {
                assert!(rel(dur, c.t_slip) < tol, "T_slip {dur} vs {}", c.t_slip);
                n_cycles += 1;
            }
            (Regime::Stick, Regime::SlipSlower) => assert!(rel(dur, c.t_stick) < tol, "T_stick {dur} vs {}", c.t_stick),
            other => panic!("unexpected transition pair {other:?}"),
        }
    }
    assert!(n_cycles >= 4, "only {n_cycles} cycles");
    assert!(rel(stats.max[0], c.x_max) < tol, "x_max {} vs {}", stats.max[0], c.x_max);
    assert!(rel(stats.min[0], c.x_min) < tol, "x_min {} vs {}", stats.min[0], c.x_min);
    assert!(rel(stats.min[1], c.v_min) < tol, "v_min {} vs {}", stats.min[1], c.v_min);
}

#[test]
fn check_values_of_model_md() {
    let c = closed_form();
    assert!((c.t_stick - 0.8).abs() < 1e-12);
    assert!((c.t_slip - 0.363155).abs() < 1e-6);
    assert!((c.x_max - 0.0606155).abs() < 1e-7);
    assert!((c.x_min - 0.0193845).abs() < 1e-7);
}

#[test]
fn f64_matches_closed_form_at_rig_rate() {
    check::<f64>(1.0 / 25600.0, 1e-9);
}

#[test]
fn f64_matches_closed_form_at_coarse_and_fine_steps() {
    check::<f64>(1e-3, 1e-9);
    check::<f64>(1e-5, 1e-9);
}

#[test]
fn f32_matches_closed_form() {
    check::<f32>(1.0 / 25600.0, 1e-5);
}
