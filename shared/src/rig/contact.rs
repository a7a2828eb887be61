//! Stick or slip, sample by sample, from the accelerations alone; and the relative velocity.
//!
//! Input: the relative acceleration of the friction face and the band, a_rel = pad_x - disc_x
//! (+ the face term with face kinematics, [`super::estimator::EstimatorConfig`]) [m/s^2].
//! Output: the contact regime (the model's [`Regime`]), the relative velocity v_r = pad - band
//! [m/s], and events with their sample index.
//!
//! **What separates stick from slip.** In stick the face moves with the band: a_rel = 0, up to
//! the sensors' noise and bias. In slip v_r != 0. With constant friction the breakaway is a
//! jump of a_rel to about -(mu_s - mu_k) N / m; with falling (Stribeck) friction it is smooth:
//! a_rel grows from 0 over several samples. The re-stick is a jump in both cases (a_rel drops
//! from its value at v_r = 0 to 0). So the decision does not wait for a jump: it takes the onset
//! where |a_rel| leaves the noise, integrates v_r through the slip, and takes the re-stick where
//! v_r is back at zero and a_rel is quiet.
//!
//! **Decision, per sample (dt = 1 / fs; a = a_rel minus the tracked bias):**
//! - Stick -> slip when |a| > `onset` (the onset level in force). The sign of a gives the
//!   direction (a < 0: the pad falls behind, slip pad slower). v_r starts from the trapezoid
//!   over the last interval, dt/2 (a[-1] + a). The event carries its *lead*: the stick samples
//!   just before it whose a was already beyond a quarter of the onset level with the slip's
//!   sign (at most [`MAX_LEAD`]); the window statistics and `analyze` date the onset back by it
//!   and take those samples out of the stick count. So a smooth breakaway detected k samples
//!   late costs no stick-fraction error once its start has left the noise.
//! - In slip v_r is integrated by the trapezoid rule, and its largest magnitude v_peak in this
//!   slip (on the slip's side) and the largest |a| are kept. Slip -> stick when |a| <= `stick`
//!   (the stick level in force) *and* v_r is back at zero: within max(`v_tol`, v_peak / 2) on
//!   the slip's side, judged on both the trapezoid v_r and the Euler extrapolation
//!   v_r[-1] + dt a[-1] (the trapezoid under-shoots by up to dt/2 a when the re-stick falls late
//!   in the interval). A quiet a in mid-slip occurs only near the peak of |v_r|, where v_r is
//!   not within v_peak / 2 of zero, so the pair cannot be met there; the v_peak / 2 margin
//!   absorbs what a residual bias integrates to over a slip.
//! - v_r beyond zero by more than max(`v_reversal`, v_peak / 2) with a not quiet is a reversal
//!   (slip pad slower <-> slip pad faster), the model's fourth case.
//! - Drift guard: `stall_samples` consecutive quiet samples in slip end it whatever v_r says.
//!   Steady sliding without oscillation cannot be told from stick by accelerometers at all.
//! - Zero-velocity update and bias: in stick v_r = 0, and a_rel's mean (true value 0) is
//!   tracked as a bias with a first-order filter of gain `bias_gain` per sample. A stick sample
//!   teaches the tracker only [`BIAS_DELAY`] samples later, once no onset has followed it (the
//!   ring of the last samples is cleared at each onset): the start of a smooth breakaway, seen
//!   late, is never learnt as a bias. (Learnt as a bias, it integrated over the slip into a
//!   v_r that crossed zero before the re-stick: a "reversal", and no re-stick ever after.)
//!
//! **Delay.** The onset is decided at the first sample with |a| above the onset level: with a
//! jump, the first sample after the breakaway; with a smooth breakaway, when a_rel has grown
//! past the level (the lead then dates it back). The re-stick is decided at the first sample
//! after it (a drops to the stick level at once). Per sample: no division, no square root.
//!
//! **Thresholds** ([`ContactThresholds`]):
//! - From the measured noise floor ([`ContactThresholds::from_noise_floor`], what the rig and
//!   `analyze` use): onset = max(6 sigma of a_rel, 2 quanta, 1e-4 m/s^2), stick = onset / 2,
//!   v_tol = 4 onset dt, v_reversal = 16 onset dt, drift guard 5 ms, bias time constant 256
//!   samples. Six sigma of Gaussian noise is exceeded once in 5e8 samples (5.5 hours at
//!   25.6 kHz). Then *adaptive*: after each slip the onset level becomes 1/16
//!   ([`ADAPT_ONSET_FRACTION`]) of the running mean of the slips' peak |a| (weight 1/4 for the
//!   newest), never below the designed level and never above 4 times it
//!   ([`ADAPT_MAX_FACTOR`]); the stick level follows at half. Large stick-slip then gets a
//!   margin over disturbances (band and pad vibration in stick) that small stick-slip cannot
//!   afford, and the bound keeps one large slip from blinding the estimator to small ones.
//! - From a breakaway jump J ([`ContactThresholds::from_breakaway_jump`], fixed, no
//!   adaptation): onset J / 2, stick J / 4, v_tol 2 J dt, v_reversal 8 J dt. The scene's J
//!   ([`ContactThresholds::for_scene`], at least [`MIN_DESIGN_JUMP_M_S2`]) is only the starting
//!   value until a floor is measured; `--breakaway-jump` keeps it fixed.
//!
//! Measured (`cargo test --release -p stickslip --test quiet_levels`): at Table 3.1's levels
//! (pad_x 2.1 to 3.7 m/s^2 peak-to-peak, the `rig_quiet_*` scenes through `sil --gain 10`)
//! the stick fraction is within 0.005 of the truth and the stick-slip frequency within 0.004 %
//! for all six cases, with the thresholds from the floor.

use crate::scene::Scene;
use crate::stickslip::Regime;

/// The smallest breakaway jump [`ContactThresholds::for_scene`] designs for [m/s^2]: onset
/// 4 m/s^2, stick 2 m/s^2 (10 and 5 counts of the rig's accelerometers at gain 0.2).
pub const MIN_DESIGN_JUMP_M_S2: f64 = 8.0;

/// Slip onset from a noise floor: this many standard deviations of a_rel's noise.
pub const ONSET_SIGMAS: f64 = 6.0;
/// Slip onset from a noise floor: at least this many quanta of a_rel (the two channels'
/// rounding, one count each in the worst case, when the noise does not dither the converter).
pub const ONSET_QUANTA: f64 = 2.0;
/// The smallest slip-onset level any design gives [m/s^2] (a floor measured as exactly 0 on an
/// ideal, noise-free input).
pub const MIN_ONSET_M_S2: f64 = 1e-4;
/// Adaptive onset: this fraction of the running mean of the slips' peak |a_rel|.
pub const ADAPT_ONSET_FRACTION: f32 = 1.0 / 16.0;
/// Adaptive onset: at most this factor above the designed onset.
pub const ADAPT_MAX_FACTOR: f32 = 4.0;

/// The thresholds of the stick/slip decision (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactThresholds {
    /// |a_rel| above which a sticking pad is taken to slip [m/s^2] (the designed value; the
    /// adaptation may raise it, see `onset_fraction`).
    pub slip_onset_m_s2: f32,
    /// |a_rel| at or below which a slipping pad back at v_r = 0 is taken to stick [m/s^2].
    pub stick_max_m_s2: f32,
    /// v_r counts as back at zero for the re-stick within this of it, on the slip's side (or
    /// within half the slip's peak |v_r|, whichever is larger) [m/s].
    pub v_tol_m_s: f32,
    /// v_r beyond zero by more than this (and by half the slip's peak), with |a_rel| above the
    /// stick level, is a reversal [m/s].
    pub v_reversal_m_s: f32,
    /// Consecutive quiet samples that end a slip whatever v_r says (0: never).
    pub stall_samples: u32,
    /// Gain per sample of the bias tracker in stick [-] (0: no bias tracking).
    pub bias_gain: f32,
    /// Adaptive onset: after each slip the onset level becomes this fraction of the running
    /// mean of the slips' peak |a_rel|, bounded to [slip_onset, onset_max_factor slip_onset]
    /// (0: fixed thresholds).
    pub onset_fraction: f32,
    /// Adaptive onset: the upper bound, as a factor of `slip_onset_m_s2` (>= 1).
    pub onset_max_factor: f32,
    /// The stick level as a fraction of the onset level in force, (0, 1].
    pub stick_ratio: f32,
}

impl ContactThresholds {
    /// Fixed thresholds for a breakaway jump of `jump_m_s2` [m/s^2] at the sampling rate
    /// `fs_hz`: onset J / 2, stick J / 4, v_tol 2 J dt, v_reversal 8 J dt, drift guard 5 ms,
    /// bias time constant 256 samples, no adaptation.
    pub fn from_breakaway_jump(jump_m_s2: f64, fs_hz: f64) -> Self {
        let dt = 1.0 / fs_hz;
        ContactThresholds {
            slip_onset_m_s2: (0.5 * jump_m_s2) as f32,
            stick_max_m_s2: (0.25 * jump_m_s2) as f32,
            v_tol_m_s: (2.0 * jump_m_s2 * dt) as f32,
            v_reversal_m_s: (8.0 * jump_m_s2 * dt) as f32,
            stall_samples: libm::ceil(5e-3 * fs_hz) as u32,
            bias_gain: 1.0 / 256.0,
            onset_fraction: 0.0,
            onset_max_factor: 1.0,
            stick_ratio: 0.5,
        }
    }

    /// Thresholds from a measured noise floor: `sigma_m_s2` the standard deviation of a_rel's
    /// noise [m/s^2] and `quantum_m_s2` its resolution (the larger count of pad_x and disc_x
    /// [m/s^2]; 0 for a continuous input). Onset = max(6 sigma, 2 quanta, 1e-4 m/s^2), the
    /// rest as [`Self::from_breakaway_jump`] with J = 2 onset, and the adaptation on: the
    /// onset rises to 1/16 of the slips' mean peak |a_rel|, at most 4 times the designed
    /// level.
    pub fn from_noise_floor(sigma_m_s2: f64, quantum_m_s2: f64, fs_hz: f64) -> Self {
        let onset = (ONSET_SIGMAS * sigma_m_s2).max(ONSET_QUANTA * quantum_m_s2).max(MIN_ONSET_M_S2);
        let mut th = Self::from_breakaway_jump(2.0 * onset, fs_hz);
        th.onset_fraction = ADAPT_ONSET_FRACTION;
        th.onset_max_factor = ADAPT_MAX_FACTOR;
        th
    }

    /// The breakaway jump of a scene at its static normal force, J = (mu_s - mu_k) N0 / m
    /// [m/s^2].
    pub fn breakaway_jump(scene: &Scene) -> f64 {
        let n0 = crate::coefficients::Coefficients::of(scene).n0;
        (scene.mu_s - scene.mu_k) * n0 / scene.m
    }

    /// [`Self::from_breakaway_jump`] with the jump of `scene`, but at least
    /// [`MIN_DESIGN_JUMP_M_S2`] (a scene with mu_k = mu_s has no jump at all: its breakaway is
    /// then seen when |a_rel| grows past 4 m/s^2). A starting value only: the rig replaces it
    /// with [`Self::from_noise_floor`] once the clamped phase has measured the floor.
    pub fn for_scene(scene: &Scene, fs_hz: f64) -> Self {
        Self::from_breakaway_jump(Self::breakaway_jump(scene).max(MIN_DESIGN_JUMP_M_S2), fs_hz)
    }
}

/// What happened at a sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactEventKind {
    StickToSlip = 0,
    SlipToStick = 1,
    /// Slip changed direction through v_r = 0 without sticking.
    Reversal = 2,
}

/// An event and the index of the sample at which it was decided (the first sample after it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ContactEvent {
    pub kind: ContactEventKind,
    pub sample: u64,
}

/// The contact estimate after one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactSample {
    pub regime: Regime,
    /// Relative velocity pad - band [m/s] (0 in stick).
    pub v_r_m_s: f32,
    /// a_rel minus the tracked bias [m/s^2].
    pub a_rel_m_s2: f32,
    pub event: Option<ContactEvent>,
    /// At a stick-to-slip event: the stick samples just before it whose a_rel had already
    /// left the noise with the slip's sign (beyond a quarter of the onset level): the slip's
    /// estimated start lies that many samples before the event (at most [`MAX_LEAD`]). 0
    /// otherwise.
    pub lead_samples: u32,
}

/// The longest backdating of a slip onset [samples].
pub const MAX_LEAD: u32 = 64;

/// Stick samples wait this many samples before they update the bias: a slip onset detected a
/// few samples late then cannot teach the tracker the start of the slip as a bias.
pub const BIAS_DELAY: usize = 8;

/// The stick/slip estimator (see the module documentation).
#[derive(Clone, Copy, Debug)]
pub struct ContactEstimator {
    th: ContactThresholds,
    dt: f32,
    half_dt: f32,
    regime: Regime,
    v_r: f32,
    /// Largest |v_r| of the current slip, on the slip's side [m/s].
    v_peak: f32,
    /// Largest |a| of the current slip [m/s^2].
    a_peak: f32,
    /// Running mean of the slips' peak |a| [m/s^2] (0 before the first slip ends).
    a_peak_mean: f32,
    /// The slip-onset and stick levels in force (the thresholds', raised by the adaptation).
    onset: f32,
    stick_max: f32,
    a_prev: f32,
    bias: f32,
    /// The last [`BIAS_DELAY`] stick samples (bias removed), oldest at `recent_at`.
    recent: [f32; BIAS_DELAY],
    recent_at: usize,
    /// Stick samples in `recent` (the bias learns only once it is full).
    recent_n: usize,
    quiet: u32,
    /// Consecutive stick samples with a_rel above / below +- a quarter of the onset level.
    run_pos: u32,
    run_neg: u32,
    sample: u64,
}

impl ContactEstimator {
    /// Starts in stick (the rig clamps the pad before the band moves), v_r = 0, no bias.
    pub fn new(th: ContactThresholds, fs_hz: f64) -> Self {
        ContactEstimator {
            th,
            dt: (1.0 / fs_hz) as f32,
            half_dt: (0.5 / fs_hz) as f32,
            regime: Regime::Stick,
            v_r: 0.0,
            v_peak: 0.0,
            a_peak: 0.0,
            a_peak_mean: 0.0,
            onset: th.slip_onset_m_s2,
            stick_max: th.stick_max_m_s2,
            a_prev: 0.0,
            bias: 0.0,
            recent: [0.0; BIAS_DELAY],
            recent_at: 0,
            recent_n: 0,
            quiet: 0,
            run_pos: 0,
            run_neg: 0,
            sample: 0,
        }
    }

    pub fn thresholds(&self) -> &ContactThresholds {
        &self.th
    }
    /// The stick level in force [m/s^2].
    pub fn stick_max_m_s2(&self) -> f32 {
        self.stick_max
    }
    pub fn regime(&self) -> Regime {
        self.regime
    }
    /// The tracked bias of a_rel [m/s^2].
    pub fn bias_m_s2(&self) -> f32 {
        self.bias
    }
    /// Sets the bias of a_rel [m/s^2] (e.g. measured in the clamped, band-still phase).
    pub fn set_bias_m_s2(&mut self, bias: f32) {
        self.bias = bias;
    }
    /// Index of the next sample.
    pub fn samples(&self) -> u64 {
        self.sample
    }

    /// Takes one sample of a_rel = pad_x - disc_x [m/s^2] (finite: the caller checks).
    #[inline(always)] // the per-sample path: compiled where it is called (see Estimator::update)
    pub fn update(&mut self, a_rel_m_s2: f32) -> ContactSample {
        let th = &self.th;
        let a = a_rel_m_s2 - self.bias;
        let abs_a = a.abs();
        let mut event = None;
        let mut lead = 0;
        match self.regime {
            Regime::Stick => {
                if abs_a > self.onset {
                    lead = if a < 0.0 { self.run_neg } else { self.run_pos };
                    self.run_pos = 0;
                    self.run_neg = 0;
                    self.regime = if a < 0.0 { Regime::SlipSlower } else { Regime::SlipFaster };
                    self.v_r = self.half_dt * (self.a_prev + a);
                    self.v_peak = 0.0;
                    self.a_peak = abs_a;
                    self.quiet = 0;
                    // the samples just before the onset may hold its start: never learnt
                    self.recent_n = 0;
                    event = Some(ContactEventKind::StickToSlip);
                } else {
                    let lead_level = 0.25 * self.onset;
                    self.run_pos = if a > lead_level { (self.run_pos + 1).min(MAX_LEAD) } else { 0 };
                    self.run_neg = if a < -lead_level { (self.run_neg + 1).min(MAX_LEAD) } else { 0 };
                    // the sample BIAS_DELAY stick samples ago is confirmed stick: learn from it
                    let old = self.recent[self.recent_at];
                    self.recent[self.recent_at] = a;
                    self.recent_at = if self.recent_at + 1 == BIAS_DELAY { 0 } else { self.recent_at + 1 };
                    if self.recent_n == BIAS_DELAY {
                        self.bias += th.bias_gain * old;
                    } else {
                        self.recent_n += 1;
                    }
                    self.v_r = 0.0;
                }
            }
            Regime::SlipSlower | Regime::SlipFaster => {
                // s = sign of v_r in this slip
                let s = if self.regime == Regime::SlipSlower { -1.0f32 } else { 1.0f32 };
                let v_new = self.v_r + self.half_dt * (self.a_prev + a);
                let euler = self.v_r + self.dt * self.a_prev;
                let sv = s * v_new;
                if sv > self.v_peak {
                    self.v_peak = sv;
                }
                if abs_a > self.a_peak {
                    self.a_peak = abs_a;
                }
                let quiet = abs_a <= self.stick_max;
                self.quiet = if quiet { self.quiet.saturating_add(1) } else { 0 };
                // back at zero: within v_tol, or within half of this slip's peak |v_r| (a quiet
                // a_rel in mid-slip comes only where |v_r| is near its peak)
                let tol = th.v_tol_m_s.max(0.5 * self.v_peak);
                let back_at_zero = sv <= tol || s * euler <= tol;
                let stalled = th.stall_samples > 0 && self.quiet >= th.stall_samples;
                if quiet && (back_at_zero || stalled) {
                    self.regime = Regime::Stick;
                    self.v_r = 0.0;
                    self.adapt();
                    event = Some(ContactEventKind::SlipToStick);
                } else if sv < -th.v_reversal_m_s.max(0.5 * self.v_peak) {
                    self.regime = if s < 0.0 { Regime::SlipFaster } else { Regime::SlipSlower };
                    self.v_r = v_new;
                    self.v_peak = -sv;
                    event = Some(ContactEventKind::Reversal);
                } else {
                    self.v_r = v_new;
                }
            }
        }
        self.a_prev = a;
        let sample = self.sample;
        self.sample = self.sample.wrapping_add(1);
        ContactSample {
            regime: self.regime,
            v_r_m_s: self.v_r,
            a_rel_m_s2: a,
            event: event.map(|kind| ContactEvent { kind, sample }),
            lead_samples: lead,
        }
    }

    /// At the end of a slip: the running mean of the slips' peak |a| (weight 1/4 for the
    /// newest), and the onset level it implies: `onset_fraction` of that mean, never below the
    /// thresholds' onset and never above `onset_max_factor` times it; the stick level follows at
    /// the thresholds' ratio. Two multiplications and compares, once per slip.
    #[inline(always)]
    fn adapt(&mut self) {
        let th = &self.th;
        if th.onset_fraction <= 0.0 {
            return;
        }
        self.a_peak_mean = if self.a_peak_mean == 0.0 {
            self.a_peak
        } else {
            self.a_peak_mean + 0.25 * (self.a_peak - self.a_peak_mean)
        };
        let hi = th.onset_max_factor * th.slip_onset_m_s2;
        let want = th.onset_fraction * self.a_peak_mean;
        self.onset = if want > hi { hi } else if want > th.slip_onset_m_s2 { want } else { th.slip_onset_m_s2 };
        self.stick_max = self.onset * th.stick_ratio;
    }
}
