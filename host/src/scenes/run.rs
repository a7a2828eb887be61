//! Running one scene: the stepper in the chosen precision, the observers (window statistics,
//! cycle spread, transition log) and the per-step sink; a halt is an outcome, not an error.

use stickslip_model::exact::{SlipPairs, TaylorFlows};
use stickslip_model::propagator::Propagator;
use stickslip_model::stats::{EventWindow, RunStats, StatsObserver};
use stickslip_model::model2::event_run::edges::EdgeStats;
use stickslip_model::model3::pneumatic_run::DriveStats;
use stickslip_model::model2::{AnyModel2Stepper, Shared, Model2Observer, Model2Segment, Model2Stats, Model2StatsObserver, Model2Transition, WideSamples, WideChunks, NS};
use stickslip_model::{
    Coefficients, ExactState, ExactStepper, ExactTables, Halt, Observer, Real, Regime, Scene, SceneError, Segment, State, StickJump,
    Transition,
};

use crate::scenes::cycles::{CycleObserver, CycleStats};
use crate::error::{HostError, Result};
use crate::scenes::series::{Sample, Sink};
use crate::scenes::table_cache::{Cached, PropagatorCache};
use crate::scenes::wide_runs::{WideReal, LOCATE_BELOW_LEVEL};
pub use crate::scenes::wide_runs::WIDE_STEPS;

/// The floating-point type the stepper runs in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Precision {
    F32,
    F64,
}

impl Precision {
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }
}

/// A run over the work budget ([`crate::limits::SUBSTEP_BUDGET`]): what it would have taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OverBudget {
    /// Substeps per step the quarter-radian rule asks for (at the steppers' cap
    /// the steppers' cap of 1e6: more were needed).
    pub substeps_per_step: u32,
    /// Steps of the run, round(duration / dt).
    pub steps: u64,
}

impl OverBudget {
    /// Whether a run of `steps` steps of `substeps_per_step` substeps each is over the budget.
    pub fn of(substeps_per_step: u32, steps: u64) -> Option<OverBudget> {
        let capped = substeps_per_step >= crate::limits::SUBSTEPS_PER_STEP_CAP;
        let work = u64::from(substeps_per_step).saturating_mul(steps);
        (capped || work > crate::limits::SUBSTEP_BUDGET).then_some(OverBudget { substeps_per_step, steps })
    }

    /// The cause, for the summary: which limit, and what to change.
    pub fn cause(&self) -> String {
        use crate::output::format::sig4;
        if self.substeps_per_step >= crate::limits::SUBSTEPS_PER_STEP_CAP {
            format!(
                "the scene's fastest mode needs {} or more substeps per step (a quarter radian each; at most {}): \
                 a mass, inertia or damping too small or a stiffness too large for dt; not run",
                self.substeps_per_step,
                crate::limits::SUBSTEPS_PER_STEP_CAP
            )
        } else {
            // the work is about max(steps, duration x the fastest mode's rate / a quarter
            // radian): a smaller dt never lowers it; a larger one does where each step is one
            // substep
            let what = if self.substeps_per_step <= 1 {
                "a shorter duration or a larger dt (each step is one substep: the steps alone are over it)"
            } else {
                "a shorter duration or a slower fastest mode (the substeps are set by the fastest mode, whatever dt)"
            };
            format!(
                "{} substeps per step x {} steps = {} substeps, over the work budget of {} (minutes to hours \
                 of computing): {what}; not run",
                self.substeps_per_step,
                self.steps,
                sig4(u64::from(self.substeps_per_step).saturating_mul(self.steps) as f64),
                sig4(crate::limits::SUBSTEP_BUDGET as f64)
            )
        }
    }
}

/// Substeps per step the scene's stepper takes (its tables built in f32, the same count as
/// in f64: the rule is evaluated in f64). For a validated scene.
pub fn substeps_per_step(scene: &Scene) -> Result<u32> {
    if scene.uses_model2() {
        let st = AnyModel2Stepper::<f32>::new(scene).map_err(|e| HostError::Input(e.to_string()))?;
        Ok(st.substeps())
    } else {
        Ok(Propagator::<f32>::new(scene, &Coefficients::of(scene), scene.dt).n_sub)
    }
}

/// The scene's run over the work budget, if it is.
pub fn over_budget(scene: &Scene) -> Result<Option<OverBudget>> {
    Ok(OverBudget::of(substeps_per_step(scene)?, planned_steps(scene)))
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outcome {
    Completed,
    /// Not run: over the work budget (classified `budget`, with its cause).
    Budget(OverBudget),
    /// An event-driven run (unilateral contact, the pneumatic drive) whose error-controlled
    /// steps used up their budget at `t` [s]: a stiff scene it crawls through, or a state it
    /// cannot leave (classified `stalled`).
    Stalled { t: f64 },
    /// `self_locked`: the scene's pad can never slip forward (its rotational stiffness at the
    /// static limit, K - s mu_s w c_N, is <= 0), so a divergence in stick is the sprag lock.
    Halted {
        halt: Halt,
        self_locked: bool,
    },
}

impl Outcome {
    /// The outcome of a run of `scene` that halted with `halt`.
    pub fn halted(scene: &Scene, halt: Halt) -> Outcome {
        let co = Coefficients::of(scene);
        let self_locked = co.effective_rotational_stiffness(scene, 1.0, scene.mu_s) <= 0.0;
        Outcome::Halted { halt, self_locked }
    }

    /// The JSON/summary keyword: completed, contact_loss, diverged, sprag, non_finite,
    /// transition_storm.
    pub fn keyword(&self) -> &'static str {
        match self {
            Outcome::Completed => "completed",
            Outcome::Budget(_) => "budget",
            Outcome::Stalled { .. } => "stalled",
            Outcome::Halted { halt, self_locked } => match *halt {
                Halt::ContactLoss { .. } => "contact_loss",
                Halt::Diverged {
                    stiffness_margin, ..
                } if stiffness_margin <= 0.0 => "sprag",
                Halt::Diverged {
                    regime: Regime::Stick,
                    ..
                } if *self_locked => "sprag",
                Halt::Diverged { .. } => "diverged",
                Halt::NonFinite { .. } => "non_finite",
                Halt::TransitionStorm { .. } => "transition_storm",
            },
        }
    }

    /// Time of the halt [s].
    pub fn halt_time(&self) -> Option<f64> {
        match self {
            Outcome::Completed => None,
            Outcome::Budget(_) => Some(0.0),
            Outcome::Stalled { t } => Some(*t),
            Outcome::Halted { halt, .. } => Some(halt.time()),
        }
    }
}

/// Everything a report needs about one run.
#[derive(Clone, Debug)]
pub struct RunReport {
    pub precision: Precision,
    /// Steps the scene asks for, round(duration / dt).
    pub steps_planned: u64,
    /// Steps completed.
    pub steps_done: u64,
    /// Start of the statistics window actually used (nearest step boundary) [s].
    pub window_start: f64,
    pub stats: RunStats,
    pub cycles: CycleStats,
    pub outcome: Outcome,
    /// First stick-to-slip transition of the run [s].
    pub first_slip: Option<f64>,
    /// Transitions in the whole run.
    pub transitions: u64,
    /// Model 2's extra window statistics (a scene with Stribeck friction or the band).
    pub model2: Option<Model2Extra>,
    /// Unilateral contact: each edge's open fraction and openings over the window.
    pub edges: Option<EdgeStats>,
    /// Pneumatic band drive: the band's mean speed and stuck fraction, the chamber pressure,
    /// the throttle, over the window.
    pub drive: Option<DriveStats>,
}

/// Peak-to-peak values only model 2 has, over the statistics window (SI units). Accelerations
/// are taken at every segment end (each substep end and each transition instant).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Model2Extra {
    /// Pad acceleration x'' [m/s^2] (the rig's pad_x).
    pub pad_acc_pp: f64,
    /// Band velocity x_b' [m/s] (V without the band).
    pub band_v_pp: f64,
    /// Band acceleration x_b'' [m/s^2] (the rig's disc_x; 0 without the band).
    pub band_acc_pp: f64,
}

impl RunReport {
    /// Whether the window holds any motion (a run that halts before it has none).
    pub fn has_window(&self) -> bool {
        self.stats.window_s > 0.0
    }

    /// Peak-to-peak of quantity `i` (0 x, 1 x', 2 phi, 3 phi'), None without a window or
    /// if not finite.
    pub fn pp(&self, i: usize) -> Option<f64> {
        let v = self.stats.pp(i);
        (self.has_window() && v.is_finite()).then_some(v)
    }
}

/// Whole-run transition log: count and first slip.
#[derive(Default)]
pub(crate) struct EventLog {
    pub(crate) transitions: u64,
    pub(crate) first_slip: Option<f64>,
}

/// Forwards every segment and transition to the window statistics, the cycle spread and the
/// event log. Segments with a non-finite state (the step that halts a run) are left out of
/// the statistics.
struct RunObserver<T: Real> {
    stats: StatsObserver<T>,
    cycles: CycleObserver,
    log: EventLog,
}

impl<T: Real> Observer<T> for RunObserver<T> {
    fn segment(&mut self, seg: &Segment<T>, prop: &Propagator<T>) {
        let finite = seg.z0.iter().chain(seg.z1.iter()).all(|v| v.is_finite());
        if finite {
            self.stats.segment(seg, prop);
        }
    }

    fn transition(&mut self, tr: &Transition<T>) {
        self.stats.transition(tr);
        self.note(tr);
    }
}

impl<T: Real> RunObserver<T> {
    /// The transition log and the cycle spread (everything but the window statistics).
    fn note(&mut self, tr: &Transition<T>) {
        self.cycles.transition(tr);
        self.log.transitions += 1;
        if tr.from == Regime::Stick && self.log.first_slip.is_none() {
            self.log.first_slip = Some(tr.t);
        }
    }
}

/// Where a run starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Start {
    /// The model's initial state: the pad stuck, moving with the band, at its rest under the
    /// load (every command's start).
    Rest,
    /// Steady sliding at the band speed ([`crate::scenes::sliding`]: the pad at rest at its sliding
    /// fixed point, the band at V) plus a velocity kick of relative size `kick` on each of the
    /// pad's degrees of freedom the scene moves: x' and y' by kick V [m/s], phi' by kick V / l
    /// [rad/s] (each pad edge by kick V). Slip with the pad slower than the band.
    Sliding { kick: f64 },
}

/// The start state of `scene` from `start` (None for [`Start::Rest`]): the state
/// [x, x', phi, phi', u, u', y, y'] in slip with the pad slower than the band. An error if the
/// scene has no steady sliding (sprag, contact loss).
pub fn start_state(scene: &Scene, start: Start) -> Result<Option<[f64; 8]>> {
    let Start::Sliding { kick } = start else { return Ok(None) };
    let fixed = crate::scenes::sliding::steady_sliding(scene);
    if let Some((_, why)) = &fixed.invalid {
        return Err(HostError::Input(format!("no start from steady sliding: {why}")));
    }
    let mut z = fixed.state;
    z[1] += kick * scene.v;
    if scene.rotation {
        z[3] += kick * scene.v / scene.l;
    }
    if scene.floating() {
        z[stickslip_model::model2::Y + 1] += kick * scene.v;
    }
    Ok(Some(z))
}

/// How much of the window statistics a run keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Detail {
    /// Everything: the exact extremes of the state too.
    Full,
    /// Stick fraction, stick-slip frequency and transitions only (the extremes in
    /// [`RunStats`] and [`Model2Extra`] stay 0): the maps' runs, several times cheaper.
    Events,
}

/// Runs a validated scene for round(duration / dt) steps, handing each completed step to `sink`.
/// A scene with a model-2 option (Stribeck friction, the band) runs on the model-2 stepper;
/// every other scene on the thesis stepper.
pub fn run<S: Sink + ?Sized>(scene: &Scene, precision: Precision, sink: &mut S) -> Result<RunReport> {
    run_from(scene, precision, Start::Rest, Detail::Full, sink)
}

/// [`run`] from `start`, keeping the statistics `detail` says.
pub fn run_from<S: Sink + ?Sized>(
    scene: &Scene,
    precision: Precision,
    start: Start,
    detail: Detail,
    sink: &mut S,
) -> Result<RunReport> {
    let mut reports = run_starts(scene, precision, detail, &mut [(start, sink)])?;
    Ok(reports.remove(0))
}

/// [`run_from`] from each start in turn, the stepper set up once (its tables are most of a
/// short run's cost) and its tables shared by every run, each run its own copy of the state
/// only: the maps' two runs of a cell.
pub fn run_starts<S: Sink + ?Sized>(
    scene: &Scene,
    precision: Precision,
    detail: Detail,
    runs: &mut [(Start, &mut S)],
) -> Result<Vec<RunReport>> {
    run_starts_cached(scene, precision, detail, runs, None)
}

/// [`run_starts`] with the thesis stepper's propagator from `cache` (built there on a miss):
/// the same runs, bit for bit; the maps' cells share the tables of equal keys.
pub fn run_starts_cached<S: Sink + ?Sized>(
    scene: &Scene,
    precision: Precision,
    detail: Detail,
    runs: &mut [(Start, &mut S)],
    cache: Option<&PropagatorCache>,
) -> Result<Vec<RunReport>> {
    let mut starts = Vec::with_capacity(runs.len());
    for (start, sink) in runs.iter_mut() {
        starts.push((start_state(scene, *start)?, &mut **sink));
    }
    let full = detail == Detail::Full;
    if scene.unilateral() {
        return crate::scenes::unilateral::runs(scene, precision, full, &mut starts);
    }
    if scene.pneumatic() {
        return crate::scenes::pneumatic::runs(scene, precision, full, &mut starts);
    }
    match (precision, scene.uses_model2()) {
        (Precision::F32, false) => thesis_runs::<f32, S>(scene, precision, full, &mut starts, cache),
        (Precision::F64, false) => thesis_runs::<f64, S>(scene, precision, full, &mut starts, cache),
        (Precision::F32, true) => model2_runs::<f32, S>(scene, precision, full, &mut starts),
        (Precision::F64, true) => model2_runs::<f64, S>(scene, precision, full, &mut starts),
    }
}

pub(crate) type Starts<'a, S> = [(Option<[f64; 8]>, &'a mut S)];

fn thesis_runs<T: Cached, S: Sink + ?Sized>(
    scene: &Scene,
    precision: Precision,
    full: bool,
    starts: &mut Starts<S>,
    cache: Option<&PropagatorCache>,
) -> Result<Vec<RunReport>> {
    // each run on the set-up's tables, from a copy of its state
    let mut runs = |tables: &ExactTables<T>, state: ExactState<T>| -> Result<Vec<RunReport>> {
        let budget = OverBudget::of(tables.propagator().n_sub, planned_steps(scene));
        // the event speed's tables, once for the runs of the scene that take stick whole
        let speed = (!full && starts.iter().any(|(_, sink)| sink.takes_stick_runs())).then(|| EventSpeed::new(scene, tables));
        starts
            .iter_mut()
            .map(|(z0, sink)| run_in(scene, precision, speed.as_ref(), ExactStepper::on(tables, state), *z0, full, budget, &mut **sink))
            .collect()
    };
    // The caller validated the scene; a failure here still gets a message, not a panic.
    let input = |e: SceneError| HostError::Input(e.to_string());
    match cache {
        Some(c) => c.with_tables::<T, _>(scene, runs).map_err(input)?,
        None => {
            let (tables, state) = ExactTables::<T>::new(scene).map_err(input)?;
            runs(&tables, state)
        }
    }
}

fn model2_runs<T: WideReal, S: Sink + ?Sized>(scene: &Scene, precision: Precision, full: bool, starts: &mut Starts<S>) -> Result<Vec<RunReport>> {
    // at event speed (runs of statistics only that take it: a map's cells) the slip tables of
    // the thread's last cell are reused where they are the same, and Stribeck slip goes in wide chunks
    let fast = !full && starts.iter().any(|(_, sink)| sink.takes_stick_runs());
    let proto = if fast { T::stepper_reusing(scene) } else { AnyModel2Stepper::<T>::new(scene) };
    let proto = proto.map_err(|e| HostError::Input(e.to_string()))?;
    let budget = OverBudget::of(proto.substeps(), planned_steps(scene));
    let wide = if fast { T::wide_chunks(&proto, scene, WIDE_STEPS) } else { None };
    let mut reports = Vec::with_capacity(starts.len());
    for (z0, sink) in starts.iter_mut() {
        // each run on the set-up's tables (tens of KB), from a copy of its state
        let stepper = proto.shared();
        let wide = wide.as_ref().filter(|_| sink.takes_stick_runs());
        reports.push(if full {
            run_model2_in::<T, S, true, false>(scene, precision, stepper, *z0, budget, None, &mut **sink)?
        } else if wide.is_some() {
            run_model2_in::<T, S, false, true>(scene, precision, stepper, *z0, budget, wide, &mut **sink)?
        } else {
            run_model2_in::<T, S, false, false>(scene, precision, stepper, *z0, budget, None, &mut **sink)?
        });
    }
    if fast {
        T::keep_donor(scene, proto);
    }
    Ok(reports)
}

/// A model-2 run's window statistics as the thesis runs report them (the pad's four
/// coordinates; the band's and the lateral ones stay in [`Model2Extra`]).
pub(crate) fn run_stats(s: &Model2Stats) -> RunStats {
    RunStats {
        min: [s.min[0], s.min[1], s.min[2], s.min[3]],
        max: [s.max[0], s.max[1], s.max[2], s.max[3]],
        stick_fraction: s.stick_fraction,
        stick_slip_hz: s.stick_slip_hz,
        slip_onsets: s.slip_onsets,
        transitions: s.transitions,
        window_s: s.window_s,
    }
}

/// The model-2 run's observers: window statistics, cycle spread, transition log. `FULL`:
/// the window statistics keep the extremes, which need z' at each segment's ends; without
/// them ([`Detail::Events`]) the stepper computes no derivatives.
pub(crate) struct Model2RunObserver<const FULL: bool, const FAST: bool = false> {
    /// The statistics window's start [s]: the window statistics take no segment ending
    /// at or before it.
    pub(crate) window_start: f64,
    pub(crate) stats: Model2StatsObserver,
    pub(crate) cycles: CycleObserver,
    pub(crate) log: EventLog,
    /// The transitions of the current step (time, regime left, regime entered, the state),
    /// for the sink's [`Sink::between`], emptied after each step; `None`: not kept.
    pub(crate) step_transitions: Option<Vec<(f64, Regime, Regime, [f64; NS])>>,
}

impl<T: Real, const FULL: bool, const FAST: bool> Model2Observer<T> for Model2RunObserver<FULL, FAST> {
    const DERIVATIVES: bool = FULL;
    /// At event speed (`FAST`, f64): transitions lifted to 2^-9 of a substep, then located on
    /// the guard's quadratic ([`Model2Observer::LOCATE_BELOW_LEVEL`]).
    const LOCATE_BELOW_LEVEL: usize = if FAST && T::DYADIC_LEVELS > 24 { LOCATE_BELOW_LEVEL } else { 0 };

    fn segment(&mut self, seg: &Model2Segment<T>) {
        if seg.t1 <= self.window_start {
            return;
        }
        let finite = seg.z0.iter().chain(seg.z1.iter()).all(|v| v.is_finite());
        if finite {
            <Model2StatsObserver as Model2Observer<T>>::segment(&mut self.stats, seg);
        }
    }

    fn transition(&mut self, tr: &Model2Transition<T>) {
        <Model2StatsObserver as Model2Observer<T>>::transition(&mut self.stats, tr);
        if let Some(v) = &mut self.step_transitions {
            v.push((tr.t, tr.from, tr.to, tr.z.map(|v| v.to_f64())));
        }
        let pad = Transition {
            t: tr.t,
            from: tr.from,
            to: tr.to,
            state: State::from_array([tr.z[0], tr.z[1], tr.z[2], tr.z[3]]),
        };
        Observer::<T>::transition(&mut self.cycles, &pad);
        self.log.transitions += 1;
        if tr.from == Regime::Stick && self.log.first_slip.is_none() {
            self.log.first_slip = Some(tr.t);
        }
    }
}

#[allow(clippy::too_many_arguments)] // a run's scene, start, budget, wide tables and sink
fn run_model2_in<T: WideReal, S: Sink + ?Sized, const FULL: bool, const FAST: bool>(
    scene: &Scene,
    precision: Precision,
    mut stepper: AnyModel2Stepper<T, Shared<'_>>,
    z0: Option<[f64; 8]>,
    budget: Option<OverBudget>,
    wide: Option<&WideChunks>,
    sink: &mut S,
) -> Result<RunReport> {
    if let Some(z0) = z0 {
        stepper.set_state(z0.map(T::from_f64), Regime::SlipSlower);
    }
    // the window starts at the step boundary nearest stats_from, as in the thesis stepper
    let window_start = window_start(scene);
    let mut obs = Model2RunObserver::<FULL, FAST> {
        window_start,
        stats: if FULL { Model2StatsObserver::new(window_start, scene.v) } else { Model2StatsObserver::events_only(window_start, scene.v) },
        cycles: CycleObserver::new(window_start),
        log: EventLog::default(),
        step_transitions: sink.wants_kinematics().then(Vec::new),
    };
    let steps_planned = planned_steps(scene);
    let (forces, kinematics, samples_from) = (sink.wants_forces(), sink.wants_kinematics(), sink.samples_from());
    let mut outcome = budget.map_or(Outcome::Completed, Outcome::Budget);
    let mut steps_done = 0;
    let steps = if budget.is_some() { 0 } else { steps_planned };
    // a wide chunk not taken is tried again after this many steps
    let mut wide_rest = 0usize;
    let mut wide_out = WideSamples::default();
    let dt = scene.dt;
    let mut i = 0u64;
    let mut next_check = 0u64;
    while i < steps {
        // (a wide chunk moves i by several steps: not every multiple is met)
        if i >= next_check {
            crate::cancel::check()?;
            next_check = i + crate::cancel::CHECK_EVERY_STEPS;
        }
        if let Some(w) = wide {
            let m = w.steps() as u64;
            if wide_rest == 0 && i + m <= steps {
                let samples = (i + m) as f64 * dt >= samples_from;
                if T::wide_step(&mut stepper, w, &mut obs, samples, &mut wide_out) {
                    if samples {
                        for k in 1..=m {
                            if (i + k) as f64 * dt >= samples_from {
                                let j = (k - 1) as usize;
                                sink.quiet_sample(i + k, dt, wide_out.pad_acc[j], wide_out.v[j], stepper.regime())?;
                            }
                        }
                    }
                    i += m;
                    steps_done += m;
                    continue;
                }
                // not taken: the sampled path's steps, and again after m - 1 of them
                wide_rest = m as usize;
            }
            wide_rest = wide_rest.saturating_sub(1);
        }
        i += 1;
        let stepped = stepper.step_observed(&mut obs);
        if let Some(trs) = &mut obs.step_transitions {
            for (t, from, to, z) in trs.drain(..) {
                if t < samples_from {
                    continue;
                }
                let zt = z.map(T::from_f64);
                for regime in [from, to] {
                    sink.between(&Sample {
                        t,
                        z: [z[0], z[1], z[2], z[3]],
                        n: f64::NAN,
                        f_f: f64::NAN,
                        pad_acc: stepper.derivative(regime, &zt)[1].to_f64(),
                        v_slide: stepper.sliding_velocity(&zt).to_f64(),
                        regime,
                    })?;
                }
            }
        }
        if let Err(halt) = stepped {
            outcome = Outcome::halted(scene, halt);
            break;
        }
        steps_done += 1;
        let t = stepper.time();
        if t < samples_from {
            continue;
        }
        let z = stepper.state();
        let regime = stepper.regime();
        sink.sample(&Sample {
            t,
            z: [z[0].to_f64(), z[1].to_f64(), z[2].to_f64(), z[3].to_f64()],
            n: if forces { stepper.normal_force(&z).to_f64() } else { f64::NAN },
            f_f: if forces { stepper.friction_force(regime, &z).to_f64() } else { f64::NAN },
            pad_acc: if kinematics { stepper.pad_acceleration().to_f64() } else { f64::NAN },
            v_slide: if kinematics { stepper.sliding_velocity(&z).to_f64() } else { f64::NAN },
            regime,
        })?;
    }
    let s2 = obs.stats.finish();
    let stats = run_stats(&s2);
    Ok(RunReport {
        precision,
        steps_planned,
        steps_done,
        window_start,
        stats,
        cycles: obs.cycles.finish(),
        outcome,
        first_slip: obs.log.first_slip,
        transitions: obs.log.transitions,
        edges: None,
        drive: None,
        model2: Some(Model2Extra {
            pad_acc_pp: s2.pp(5),
            band_v_pp: s2.pp(4),
            band_acc_pp: s2.pp(6),
        }),
    })
}

/// What a thesis run of [`Detail::Events`] at event speed reads beside the stepper's tables
/// (a map cell's runs share it): the jump over stick, the regimes' Taylor flows for the
/// located transitions (f64) and the slip flows over two steps (f64).
pub(crate) struct EventSpeed<T: Real> {
    jump: StickJump<T>,
    taylor: TaylorFlows,
    pairs: Option<SlipPairs<T>>,
}

impl<T: Real> EventSpeed<T> {
    fn new(scene: &Scene, tables: &ExactTables<T>) -> Self {
        EventSpeed {
            jump: StickJump::<T>::new(scene),
            taylor: TaylorFlows::new(scene),
            pairs: (T::DYADIC_LEVELS > 24).then(|| SlipPairs::new(scene, tables)),
        }
    }
}

/// Steps a thesis run of [`Detail::Events`] steps in stick before it tries the jump over
/// stick again ([`run_in`]).
const JUMP_RETRY_STEPS: u64 = 16;

/// Most quiet steps a thesis run of [`Detail::Events`] takes in one go ([`run_in`]), so that
/// the cancellation check between them runs at least this often.
const QUIET_STEPS_MAX: u64 = 1 << 16;

/// The first step k >= 0 whose end time k dt (formed as the run forms it) is at or after `t`
/// (0 for t <= 0 or -inf; u64::MAX if none, t = inf or NaN).
pub fn first_step_at(dt: f64, t: f64) -> u64 {
    if !(t > 0.0) {
        return if t.is_nan() { u64::MAX } else { 0 };
    }
    let guess = (t / dt).ceil();
    if !(guess < 9.0e18) {
        return u64::MAX;
    }
    let mut k = guess as u64;
    while k > 0 && (k - 1) as f64 * dt >= t {
        k -= 1;
    }
    while (k as f64 * dt) < t {
        k += 1;
    }
    k
}

/// Start of the statistics window [s]: the step boundary nearest stats_from (as the thesis
/// stepper's statistics take it).
pub fn window_start(scene: &Scene) -> f64 {
    (scene.stats_from / scene.dt).round() * scene.dt
}

/// round(duration / dt), at least one.
pub fn planned_steps(scene: &Scene) -> u64 {
    ((scene.duration / scene.dt).round() as u64).max(1)
}

/// A quiet step's sample for [`run_in`]: step `k + 1`, handed to the sink until it fails
/// (`failed`).
#[inline(always)]
fn quiet_sample<T: Real, S: Sink + ?Sized>(sink: &mut S, k: &mut u64, dt: f64, v_slide: T, acc: T, regime: Regime, failed: &mut Option<HostError>) {
    *k += 1;
    if failed.is_none() {
        if let Err(e) = sink.quiet_sample(*k, dt, acc.to_f64(), v_slide.to_f64(), regime) {
            *failed = Some(e);
        }
    }
}

#[allow(clippy::too_many_arguments)] // the run's scene, precision, tables, start and sink
fn run_in<T: Cached, S: Sink + ?Sized>(
    scene: &Scene,
    precision: Precision,
    speed: Option<&EventSpeed<T>>,
    mut stepper: ExactStepper<T, &ExactTables<T>>,
    z0: Option<[f64; 8]>,
    full: bool,
    budget: Option<OverBudget>,
    sink: &mut S,
) -> Result<RunReport> {
    if let Some(z) = z0 {
        let pad = [z[0], z[1], z[2], z[3]].map(T::from_f64);
        stepper.set_state(State::from_array(pad), Regime::SlipSlower);
    }
    let v = T::from_f64(scene.v);
    let stats = StatsObserver::<T>::new(scene.stats_from, scene.dt);
    let window_start = stats.window_start();
    // Detail::Events: the stepper's fast path, the window's statistics from its transitions
    let mut events = EventWindow::new(window_start, stepper.regime() == Regime::Stick);
    let mut obs = RunObserver {
        stats,
        cycles: CycleObserver::new(window_start),
        log: EventLog::default(),
    };
    let steps_planned = planned_steps(scene);
    let (forces, kinematics, samples_from) = (sink.wants_forces(), sink.wants_kinematics(), sink.samples_from());
    let mut outcome = budget.map_or(Outcome::Completed, Outcome::Budget);
    let mut steps_done = 0;
    let steps_to_run = if budget.is_some() { 0 } else { steps_planned };
    // stick at event speed where the sink takes stick phases whole (the maps' cells)
    let speed = speed.filter(|_| !full && sink.takes_stick_runs());
    let jump = speed.map(|e| &e.jump);
    let taylor = speed.map(|e| &e.taylor);
    let pairs = speed.and_then(|e| e.pairs.as_ref());
    let mut next_jump_try = 0u64;
    // the first step whose end the sink reads (k dt >= samples_from)
    let first_sampled = first_step_at(scene.dt, samples_from);
    let mut iterations = 0u64;
    while steps_done < steps_to_run {
        crate::cancel::check_every(iterations)?;
        iterations += 1;
        if let Some(jump) = jump {
            if stepper.regime() == Regime::Stick && steps_done >= next_jump_try {
                let (tables, state) = stepper.parts_mut();
                let first = state.steps() + 1;
                let n = tables.jump_stick(jump, state, steps_to_run - steps_done);
                // after a jump the guard is near; after a refusal the bound rarely clears at
                // once: step a while before trying again
                next_jump_try = steps_done + n + JUMP_RETRY_STEPS;
                if n > 0 {
                    steps_done += n;
                    sink.stick_samples(first, n, scene.dt)?;
                    continue;
                }
            }
            // the common steps at loop speed, up to the next step that fires, may crest or
            // leaves the range (that one below), in stick no further than the next jump's try
            // (and no more than QUIET_STEPS_MAX at once: the cancellation check runs between)
            let left = (steps_to_run - steps_done).min(QUIET_STEPS_MAX);
            let max = if stepper.regime() == Regime::Stick && next_jump_try > steps_done { (next_jump_try - steps_done).min(left) } else { left };
            let regime = stepper.regime();
            let (tables, state) = stepper.parts_mut();
            let mut k = state.steps();
            let mut failed = None;
            let dt = scene.dt;
            let n = if k + 1 < first_sampled {
                // before the samples the sink reads: the state alone
                let max = max.min(first_sampled - 1 - k);
                if regime == Regime::Stick {
                    tables.quiet_stick_steps(state, max, |_, _| {})
                } else {
                    // in slip two steps at a time while a pair has no event, then a couple of
                    // single steps (the step of an event is left to the located step)
                    let mut done = 0;
                    loop {
                        if let Some(p) = pairs {
                            done += tables.quiet_slip_pairs(p, state, max - done);
                        }
                        let single = (max - done).min(2);
                        let m = tables.quiet_slip_steps(state, single, |_, _| {});
                        done += m;
                        if m < single || done == max || pairs.is_none() {
                            if pairs.is_none() && m == single && done < max {
                                done += tables.quiet_slip_steps(state, max - done, |_, _| {});
                            }
                            break;
                        }
                    }
                    done
                }
            } else if let Some(mut w) = sink.take_window() {
                // the window's statistics by value, in registers through the loop
                let n = if regime == Regime::Stick {
                    tables.quiet_stick_steps(state, max, |z, acc| {
                        k += 1;
                        w.take(k, acc.to_f64(), (z[1] - v).to_f64())
                    })
                } else {
                    tables.quiet_slip_steps(state, max, |z, acc| {
                        k += 1;
                        w.take(k, acc.to_f64(), (z[1] - v).to_f64())
                    })
                };
                sink.put_window(w);
                n
            } else if regime == Regime::Stick {
                tables.quiet_stick_steps(state, max, |z, acc| quiet_sample(sink, &mut k, dt, z[1] - v, acc, regime, &mut failed))
            } else {
                tables.quiet_slip_steps(state, max, |z, acc| quiet_sample(sink, &mut k, dt, z[1] - v, acc, regime, &mut failed))
            };
            if let Some(e) = failed {
                return Err(e);
            }
            steps_done += n;
            if n == max {
                continue;
            }
        }
        let stepped = if full {
            stepper.step_observed(&mut obs)
        } else {
            let r = match taylor {
                Some(taylor) => {
                    let (tables, state) = stepper.parts_mut();
                    T::step_located(tables, state, taylor)
                }
                None => stepper.step(),
            };
            for tr in stepper.transitions() {
                events.transition(tr.t, tr.from == Regime::Stick, tr.to == Regime::Stick);
                obs.note(tr);
                if kinematics && tr.t >= samples_from {
                    let z = tr.state.to_array();
                    for regime in [tr.from, tr.to] {
                        sink.between(&Sample {
                            t: tr.t,
                            z: z.map(|v| v.to_f64()),
                            n: f64::NAN,
                            f_f: f64::NAN,
                            pad_acc: stepper.propagator().accelerations(regime, &z).0.to_f64(),
                            v_slide: (z[1] - v).to_f64(),
                            regime,
                        })?;
                    }
                }
            }
            r
        };
        if let Err(halt) = stepped {
            outcome = Outcome::halted(scene, halt);
            break;
        }
        steps_done += 1;
        let t = stepper.time();
        if t < samples_from {
            continue;
        }
        let st = stepper.state();
        let regime = stepper.regime();
        sink.sample(&Sample {
            t,
            z: [
                st.x.to_f64(),
                st.xdot.to_f64(),
                st.phi.to_f64(),
                st.phidot.to_f64(),
            ],
            n: if forces { stepper.normal_force().to_f64() } else { f64::NAN },
            f_f: if forces { stepper.friction_force().to_f64() } else { f64::NAN },
            pad_acc: if kinematics { stepper.propagator().accelerations(regime, &st.to_array()).0.to_f64() } else { f64::NAN },
            v_slide: if kinematics { (st.xdot - v).to_f64() } else { f64::NAN },
            regime,
        })?;
    }
    Ok(RunReport {
        precision,
        steps_planned,
        steps_done,
        window_start,
        stats: if full { obs.stats.finish() } else { events.finish(steps_done as f64 * scene.dt) },
        cycles: obs.cycles.finish(),
        outcome,
        first_slip: obs.log.first_slip,
        transitions: obs.log.transitions,
        model2: None,
        edges: None,
        drive: None,
    })
}
