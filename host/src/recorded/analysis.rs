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
    /// Why the estimator cannot decide stick from slip on this record (its stick fraction
    /// and frequency are then not reported), or `None`.
    pub undecided: Option<String>,
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

#[derive(Clone, Copy)]
struct Pending {
    t: f64,
    a: [f64; CH],
    /// The first row after a gap (`--gaps split`).
    gap_before: bool,
}

struct Running {
    fs: f64,
    from_eff: f64,
    /// The rig, playing the record back (`Rig::for_recording`): its estimator and windows.
    rig: Box<Rig>,
    welch: Option<Welch>,
    envelope: Option<Envelope>,
    n: u64,
    t_first: f64,
    t_last: f64,
    extremes: Extremes<f64, CH>,
    sum: [f64; CH],
    sq: [f64; CH],
    groan_sq: [f64; CH],
    prev: [f64; CH],
    step: [f64; CH],
    stick: u64,
    onsets: OnsetRate,
    first_onset: Option<f64>,
    at_range: u64,
    at_range_ch: [u64; CH],
    floor: Option<FloorOutcome>,
    /// `Some` when the windows are kept.
    windows: Option<Vec<EstimatorWindow>>,
    /// The statistics' groan band-pass (the estimator's coefficients) on each channel minus
    /// its first sample, and that first sample.
    groan: stickslip_model::rig::bandpass::BandPass<GROAN_SECTIONS>,
    groan_state: [CascadeState<GROAN_SECTIONS>; CH],
    groan_origin: Option<[f64; CH]>,
    /// To restart the rig after a gap: its configuration and floor design.
    rig_cfg: RigConfig,
    design: Option<(stickslip_model::rig::noise_floor::FloorReport, ContactThresholds)>,
    /// Onsets of the blocks before the current one: (n - 1) summed, and their spans [s].
    onset_intervals: u64,
    onset_span: f64,
    last_onset: f64,
    /// The rig's estimator has started (see [`Running::process`]); the rows held meanwhile;
    /// the stick level [m/s^2] and a_rel's bias that start it; the face term.
    started: bool,
    held: Vec<(f64, [f64; CH])>,
    start_level: f32,
    start_bias: f32,
    face: f32,
}

impl Running {
    /// After a gap: the rig starts again from rest with the same thresholds (its filters and
    /// contact state do not reach across the gap), the onsets of the block before are kept
    /// apart, and the spectrum's partial segment is dropped.
    fn restart(&mut self) {
        if let Some((n, first, last)) = self.onsets.first().map(|f| (self.onsets.count(), f, self.onsets_last())) {
            if n >= 2 && last > first {
                self.onset_intervals += u64::from(n - 1);
                self.onset_span += last - first;
            }
        }
        self.onsets = OnsetRate::new();
        self.flush_held();
        self.started = false;
        if let Ok(rig) = Rig::for_recording(&self.rig_cfg, self.design) {
            self.rig = Box::new(rig);
        }
        if let Some(w) = &mut self.welch {
            w.restart();
        }
    }

    fn onsets_last(&self) -> f64 {
        self.last_onset
    }

    /// The stick-slip frequency over the blocks (one block: the onsets' rate as before).
    fn hz(&self) -> Option<f64> {
        let (mut n, mut span) = (self.onset_intervals, self.onset_span);
        if let Some(first) = self.onsets.first() {
            if self.onsets.count() >= 2 && self.last_onset > first {
                if n == 0 {
                    return self.onsets.hz();
                }
                n += u64::from(self.onsets.count() - 1);
                span += self.last_onset - first;
            }
        }
        (n > 0 && span > 0.0).then(|| n as f64 / span)
    }

    /// One row. The rig's estimator starts in stick (the rig clamps the pad before the band
    /// moves): it is started at the first [`START_RUN`] rows in a row whose a_rel is within its
    /// stick level of the floor's mean, so a record that starts inside a slip does not start
    /// it in stick with a wrong relative velocity. Rows before that (the record's first,
    /// partial slip) go into the statistics and count as slip, not through the rig. A record
    /// that starts in stick (a clamped lead-in) starts it at its first row, as the rig does.
    #[inline]
    fn process(&mut self, t: f64, a: &[f64; CH]) {
        if self.started {
            return self.process_row(t, a, true);
        }
        let rel = (a[1] - a[0]) as f32 + self.face * (a[3] - a[2]) as f32 - self.start_bias;
        self.held.push((t, *a));
        if rel.abs() <= self.start_level {
            if self.held.len() >= START_RUN {
                self.started = true;
                for (t, a) in std::mem::take(&mut self.held) {
                    self.process_row(t, &a, true);
                }
            }
        } else {
            self.flush_held();
        }
    }

    /// The held rows, not played (the record ended, or the run of quiet rows broke).
    fn flush_held(&mut self) {
        for (t, a) in std::mem::take(&mut self.held) {
            self.process_row(t, &a, false);
        }
    }

    #[inline]
    fn process_row(&mut self, t: f64, a: &[f64; CH], played: bool) {
        let mut bits = 0u16;
        for (i, v) in a.iter().enumerate() {
            if v.abs() >= SENSOR_RANGE_M_S2 {
                bits |= 1 << i;
            }
        }
        let mut stick = false;
        let mut onset_lead = None;
        if played {
            let cal = Calibrated {
                accel_m_s2: a.map(|v| v as f32),
                pressure_bar: [0.0; 2],
                saturation: Saturation { bits },
            };
            let s = self.rig.play(&cal);
            if s.window_ready {
                let closed = self.rig.take_window();
                if let (Some(w), Some(closed)) = (&mut self.windows, closed) {
                    w.push(EstimatorWindow { t_end_s: t, report: closed.report });
                }
            }
            let onset = matches!(s.contact.event, Some(e) if e.kind == ContactEventKind::StickToSlip);
            if onset && self.first_onset.is_none() {
                self.first_onset = Some(t - s.contact.lead_samples as f64 / self.fs);
            }
            stick = s.contact.regime == Regime::Stick;
            onset_lead = onset.then_some(s.contact.lead_samples);
        }
        if t < self.from_eff {
            return;
        }
        if self.n == 0 {
            self.t_first = t;
        }
        self.t_last = t;
        self.n += 1;
        let o = *self.groan_origin.get_or_insert(*a);
        let g: [f32; CH] = std::array::from_fn(|c| self.groan.run(&mut self.groan_state[c], (a[c] - o[c]) as f32));
        for c in 0..CH {
            let v = a[c];
            self.extremes.take(c, v);
            self.sum[c] += v;
            self.sq[c] += v * v;
            let d = (v - self.prev[c]).abs();
            if d > 0.0 && d < self.step[c] && self.n > 1 {
                self.step[c] = d;
            }
            self.prev[c] = v;
            let gv = g[c] as f64;
            self.groan_sq[c] += gv * gv;
        }
        if bits != 0 {
            self.at_range += 1;
            for c in 0..CH {
                if bits & (1 << c) != 0 {
                    self.at_range_ch[c] += 1;
                }
            }
        }
        if stick {
            self.stick += 1;
        }
        if let Some(lead_samples) = onset_lead {
            // the estimator dates the slip back by its lead: those samples were counted stick
            let lead = (lead_samples as u64).min(self.stick);
            self.stick -= lead;
            let t = t - lead as f64 / self.fs;
            self.onsets.add(t);
            self.last_onset = t;
        }
        if let Some(w) = &mut self.welch {
            w.push(a);
        }
        if let Some(e) = &mut self.envelope {
            e.push(t, a);
        }
    }
}

/// a_rel of a buffered row: pad_x - disc_x + the face term.
fn a_rel_of(p: &Pending, face_coefficient: f32) -> f32 {
    (p.a[1] - p.a[0]) as f32 + face_coefficient * (p.a[3] - p.a[2]) as f32
}

enum Phase {
    Preview(Vec<Pending>),
    Running(Box<Running>),
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

    /// Rows taken so far.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Takes one sample: time [s], its printed resolution [s] (0 if exact), the four
    /// accelerations [m/s^2]; `line` is named in errors. The error is one line starting with
    /// "line N" (the caller adds the file).
    pub fn push(&mut self, line: u64, t: f64, t_resolution: f64, a: &[f64; CH]) -> Result<(), String> {
        self.check_time(line, t, t_resolution)?;
        if self.rows == 0 {
            self.t0 = t;
            self.line_first = line;
            self.block_t0 = t;
        }
        let gap = std::mem::take(&mut self.gap_pending);
        if gap {
            self.block_t0 = t;
            self.block_rows = 0;
        }
        self.t_prev = t;
        self.line_prev = line;
        self.rows += 1;
        self.block_rows += 1;
        match &mut self.phase {
            Phase::Running(r) => {
                if gap {
                    r.restart();
                }
                r.process(t, a)
            }
            Phase::Preview(buf) => {
                buf.push(Pending { t, a: *a, gap_before: gap });
                let c = self.cfg.face_coefficient;
                let more = match self.cfg.floor {
                    FloorSource::Range(_, to) => t <= to,
                    // anywhere: the search over the held rows (standard input)
                    FloorSource::Auto => buf.len() < MAX_AUTO_PREVIEW_ROWS,
                    // until a quiet stretch before a signal shows (checked every PREVIEW_ROWS)
                    FloorSource::Lead => {
                        buf.len() < MAX_AUTO_PREVIEW_ROWS
                            && (buf.len() % PREVIEW_ROWS != 0 || {
                                let rel: Vec<f32> = buf.iter().map(|p| a_rel_of(p, c)).collect();
                                find_quiet(&rel).is_none()
                            })
                    }
                    _ => false,
                };
                if more && matches!(self.cfg.floor, FloorSource::Range(..)) && buf.len() >= MAX_QUIET_ROWS {
                    return Err(format!(
                        "line {line}: --quiet: more than {MAX_QUIET_ROWS} rows before its end: give a shorter quiet stretch"
                    ));
                }
                if buf.len() >= PREVIEW_ROWS && !more {
                    self.start()?;
                }
            }
        }
        Ok(())
    }

    /// The mean interval of the rows so far, within the blocks [s].
    fn mean_interval(&self) -> f64 {
        if self.gaps.is_empty() {
            (self.t_prev - self.t0) / (self.rows - 1) as f64
        } else {
            (self.done_span + (self.t_prev - self.block_t0)) / self.intervals() as f64
        }
    }

    /// The intervals the mean is taken over (within the blocks).
    fn intervals(&self) -> u64 {
        if self.gaps.is_empty() {
            self.rows.saturating_sub(1)
        } else {
            self.done_intervals + self.block_rows.saturating_sub(1)
        }
    }

    fn check_time(&mut self, line: u64, t: f64, res: f64) -> Result<(), String> {
        use crate::output::format::sig4;
        if !t.is_finite() {
            return Err(format!("line {line}: time {t} is not a finite number"));
        }
        let res_prev = std::mem::replace(&mut self.res_prev, res);
        self.res_max = self.res_max.max(res);
        if self.rows == 0 {
            return Ok(());
        }
        let dt = t - self.t_prev;
        if !(dt > 0.0) {
            let what = if dt == 0.0 { "repeats" } else { "goes back" };
            let hint = if dt == 0.0 && res.max(res_prev) > 0.0 {
                format!(" (printed to {} s: too few decimals for the sampling interval?)", sig4(res.max(res_prev)))
            } else {
                String::new()
            };
            return Err(format!(
                "line {line}: time {} s {what}: it does not come after {} s (line {}): the time column must increase strictly{hint}",
                sig4(t),
                sig4(self.t_prev),
                self.line_prev
            ));
        }
        if self.rows >= 2 && self.intervals() > 0 {
            let mean = self.mean_interval();
            let eps = 8.0 * f64::EPSILON * t.abs().max(self.t0.abs());
            // each row's time is within half its printed resolution of the truth
            let tol = RATE_TOLERANCE * mean + 0.5 * (res + res_prev) + eps;
            if (dt - mean).abs() > tol {
                let k = dt / mean;
                if dt > mean && self.split_gaps {
                    self.gaps.push(Gap { line, t_before: self.t_prev, t_after: t, intervals: k });
                    self.done_intervals += self.block_rows - 1;
                    self.done_span += self.t_prev - self.block_t0;
                    self.gap_pending = true;
                    return Ok(());
                }
                let whole = k.round();
                let what = if dt > mean && whole >= 2.0 && (dt - whole * mean).abs() <= tol {
                    format!("a drop: {} row{} missing", whole - 1.0, if whole == 2.0 { "" } else { "s" })
                } else if dt > mean {
                    "a gap".to_string()
                } else {
                    "a short interval: a row out of place or an irregular clock".to_string()
                };
                let way_on = if dt > mean { " (--gaps split analyses the contiguous blocks and lists the gaps)" } else { "" };
                return Err(format!(
                    "line {line}: time {} s after {} s (line {}): an interval of {} s where the rows before have a mean interval of {} s ({} of them): {what}; the time column must be uniformly sampled (within 1 % plus the printed resolution){way_on}",
                    sig4(t),
                    sig4(self.t_prev),
                    self.line_prev,
                    sig4(dt),
                    sig4(mean),
                    sig4(k),
                ));
            }
        }
        Ok(())
    }

    /// Sets up the estimator, filters and spectrum at the rate of the rows so far, and runs
    /// the buffered rows through them.
    fn start(&mut self) -> Result<(), String> {
        let Phase::Preview(buf) = &mut self.phase else { return Ok(()) };
        let buf = std::mem::take(buf);
        let k = buf.len();
        let fs = if self.gaps.is_empty() {
            (k - 1) as f64 / (buf[k - 1].t - buf[0].t)
        } else {
            1.0 / self.mean_interval()
        };
        let lines = format!("lines {} to {}", self.line_first, self.line_prev);
        let nyquist_min = 2.0 * GROAN_BAND_HZ.1;
        if !(fs > nyquist_min) {
            return Err(format!(
                "{lines}: sample rate {fs:.6} Hz from the time column: the groan band ({} to {} Hz) needs more than {nyquist_min} Hz",
                GROAN_BAND_HZ.0, GROAN_BAND_HZ.1
            ));
        }
        let ecfg = EstimatorConfig {
            fs_hz: fs,
            contact: ContactThresholds::from_breakaway_jump(self.cfg.breakaway_jump_m_s2, fs),
            window_samples: ((stickslip_model::rig::WINDOW_S * fs).round() as u32).max(1),
            band_speed_m_s: self.cfg.band_speed_m_s,
            face_coefficient: self.cfg.face_coefficient,
            ..EstimatorConfig::default()
        };
        ecfg.validate().map_err(|e| format!("{lines}: sample rate {fs:.6} Hz: the rig's estimator refuses it: {e}"))?;
        let floor = self.design_floor(&buf, fs)?;
        let design = floor.as_ref().map(|f| {
            (f.report, ContactThresholds::from_noise_floor(f.report.sigma_m_s2[A_REL] as f64, f.quantum_m_s2, fs))
        });
        let rig_cfg = RigConfig::recording(ecfg);
        let rig = Rig::for_recording(&rig_cfg, design)
            .map_err(|e| format!("{lines}: sample rate {fs:.6} Hz: the rig's estimator refuses it: {e}"))?;
        let groan = *rig.estimator().groan_filter();
        let start_level = rig.estimator().contact().thresholds().stick_max_m_s2;
        let start_bias = design.as_ref().map_or(0.0, |d| d.0.mean_m_s2[A_REL]);
        let segment = self.cfg.segment.unwrap_or_else(|| default_segment(fs));
        let mut r = Running {
            fs,
            from_eff: self.cfg.from_s - 0.25 / fs,
            rig: Box::new(rig),
            welch: self.cfg.spectra.then(|| Welch::new(segment)),
            envelope: self.cfg.figures.then(Envelope::new),
            n: 0,
            t_first: 0.0,
            t_last: 0.0,
            extremes: Extremes::<f64, CH>::EMPTY,
            sum: [0.0; CH],
            sq: [0.0; CH],
            groan_sq: [0.0; CH],
            prev: [0.0; CH],
            step: [f64::INFINITY; CH],
            stick: 0,
            onsets: OnsetRate::new(),
            first_onset: None,
            at_range: 0,
            at_range_ch: [0; CH],
            floor,
            windows: self.cfg.windows.then(Vec::new),
            groan,
            groan_state: [CascadeState::<GROAN_SECTIONS>::ZERO; CH],
            groan_origin: None,
            rig_cfg,
            design,
            onset_intervals: 0,
            onset_span: 0.0,
            last_onset: 0.0,
            started: false,
            held: Vec::with_capacity(START_RUN),
            start_level,
            start_bias,
            face: self.cfg.face_coefficient,
        };
        for p in &buf {
            if p.gap_before {
                r.restart();
            }
            r.process(p.t, &p.a);
        }
        self.phase = Phase::Running(Box::new(r));
        Ok(())
    }

    /// The noise floor the thresholds come from (`None` for [`FloorSource::Jump`]).
    fn design_floor(&self, buf: &[Pending], _fs: f64) -> Result<Option<FloorOutcome>, String> {
        let a_rel = |p: &Pending| a_rel_of(p, self.cfg.face_coefficient);
        let (rows, auto): (Vec<&Pending>, bool) = match self.cfg.floor {
            FloorSource::Jump => return Ok(None),
            FloorSource::Found(f) => return Ok(Some(f)),
            FloorSource::Auto => {
                let mut q = super::quiet::QuietSearch::new(self.cfg.face_coefficient);
                for p in buf {
                    q.push(p.t, &p.a);
                }
                return Ok(q.finish().ok());
            }
            FloorSource::Range(from, to) => (buf.iter().filter(|p| p.t >= from && p.t <= to).collect(), false),
            FloorSource::Lead => {
                let rel: Vec<f32> = buf.iter().map(a_rel).collect();
                match find_quiet(&rel) {
                    Some((i0, i1)) => (buf[i0..i1].iter().collect(), true),
                    // no quiet stretch against a signal: the fixed thresholds of the jump
                    None => return Ok(None),
                }
            }
        };
        if rows.len() < MIN_FLOOR_SAMPLES as usize {
            let what = match self.cfg.floor {
                FloorSource::Range(from, to) => format!("--quiet {from}:{to}: {} rows in it", rows.len()),
                _ => format!(
                    "no quiet stretch of {MIN_FLOOR_SAMPLES} rows in the first {} (the clamped, band-still phase a record should start with)",
                    buf.len()
                ),
            };
            return Err(format!(
                "{what}: the noise floor needs at least {MIN_FLOOR_SAMPLES}: give --quiet FROM:TO over a stretch where nothing moves, or --breakaway-jump M_S2 for fixed thresholds"
            ));
        }
        let mut nf = NoiseFloor::new();
        for p in &rows {
            nf.add(&p.a.map(|v| v as f32), a_rel(p));
        }
        // the quantum: the smallest nonzero step of pad_x and of disc_x over the buffered rows
        let step = |c: usize| {
            buf.windows(2)
                .map(|w| (w[1].a[c] - w[0].a[c]).abs())
                .filter(|&d| d > 0.0)
                .fold(f64::INFINITY, f64::min)
        };
        let q = [step(1), step(0)].into_iter().filter(|v| v.is_finite()).fold(0.0, f64::max);
        Ok(Some(FloorOutcome {
            t_from: rows[0].t,
            t_to: rows[rows.len() - 1].t,
            auto,
            report: nf.report(),
            quantum_m_s2: q,
            quiet_blocks: 0,
        }))
    }

    /// The statistics. Errors (one line, starting with what is wrong): no rows, a single row,
    /// no row at or after `from_s`.
    pub fn finish(mut self) -> Result<Analysis, String> {
        if self.rows == 0 {
            return Err("no data rows".into());
        }
        if self.rows == 1 {
            return Err(format!("line {}: a single data row: the sample rate needs at least two", self.line_first));
        }
        if matches!(self.phase, Phase::Preview(_)) {
            self.start()?;
        }
        let mean_interval = self.mean_interval();
        let Phase::Running(r) = self.phase else { unreachable!("started above") };
        let mut r = *r;
        r.flush_held();
        if r.n == 0 {
            return Err(format!(
                "--from {} s: no row at or after it (the last row, line {}, is at {} s)",
                self.cfg.from_s, self.line_prev, self.t_prev
            ));
        }
        let sample_rate_hz = if self.gaps.is_empty() {
            (self.rows - 1) as f64 / (self.t_prev - self.t0)
        } else {
            1.0 / mean_interval
        };
        if r.floor.is_none() && self.floor_note.is_none() && self.cfg.floor == FloorSource::Auto {
            self.floor_note = Some(format!("no quiet rows found in the first {MAX_AUTO_PREVIEW_ROWS} rows read from standard input"));
        }
        let hz_pooled = r.hz();
        let spectrum = r.welch.and_then(|w| w.finish(sample_rate_hz));
        let n = r.n as f64;
        let channels = std::array::from_fn(|c| ChannelStats {
            pp: r.extremes.pp(c),
            rms: (r.sq[c] / n).sqrt(),
            mean: r.sum[c] / n,
            min: r.extremes.min[c],
            max: r.extremes.max[c],
            peak_hz: spectrum.as_ref().and_then(|s| s.peak(c)).map(|p| p.1),
            groan_rms: (r.groan_sq[c] / n).sqrt(),
            step: if r.step[c].is_finite() { r.step[c] } else { 0.0 },
        });
        let stick_slip_hz = hz_pooled;
        let thresholds = *r.rig.estimator().contact().thresholds();
        // the rig's rule (stickslip_model::rig::health): flat, saturated, noisier than the
        // signal; pad_x must carry a signal, disc_x must not be saturated
        let present = self.present;
        let verdict = HealthReport::new(std::array::from_fn(|c| {
            if !present[c] {
                return ChannelHealth::default();
            }
            ChannelHealth::assess(
                channels[c].pp as f32,
                channels[c].rms as f32,
                r.at_range_ch[c] > 0,
                // a floor found in the stick phases is a noise floor of a_rel, pad_x and disc_x
                // only: the pad still rotates in stick, so the edge sensors' is not theirs
                r.floor.as_ref().filter(|f| f.quiet_blocks == 0 || c == PAD_X || c == DISC_X).map(|f| (f.report.mean_m_s2[c], f.report.sigma_m_s2[c])),
            )
        }));
        let health: [Vec<&'static str>; CH] = std::array::from_fn(|c| verdict.channels[c].words().collect());
        let undecided = verdict.undecidable().then(|| {
            let mut bad = vec![];
            for (c, name) in [(PAD_X, "pad_x"), (DISC_X, "disc_x")] {
                for what in verdict.channels[c].words() {
                    if !(c == DISC_X && what == "flat") {
                        bad.push(format!("{name} {what}"));
                    }
                }
            }
            format!("{}: the contact estimate (stick fraction, frequency) would be a guess", bad.join(", "))
        });
        Ok(Analysis {
            channels,
            stick_fraction: r.stick as f64 / n,
            stick_slip_hz,
            slip_onsets: u64::from(r.onsets.count()),
            first_onset_s: r.first_onset,
            sample_rate_hz,
            setup_rate_hz: r.fs,
            rows: self.rows,
            samples: r.n,
            t_first: r.t_first,
            t_last: r.t_last,
            from_s: self.cfg.from_s,
            time_resolution_s: self.res_max,
            samples_at_range: r.at_range,
            thresholds,
            breakaway_jump_m_s2: self.cfg.breakaway_jump_m_s2,
            floor: r.floor,
            at_range: r.at_range_ch,
            undecided,
            health,
            spectrum,
            envelope: r.envelope.map(Envelope::finish).unwrap_or_default(),
            windows: r.windows.unwrap_or_default(),
            present,
            gaps: self.gaps,
            floor_note: self.floor_note,
            notes: self.notes,
            format: "",
        })
    }
}
