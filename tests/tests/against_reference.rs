//! The exact stepper (f64, default step 1/25600 s) against the independent event-driven
//! DOP853 reference, on the six cases and the 1-DOF oracle.

use stickslip::numerics::reference::thesis::{self, Regime as ReferenceRegime};
use stickslip_model::stats::StatsObserver;
use stickslip_model::{catalogue::CASE_BETAS, Caliper, ExactStepper, Observer, Regime, Scene, Transition};

struct Collect {
    stats: StatsObserver<f64>,
    tr: Vec<(f64, Regime, Regime)>,
}
impl Observer<f64> for Collect {
    fn segment(&mut self, s: &stickslip_model::Segment<f64>, p: &stickslip_model::propagator::Propagator<f64>) {
        self.stats.segment(s, p)
    }
    fn transition(&mut self, t: &Transition<f64>) {
        self.stats.transition(t);
        self.tr.push((t.t, t.from, t.to));
    }
}

fn exact(scene: &Scene) -> (stickslip_model::stats::RunStats, Vec<(f64, Regime, Regime)>) {
    let mut st = ExactStepper::<f64>::new(scene).unwrap();
    let mut c = Collect { stats: StatsObserver::new(scene.stats_from, scene.dt), tr: Vec::new() };
    let n = (scene.duration / scene.dt).round() as u64;
    for _ in 0..n {
        st.step_observed(&mut c).unwrap();
    }
    (c.stats.finish(), c.tr)
}

fn same(m: ReferenceRegime, r: Regime) -> bool {
    matches!((m, r), (ReferenceRegime::Stick, Regime::Stick) | (ReferenceRegime::Slower, Regime::SlipSlower) | (ReferenceRegime::Faster, Regime::SlipFaster))
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

#[test]
fn pull_cases_match_the_reference_trajectory_and_statistics() {
    for (name, beta) in CASE_BETAS {
        let scene = Scene::case(Caliper::Pull, beta);
        let r = thesis::simulate(&scene);
        let (s, tr) = exact(&scene);
        // the same sequence of transitions at the same times
        assert_eq!(tr.len(), r.transitions.len(), "pull_{name}: transition count");
        let worst_t = tr.iter().zip(&r.transitions).map(|(a, b)| (a.0 - b.0).abs()).fold(0.0, f64::max);
        let worst_pp = (0..4).map(|i| rel(s.pp(i), r.stats.pp(i))).fold(0.0, f64::max);
        eprintln!("pull_{name}: {} transitions, worst time difference {worst_t:.2e} s, worst pp relative difference {worst_pp:.2e}", tr.len());
        for (a, b) in tr.iter().zip(&r.transitions) {
            assert!(same(b.1, a.1) && same(b.2, a.2), "pull_{name}: {a:?} vs {b:?}");
            assert!((a.0 - b.0).abs() < 1e-9, "pull_{name}: transition at {} vs {}", a.0, b.0);
        }
        for i in 0..4 {
            assert!(rel(s.pp(i), r.stats.pp(i)) < 1e-6, "pull_{name}: pp[{i}] {} vs {}", s.pp(i), r.stats.pp(i));
        }
        assert!((s.stick_fraction - r.stats.stick_fraction).abs() < 1e-6, "pull_{name}: stick fraction");
        assert!(rel(s.stick_slip_hz, r.stats.stick_slip_hz) < 1e-6, "pull_{name}: frequency");
    }
}

#[test]
fn push_cases_match_the_reference_statistics() {
    for (name, beta) in CASE_BETAS {
        let scene = Scene::case(Caliper::Push, beta);
        let r = thesis::simulate(&scene);
        let (s, _) = exact(&scene);
        let worst_pp = (0..4).map(|i| rel(s.pp(i), r.stats.pp(i))).fold(0.0, f64::max);
        eprintln!(
            "push_{name}: worst pp relative difference {worst_pp:.2e}, stick fraction {:.5} vs {:.5}, frequency {:.4} vs {:.4} Hz",
            s.stick_fraction, r.stats.stick_fraction, s.stick_slip_hz, r.stats.stick_slip_hz
        );
        for i in 0..4 {
            assert!(rel(s.pp(i), r.stats.pp(i)) < 0.01, "push_{name}: pp[{i}] {} vs {}", s.pp(i), r.stats.pp(i));
        }
        assert!((s.stick_fraction - r.stats.stick_fraction).abs() < 0.01, "push_{name}: stick fraction");
        assert!(rel(s.stick_slip_hz, r.stats.stick_slip_hz) < 0.01, "push_{name}: frequency");
    }
}

#[test]
fn pull_center_converges_at_every_step_size() {
    // The exact method's error does not grow with the step: from 1 ms to 10 us the periodic
    // pull_center run stays on the reference trajectory.
    let base = Scene::case(Caliper::Pull, 0.040);
    let r = thesis::simulate(&base);
    for dt in [1e-3, 2.5e-4, 1e-4, 1.0 / 25600.0, 1e-5] {
        let mut scene = base;
        scene.dt = dt;
        let (s, tr) = exact(&scene);
        assert_eq!(tr.len(), r.transitions.len(), "dt {dt}: transition count");
        let worst_t = tr.iter().zip(&r.transitions).map(|(a, b)| (a.0 - b.0).abs()).fold(0.0, f64::max);
        let worst_pp = (0..4).map(|i| rel(s.pp(i), r.stats.pp(i))).fold(0.0, f64::max);
        eprintln!("pull_center dt {dt:.3e}: worst transition time difference {worst_t:.2e} s, worst pp difference {worst_pp:.2e}");
        assert!(worst_t < 1e-9, "dt {dt}: transition times off by {worst_t}");
        assert!(worst_pp < 1e-7, "dt {dt}: pp off by {worst_pp}");
        assert!((s.stick_fraction - r.stats.stick_fraction).abs() < 1e-7);
    }
}

#[test]
fn oracle_1dof_matches_the_reference_too() {
    // the reference on the closed-form scene: its own accuracy, for the record
    let s = Scene::oracle_1dof();
    let r = thesis::simulate(&s);
    let x_max = 0.4 * 10.0 / 100.0 + ((0.2f64 * 10.0 / 100.0).powi(2) + (0.05f64 / 10.0).powi(2)).sqrt();
    assert!(rel(r.stats.max[0], x_max) < 1e-9, "reference x_max {} vs {}", r.stats.max[0], x_max);
    assert!((r.transitions[0].0 - 1.2).abs() < 1e-9);
    let (e, _) = exact(&s);
    assert!(rel(e.max[0], r.stats.max[0]) < 1e-9);
}
