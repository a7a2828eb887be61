//! What the host's event-driven runs share (unilateral contact, `crate::scenes::unilateral`;
//! the pneumatic drive, `crate::scenes::pneumatic`): the statistics observer, the grid samples
//! handed to a sink, and the report around them. Each runner maps its own sample to a
//! [`GridView`] and its own stop to a halt. The grid times are these runs' cancellation
//! points ([`crate::cancel::check_every`]): a cancelled command's run stops at the next one.

use stickslip_model::model2::Model2StatsObserver;
use stickslip_model::{Halt, Regime, Scene};

use crate::error::Result;
use crate::scenes::cycles::CycleObserver;
use crate::scenes::run::{planned_steps, run_stats, window_start, EventLog, Model2Extra, Model2RunObserver, OverBudget, Outcome, Precision, RunReport};
use crate::scenes::series::{Sample, Sink};

/// Why an event-driven run stopped short: the model's halt, or its error-controlled steps out
/// of their budget at `t` [s] (a stall: reported as the outcome `stalled`, not as a halt of the
/// model).
pub(crate) enum GridStop {
    Halt(Halt),
    Stalled { t: f64 },
}

/// One grid sample of an event-driven run: time [s], regime, the pad's [x, x', phi, phi'], the
/// normal force [N], the friction force on the pad [N], x'' [m/s^2] and the sliding velocity
/// [m/s].
pub(crate) struct GridView {
    pub t: f64,
    pub regime: Regime,
    pub z: [f64; 4],
    pub n: f64,
    pub f_f: f64,
    pub pad_acc: f64,
    pub v_slide: f64,
}

/// Runs `run` (window start, end time, the observer, the sample callback; a stop of the run
/// given as its halt) and builds its report (f64; `edges` and `drive` left for the caller).
/// `interpolate`: the observer interpolates in a segment (false where segments end at every
/// extreme).
pub(crate) fn report<S: Sink + ?Sized, const FULL: bool>(
    scene: &Scene,
    sink: &mut S,
    interpolate: bool,
    run: impl FnOnce(f64, f64, &mut Model2RunObserver<FULL>, &mut dyn FnMut(&GridView) -> bool) -> std::result::Result<(), GridStop>,
) -> Result<RunReport> {
    let window_start = window_start(scene);
    let steps_planned = planned_steps(scene);
    // the work budget, as the stepped runs have it: an event-driven run does at least one
    // unit of work per grid time (a sample), so more grid times than the budget are not run
    // (dt 1e-9 or a duration of days ran for hours)
    let budget = OverBudget::of(1, steps_planned);
    let mut obs = Model2RunObserver::<FULL> {
        window_start,
        stats: match (FULL, interpolate) {
            (true, true) => Model2StatsObserver::new(window_start, scene.v),
            (true, false) => Model2StatsObserver::new(window_start, scene.v).without_interpolation(),
            (false, _) => Model2StatsObserver::events_only(window_start, scene.v),
        },
        cycles: CycleObserver::new(window_start),
        log: EventLog::default(),
        step_transitions: None,
    };
    let (forces, kinematics, samples_from) = (sink.wants_forces(), sink.wants_kinematics(), sink.samples_from());
    let mut steps_done: u64 = 0;
    let mut sink_error = None;
    let result = {
        let mut on_sample = |g: &GridView| -> bool {
            // the command's cancellation point (Ctrl-C in the Python module), every
            // CHECK_EVERY_STEPS grid times
            if let Err(e) = crate::cancel::check_every(steps_done) {
                sink_error = Some(e);
                return false;
            }
            steps_done += 1;
            if g.t < samples_from {
                return true;
            }
            let sample = Sample {
                t: g.t,
                z: g.z,
                n: if forces { g.n } else { f64::NAN },
                f_f: if forces { g.f_f } else { f64::NAN },
                pad_acc: if kinematics { g.pad_acc } else { f64::NAN },
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
        if budget.is_some() {
            Ok(())
        } else {
            run(window_start, steps_planned as f64 * scene.dt, &mut obs, &mut on_sample)
        }
    };
    if let Some(e) = sink_error {
        return Err(e);
    }
    let outcome = match (budget, result) {
        (Some(b), _) => Outcome::Budget(b),
        (None, Ok(())) => Outcome::Completed,
        (None, Err(GridStop::Halt(h))) => Outcome::halted(scene, h),
        (None, Err(GridStop::Stalled { t })) => Outcome::Stalled { t },
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
        drive: None,
    })
}
