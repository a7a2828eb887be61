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
//!   open for part of the window, whatever the friction did (the run's `stick_fraction` and
//!   `stick_slip_hz` still say that; `open_fraction_trail` and `open_fraction_lead` how long).
//!   `contact_loss` is then kept for runs in which both edges open (the pad leaves the band).
//!
//! Accelerations are sampled at every step end: `pad_x_pp` is the peak-to-peak of the pad's
//! x'' (the rig's pad_x) over the window, `groan_rms` the RMS over the window of x'' through the
//! rig's groan band-pass (100 to 500 Hz, 4th-order Butterworth, [`stickslip_model::rig::bandpass`],
//! run from [`GROAN_SETTLE_S`] before the window, so that it has settled). Stick fraction and stick-slip frequency are the run's
//! exact window statistics (as `simulate` reports them).

use serde::{Deserialize, Serialize};
use stickslip_model::model2::event_run::edges::{LEAD, TRAIL};
use stickslip_model::rig::bandpass::{BandPass, CascadeState, GROAN_BAND_HZ, GROAN_SECTIONS};
use stickslip_model::Scene;

use crate::error::Result;
use crate::scenes::run::{self, Detail, Outcome, Precision, RunReport, Start};
use crate::scenes::series::{Sample, Sink};
use crate::scenes::sliding::{self, SlidingStability};

/// A completed run whose window never sticks is steady sliding while its sliding velocity's
/// peak-to-peak is at most `STEADY_PP` kick V.
pub const STEADY_PP: f64 = 4.0;

/// The groan band-pass starts this long before the window [s]: its slowest poles (the analog
/// -362 +- 612i rad/s, near the 100 Hz edge) decay with a time constant of 2.8 ms, so the
/// start-up transient is down by e^-18 = 1.5e-8 when the window opens.
pub const GROAN_SETTLE_S: f64 = 0.05;

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
    groan: Option<BandPass<GROAN_SECTIONS>>,
    groan_state: CascadeState<GROAN_SECTIONS>,
    acc: (f64, f64),
    v: (f64, f64),
    groan_sq: f64,
    n: u64,
}

impl CellSink {
    fn new(scene: &Scene) -> CellSink {
        let start = run::window_start(scene);
        CellSink {
            // sample times are step ends: the window's first sample is the step ending at its start
            window_from: start - 0.5 * scene.dt,
            filter_from: start - GROAN_SETTLE_S - 0.5 * scene.dt,
            groan: BandPass::butterworth(GROAN_BAND_HZ.0, GROAN_BAND_HZ.1, 1.0 / scene.dt).ok(),
            groan_state: Default::default(),
            acc: (f64::INFINITY, f64::NEG_INFINITY),
            v: (f64::INFINITY, f64::NEG_INFINITY),
            groan_sq: 0.0,
            n: 0,
        }
    }
}

impl Sink for CellSink {
    fn wants_forces(&self) -> bool {
        false
    }

    fn wants_kinematics(&self) -> bool {
        true
    }

    fn samples_from(&self) -> f64 {
        self.filter_from
    }

    #[inline]
    fn sample(&mut self, s: &Sample) -> Result<()> {
        if s.t < self.filter_from {
            return Ok(());
        }
        let g = match &self.groan {
            Some(bp) => bp.run(&mut self.groan_state, s.pad_acc as f32) as f64,
            None => 0.0,
        };
        if s.t >= self.window_from && s.pad_acc.is_finite() && s.v_slide.is_finite() {
            self.acc = (self.acc.0.min(s.pad_acc), self.acc.1.max(s.pad_acc));
            self.v = (self.v.0.min(s.v_slide), self.v.1.max(s.v_slide));
            self.groan_sq += g * g;
            self.n += 1;
        }
        Ok(())
    }
}

/// The regime of a run (see the module's documentation).
pub fn classify(report: &RunReport, slide_v_pp: f64, steady_limit: f64) -> &'static str {
    match report.outcome {
        Outcome::Budget(_) => "budget",
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
    let window = report.has_window() && sink.n > 0;
    let slide_v_pp = if window { sink.v.1 - sink.v.0 } else { f64::NAN };
    let regime = classify(report, slide_v_pp, STEADY_PP * kick * scene.v);
    let w = |v: f64| if window { fin(v) } else { None };
    RunCell {
        regime: regime.to_string(),
        stick_fraction: w(report.stats.stick_fraction),
        stick_slip_hz: if report.stats.slip_onsets >= 2 { w(report.stats.stick_slip_hz) } else { None },
        pad_x_pp: w(sink.acc.1 - sink.acc.0),
        groan_rms: if sink.groan.is_some() && window { fin((sink.groan_sq / sink.n as f64).sqrt()) } else { None },
        slide_v_pp: w(slide_v_pp),
        halt_s: report.outcome.halt_time(),
        open_fraction_trail: report.edges.and_then(|e| w(e.open_fraction(TRAIL))),
        open_fraction_lead: report.edges.and_then(|e| w(e.open_fraction(LEAD))),
    }
}

/// Runs `scene` from each of `starts` (one stepper set-up) and classifies each run; also
/// returns the steps they took.
pub fn run_cells(scene: &Scene, precision: Precision, starts: &[Start], kick: f64) -> Result<(Vec<RunCell>, u64)> {
    let mut sinks: Vec<CellSink> = starts.iter().map(|_| CellSink::new(scene)).collect();
    let mut runs: Vec<(Start, &mut CellSink)> = starts.iter().copied().zip(sinks.iter_mut()).collect();
    let reports = run::run_starts(scene, precision, Detail::Events, &mut runs)?;
    let steps = reports.iter().map(|r| r.steps_done).sum();
    Ok((reports.iter().zip(&sinks).map(|(r, s)| run_cell(scene, r, s, kick)).collect(), steps))
}

/// What one cell runs.
#[derive(Clone, Copy, Debug)]
pub struct CellOptions {
    pub precision: Precision,
    /// The relative velocity kick of the start from steady sliding ([`Start::Sliding`]).
    pub kick: f64,
}

/// The cell of `scene` (already built from the base scene and the cell's values): linear
/// analysis, the run from sliding (unless steady sliding does not exist: then its regime is
/// the reason, sprag or contact_loss), the run from rest. Returns the steps run.
pub fn cell(index: usize, params: &[(String, f64)], scene: std::result::Result<Scene, String>, o: CellOptions) -> Result<(CellJson, u64)> {
    let params: serde_json::Map<String, serde_json::Value> =
        params.iter().map(|(k, v)| (k.clone(), serde_json::Value::from(*v))).collect();
    let scene = match scene {
        Ok(s) => s,
        Err(why) => {
            return Ok((CellJson { index, params, invalid: Some(why), linear: None, from_sliding: None, from_rest: None }, 0));
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
            let (mut runs, steps) = run_cells(&scene, o.precision, &[rest], o.kick)?;
            (none, runs.remove(0), steps)
        }
        None => {
            let (mut runs, steps) = run_cells(&scene, o.precision, &[Start::Sliding { kick: o.kick }, rest], o.kick)?;
            let from_rest = runs.remove(1);
            (runs.remove(0), from_rest, steps)
        }
    };
    Ok((
        CellJson { index, params, invalid: None, linear: Some(LinearCell::of(&lin)), from_sliding: Some(from_sliding), from_rest: Some(from_rest) },
        steps,
    ))
}
