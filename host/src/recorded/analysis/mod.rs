//! The streaming analysis of a four-channel record: running statistics, the rig's estimator
//! sample by sample, Welch spectra and a bounded envelope for the figures. Fed one sample at
//! a time, by the CSV reader (`analyze`, `compare`) or by the virtual rig (`sil`); memory
//! does not grow with the record.
//!
//! **Time column.** Strictly increasing, and uniform at full precision: every interval must
//! lie within [`RATE_TOLERANCE`] (1 %) of the mean interval of the rows before it, plus half
//! the printed resolution of each of its two rows (a time printed to 1 us is off by up to
//! 0.5 us; each row's own resolution counts, so one `0.0` or `0.25` in the column loosens the
//! check of its own two intervals only) and a few ulps. A time that repeats, goes back, or
//! jumps (rows missing, a gap) is an error naming its line and what it is (a drop of k rows
//! where the interval is k + 1 mean intervals); with [`Analyzer::split_gaps`] a jump forward
//! instead ends a contiguous block and starts the next (see [`Gap`]). The sample rate reported
//! is (rows - 1) / (t_last - t_first) over the whole column (with gaps: the intervals within
//! the blocks over their span). The estimator and the groan band-pass are set up after the
//! first [`PREVIEW_ROWS`] rows (held in a fixed buffer), at the rate those rows give.
//!
//! **Channels.** pad_x is needed; disc_x, pad_trail and pad_lead may be absent
//! ([`Analyzer::set_present`]): an absent channel runs through the estimator as 0 (without
//! disc_x, a_rel = pad_x: the band taken at constant speed; without either edge sensor the
//! face term is left out) and its statistics are absent, not zero.
//!
//! **Statistics** over the samples at t >= `from_s` (to a quarter of a sample interval):
//! - peak-to-peak = max - min, RMS about zero (the IEPE accelerometers are AC-coupled; the rig's
//!   window statistics use the same definition) and the mean, in f64 of the values as read;
//! - groan-band RMS: RMS of the rig's groan band-pass (4th-order Butterworth, 100 to 500 Hz,
//!   bilinear transform, f32: `shared::rig::bandpass`, the estimator's own coefficients) run
//!   on each channel minus its first sample: the filter starts as if the record had held its
//!   first value forever, so a constant signal gives 0 (from rest, the step onto the
//!   record's first value would ring through the band: 0.021 m/s^2 of RMS on a constant
//!   1 m/s^2 over a second). The rig's own windows keep the rig's filter, from rest;
//! - spectral peak: the largest bin above 0 Hz of the Welch PSD (see [`super::spectrum`]),
//!   good to one bin (the resolution is reported);
//! - stick fraction and stick-slip frequency from the rig's estimator, run by the rig itself
//!   (`shared::rig::pipeline::Rig`, the type the firmware runs, made for a recording by
//!   `Rig::for_recording`: the record is the rig's record 1, and every row goes through
//!   `Rig::play`, the firmware's per-sample chain after its calibration), fed every row as
//!   calibrated accelerations (f32) from the first row on: stick fraction = samples estimated
//!   in stick / samples; frequency = (n - 1) /
//!   (time of the last onset - time of the first) over the n stick-to-slip onsets it decided,
//!   none with fewer than two (with gaps: the intervals between onsets within a block over
//!   their time). Its contact thresholds come from a breakaway jump J [m/s^2]
//!   (onset J/2, stick J/4: `ContactThresholds::from_breakaway_jump`), or from a noise floor
//!   (the quiet rows found anywhere in the record, [`super::quiet`]; the first quiet stretch
//!   before a signal, as the rig's sequencer measures its clamped phase; or `--quiet`), which
//!   the rig holds as it holds its clamp's;
//! - the estimator's own window statistics (with `AnalysisConfig::windows`): every window the
//!   estimator closes, from the first row on, as the firmware's `window` records report them
//!   (`shared::rig::window`: pp, RMS, groan RMS per channel in f32, stick fraction, stick-slip
//!   frequency and onsets within the window), with the time column's value at its last sample;
//! - the first slip onset: the time column's value at the estimator's first stick-to-slip
//!   onset over the whole record, before `from_s` too. With the record's time zero at the
//!   band's start (as the virtual rig writes it), it is the first breakaway's time, which
//!   depends on the friction level itself (mu_s N / k V for a pad held by a spring k) where
//!   the accelerations do not (`stickslip fit`).

use stickslip_model::rig::bandpass::{CascadeState, GROAN_BAND_HZ, GROAN_SECTIONS};
use stickslip_model::rig::calibration::{Calibrated, Saturation};
use stickslip_model::rig::contact::{ContactEventKind, ContactThresholds};
use stickslip_model::rig::estimator::EstimatorConfig;
use stickslip_model::rig::health::{ChannelHealth, HealthReport};
use stickslip_model::rig::noise_floor::{NoiseFloor, A_REL, MIN_FLOOR_SAMPLES};
use stickslip_model::rig::pipeline::{Rig, RigConfig};
use stickslip_model::rig::window::WindowReport;
use stickslip_model::rig::{DISC_X, PAD_X};
use stickslip_model::stats::{Extremes, OnsetRate};
use stickslip_model::Regime;

use super::envelope::{Bucket, Envelope};
use super::spectrum::{default_segment, Spectrum, Welch, CH};

mod finish;
pub mod intervals;
mod running;
mod set_up;
mod time_column;
use intervals::{IntervalStats, OnsetIntervals};
use running::*;

/// Quiet rows in a row that start the rig's estimator ([`Running::process`]): 0.6 ms at
/// 25.6 kHz; a slip's a_rel crosses the stick level in about one sample.
pub const START_RUN: usize = 16;

/// Rows read before the sample rate is fixed for the estimator.
pub const PREVIEW_ROWS: usize = 4096;
/// With the floor found automatically, the rows held back until a quiet stretch before a signal
/// shows (10.2 s at 25.6 kHz, about 10 MB): a recording without one is analysed with the
/// fixed thresholds of the breakaway jump.
pub const MAX_AUTO_PREVIEW_ROWS: usize = 1 << 18;
/// [`find_quiet`]: a block is loud with a variance above this times the quietest block's.
pub const QUIET_LOUD_FACTOR: f64 = 16.0;
/// Allowed deviation of one interval from the mean interval [-].
pub const RATE_TOLERANCE: f64 = 0.01;
/// The accelerometers' measuring range [m/s^2] (Type 4508: 700): samples at or beyond it are
/// counted.
pub const SENSOR_RANGE_M_S2: f64 = stickslip_model::rig::ACCEL_RANGE_M_S2;

/// What to compute.
#[derive(Clone, Debug)]
pub struct AnalysisConfig {
    /// Statistics start [s] (samples before it only run through the estimator and filters).
    pub from_s: f64,
    /// Welch segment length [samples]; default [`default_segment`] of the rate.
    pub segment: Option<usize>,
    /// Breakaway jump J for the estimator's thresholds [m/s^2]: the thresholds with
    /// `floor` off, else only the starting value the floor replaces.
    pub breakaway_jump_m_s2: f64,
    /// Where the contact thresholds come from.
    pub floor: FloorSource,
    /// The estimator's face term (`EstimatorConfig::face_coefficient`, 0 without the face).
    pub face_coefficient: f32,
    /// Band speed for the estimator's configuration [m/s] (its lockstep model, which this
    /// analysis does not start).
    pub band_speed_m_s: f64,
    /// Keep the envelope and spectra for figures.
    pub figures: bool,
    /// Compute the Welch spectra (the spectral peaks); off, `Analysis::spectrum` is `None`
    /// and no sample goes through an FFT (a fit that does not weigh the peaks).
    pub spectra: bool,
    /// Keep the estimator's window statistics ([`Analysis::windows`]: one entry per
    /// `stickslip_model::rig::WINDOW_S` of record, in whole samples at the record's rate).
    pub windows: bool,
}

/// One window the estimator closed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EstimatorWindow {
    /// The time column's value at the window's last sample [s].
    pub t_end_s: f64,
    /// The estimator's report (`first_sample` counts rows from the first row, from 0).
    pub report: WindowReport,
}

/// Where the contact thresholds come from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FloorSource {
    /// From `breakaway_jump_m_s2` (onset J/2, stick J/4), fixed.
    Jump,
    /// From the quiet rows found anywhere ([`super::quiet::QuietSearch`]) in the first
    /// [`MAX_AUTO_PREVIEW_ROWS`] rows, held back (standard input); a file is searched whole
    /// in a first pass instead, and comes as [`FloorSource::Found`].
    Auto,
    /// From the noise floor of the record's first quiet stretch before a signal, as the rig
    /// measures its clamped phase (see [`find_quiet`]; the virtual rig, `sil`).
    Lead,
    /// From the noise floor of the rows with FROM <= t <= TO [s].
    Range(f64, f64),
    /// A floor found before the analysis (a first pass over the file).
    Found(FloorOutcome),
}

/// A jump forward in the time column that `--gaps split` analysed around.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gap {
    /// The row after the gap (its line, or sample).
    pub line: u64,
    /// The last time before it and the first after it [s].
    pub t_before: f64,
    pub t_after: f64,
    /// The interval in mean intervals of the rows before it.
    pub intervals: f64,
}

/// Rows per block of the quiet-stretch search.
pub const QUIET_BLOCK: usize = 32;
/// The most rows `FloorSource::Range` buffers before the estimator starts.
pub const MAX_QUIET_ROWS: usize = 1 << 22;

/// The noise floor the thresholds were designed from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloorOutcome {
    /// The stretch [s] (first and last row's time) and how it was chosen.
    pub t_from: f64,
    pub t_to: f64,
    pub auto: bool,
    pub report: stickslip_model::rig::noise_floor::FloorReport,
    /// The quantum used: the larger smallest nonzero step of pad_x and disc_x in the
    /// buffered rows [m/s^2] (0 for a continuous record).
    pub quantum_m_s2: f64,
    /// Found anywhere: the quiet blocks of a_rel it was taken from (0: one stretch).
    pub quiet_blocks: u64,
    /// Found anywhere: the runs of one value on every channel at the record's start and end
    /// [s] (first and last row's time), left out of the floor as a logger's fill
    /// ([`super::quiet`]).
    pub fill_lead: Option<(f64, f64)>,
    pub fill_trail: Option<(f64, f64)>,
    /// Runs of one value on every channel between (a logger holding its last value through a
    /// dropout): how many, their rows in whole blocks, the first one's span [s]. Left out of
    /// the floor, not of the statistics (a note says so).
    pub fill_inside: Option<(u64, u64, (f64, f64))>,
}

/// Statistics of one channel [m/s^2, Hz].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ChannelStats {
    pub pp: f64,
    pub rms: f64,
    pub mean: f64,
    pub min: f64,
    pub max: f64,
    /// Frequency of the largest Welch bin above 0 Hz; `None` without a spectrum.
    pub peak_hz: Option<f64>,
    pub groan_rms: f64,
    /// The smallest nonzero change between consecutive analysed samples [m/s^2]: the
    /// recording's amplitude resolution (one ADC count of a quantised record) or finer; 0
    /// where the channel never changes.
    pub step: f64,
}

/// The result of an analysis.
#[derive(Clone, Debug)]
pub struct Analysis {
    pub channels: [ChannelStats; CH],
    pub stick_fraction: f64,
    /// `None` with fewer than two onsets.
    pub stick_slip_hz: Option<f64>,
    pub slip_onsets: u64,
    /// Time of the estimator's first stick-to-slip onset in the whole record, before
    /// `from_s` too [s]; `None` without one.
    pub first_onset_s: Option<f64>,
    /// From the whole time column [Hz].
    pub sample_rate_hz: f64,
    /// The rate the estimator and band-pass were set up with (first rows) [Hz].
    pub setup_rate_hz: f64,
    /// Rows read.
    pub rows: u64,
    /// Samples in the statistics.
    pub samples: u64,
    /// Time of the first and last analysed sample [s].
    pub t_first: f64,
    pub t_last: f64,
    pub from_s: f64,
    /// Coarsest printed resolution of the time column [s] (0 for generated samples).
    pub time_resolution_s: f64,
    /// Analysed samples with a channel at or beyond the sensor range.
    pub samples_at_range: u64,
    pub thresholds: ContactThresholds,
    pub breakaway_jump_m_s2: f64,
    /// The noise floor the thresholds came from (`None`: from the breakaway jump).
    pub floor: Option<FloorOutcome>,
    /// Analysed samples at or beyond the sensor range, per channel.
    pub at_range: [u64; CH],
    /// Analysed samples at the format's full scale (an integer WAV's extreme codes), per
    /// channel: from [`super::wav::FULL_SCALE_MIN_SAMPLES`] on, the channel is saturated.
    pub at_full_scale: [u64; CH],
    /// The format's full scale in words, where it has one.
    pub full_scale: Option<String>,
    /// Why the estimator cannot decide stick from slip on this record (its stick fraction
    /// and frequency are then not reported), or `None`.
    pub undecided: Option<String>,
    /// The intervals between slip onsets (within blocks): their spread, and how many are far
    /// from their median ([`intervals`]).
    pub onset_intervals: IntervalStats,
    /// No stick-slip seen: no slip onset, or onsets that are noise crossing the onset level, or
    /// a pad that moves below it with no onset (the reasons `blips`, `never started`, `moves
    /// below`, `below the guess` of [`finish`]). Not where the estimate is not told for other
    /// reasons (slips too slow for the estimator, an offset, split slips).
    pub no_stick_slip_seen: bool,
    /// Per channel, what is wrong with it, or empty: "flat" (no sample changed: dead, or a
    /// signal below one count), "saturated" (samples at the range), "noisier than the signal"
    /// (RMS under twice the floor's sigma).
    pub health: [Vec<&'static str>; CH],
    pub spectrum: Option<Spectrum>,
    /// Empty unless figures were asked for.
    pub envelope: Vec<Bucket>,
    /// The estimator's windows, in order; empty unless `AnalysisConfig::windows`.
    pub windows: Vec<EstimatorWindow>,
    /// disc_x, pad_x, pad_trail, pad_lead: which the record has (an absent channel's
    /// statistics are not reported).
    pub present: [bool; CH],
    /// The jumps in the time column analysed around (`--gaps split`).
    pub gaps: Vec<Gap>,
    /// Why the thresholds did not come from a floor (no quiet rows found), if so.
    pub floor_note: Option<String>,
    /// What was assumed (absent channels, units), one sentence each.
    pub notes: Vec<String>,
    /// The recording's format ("CSV", "UFF dataset 58", "WAV"; "" for the virtual rig's).
    pub format: &'static str,
}

impl Analysis {
    /// Duration the analysed samples cover, samples / sample rate [s].
    pub fn duration_s(&self) -> f64 {
        self.samples as f64 / self.sample_rate_hz
    }
}

/// The first quiet stretch of a_rel (row range `i0..i1`), or `None`: blocks of
/// [`QUIET_BLOCK`] rows, each with its variance about its own mean; a block is quiet when its
/// variance is at most 4 times the smallest (its RMS at most twice), or 0 where the smallest is
/// 0 (a record whose quiet rows do not change by a count); the stretch is the first run of
/// consecutive quiet blocks at least [`MIN_FLOOR_SAMPLES`] rows long. In stick a_rel is 0 up to
/// noise like in the clamped phase: a stick longer than the run qualifies too. `None` as well
/// when no block is loud, with a variance above [`QUIET_LOUD_FACTOR`] times the smallest (its
/// RMS above 4 times): a stretch is quiet only against a signal (a recording of steady
/// sines, or one that is still quiet at the end of the rows given, has none).
pub fn find_quiet(a_rel: &[f32]) -> Option<(usize, usize)> {
    let var: Vec<f64> = a_rel
        .chunks_exact(QUIET_BLOCK)
        .map(|b| {
            let m = b.iter().map(|&v| v as f64).sum::<f64>() / b.len() as f64;
            b.iter().map(|&v| (v as f64 - m).powi(2)).sum::<f64>() / b.len() as f64
        })
        .collect();
    let vmin = var.iter().copied().fold(f64::INFINITY, f64::min);
    let vmax = var.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !vmin.is_finite() || !(vmax > QUIET_LOUD_FACTOR * vmin) {
        return None;
    }
    let need = (MIN_FLOOR_SAMPLES as usize).div_ceil(QUIET_BLOCK);
    let mut run = 0;
    for (k, &v) in var.iter().enumerate() {
        if v <= 4.0 * vmin {
            run += 1;
        } else {
            if run >= need {
                return Some(((k - run) * QUIET_BLOCK, k * QUIET_BLOCK));
            }
            run = 0;
        }
    }
    (run >= need).then(|| ((var.len() - run) * QUIET_BLOCK, var.len() * QUIET_BLOCK))
}

/// The streaming analysis (see the module documentation).
pub struct Analyzer {
    cfg: AnalysisConfig,
    rows: u64,
    t0: f64,
    t_prev: f64,
    line_first: u64,
    line_prev: u64,
    res_max: f64,
    /// The previous row's printed time resolution [s].
    res_prev: f64,
    phase: Phase,
    present: [bool; CH],
    split_gaps: bool,
    gaps: Vec<Gap>,
    /// The current block's first time, and the intervals and span of the blocks before it.
    block_t0: f64,
    block_rows: u64,
    done_intervals: u64,
    done_span: f64,
    /// The next row starts a block (`--gaps split`).
    gap_pending: bool,
    floor_note: Option<String>,
    notes: Vec<String>,
    /// Samples at the format's full scale per channel (t >= from_s), and the full scale in words.
    at_full_scale: [u64; CH],
    full_scale: Option<String>,
}

impl Analyzer {
    pub fn new(cfg: AnalysisConfig) -> Self {
        Analyzer {
            cfg,
            rows: 0,
            t0: 0.0,
            t_prev: 0.0,
            line_first: 0,
            line_prev: 0,
            res_max: 0.0,
            res_prev: 0.0,
            phase: Phase::Preview(Vec::with_capacity(PREVIEW_ROWS)),
            present: [true; CH],
            split_gaps: false,
            gaps: Vec::new(),
            block_t0: 0.0,
            block_rows: 0,
            done_intervals: 0,
            done_span: 0.0,
            gap_pending: false,
            floor_note: None,
            notes: Vec::new(),
            at_full_scale: [0; CH],
            full_scale: None,
        }
    }

    /// Which channels the record has (default all four). Without pad_trail or pad_lead the
    /// estimator's face term is left out; the notes say what was assumed.
    pub fn set_present(&mut self, present: [bool; CH]) {
        self.present = present;
        if !present[DISC_X] {
            self.notes.push("no disc_x: a_rel = pad_x alone (the band taken at constant speed)".into());
        }
        if !(present[2] && present[3]) && self.cfg.face_coefficient != 0.0 {
            self.cfg.face_coefficient = 0.0;
            self.notes.push("no pad_trail or pad_lead: the estimator's face term is left out".into());
        }
    }

    /// `--gaps split`: a jump forward in the time column ends a block instead of being an error.
    pub fn split_gaps(&mut self, on: bool) {
        self.split_gaps = on;
    }

    /// Why the floor is not used (the search found none), for the report.
    pub fn note_floor(&mut self, why: String) {
        self.floor_note = Some(why);
    }

    /// A sentence for the report's notes.
    pub fn note(&mut self, n: String) {
        self.notes.push(n);
    }

    /// The record's format has a full scale (`what`, in words: an integer WAV's extreme codes).
    pub fn set_full_scale(&mut self, what: String) {
        self.full_scale = Some(what);
    }

    /// The row just pushed (at time `t`) has samples at the format's full scale (bit c:
    /// channel c): counted where the statistics are (t >= `from_s`, to a quarter of an
    /// interval). From [`super::wav::FULL_SCALE_MIN_SAMPLES`] of them the channel is saturated,
    /// as at the sensors' range.
    pub fn at_full_scale(&mut self, t: f64, bits: u8) {
        let quarter = if self.rows >= 2 { 0.25 * self.mean_interval() } else { 0.0 };
        if !(t >= self.cfg.from_s - quarter) {
            return;
        }
        for c in 0..CH {
            if bits & (1 << c) != 0 {
                self.at_full_scale[c] += 1;
            }
        }
    }

    /// Rows taken so far.
    pub fn rows(&self) -> u64 {
        self.rows
    }
}
