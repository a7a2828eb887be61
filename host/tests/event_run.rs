//! Statistics at event speed (`stickslip_model::model2::event_run`, host `scenes::event`):
//! against the independent model-2 reference (DOP853 at rtol 1e-12) and against the sampled
//! path (the stepper on the grid), on model-2 scenes with Stribeck and Coulomb friction, the
//! band, the face and the floating pad. No timing here: `cargo run --release -p stickslip
//! --example event_speed` measures error and time.

use stickslip::numerics::reference::model2 as reference;
use stickslip::scenes::builtin;
use stickslip::scenes::event;
use stickslip::scenes::run::{self, Precision, RunReport};
use stickslip::scenes::series::NoSink;
use stickslip_model::model2::event_run::{EventRunner, Fallback, DEFAULT_RTOL};
use stickslip_model::model2::{Model2Observer, Model2Segment, Model2Transition};
use stickslip_model::{Caliper, FrictionLaw, Regime, Scene};

fn rel(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else {
        (a - b).abs() / b.abs().max(a.abs())
    }
}

fn event_report(scene: &Scene) -> RunReport {
    match event::run(scene, Precision::F64, DEFAULT_RTOL).unwrap() {
        Some(Ok((r, _))) => r,
        other => panic!("the event path does not run the scene: {:?}", other.map(|r| r.err())),
    }
}

/// The 1-DOF Stribeck oracle's period and x amplitude against the reference, as `accuracy`
/// measures them: within 1e-9 at the default tolerance (measured 4e-11), and the error falls
/// with the tolerance.
#[test]
fn the_stribeck_oracle_matches_the_reference() {
    let scene = builtin::find("oracle_stribeck").unwrap().scene;
    let r = reference::simulate(&scene).unwrap();
    let st = r.stats(&scene).unwrap();
    let error = |rep: &RunReport| {
        let pe = rel(rep.cycles.period.mean().unwrap(), {
            let on: Vec<f64> = r.transitions.iter().filter(|t| t.from == stickslip::numerics::reference::Regime::Stick && t.t >= scene.stats_from).map(|t| t.t).collect();
            (on[on.len() - 1] - on[0]) / (on.len() - 1) as f64
        });
        pe.max(rel(rep.pp(0).unwrap(), st.pp(0)))
    };
    let e = error(&event_report(&scene));
    let loose = match event::run(&scene, Precision::F64, 1e-6).unwrap() {
        Some(Ok((rep, _))) => error(&rep),
        _ => panic!("not run"),
    };
    println!("oracle_stribeck error {e:.3e} at rtol {DEFAULT_RTOL:e}, {loose:.3e} at 1e-6");
    assert!(e <= 1e-9, "error {e:e}");
    assert!(loose > e && loose <= 1e-5, "error {loose:e} at 1e-6");
}

/// (name, scene) of the model-2 scenes compared with the sampled path.
fn scenes() -> Vec<(String, Scene)> {
    let mut v: Vec<(String, Scene)> = ["oracle_stribeck", "rig_pull_center", "rig_push_trail", "rig_float_push_center", "rig_float_pull_lead", "rig_quiet_pull_center"]
        .iter()
        .map(|n| (n.to_string(), builtin::find(n).unwrap().scene))
        .collect();
    let mut stribeck = Scene::case(Caliper::Pull, 0.040);
    stribeck.friction = FrictionLaw::Stribeck;
    stribeck.v_s = 0.002;
    v.push(("pull_center + Stribeck".into(), stribeck));
    let mut coulomb_band = Scene::case(Caliper::Pull, 0.040);
    coulomb_band.band = true;
    v.push(("pull_center + band (Coulomb)".into(), coulomb_band));
    let mut face = Scene::case(Caliper::Push, 0.055);
    face.face = true;
    face.c_x = 15.0;
    face.c_phi = 0.05;
    v.push(("push_lead + face, damped (Coulomb)".into(), face));
    v
}

/// The event path's statistics equal the sampled path's: the peak-to-peak values of x, x',
/// phi, phi' and the band velocity within 2e-5 (relative: the sampled path's own error, held
/// to 1e-5 against the reference by model2_reference.rs; its extremes are cubic Hermite
/// interpolants on its substeps; measured up to 9e-6 on the 2-DOF Stribeck scenes), the accelerations' within 2e-3 (the sampled
/// path takes them at its substep ends only), stick fraction and mean period within 1e-6,
/// the same transitions and slip onsets.
#[test]
fn the_event_path_gives_the_sampled_paths_statistics() {
    let mut failures = Vec::new();
    for (name, scene) in scenes() {
        let grid = run::run(&scene, Precision::F64, &mut NoSink).unwrap();
        let ev = event_report(&scene);
        let (g2, e2) = (grid.model2.unwrap(), ev.model2.unwrap());
        let pp = (0..4).map(|i| rel(ev.pp(i).unwrap_or(0.0), grid.pp(i).unwrap_or(0.0))).fold(rel(e2.band_v_pp, g2.band_v_pp), f64::max);
        let acc = rel(e2.pad_acc_pp, g2.pad_acc_pp).max(rel(e2.band_acc_pp, g2.band_acc_pp));
        let stick = (ev.stats.stick_fraction - grid.stats.stick_fraction).abs();
        let period = match (ev.cycles.period.mean(), grid.cycles.period.mean()) {
            (Some(a), Some(b)) => rel(a, b),
            (None, None) => 0.0,
            _ => 1.0,
        };
        let same = ev.transitions == grid.transitions && ev.stats.slip_onsets == grid.stats.slip_onsets && ev.outcome == grid.outcome;
        println!("{name:<36} pp {pp:.1e}  acc {acc:.1e}  stick {stick:.1e}  period {period:.1e}  transitions {} / {}", ev.transitions, grid.transitions);
        if !(pp <= 2e-5 && acc <= 2e-3 && stick <= 1e-6 && period <= 1e-6 && same) {
            failures.push(name);
        }
    }
    assert!(failures.is_empty(), "differ: {failures:?}");
}

/// Records what the event runner hands its observer.
#[derive(Default)]
struct Log {
    segments: Vec<(f64, f64, Regime)>,
    transitions: Vec<(f64, Regime, Regime)>,
}

impl Model2Observer<f64> for Log {
    fn segment(&mut self, s: &Model2Segment<f64>) {
        self.segments.push((s.t0, s.t1, s.regime));
    }
    fn transition(&mut self, t: &Model2Transition<f64>) {
        self.transitions.push((t.t, t.from, t.to));
    }
}

/// The segments tile [0, t_end] in order, one ends at the window's start, each transition
/// joins two segments of its regimes, and the state at the end is in the last regime.
#[test]
fn segments_tile_the_run_and_transitions_join_them() {
    let scene = builtin::find("oracle_stribeck").unwrap().scene;
    let mut r = EventRunner::new(&scene, DEFAULT_RTOL).unwrap();
    let mut log = Log::default();
    r.run(1.3, 6.0, &mut log).unwrap();
    let mut t = 0.0;
    for &(t0, t1, _) in &log.segments {
        assert_eq!(t0, t);
        assert!(t1 >= t0);
        t = t1;
    }
    assert_eq!(t, 6.0);
    assert!(log.segments.iter().any(|s| s.1 == 1.3));
    for &(tt, from, to) in &log.transitions {
        let i = log.segments.iter().position(|s| s.1 == tt).expect("a segment ends at the transition");
        assert_eq!(log.segments[i].2, from);
        assert_eq!(log.segments[i + 1].2, to);
    }
    assert_eq!(r.regime(), log.segments.last().unwrap().2);
    assert!(log.transitions.len() >= 4);
}

/// A run the stepper halts (a scene out of range) is given back, and the command then steps
/// on the grid: the summary equals `--grid`'s.
#[test]
fn a_run_out_of_range_falls_back_to_the_grid() {
    // strong Stribeck friction on a fast band: the pad's rotation overshoots and N goes
    // negative (as cli.rs's `lift.toml` on the thesis model)
    let mut scene = Scene::case(Caliper::Push, 0.040);
    scene.friction = FrictionLaw::Stribeck;
    scene.v_s = 0.01;
    (scene.mu_s, scene.mu_k, scene.v) = (4.0, 3.6, 0.5);
    let grid = run::run(&scene, Precision::F64, &mut NoSink).unwrap();
    assert!(matches!(grid.outcome, run::Outcome::Halted { .. }), "{:?}", grid.outcome);
    match event::run(&scene, Precision::F64, DEFAULT_RTOL).unwrap() {
        Some(Err(Fallback::Range { t })) => assert!(t > 0.0),
        other => panic!("not given back: {:?}", other.map(|r| r.err())),
    }
    assert!(event::try_run(&scene, Precision::F64, true).unwrap().is_none());
}

/// A 2-DOF Stribeck case and a rig-set case (Stribeck, band, face, damping) against the
/// reference: frequency, x pp, x' pp and stick fraction within 1e-8 (measured up to 1.7e-10;
/// the sampled path is held to 1e-5 on the same scenes by model2_reference.rs).
#[test]
fn two_dof_stribeck_and_the_rig_set_match_the_reference() {
    let mut stribeck = Scene::case(Caliper::Pull, 0.040);
    stribeck.friction = FrictionLaw::Stribeck;
    stribeck.v_s = 0.002;
    let rig = builtin::find("rig_pull_center").unwrap().scene;
    for (name, scene) in [("pull_center + Stribeck", stribeck), ("rig_pull_center", rig)] {
        let r = reference::simulate(&scene).unwrap().stats(&scene).unwrap();
        let e = event_report(&scene);
        let errors = [
            rel(e.stats.stick_slip_hz, r.stick_slip_hz),
            rel(e.pp(0).unwrap(), r.pp(0)),
            rel(e.pp(1).unwrap(), r.pp(1)),
            (e.stats.stick_fraction - r.stick_fraction).abs(),
        ];
        println!("{name} {errors:?}");
        assert!(errors.iter().all(|&x| x <= 1e-8), "{name} {errors:?}");
    }
}
