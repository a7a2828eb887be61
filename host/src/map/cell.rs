//! One cell of a map: the linear stability of steady sliding, a run from perturbed steady
//! sliding and a run from the default stuck start, each classified.
//!
//! **Regimes of a run.** A run that halts is its halt: `contact_loss`, `sprag`, or
//! `method_unstable` (any other halt: divergence, a non-finite state, a storm of transitions).
//! A run that completes is judged on its statistics window (t >= stats_from):
//! - `stick_slip`: at least one stick-to-slip transition in the window;
//! - `stuck`: stick in the window and no breakaway (the pad stays stuck, or its stick-slip
//!   period exceeds the window: lengthen `--duration`);
//! - `steady_sliding`: never in stick, and the sliding velocity's peak-to-peak at most
//!   [`STEADY_PP`] times kick V (the perturbation's own peak-to-peak is 2 kick V: at most a
//!   doubling of the kick's amplitude);
//! - `sliding_oscillation`: never in stick, and the sliding velocity swings more than that
//!   (unstable sliding that never reaches stick within the run, or an undamped transient);
//! - `edge_open` (unilateral contact only, `contact = "unilateral"`): an edge of the pad was
//!   open for part or all of the window, whatever the friction did (the run's `stick_fraction` and
//!   `stick_slip_hz` still say that; `open_fraction_trail` and `open_fraction_lead` how long).
//!   `contact_loss` is then kept for runs in which both edges open (the pad leaves the band).
//!
//! Accelerations are sampled at every step end, and the extremes also take each transition
//! inside a step (both sides of it: x'' jumps there, and under Stribeck friction it peaks at a
//! re-stick, between step ends; the stepped runs of the thesis model and of model 2, not the
//! event-driven runs of unilateral contact and the pneumatic drive, which sample step ends):
//! `pad_x_pp` is the peak-to-peak of the pad's x'' (the rig's pad_x) over the window, `groan_rms` the RMS over the window of x'' through the
//! rig's groan band-pass (100 to 500 Hz, 4th-order Butterworth, [`stickslip_model::rig::bandpass`],
//! run from [`GROAN_SETTLE_S`] before the window, so that it has settled). Stick fraction and stick-slip frequency are the run's
//! exact window statistics (as `simulate` reports them).

use std::cell::RefCell;
use std::sync::Arc;

use serde::{Deserialize, Serialize};
use stickslip_model::model2::event_run::edges::{LEAD, TRAIL};
use stickslip_model::rig::bandpass::{BandPass, CascadeState, GROAN_BAND_HZ, GROAN_SECTIONS};
use stickslip_model::Scene;

use crate::error::Result;
use crate::scenes::run::{self, Detail, Outcome, Precision, RunReport, Start};
use crate::scenes::series::{QuietWindow, Sample, Sink};
use crate::scenes::sliding::{self, SlidingStability};
use crate::scenes::table_cache::PropagatorCache;
use super::ring_down::{RingDown, RING_LOOP_MAX};

/// A completed run whose window never sticks is steady sliding while its sliding velocity's
/// peak-to-peak is at most `STEADY_PP` kick V.
pub const STEADY_PP: f64 = 4.0;

/// The groan band-pass starts this long before the window [s]: its slowest poles (the analog
/// -362 +- 612i rad/s, near the 100 Hz edge) decay with a time constant of 2.8 ms, so the
/// start-up transient is down by e^-18 = 1.5e-8 when the window opens.
pub const GROAN_SETTLE_S: f64 = 0.05;

/// The steps of a cell's runs: every step of the runs (`done`), and of those the ones jumped
/// over in stick, in closed form (`jumped`, [`Sink::stick_samples`]), not stepped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Steps {
    pub done: u64,
    pub jumped: u64,
}

impl std::ops::Add for Steps {
    type Output = Steps;
    fn add(self, o: Steps) -> Steps {
        Steps { done: self.done + o.done, jumped: self.jumped + o.jumped }
    }
}

/// One mode of the linearisation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModeJson {
    /// Real part of the eigenvalue [1/s] (> 0 grows).
    pub growth_rate: Option<f64>,
    /// |imaginary part| / 2 pi [Hz].
    pub hz: Option<f64>,
}

/// The linear stability of steady sliding at the band speed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LinearCell {
    /// Every mode decays (or is neutral), and steady sliding exists.
    pub stable: bool,
    /// Largest real part of the eigenvalues [1/s].
    pub max_growth_rate: Option<f64>,
    /// Frequency of the fastest-growing mode [Hz]; null when stable (0: a real eigenvalue).
    pub unstable_hz: Option<f64>,
    /// Why steady sliding does not exist: `sprag` or `contact_loss` (null: it exists).
    pub no_steady_sliding: Option<String>,
    /// Every mode, one per complex pair, fastest growth first.
    pub modes: Vec<ModeJson>,
}

/// One run of a cell.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunCell {
    /// steady_sliding, stick_slip, sliding_oscillation, stuck, edge_open, sprag, contact_loss,
    /// method_unstable.
    pub regime: String,
    /// Time in stick / window [-] (null: no window).
    pub stick_fraction: Option<f64>,
    /// (n - 1) / (last - first stick-to-slip transition in the window) [Hz] (null: fewer than 2).
    pub stick_slip_hz: Option<f64>,
    /// Peak-to-peak of the pad's x'' over the window [m/s^2].
    pub pad_x_pp: Option<f64>,
    /// RMS of x'' through the groan band-pass over the window [m/s^2].
    pub groan_rms: Option<f64>,
    /// Peak-to-peak of the sliding velocity over the window [m/s].
    pub slide_v_pp: Option<f64>,
    /// Time of the halt [s] (null: completed).
    pub halt_s: Option<f64>,
    /// Unilateral contact only: the fraction of the window each edge was open [-].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub open_fraction_trail: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub open_fraction_lead: Option<f64>,
}

/// One cell.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CellJson {
    pub index: usize,
    /// The swept keys' values, in sweep order.
    pub params: serde_json::Map<String, serde_json::Value>,
    /// Why the cell's scene is invalid (then nothing else is computed).
    pub invalid: Option<String>,
    pub linear: Option<LinearCell>,
    pub from_sliding: Option<RunCell>,
    pub from_rest: Option<RunCell>,
}

fn fin(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}

impl LinearCell {
    pub fn of(lin: &SlidingStability) -> LinearCell {
        LinearCell {
            stable: lin.invalid.is_none() && lin.stable(),
            max_growth_rate: fin(lin.max_growth_rate()),
            unstable_hz: if lin.invalid.is_none() { lin.unstable_mode().map(|m| m.frequency_hz) } else { None },
            no_steady_sliding: lin.invalid.as_ref().map(|(k, _)| k.keyword().to_string()),
            modes: lin.modes.iter().map(|m| ModeJson { growth_rate: fin(m.growth_rate), hz: fin(m.frequency_hz) }).collect(),
        }
    }
}

/// Window statistics the run report does not keep: extremes of x'' and of the sliding
/// velocity, and the groan band's mean square.
struct CellSink {
    window_from: f64,
    /// The groan filter runs from here (its settling time before the window).
    filter_from: f64,
    /// The groan filter, the extremes, the band's sum of squares and the count (with the first
    /// steps of the filter and the window: a quiet step's sample is placed by its number).
    w: QuietWindow,
    /// The filter's free response in closed form, for stick phases ([`RingDown`]).
    ring: Option<Arc<RingDown>>,
    /// Take stick phases whole ([`Sink::takes_stick_runs`]).
    stick_runs: bool,
    /// Steps taken whole in stick ([`Sink::stick_samples`]), not stepped.
    jumped: u64,
    /// The sliding velocity's distance from zero over the whole run (every sample), kept only
    /// where asked ([`CellSink::with_margin`]).
    margin: Option<SlipMargin>,
}

/// Whether a run stayed in one slip, clear of the velocity match, at every instant: its
/// sliding velocity V_r at every sample (every step end from the first) of one sign and at
/// least `CLEAR` times what it can change within a step, estimated from the samples as the
/// largest first and second differences (max |dV_r| over a step is at most
/// max |V_r(n+1) - V_r(n)| + max |V_r''| dt^2 / 8; the second difference bounds the latter with
/// room). Such a run located no velocity match and never stuck: it read neither mu_s nor any
/// transition's rule (a Coulomb slip's forcing is mu_k N).
#[derive(Clone, Copy, Debug)]
struct SlipMargin {
    sign: f64,
    min_abs: f64,
    max_d1: f64,
    max_d2: f64,
    prev: Option<(f64, Option<f64>)>,
    broken: bool,
    n: u64,
}

impl SlipMargin {
    /// The margin the clearance must exceed, in units of the per-step change bound.
    const CLEAR: f64 = 4.0;

    fn new() -> SlipMargin {
        SlipMargin { sign: 0.0, min_abs: f64::INFINITY, max_d1: 0.0, max_d2: 0.0, prev: None, broken: false, n: 0 }
    }

    fn sample(&mut self, v: f64, stick: bool) {
        if stick || !v.is_finite() || v == 0.0 || (self.sign != 0.0 && v.signum() != self.sign) {
            self.broken = true;
            return;
        }
        self.sign = v.signum();
        self.min_abs = self.min_abs.min(v.abs());
        if let Some((p, pd)) = self.prev {
            let d = v - p;
            self.max_d1 = self.max_d1.max(d.abs());
            if let Some(pd) = pd {
                self.max_d2 = self.max_d2.max((d - pd).abs());
            }
            self.prev = Some((v, Some(d)));
        } else {
            self.prev = Some((v, None));
        }
        self.n += 1;
    }

    fn clear(&self) -> bool {
        !self.broken && self.n >= 3 && self.min_abs > Self::CLEAR * (self.max_d1 + self.max_d2)
    }
}

impl CellSink {
    /// A sink that also keeps [`SlipMargin`] over every sample of the run.
    fn with_margin(scene: &Scene) -> CellSink {
        CellSink { margin: Some(SlipMargin::new()), ..CellSink::new(scene) }
    }

    fn new(scene: &Scene) -> CellSink {
        let start = run::window_start(scene);
        let (groan, ring) = groan_filter(scene.dt);
        CellSink {
            // sample times are step ends: the window's first sample is the step ending at its start
            window_from: start - 0.5 * scene.dt,
            filter_from: start - GROAN_SETTLE_S - 0.5 * scene.dt,
            w: QuietWindow {
                groan,
                groan_state: Default::default(),
                filter_k: first_at(0, u64::MAX, scene.dt, start - GROAN_SETTLE_S - 0.5 * scene.dt),
                window_k: first_at(0, u64::MAX, scene.dt, start - 0.5 * scene.dt),
                acc: (f64::INFINITY, f64::NEG_INFINITY),
                v: (f64::INFINITY, f64::NEG_INFINITY),
                groan_sq: 0.0,
                n: 0,
            },
            ring,
            stick_runs: true,
            jumped: 0,
            margin: None,
        }
    }
}

impl CellSink {
    /// `n` samples of zero input through the groan filter, summed if `in_window`: by the filter itself when the run is shorter than the
    /// filter's decay ([`RingDown::decay_samples`]), else in closed form.
    fn zero_input(&mut self, n: u64, in_window: bool) {
        let Some(bp) = &self.w.groan else { return };
        match &self.ring {
            Some(ring) if n >= ring.decay_samples => {
                if in_window {
                    self.w.groan_sq += ring.energy(&self.w.groan_state);
                }
                self.w.groan_state = CascadeState::ZERO;
            }
            Some(ring) if n > RING_LOOP_MAX => {
                // the sum over n samples: the whole free response's less what follows them
                let s = RingDown::values(&self.w.groan_state);
                let after = ring.advance(&s, n);
                if in_window {
                    self.w.groan_sq += (ring.quad(&s) - ring.quad(&after)).max(0.0);
                }
                self.w.groan_state = RingDown::state(&after);
            }
            _ => {
                for _ in 0..n {
                    let g = bp.run(&mut self.w.groan_state, 0.0) as f64;
                    if in_window {
                        self.w.groan_sq += g * g;
                    }
                }
            }
        }
    }
}

thread_local! {
    /// The last groan filter designed on this thread, by the step's bits: a map's cells share
    /// one step, and the filter's design and its ring-down's closed form (the Gramian, the
    /// powers) are the same for all of them.
    static GROAN_FILTER: RefCell<Option<(u64, GroanFilter)>> = const { RefCell::new(None) };
}

/// The groan band-pass at the rate 1 / dt (None where it cannot be designed) and its
/// ring-down in closed form.
type GroanFilter = (Option<BandPass<GROAN_SECTIONS>>, Option<Arc<RingDown>>);

/// [`GroanFilter`] for step `dt`, designed once a thread and step.
fn groan_filter(dt: f64) -> GroanFilter {
    GROAN_FILTER.with(|slot| {
        let mut slot = slot.borrow_mut();
        if let Some((bits, f)) = slot.as_ref() {
            if *bits == dt.to_bits() {
                return f.clone();
            }
        }
        let groan = BandPass::butterworth(GROAN_BAND_HZ.0, GROAN_BAND_HZ.1, 1.0 / dt).ok();
        let f = (groan, groan.as_ref().and_then(RingDown::of).map(Arc::new));
        *slot = Some((dt.to_bits(), f.clone()));
        f
    })
}

/// The first step k in `from..to` whose time k dt is at or after `t` (`to` if none), times
/// formed as the run forms them.
fn first_at(from: u64, to: u64, dt: f64, t: f64) -> u64 {
    let mut k = ((t / dt).ceil().max(from as f64) as u64).clamp(from, to);
    while k > from && (k - 1) as f64 * dt >= t {
        k -= 1;
    }
    while k < to && (k as f64 * dt) < t {
        k += 1;
    }
    k
}

impl Sink for CellSink {
    fn wants_forces(&self) -> bool {
        false
    }

    fn takes_stick_runs(&self) -> bool {
        self.stick_runs
    }

    fn stick_samples(&mut self, first: u64, n: u64, dt: f64) -> Result<()> {
        if n == 0 {
            return Ok(());
        }
        self.jumped += n;
        if let Some(m) = &mut self.margin {
            m.broken = true;
        }
        let end = first + n;
        let f0 = first_at(first, end, dt, self.filter_from);
        let w0 = first_at(f0, end, dt, self.window_from);
        // before the window: the filter runs, nothing is summed
        self.zero_input(w0 - f0, false);
        if end > w0 {
            self.zero_input(end - w0, true);
            self.w.acc = (self.w.acc.0.min(0.0), self.w.acc.1.max(0.0));
            self.w.v = (self.w.v.0.min(0.0), self.w.v.1.max(0.0));
            self.w.n += end - w0;
        }
        Ok(())
    }

    fn wants_kinematics(&self) -> bool {
        true
    }

    fn samples_from(&self) -> f64 {
        if self.margin.is_some() {
            f64::NEG_INFINITY
        } else {
            self.filter_from
        }
    }

    /// A transition's state in the window: the extremes of x'' and of the sliding velocity
    /// take it (x'' peaks there, at a re-stick under Stribeck friction, between step ends).
    fn between(&mut self, s: &Sample) -> Result<()> {
        if s.t >= self.window_from && s.pad_acc.is_finite() && s.v_slide.is_finite() {
            self.w.acc = (self.w.acc.0.min(s.pad_acc), self.w.acc.1.max(s.pad_acc));
            self.w.v = (self.w.v.0.min(s.v_slide), self.w.v.1.max(s.v_slide));
        }
        Ok(())
    }

    #[inline]
    fn sample(&mut self, s: &Sample) -> Result<()> {
        if let Some(m) = &mut self.margin {
            m.sample(s.v_slide, s.regime == stickslip_model::Regime::Stick);
        }
        if s.t < self.filter_from {
            return Ok(());
        }
        self.w.sample(s.pad_acc, s.v_slide, s.t >= self.window_from);
        Ok(())
    }

    fn take_window(&mut self) -> Option<QuietWindow> {
        (self.margin.is_none() && self.w.groan.is_some()).then_some(self.w)
    }

    fn put_window(&mut self, w: QuietWindow) {
        self.w = w;
    }

    #[inline(always)]
    fn quiet_sample(&mut self, k: u64, _dt: f64, pad_acc: f64, v_slide: f64, regime: stickslip_model::Regime) -> Result<()> {
        if let Some(m) = &mut self.margin {
            m.sample(v_slide, regime == stickslip_model::Regime::Stick);
        }
        self.w.take(k, pad_acc, v_slide);
        Ok(())
    }
}

/// The regime of a run (see the module's documentation).
pub fn classify(report: &RunReport, slide_v_pp: f64, steady_limit: f64) -> &'static str {
    match report.outcome {
        Outcome::Budget(_) => "budget",
        // the event runner's steps out of their budget: the method, not the model
        Outcome::Stalled { .. } => "method_unstable",
        Outcome::Halted { .. } => match report.outcome.keyword() {
            "contact_loss" => "contact_loss",
            "sprag" => "sprag",
            _ => "method_unstable",
        },
        Outcome::Completed => {
            let st = &report.stats;
            if report.edges.is_some_and(|e| e.open_s.iter().any(|&s| s > 0.0)) {
                "edge_open"
            } else if st.slip_onsets > 0 {
                "stick_slip"
            } else if st.stick_fraction > 0.0 {
                "stuck"
            } else if slide_v_pp <= steady_limit {
                "steady_sliding"
            } else {
                "sliding_oscillation"
            }
        }
    }
}

/// The run's cell from its report and window sink.
fn run_cell(scene: &Scene, report: &RunReport, sink: &CellSink, kick: f64) -> RunCell {
    let window = report.has_window() && sink.w.n > 0;
    let slide_v_pp = if window { sink.w.v.1 - sink.w.v.0 } else { f64::NAN };
    let regime = classify(report, slide_v_pp, STEADY_PP * kick * scene.v);
    let w = |v: f64| if window { fin(v) } else { None };
    RunCell {
        regime: regime.to_string(),
        stick_fraction: w(report.stats.stick_fraction),
        stick_slip_hz: if report.stats.slip_onsets >= 2 { w(report.stats.stick_slip_hz) } else { None },
        pad_x_pp: w(sink.w.acc.1 - sink.w.acc.0),
        groan_rms: if sink.w.groan.is_some() && window { fin((sink.w.groan_sq / sink.w.n as f64).sqrt()) } else { None },
        slide_v_pp: w(slide_v_pp),
        halt_s: report.outcome.halt_time(),
        open_fraction_trail: report.edges.and_then(|e| w(e.open_fraction(TRAIL))),
        open_fraction_lead: report.edges.and_then(|e| w(e.open_fraction(LEAD))),
    }
}

/// Runs `scene` from each of `starts` (one stepper set-up) and classifies each run; also
/// returns the steps they took.
pub fn run_cells(scene: &Scene, o: CellOptions, starts: &[Start], cache: &PropagatorCache) -> Result<(Vec<RunCell>, Steps)> {
    let (precision, kick) = (o.precision, o.kick);
    let mut sinks: Vec<CellSink> = starts.iter().map(|_| CellSink { stick_runs: o.stick_jump, ..CellSink::new(scene) }).collect();
    let mut runs: Vec<(Start, &mut CellSink)> = starts.iter().copied().zip(sinks.iter_mut()).collect();
    let reports = run::run_starts_cached(scene, precision, Detail::Events, &mut runs, Some(cache))?;
    let steps = Steps { done: reports.iter().map(|r| r.steps_done).sum(), jumped: sinks.iter().map(|s| s.jumped).sum() };
    Ok((reports.iter().zip(&sinks).map(|(r, s)| run_cell(scene, r, s, kick)).collect(), steps))
}

/// Whether a map's runs from sliding may be shared by cells that differ only in mu_s: where
/// slip's forcing does not read mu_s (Coulomb friction: mu_k N; Stribeck's curve starts at
/// mu_s) and the runs are the stepper's (not unilateral contact's or the pneumatic drive's
/// event-driven paths). Whether a given run read mu_s is then [`sliding_run_free_of_mu_s`]'s
/// test.
pub fn mu_s_free(scene: &Scene) -> bool {
    scene.friction == stickslip_model::FrictionLaw::Coulomb && !scene.unilateral() && !scene.pneumatic()
}

/// The run from sliding of `scene` when it read no mu_s, for the cells that differ from
/// `scene` only in mu_s: `Some` when the scene is [`mu_s_free`], steady sliding exists, and the
/// run completed with no transition, its sliding velocity clear of zero throughout
/// ([`SlipMargin`]: no velocity match was located, so neither stick's limit nor the
/// velocity match's rule was read); `None` otherwise (each cell then runs its own). Returns
/// the steps run.
pub fn sliding_run_free_of_mu_s(scene: &Scene, o: CellOptions, cache: &PropagatorCache) -> Result<(Option<RunCell>, Steps)> {
    if !mu_s_free(scene) || sliding::sliding_stability(scene).invalid.is_some() {
        return Ok((None, Steps::default()));
    }
    let mut sink = CellSink { stick_runs: o.stick_jump, ..CellSink::with_margin(scene) };
    let report = {
        let mut runs = [(Start::Sliding { kick: o.kick }, &mut sink)];
        run::run_starts_cached(scene, o.precision, Detail::Events, &mut runs, Some(cache))?.remove(0)
    };
    let free = matches!(report.outcome, Outcome::Completed) && report.transitions == 0 && sink.margin.is_some_and(|m| m.clear());
    Ok((free.then(|| run_cell(scene, &report, &sink, o.kick)), Steps { done: report.steps_done, jumped: sink.jumped }))
}

/// What one cell runs.
#[derive(Clone, Copy, Debug)]
pub struct CellOptions {
    pub precision: Precision,
    /// The relative velocity kick of the start from steady sliding ([`Start::Sliding`]).
    pub kick: f64,
    /// Statistics at event speed in the thesis model's runs: the stepper jumps over stick
    /// while a closed-form bound keeps the guard ([`stickslip_model::StickJump`]) and the
    /// groan filter's zero input is summed in closed form; the common steps run in a tight
    /// loop ([`stickslip_model::ExactTables::quiet_steps`]; in slip two at a time before the
    /// samples, [`stickslip_model::exact::SlipPairs`]) and, in f64, a step's transitions are
    /// located on the exact flow's Taylor polynomial
    /// ([`stickslip_model::ExactTables::step_located`]). `false` steps and samples every step
    /// as `simulate` does (the same map to rounding except where the run is sensitive at the
    /// last digit: the tests `stick_jump` and `map_located`). Model 2's runs in f64 (Stribeck,
    /// exponent 1, one substep a step) go 4 steps at a time in slip and in stick
    /// ([`stickslip_model::model2::WideChunks`]) and locate transitions on the guard's quadratic
    /// ([`stickslip_model::model2::Model2Observer::LOCATE_BELOW_LEVEL`]): the statistics to
    /// 1e-5 of the stepped run's, the groan RMS to about 3e-4 (the test `map_wide`).
    pub stick_jump: bool,
}

/// The cell of `scene` (already built from the base scene and the cell's values): linear
/// analysis, the run from sliding (unless steady sliding does not exist: then its regime is
/// the reason, sprag or contact_loss), the run from rest. Returns the steps run.
/// `from_sliding`: the run from sliding already run for a scene that differs from this one
/// only in mu_s and read no mu_s ([`sliding_run_free_of_mu_s`]): taken as this cell's.
/// `cache`: the thesis stepper's propagators by key, shared by the map's cells.
pub fn cell(
    index: usize,
    params: &[(String, f64)],
    scene: std::result::Result<Scene, String>,
    o: CellOptions,
    from_sliding: Option<&RunCell>,
    cache: &PropagatorCache,
) -> Result<(CellJson, Steps)> {
    let params: serde_json::Map<String, serde_json::Value> =
        params.iter().map(|(k, v)| (k.clone(), serde_json::Value::from(*v))).collect();
    let scene = match scene {
        Ok(s) => s,
        Err(why) => {
            return Ok((CellJson { index, params, invalid: Some(why), linear: None, from_sliding: None, from_rest: None }, Steps::default()));
        }
    };
    let lin = sliding::sliding_stability(&scene);
    let rest = Start::Rest;
    let (from_sliding, from_rest, steps) = match &lin.invalid {
        Some((kind, _)) => {
            let none = RunCell {
                regime: kind.keyword().to_string(),
                stick_fraction: None,
                stick_slip_hz: None,
                pad_x_pp: None,
                groan_rms: None,
                slide_v_pp: None,
                halt_s: None,
                open_fraction_trail: None,
                open_fraction_lead: None,
            };
            let (mut runs, steps) = run_cells(&scene, o, &[rest], cache)?;
            (none, runs.remove(0), steps)
        }
        None => match from_sliding.filter(|_| mu_s_free(&scene)) {
            Some(shared) => {
                let (mut runs, steps) = run_cells(&scene, o, &[rest], cache)?;
                (shared.clone(), runs.remove(0), steps)
            }
            None => {
                let (mut runs, steps) = run_cells(&scene, o, &[Start::Sliding { kick: o.kick }, rest], cache)?;
                let from_rest = runs.remove(1);
                (runs.remove(0), from_rest, steps)
            }
        },
    };
    Ok((
        CellJson { index, params, invalid: None, linear: Some(LinearCell::of(&lin)), from_sliding: Some(from_sliding), from_rest: Some(from_rest) },
        steps,
    ))
}
