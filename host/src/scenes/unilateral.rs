//! Runs of a scene with unilateral contact (`contact = "unilateral"`; model 3, option 2;
//! issue 34): the model crate's event runner ([`stickslip_model::model2::event_run`]) with the
//! edges' contact states, stepping to every grid time so that a sink gets its samples (the
//! state at each k dt from the exact flow or a Dormand-Prince step, not an interpolation), and
//! the edges' open fractions and openings in the report.
//!
//! f64 only: the fixed-step model-2 stepper (and so the firmware and the virtual rig) carries
//! bilateral springs and refuses such a scene. The event runner's tolerance in Stribeck slip is
//! [`UNILATERAL_RTOL`], tighter than its default: whether a near-grazing edge dips below zero
//! is decided by the state's error (host/tests/unilateral.rs: at 1e-10 a grid step of 1e-3 s
//! lost 3 of 42 openings of a chattering scene; at 1e-12 every step from 1e-5 to 2e-3 s gives
//! the same openings and open time within 1e-9 s).

use stickslip_model::model2::event_run::{EventRunner, Fallback, GridSample};

/// The event runner's tolerance for unilateral contact (module comment).
pub const UNILATERAL_RTOL: f64 = 1e-12;
use stickslip_model::model2::Model2StatsObserver;
use stickslip_model::{Halt, Regime, Scene};

use crate::error::{HostError, Result};
use crate::scenes::cycles::CycleObserver;
use crate::scenes::run::{
    planned_steps, run_stats, window_start, EventLog, Model2Extra, Model2RunObserver, Outcome, Precision, RunReport, Starts,
};
use crate::scenes::series::{Sample, Sink};

/// Every start of `starts` run on its own event runner (each a copy of the set-up).
pub(crate) fn runs<S: Sink + ?Sized>(scene: &Scene, precision: Precision, full: bool, starts: &mut Starts<S>) -> Result<Vec<RunReport>> {
    if precision != Precision::F64 {
        return Err(HostError::Input(
            "contact = \"unilateral\" runs in f64 only (its event-driven path has no f32 form): use --precision f64".into(),
        ));
    }
    let proto = EventRunner::new(scene, UNILATERAL_RTOL).map_err(|e| HostError::Input(e.to_string()))?;
    let mut reports = Vec::with_capacity(starts.len());
    for (z0, sink) in starts.iter_mut() {
        let mut runner = proto.clone();
        if let Some(z0) = z0 {
            runner.set_state(*z0, Regime::SlipSlower);
        }
        reports.push(if full { run_one::<S, true>(scene, runner, &mut **sink)? } else { run_one::<S, false>(scene, runner, &mut **sink)? });
    }
    Ok(reports)
}

fn run_one<S: Sink + ?Sized, const FULL: bool>(scene: &Scene, mut runner: EventRunner, sink: &mut S) -> Result<RunReport> {
    let window_start = window_start(scene);
    let steps_planned = planned_steps(scene);
    let mut obs = Model2RunObserver::<FULL> {
        window_start,
        stats: if FULL {
            Model2StatsObserver::new(window_start, scene.v).without_interpolation()
        } else {
            Model2StatsObserver::events_only(window_start, scene.v)
        },
        cycles: CycleObserver::new(window_start),
        log: EventLog::default(),
    };
    let (forces, kinematics, samples_from) = (sink.wants_forces(), sink.wants_kinematics(), sink.samples_from());
    let mut steps_done: u64 = 0;
    let mut sink_error = None;
    let result = {
        let mut on_sample = |g: &GridSample| -> bool {
            steps_done += 1;
            if g.t < samples_from {
                return true;
            }
            let z = &g.z;
            let sample = Sample {
                t: g.t,
                z: [z[0], z[1], z[2], z[3]],
                n: if forces { g.n } else { f64::NAN },
                f_f: if forces { g.f_f } else { f64::NAN },
                pad_acc: if kinematics { g.d[1] } else { f64::NAN },
                v_slide: if kinematics { g.v_slide } else { f64::NAN },
                regime: g.regime,
            };
            match sink.sample(&sample) {
                Ok(()) => true,
                Err(e) => {
                    sink_error = Some(e);
                    false
                }
            }
        };
        runner.run_sampled(window_start, steps_planned as f64 * scene.dt, scene.dt, &mut obs, &mut on_sample)
    };
    if let Some(e) = sink_error {
        return Err(e);
    }
    let outcome = match result {
        Ok(()) => Outcome::Completed,
        Err(f) => Outcome::halted(scene, halt_of(&runner, f)),
    };
    let s2 = obs.stats.finish();
    Ok(RunReport {
        precision: Precision::F64,
        steps_planned,
        steps_done,
        window_start,
        stats: run_stats(&s2),
        cycles: obs.cycles.finish(),
        outcome,
        first_slip: obs.log.first_slip,
        transitions: obs.log.transitions,
        model2: Some(Model2Extra { pad_acc_pp: s2.pp(5), band_v_pp: s2.pp(4), band_acc_pp: s2.pp(6) }),
        edges: runner.edges(),
        drive: None,
    })
}

/// The halt a fallback of a unilateral run stands for (no sampled path runs it instead).
fn halt_of(runner: &EventRunner, f: Fallback) -> Halt {
    let regime = runner.regime();
    match f {
        Fallback::BothEdgesOpen { t } => Halt::ContactLoss { t, n: 0.0 },
        Fallback::Range { t } => {
            if !runner.state().iter().all(|v| v.is_finite()) {
                Halt::NonFinite { t }
            } else if runner.open_edges().iter().any(|&o| o) {
                // one edge open and the state out of range: the pad tips over about its
                // closed edge, the open one never closing again
                Halt::ContactLoss { t, n: 0.0 }
            } else {
                Halt::Diverged { t, regime, stiffness_margin: f64::INFINITY }
            }
        }
        Fallback::StepUnderflow { t } | Fallback::Stalled { t } => Halt::TransitionStorm { t },
        Fallback::StartOnGuard => Halt::TransitionStorm { t: 0.0 },
    }
}
