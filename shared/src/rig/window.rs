//! Statistics over consecutive windows of samples (default 100 ms = 2560 samples).
//!
//! Per window, over the samples that passed the estimator's input check:
//! - peak-to-peak (max - min) and RMS (about zero: the IEPE accelerometers are AC-coupled) of
//!   each accelerometer [m/s^2]; the thesis's Table 3.1 reports peak-to-peak;
//! - RMS of each accelerometer in the groan band (the band-pass output);
//! - stick fraction: samples estimated in stick / samples;
//! - stick-slip frequency: 1 / mean interval between successive stick-to-slip onsets inside the
//!   window, (n - 1) fs / (last - first) with onsets at sample indices (`stats::OnsetRate`, the
//!   one definition, in f32 here); 0 with fewer than two;
//! - for the lockstep model, over the samples it ran: its stick fraction and stick-slip
//!   frequency (same definitions, from its own regime and transitions) and the RMS of the
//!   residual (measured pad_x minus the model's x'').
//!
//! Per sample only comparisons, additions and multiplications: the squares are summed in f32
//! over blocks of 256 samples and the block sums added to the totals (so no f32 sum runs over
//! more than 256 terms: relative error below 256 x 2^-24 = 1.5e-5). The sample that closes a
//! window only sets its sums aside; the divisions and square roots are taken by
//! [`WindowAccumulator::take_report`], which the caller runs outside the sample deadline (the
//! firmware's main loop), before the next window closes: a window not taken by then is
//! replaced and counted in [`WindowAccumulator::windows_dropped`]. A statistic that comes out
//! non-finite (impossible with inputs that passed the check, but checked) is reported as 0 and
//! flagged.

use super::lockstep::ModelSample;
use super::ACCEL_CHANNELS;
use crate::exact::Halt;
use crate::stats::{Extremes, OnsetRate};

/// The default window: [`crate::design::WINDOW_S`] (100 ms) at [`crate::design::SAMPLE_RATE_HZ`] (25.6 kHz),
/// 2 560 samples.
pub const DEFAULT_WINDOW_SAMPLES: u32 = (crate::design::WINDOW_S * crate::design::SAMPLE_RATE_HZ + 0.5) as u32;
/// Squares are summed in f32 blocks of this many samples.
const BLOCK: u32 = 256;
/// Sum-of-squares slots: 4 raw channels, 4 band-passed channels, the model residual.
const SQ: usize = 2 * ACCEL_CHANNELS + 1;
const RESIDUAL: usize = 2 * ACCEL_CHANNELS;

/// The lockstep model's statistics over the samples of a window in which it ran.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ModelWindow {
    /// Samples of the window in which the model ran (and had not halted).
    pub samples: u32,
    pub stick_fraction: f32,
    pub stick_slip_hz: f32,
    pub slip_onsets: u32,
    /// RMS of measured pad_x minus the model's x'' [m/s^2].
    pub residual_rms_m_s2: f32,
    /// Why the model stopped, if it did (in this window or before).
    pub halt: Option<Halt>,
}

/// The statistics of one window.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WindowReport {
    /// Window number, from 0.
    pub index: u32,
    /// Estimator sample index of the window's first sample.
    pub first_sample: u64,
    /// Samples in the window (including faulted ones).
    pub samples: u32,
    /// Samples that passed the input check (the statistics are over these).
    pub valid_samples: u32,
    /// Peak-to-peak per accelerometer [m/s^2].
    pub pp_m_s2: [f32; ACCEL_CHANNELS],
    /// RMS per accelerometer [m/s^2].
    pub rms_m_s2: [f32; ACCEL_CHANNELS],
    /// RMS in the groan band per accelerometer [m/s^2].
    pub groan_rms_m_s2: [f32; ACCEL_CHANNELS],
    pub stick_fraction: f32,
    /// [Hz]
    pub stick_slip_hz: f32,
    /// Stick-to-slip onsets in the window.
    pub slip_onsets: u32,
    /// Samples with any accelerometer at its range or at an ADC rail.
    pub saturated_samples: u32,
    /// Samples refused by the estimator's input check (non-finite or implausible).
    pub faulted_samples: u32,
    /// Present when the lockstep model ran during the window.
    pub model: Option<ModelWindow>,
    /// A statistic came out non-finite and was replaced by 0.
    pub non_finite: bool,
}

/// One sample's contribution to the window statistics.
#[derive(Clone, Copy, Debug)]
pub struct SampleStats<'a> {
    pub accel_m_s2: &'a [f32; ACCEL_CHANNELS],
    pub groan_m_s2: &'a [f32; ACCEL_CHANNELS],
    pub stick: bool,
    pub slip_onset: bool,
    /// At a slip onset: the samples before it that already belonged to the slip
    /// (`ContactSample::lead_samples`): they leave the stick count (as far as this window
    /// counted them) and the onset is dated back by them.
    pub onset_lead: u32,
    pub saturated: bool,
    pub model: Option<&'a ModelSample>,
}

/// The running sums of one window.
#[derive(Clone, Copy, Debug)]
struct WindowSums {
    index: u32,
    first_sample: u64,
    /// Samples in the window (valid or not), and the window-relative index of the next.
    n: u32,
    valid: u32,
    extremes: Extremes<f32, ACCEL_CHANNELS>,
    sq_block: [f32; SQ],
    sq_total: [f32; SQ],
    block_n: u32,
    stick: u32,
    /// Slip onsets at window-relative sample indices.
    onsets: OnsetRate<u32>,
    saturated: u32,
    faulted: u32,
    model_n: u32,
    model_stick: u32,
    model_onsets: OnsetRate<u32>,
    model_seen: bool,
    model_halt: Option<Halt>,
}

impl WindowSums {
    fn fresh(index: u32, first_sample: u64) -> Self {
        WindowSums {
            index,
            first_sample,
            n: 0,
            valid: 0,
            extremes: Extremes::<f32, ACCEL_CHANNELS>::EMPTY,
            sq_block: [0.0; SQ],
            sq_total: [0.0; SQ],
            block_n: 0,
            stick: 0,
            onsets: OnsetRate::new(),
            saturated: 0,
            faulted: 0,
            model_n: 0,
            model_stick: 0,
            model_onsets: OnsetRate::new(),
            model_seen: false,
            model_halt: None,
        }
    }

    fn fold(&mut self) {
        for k in 0..SQ {
            self.sq_total[k] += self.sq_block[k];
            self.sq_block[k] = 0.0;
        }
        self.block_n = 0;
    }

    /// The statistics: the divisions and square roots.
    fn report(mut self, fs: f32) -> WindowReport {
        self.fold();
        let mut non_finite = false;
        let mut clean = |v: f32| {
            if v.is_finite() {
                v
            } else {
                non_finite = true;
                0.0
            }
        };
        let valid = self.valid;
        let rms = |sum: f32, n: u32| if n > 0 { libm::sqrtf(sum / n as f32) } else { 0.0 };
        let mut pp = [0.0f32; ACCEL_CHANNELS];
        let mut rms_raw = [0.0f32; ACCEL_CHANNELS];
        let mut rms_groan = [0.0f32; ACCEL_CHANNELS];
        for i in 0..ACCEL_CHANNELS {
            pp[i] = clean(if valid > 0 { self.extremes.pp(i) } else { 0.0 });
            rms_raw[i] = clean(rms(self.sq_total[i], valid));
            rms_groan[i] = clean(rms(self.sq_total[ACCEL_CHANNELS + i], valid));
        }
        let stick_fraction = clean(if valid > 0 { self.stick as f32 / valid as f32 } else { 0.0 });
        let stick_slip_hz = clean(self.onsets.hz_at(fs));
        let model = if self.model_seen {
            let n = self.model_n;
            Some(ModelWindow {
                samples: n,
                stick_fraction: clean(if n > 0 { self.model_stick as f32 / n as f32 } else { 0.0 }),
                stick_slip_hz: clean(self.model_onsets.hz_at(fs)),
                slip_onsets: self.model_onsets.count(),
                residual_rms_m_s2: clean(rms(self.sq_total[RESIDUAL], n)),
                halt: self.model_halt,
            })
        } else {
            None
        };
        WindowReport {
            index: self.index,
            first_sample: self.first_sample,
            samples: self.n,
            valid_samples: valid,
            pp_m_s2: pp,
            rms_m_s2: rms_raw,
            groan_rms_m_s2: rms_groan,
            stick_fraction,
            stick_slip_hz,
            slip_onsets: self.onsets.count(),
            saturated_samples: self.saturated,
            faulted_samples: self.faulted,
            model,
            non_finite,
        }
    }
}

/// Accumulates the statistics of the current window; holds the last closed one until taken.
#[derive(Clone, Copy, Debug)]
pub struct WindowAccumulator {
    len: u32,
    fs: f32,
    sums: WindowSums,
    closed: Option<WindowSums>,
    dropped: u32,
}

impl WindowAccumulator {
    /// Windows of `len` samples (at least 1) at `fs_hz`.
    pub fn new(len: u32, fs_hz: f64) -> Self {
        WindowAccumulator { len: len.max(1), fs: fs_hz as f32, sums: WindowSums::fresh(0, 0), closed: None, dropped: 0 }
    }

    /// Window length [samples].
    pub fn window_samples(&self) -> u32 {
        self.len
    }

    /// Closed windows replaced before they were taken.
    pub fn windows_dropped(&self) -> u32 {
        self.dropped
    }

    /// Adds a valid sample; returns true when it closes the window (its report is then
    /// waiting in [`Self::take_report`]).
    #[inline(always)] // the per-sample path: compiled where it is called (see Estimator::update)
    pub fn add(&mut self, s: &SampleStats<'_>) -> bool {
        let w = &mut self.sums;
        let at = w.n;
        for i in 0..ACCEL_CHANNELS {
            let a = s.accel_m_s2[i];
            w.extremes.take(i, a);
            w.sq_block[i] += a * a;
            let g = s.groan_m_s2[i];
            w.sq_block[ACCEL_CHANNELS + i] += g * g;
        }
        if s.stick {
            w.stick += 1;
        }
        if s.slip_onset {
            let lead = s.onset_lead.min(w.stick);
            w.stick -= lead;
            w.onsets.add(at.saturating_sub(s.onset_lead));
        }
        if s.saturated {
            w.saturated += 1;
        }
        if let Some(m) = s.model {
            w.model_seen = true;
            if !m.halted {
                w.model_n += 1;
                if m.regime == crate::stickslip::Regime::Stick {
                    w.model_stick += 1;
                }
                if m.slip_onset {
                    w.model_onsets.add(at);
                }
                w.sq_block[RESIDUAL] += m.residual_m_s2 * m.residual_m_s2;
            }
        }
        w.valid += 1;
        w.block_n += 1;
        if w.block_n >= BLOCK {
            w.fold();
        }
        self.step()
    }

    /// Counts a sample the estimator refused; returns true when it closes the window.
    #[inline]
    pub fn add_faulted(&mut self, model_running: bool) -> bool {
        self.sums.faulted += 1;
        self.sums.model_seen |= model_running;
        self.step()
    }

    /// Records that the lockstep model halted (kept in this window and every later one), or,
    /// with `None`, that a new model runs.
    pub fn set_model_halt(&mut self, h: Option<Halt>) {
        self.sums.model_halt = h;
    }

    #[inline(always)]
    fn step(&mut self) -> bool {
        self.sums.n += 1;
        if self.sums.n < self.len {
            return false;
        }
        if self.closed.is_some() {
            self.dropped = self.dropped.saturating_add(1);
        }
        let w = &self.sums;
        let mut next = WindowSums::fresh(w.index.wrapping_add(1), w.first_sample.wrapping_add(w.n as u64));
        next.model_halt = w.model_halt;
        self.closed = Some(core::mem::replace(&mut self.sums, next));
        true
    }

    /// The report of the last closed window, once (the divisions and square roots are taken
    /// here, not in the sample that closed it).
    pub fn take_report(&mut self) -> Option<WindowReport> {
        let fs = self.fs;
        self.closed.take().map(|w| w.report(fs))
    }
}
