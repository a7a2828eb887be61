//! Runs of a scene with the pneumatic band drive (`drive = "pneumatic"`; model 3, option 1;
//! issue 34): the model crate's [`PneumaticRunner`] (the cylinder's air column, throttle and
//! seal with model 2's pad and band), stepping to every grid time so that a sink gets its
//! samples, and the drive's statistics (the band's mean speed and stuck fraction, the chamber
//! pressure, the throttle as given or solved) in the report.
//!
//! f64 only: the fixed-step steppers (and so the firmware and the virtual rig) drive the band
//! at V and refuse such a scene.

use stickslip_model::model2::Model2StatsObserver;
use stickslip_model::model3::pneumatic_run::{PneumaticRunner, PneumaticSample, PneumaticStop};
use stickslip_model::{Halt, Scene};

use crate::error::{HostError, Result};
use crate::scenes::cycles::CycleObserver;
use crate::scenes::run::{
    planned_steps, run_stats, window_start, EventLog, Model2Extra, Model2RunObserver, Outcome, Precision, RunReport, Starts,
};
use crate::scenes::series::{Sample, Sink};

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
    let window_start = window_start(scene);
    let steps_planned = planned_steps(scene);
    let mut obs = Model2RunObserver::<FULL> {
        window_start,
        stats: if FULL { Model2StatsObserver::new(window_start, scene.v) } else { Model2StatsObserver::events_only(window_start, scene.v) },
        cycles: CycleObserver::new(window_start),
        log: EventLog::default(),
    };
    let (forces, kinematics, samples_from) = (sink.wants_forces(), sink.wants_kinematics(), sink.samples_from());
    let mut steps_done: u64 = 0;
    let mut sink_error = None;
    let result = {
        let mut on_sample = |g: &PneumaticSample| -> bool {
            steps_done += 1;
            if g.t < samples_from {
                return true;
            }
            let w = &g.w;
            let sample = Sample {
                t: g.t,
                z: [w[0], w[1], w[2], w[3]],
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
        Err(PneumaticStop::Halt(h)) => Outcome::halted(scene, h),
        Err(PneumaticStop::Stalled { t }) => Outcome::halted(scene, Halt::TransitionStorm { t }),
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
        edges: None,
        drive: Some(runner.drive_stats()),
    })
}
