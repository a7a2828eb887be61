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
use stickslip_model::{Halt, Regime, Scene};

use crate::error::{HostError, Result};
use crate::scenes::grid_run::{self, GridStop, GridView};
use crate::scenes::run::{Precision, RunReport, Starts};
use crate::scenes::series::Sink;

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
    let mut report = grid_run::report::<S, FULL>(scene, sink, false, |t_from, t_end, obs, on_sample| {
        runner
            .run_sampled(t_from, t_end, scene.dt, obs, &mut |g: &GridSample| {
                let z = &g.z;
                on_sample(&GridView { t: g.t, regime: g.regime, z: [z[0], z[1], z[2], z[3]], n: g.n, f_f: g.f_f, pad_acc: g.d[1], v_slide: g.v_slide })
            })
            .map_err(|f| match f {
                Fallback::Stalled { t } | Fallback::StepUnderflow { t } => GridStop::Stalled { t },
                f => GridStop::Halt(halt_of(&runner, f)),
            })
    })?;
    report.edges = runner.edges();
    Ok(report)
}

/// The halt a fallback of a unilateral run stands for (no sampled path runs it instead).
pub(crate) fn halt_of(runner: &EventRunner, f: Fallback) -> Halt {
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
