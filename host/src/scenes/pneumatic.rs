//! Runs of a scene with the pneumatic band drive (`drive = "pneumatic"`; model 3, option 1;
//! issue 34): the model crate's [`PneumaticRunner`] (the cylinder's air column, throttle and
//! seal with model 2's pad and band), stepping to every grid time so that a sink gets its
//! samples, and the drive's statistics (the band's mean speed and stuck fraction, the chamber
//! pressure, the throttle as given or solved) in the report.
//!
//! f64 only: the fixed-step steppers (and so the firmware and the virtual rig) drive the band
//! at V and refuse such a scene.

use stickslip_model::model3::pneumatic_run::{PneumaticRunner, PneumaticSample, PneumaticStop};
use stickslip_model::{Halt, Scene};

use crate::error::{HostError, Result};
use crate::scenes::grid_run::{self, GridStop, GridView};
use crate::scenes::run::{Precision, RunReport, Starts};
use crate::scenes::series::Sink;

/// The runner's tolerance (every component's local error relative to its largest magnitude).
pub const PNEUMATIC_RTOL: f64 = 1e-10;

/// Every start of `starts` run on its own runner (each a copy of the set-up).
pub(crate) fn runs<S: Sink + ?Sized>(scene: &Scene, precision: Precision, full: bool, starts: &mut Starts<S>) -> Result<Vec<RunReport>> {
    if precision != Precision::F64 {
        return Err(HostError::Input(
            "drive = \"pneumatic\" runs in f64 only (its event-driven path has no f32 form): use --precision f64".into(),
        ));
    }
    let proto = PneumaticRunner::new(scene, PNEUMATIC_RTOL).map_err(|e| HostError::Input(e.to_string()))?;
    let mut reports = Vec::with_capacity(starts.len());
    for (z0, sink) in starts.iter_mut() {
        let mut runner = proto.clone();
        if let Some(z0) = z0 {
            runner.set_sliding(*z0);
        }
        reports.push(if full { run_one::<S, true>(scene, runner, &mut **sink)? } else { run_one::<S, false>(scene, runner, &mut **sink)? });
    }
    Ok(reports)
}

fn run_one<S: Sink + ?Sized, const FULL: bool>(scene: &Scene, mut runner: PneumaticRunner, sink: &mut S) -> Result<RunReport> {
    let mut report = grid_run::report::<S, FULL>(scene, sink, true, |t_from, t_end, obs, on_sample| {
        runner
            .run_sampled(t_from, t_end, scene.dt, obs, &mut |g: &PneumaticSample| {
                let w = &g.w;
                on_sample(&GridView { t: g.t, regime: g.regime, z: [w[0], w[1], w[2], w[3]], n: g.n, f_f: g.f_f, pad_acc: g.d[1], v_slide: g.v_slide })
            })
            .map_err(stop_of)
    })?;
    report.drive = Some(runner.drive_stats());
    Ok(report)
}

/// A stop of a pneumatic run as the grid run reports it: the model's halt, or a stall (its step
/// budget used up: the outcome `stalled`).
fn stop_of(stop: PneumaticStop) -> GridStop {
    match stop {
        PneumaticStop::Halt(h) => GridStop::Halt(h),
        PneumaticStop::Stalled { t } => GridStop::Stalled { t },
    }
}

/// The halt a stop of a pneumatic run stands for, for the numerics' tables (`accuracy`,
/// `stability`): the model's own, or a stalled run (its step budget used up) as a
/// `transition_storm`.
pub(crate) fn halt_of(stop: PneumaticStop) -> Halt {
    match stop {
        PneumaticStop::Halt(h) => h,
        PneumaticStop::Stalled { t } => Halt::TransitionStorm { t },
    }
}
