//! Model 3's rows of the report: unilateral contact's event runner (the model crate's
//! `model2::event_run` with its edges) at several tolerances against the independent reference
//! (`reference::model2::simulate_unilateral`: DOP853 at rtol 1e-12 on model 2's reference
//! right-hand side with the open spring taken out), and that reference's own work-precision rows.
//!
//! The error is the periodic scenes' (the period of the slip onsets, the x amplitude; the final
//! state beside it), and where the edges' open time differs it too: the larger of the period,
//! amplitude and open-time errors (the open time relative to the reference's, summed over both
//! edges), 1 when the edges' openings differ in number.

use super::*;
use crate::numerics::reference::model2::{simulate_unilateral, UnilateralRun};
use crate::numerics::reference::pneumatic as pneumatic_reference;
use stickslip_model::model2::event_run::EventRunner;
use stickslip_model::model3::pneumatic_run::{PneumaticRunner, PneumaticSample};
use stickslip_model::{rig_set, BandDrive, Caliper, ContactLaw};

/// The unilateral scene's name in the rows.
pub const UNILATERAL_SCENE: &str = "rig_float_pull_edge";
/// The event runner's method name in the rows.
pub const EVENT_METHOD: &str = "event";
/// The event runner's tolerances in the full report and in `--quick`.
pub const FULL_EVENT_RTOLS: [f64; 4] = [1e-6, 1e-8, 1e-10, 1e-12];
pub const QUICK_EVENT_RTOLS: [f64; 2] = [1e-8, 1e-12];
/// `--check`: the event runner at the host's unilateral tolerance (1e-12).
pub const BOUND_UNILATERAL: f64 = 1e-6;
/// The pneumatic scene's name in the rows.
pub const PNEUMATIC_SCENE: &str = "rig_push_center_pneumatic";
/// The pneumatic runner's method name in the rows.
pub const PNEUMATIC_METHOD: &str = "pneumatic";
/// The pneumatic runner's tolerances in the full report and in `--quick`.
pub const FULL_PNEUMATIC_RTOLS: [f64; 4] = [1e-6, 1e-8, 1e-10, 1e-12];
pub const QUICK_PNEUMATIC_RTOLS: [f64; 2] = [1e-8, 1e-10];
/// `--check`: the pneumatic runner at the host's tolerance (1e-10).
pub const BOUND_PNEUMATIC: f64 = 1e-6;

/// `rig_float_push_center` turned to the pull caliper with the load 11.5 mm from the trailing
/// edge (its lead edge opens and closes about 200 times a second), 0.8 s, window from 0.4 s.
pub fn unilateral_scene() -> Scene {
    let mut s = rig_set::rig_float_scene(Caliper::Push, 0.04);
    s.caliper = Caliper::Pull;
    s.beta = 0.0115;
    s.contact = ContactLaw::Unilateral;
    s.duration = 0.8;
    s.stats_from = 0.4;
    s
}

/// What a unilateral run shows: the observed run, and each edge's open time [s] and openings in
/// the window.
pub(super) struct EdgeObserved {
    pub(super) o: Observed,
    pub(super) open_s: f64,
    pub(super) openings: u64,
}

fn of_reference(r: &UnilateralRun) -> EdgeObserved {
    EdgeObserved {
        o: Observed {
            onsets: r.onsets.clone(),
            min: r.min,
            max: r.max,
            stick_fraction: r.stick_fraction,
            final_state: [r.final_state[0], r.final_state[1], r.final_state[2], r.final_state[3]],
            steps: r.accepted_steps,
            halt: None,
        },
        open_s: r.open_s[0] + r.open_s[1],
        openings: r.openings[0] + r.openings[1],
    }
}

/// The reference at `tol`.
pub(super) fn observe_unilateral_reference(scene: &Scene, tol: Tolerances) -> Result<EdgeObserved> {
    Ok(of_reference(&simulate_unilateral(scene, tol).map_err(HostError::Input)?))
}

/// The event runner at `rtol` (untimed).
fn observe_event(scene: &Scene, rtol: f64) -> Result<EdgeObserved> {
    let mut runner = EventRunner::new(scene, rtol).map_err(|e| HostError::Input(e.to_string()))?;
    let from = scene.stats_from;
    let mut ob = Model2OnsetObserver { stats: Model2StatsObserver::new(from, scene.v).without_interpolation(), onsets: Vec::new(), from };
    let run = runner.run(from, scene.duration, &mut ob);
    let s = ob.stats.finish();
    let z = runner.state();
    let e = runner.edges().unwrap_or_default();
    Ok(EdgeObserved {
        o: Observed {
            onsets: ob.onsets,
            min: [s.min[0], s.min[1], s.min[2], s.min[3]],
            max: [s.max[0], s.max[1], s.max[2], s.max[3]],
            stick_fraction: s.stick_fraction,
            final_state: [z[0], z[1], z[2], z[3]],
            steps: runner.counts().steps,
            halt: run.err().map(|f| crate::scenes::unilateral::halt_of(&runner, f)),
        },
        open_s: e.open_s[0] + e.open_s[1],
        openings: e.openings[0] + e.openings[1],
    })
}

/// (error, period, amplitude, final) of `got` against the reference `truth_run` (module doc).
fn edge_errors(truth: &Truth, truth_run: &EdgeObserved, got: &EdgeObserved) -> (Option<f64>, Option<f64>, Option<f64>, Option<f64>) {
    let (error, ep, ea, ef) = measure(truth, &got.o);
    let open = if got.openings != truth_run.openings {
        1.0
    } else if truth_run.open_s > 0.0 {
        rel(got.open_s, truth_run.open_s)
    } else {
        got.open_s
    };
    (error.map(|e| e.max(open)), ep, ea, ef)
}

/// The unilateral scene's rows: the event runner at each of `event_rtols`, the reference at
/// each of `rtols` (loose tolerances), against the reference at rtol 1e-12.
pub(super) fn unilateral_rows(event_rtols: &[f64], rtols: &[f64], repeats: usize) -> Result<Vec<Row>> {
    let scene = unilateral_scene();
    let truth_run = observe_unilateral_reference(&scene, Tolerances::default())?;
    let truth = periodic_truth(&truth_run.o);
    let mut rows = Vec::new();
    for &rtol in event_rtols {
        let got = observe_event(&scene, rtol)?;
        let mut best = f64::INFINITY;
        for _ in 0..repeats.max(1) {
            let mut runner = EventRunner::new(&scene, rtol).map_err(|e| HostError::Input(e.to_string()))?;
            let mut ob = Model2StatsObserver::events_only(scene.stats_from, scene.v);
            let t0 = Instant::now();
            let _ = std::hint::black_box(runner.run(scene.stats_from, scene.duration, &mut ob));
            best = best.min(t0.elapsed().as_secs_f64());
        }
        rows.push(tolerance_row(UNILATERAL_SCENE, EVENT_METHOD, rtol, edge_errors(&truth, &truth_run, &got), &got.o, best));
    }
    rows.extend(loose_reference_rows(UNILATERAL_SCENE, rtols, repeats, |tol| observe_unilateral_reference(&scene, tol), |got| {
        (edge_errors(&truth, &truth_run, got), &got.o)
    }));
    Ok(rows)
}

/// `rig_push_center` (hinged, push, beta 40 mm) with the pneumatic drive on a 15 mm column and
/// a 40 / 30 N seal, 1 s, window from 0.1 s: the band breaks away 6 times, the pad slips once
/// per breakaway (host/tests/pneumatic_reference.rs).
pub fn pneumatic_scene() -> Scene {
    let mut s = rig_set::rig_scene(Caliper::Push, 0.04);
    s.drive = BandDrive::Pneumatic;
    s.column_length = 0.015;
    s.seal_static = 40.0;
    s.seal_kinetic = 30.0;
    s.duration = 1.0;
    s.stats_from = 0.1;
    s
}

/// What a pneumatic run shows: the pad's observed run, the band's mean speed [m/s] and its
/// breakaways in the window.
pub(super) struct DriveObserved {
    pub(super) o: Observed,
    pub(super) mean_speed: f64,
    pub(super) breakaways: u64,
}

fn observe_pneumatic_reference(scene: &Scene, tol: Tolerances) -> Result<DriveObserved> {
    let r = pneumatic_reference::simulate(scene, tol).map_err(HostError::Input)?;
    let from = scene.stats_from;
    let onsets = r
        .pad_transitions()
        .iter()
        .filter(|(t, from_r, _)| *t >= from && *from_r == pneumatic_reference::PadRegime::Stick)
        .map(|(t, _, _)| *t)
        .collect();
    let st = &r.stats.pad;
    Ok(DriveObserved {
        o: Observed {
            onsets,
            min: st.min,
            max: st.max,
            stick_fraction: st.stick_fraction,
            final_state: [r.final_state[0], r.final_state[1], r.final_state[2], r.final_state[3]],
            steps: r.accepted_steps,
            halt: None,
        },
        mean_speed: r.stats.band_mean_speed,
        breakaways: r.stats.band_breakaways as u64,
    })
}

/// The pneumatic runner at `rtol` (untimed), as the host runs it (samples on the grid).
fn observe_pneumatic(scene: &Scene, rtol: f64) -> Result<DriveObserved> {
    let mut runner = PneumaticRunner::new(scene, rtol).map_err(|e| HostError::Input(e.to_string()))?;
    let from = scene.stats_from;
    let mut ob = Model2OnsetObserver { stats: Model2StatsObserver::new(from, scene.v), onsets: Vec::new(), from };
    let run = runner.run_sampled(from, scene.duration, scene.dt, &mut ob, &mut |_: &PneumaticSample| true);
    let s = ob.stats.finish();
    let w = runner.state();
    let d = runner.drive_stats();
    Ok(DriveObserved {
        o: Observed {
            onsets: ob.onsets,
            min: [s.min[0], s.min[1], s.min[2], s.min[3]],
            max: [s.max[0], s.max[1], s.max[2], s.max[3]],
            stick_fraction: s.stick_fraction,
            final_state: [w[0], w[1], w[2], w[3]],
            steps: runner.counts().steps,
            halt: run.err().map(crate::scenes::pneumatic::halt_of),
        },
        mean_speed: d.mean_speed(),
        breakaways: d.breakaways,
    })
}

/// (error, period, amplitude, final) of a pneumatic run against the reference: the periodic
/// scenes' error and the band's mean speed's relative error, 1 where the band's breakaways
/// differ in number.
fn drive_errors(truth: &Truth, truth_run: &DriveObserved, got: &DriveObserved) -> (Option<f64>, Option<f64>, Option<f64>, Option<f64>) {
    let (error, ep, ea, ef) = measure(truth, &got.o);
    let band = if got.breakaways != truth_run.breakaways { 1.0 } else { rel(got.mean_speed, truth_run.mean_speed) };
    (error.map(|e| e.max(band)), ep, ea, ef)
}

/// The pneumatic scene's rows: the runner at each of `runner_rtols`, the reference at each of
/// `rtols` (loose), against the reference at rtol 1e-12.
pub(super) fn pneumatic_rows(runner_rtols: &[f64], rtols: &[f64], repeats: usize) -> Result<Vec<Row>> {
    let scene = pneumatic_scene();
    let truth_run = observe_pneumatic_reference(&scene, Tolerances::default())?;
    let truth = periodic_truth(&truth_run.o);
    let mut rows = Vec::new();
    for &rtol in runner_rtols {
        let got = observe_pneumatic(&scene, rtol)?;
        let mut best = f64::INFINITY;
        for _ in 0..repeats.max(1) {
            let mut runner = PneumaticRunner::new(&scene, rtol).map_err(|e| HostError::Input(e.to_string()))?;
            let t0 = Instant::now();
            let _ = std::hint::black_box(runner.run_sampled(scene.stats_from, scene.duration, scene.dt, &mut (), &mut |_: &PneumaticSample| true));
            best = best.min(t0.elapsed().as_secs_f64());
        }
        rows.push(tolerance_row(PNEUMATIC_SCENE, PNEUMATIC_METHOD, rtol, drive_errors(&truth, &truth_run, &got), &got.o, best));
    }
    rows.extend(loose_reference_rows(PNEUMATIC_SCENE, rtols, repeats, |tol| observe_pneumatic_reference(&scene, tol), |got| {
        (drive_errors(&truth, &truth_run, got), &got.o)
    }));
    Ok(rows)
}

/// A reference's own rows at loose tolerances (`Tolerances::loose(rtol)` for each of `rtols`),
/// timed over `repeats`: `errors` gives a run's errors and its observed run. A loose reference
/// may fail (an edge's graze missed, the pad then in the air): a row without an error, not the
/// report's end.
fn loose_reference_rows<O>(
    name: &str,
    rtols: &[f64],
    repeats: usize,
    observe: impl Fn(Tolerances) -> Result<O>,
    errors: impl Fn(&O) -> ((Option<f64>, Option<f64>, Option<f64>, Option<f64>), &Observed),
) -> Vec<Row> {
    let mut rows = Vec::new();
    for &rtol in rtols {
        let mut best = f64::INFINITY;
        let mut got = None;
        for _ in 0..repeats.max(1) {
            let t0 = Instant::now();
            let g = observe(Tolerances::loose(rtol));
            best = best.min(t0.elapsed().as_secs_f64());
            got = Some(g);
        }
        match got.expect("at least one repeat") {
            Ok(got) => {
                let (err, o) = errors(&got);
                rows.push(tolerance_row(name, "dop853_adaptive", rtol, err, o, best));
            }
            Err(e) => {
                let mut r = tolerance_row(name, "dop853_adaptive", rtol, (None, None, None, None), &Observed::default(), best);
                r.outcome = if e.to_string().contains("contact_loss") { "contact_loss".into() } else { "failed".into() };
                rows.push(r);
            }
        }
    }
    rows
}
