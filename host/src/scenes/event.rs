//! Statistics at event speed: a model-2 run from event to event (the model crate's
//! `model2::event_run`), with the sampled run's observers and report, for runs that need no
//! samples on the grid (`simulate` without `--csv`, `cases`).
//!
//! Used by default where it pays ([`pays`]: a scene whose fastest mode is slow against the
//! sample rate, such as the 1-DOF Stribeck oracle); `simulate --events` runs it wherever it
//! covers the scene. Covered: every model-2 scene (Stribeck or Coulomb friction, the band, the face, the
//! floating pad) in f64 from the rest start. Not covered, and run on the sampled path: the
//! thesis model, f32, a run over the work budget, and every run the event runner gives back
//! (a state out of range, that is a halt, or a step size underflow: [`Fallback`]).
//! Error and time against the model-2 reference: `cargo run --release -p stickslip --example
//! event_speed`.

use stickslip_model::model2::event_run::{EventCounts, EventRunner, Fallback, DEFAULT_RTOL};
use stickslip_model::model2::{Model2StatsObserver, System};
use stickslip_model::{Coefficients, Scene};

use crate::error::{HostError, Result};
use crate::scenes::cycles::CycleObserver;
use crate::scenes::run::{
    planned_steps, window_start, EventLog, Model2Extra, Model2RunObserver, run_stats, Outcome, OverBudget, Precision, RunReport,
};

/// What the event run did, for the report's method line.
#[derive(Clone, Copy, Debug)]
pub struct EventRun {
    pub rtol: f64,
    pub counts: EventCounts,
}

impl EventRun {
    /// The method, for the summary: "event-driven (...)".
    pub fn describe(&self) -> String {
        let c = &self.counts;
        format!(
            "event-driven: exact flows, Dormand-Prince 5(4) in Stribeck slip at rtol {:e}; {} steps, {} events",
            self.rtol, c.steps, c.events
        )
    }
}

/// Whether the event path covers `scene` in `precision` (before running it).
pub fn covers(scene: &Scene, precision: Precision) -> bool {
    if !(precision == Precision::F64 && scene.uses_model2()) {
        return false;
    }
    if scene.unilateral() || scene.pneumatic() {
        // unilateral contact's and the pneumatic drive's runs are event-driven anyway, with
        // their samples on the grid (`crate::scenes::unilateral`, `crate::scenes::pneumatic`)
        return false;
    }
    true
}

/// The fastest linear mode's turn per sample, dt x rate [rad], above which the grid is
/// cheaper (the rig sets, at about 0.1 rad per sample, run 4 to 7 times slower event-driven:
/// their error-controlled steps are a few hundredths of a radian; `simulate rig_push_trail`
/// against `simulate rig_push_trail --grid`).
pub const PAYS_BELOW_RAD_PER_SAMPLE: f64 = 0.005;

/// Whether the event path is expected to be cheaper than the grid for `scene`: its fastest
/// linear mode turns at most [`PAYS_BELOW_RAD_PER_SAMPLE`] per sample (oracle_stribeck: 4e-4).
pub fn pays(scene: &Scene) -> bool {
    let co = Coefficients::of(scene);
    let rate = System::of(scene, &co).linear_rate(scene, &co);
    rate * scene.dt <= PAYS_BELOW_RAD_PER_SAMPLE
}

/// The sampled path's work budget of `scene`, from its substep rule (the same count the
/// stepper's set-up takes, without building its tables).
fn budget(scene: &Scene) -> Option<OverBudget> {
    let co = Coefficients::of(scene);
    let rate = System::of(scene, &co).linear_rate(scene, &co);
    let n_sub = (scene.dt * rate / 0.25).ceil().clamp(1.0, 1e6) as u32;
    OverBudget::of(n_sub, planned_steps(scene))
}

/// The event run of a validated scene at tolerance `rtol`: its report (the sampled run's
/// report, the same steps planned and done) or why it stopped short (the caller runs the
/// sampled path). `Ok(None)` when the event path does not cover the scene.
pub fn run(scene: &Scene, precision: Precision, rtol: f64) -> Result<Option<std::result::Result<(RunReport, EventRun), Fallback>>> {
    if !covers(scene, precision) || budget(scene).is_some() {
        return Ok(None);
    }
    let mut runner = EventRunner::new(scene, rtol).map_err(|e| HostError::Input(e.to_string()))?;
    let window_start = window_start(scene);
    let steps_planned = planned_steps(scene);
    let mut obs = Model2RunObserver::<true> {
        window_start,
        stats: Model2StatsObserver::new(window_start, scene.v).without_interpolation(),
        cycles: CycleObserver::new(window_start),
        log: EventLog::default(),
        step_transitions: None,
    };
    if let Err(f) = runner.run(window_start, steps_planned as f64 * scene.dt, &mut obs) {
        return Ok(Some(Err(f)));
    }
    let s2 = obs.stats.finish();
    let stats = run_stats(&s2);
    let report = RunReport {
        precision,
        steps_planned,
        steps_done: steps_planned,
        window_start,
        stats,
        cycles: obs.cycles.finish(),
        outcome: Outcome::Completed,
        first_slip: obs.log.first_slip,
        transitions: obs.log.transitions,
        model2: Some(Model2Extra { pad_acc_pp: s2.pp(5), band_v_pp: s2.pp(4), band_acc_pp: s2.pp(6) }),
        edges: None,
        drive: None,
    };
    Ok(Some(Ok((report, EventRun { rtol, counts: runner.counts() }))))
}

/// [`run`] at the default tolerance where it [`pays`] (or wherever it covers the scene, with
/// `force`), or None (not covered, not paying, or given back: run the sampled path).
pub fn try_run(scene: &Scene, precision: Precision, force: bool) -> Result<Option<(RunReport, EventRun)>> {
    if !force && !pays(scene) {
        return Ok(None);
    }
    Ok(run(scene, precision, DEFAULT_RTOL)?.and_then(|r| r.ok()))
}
