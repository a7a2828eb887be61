//! Stick or slip, sample by sample, from the accelerations alone; and the relative velocity.
//!
//! Input: the relative acceleration of pad and band, a_rel = pad_x - disc_x [m/s^2]. Output:
//! the contact regime (the model's [`Regime`]), the relative velocity v_r = pad - band [m/s],
//! and events with their sample index.
//!
//! **What the model says the signal looks like** (docs/model.md). In stick the pad moves with
//! the band: a_rel = 0 exactly, whatever the rotation does. At breakaway the friction drops from
//! mu_s N to mu_k N at once, so a_rel jumps from 0 to about -(mu_s - mu_k) N / m (20 to 48 m/s^2
//! for the six default cases; negative: the pad falls behind). During the slip a_rel swings
//! through zero at the velocity minimum, where |v_r| is largest (about 0.04 m/s), and at the
//! re-stick it is back near +(mu_s - mu_k) N / m when v_r reaches zero, then drops to 0.
//!
//! **Decision, per sample (dt = 1 / fs):**
//! - Stick -> slip when |a| > `slip_onset` (a = a_rel minus the tracked bias). The sign of a
//!   gives the direction: a < 0 the pad falls behind (slip, pad slower), a > 0 it runs ahead.
//!   v_r starts from the trapezoid over the last interval, dt/2 (a[-1] + a).
//! - In slip v_r is integrated by the trapezoid rule. Slip -> stick when |a| <= `stick_max`
//!   (the acceleration has dropped to the stick level) *and* v_r has come back to zero within
//!   `v_tol`, judged on both the trapezoid v_r and the Euler extrapolation v_r[-1] + dt a[-1]
//!   (the trapezoid alone under-shoots by up to a dt / 2 when the re-stick falls late in the
//!   interval, because a drops to 0 at the re-stick). In mid-slip |a| is small only where
//!   |v_r| is largest, so the pair of conditions cannot be met there.
//!   Once v_r has come back to zero it may run on through it by a small drift (an uncorrected
//!   offset on a_rel integrates over the slip): the slip stays ready to stick as long as v_r
//!   has not gone beyond zero by `v_reversal`.
//! - v_r going through zero by more than `v_reversal` while |a| stays above `stick_max` is a
//!   reversal (slip pad slower <-> slip pad faster), the model's fourth case, reported
//!   `v_reversal / J` samples late at most.
//! - Drift guard: `stall_samples` consecutive samples of |a| <= `stick_max` in slip end it
//!   whatever v_r says (a slip of this model changes its acceleration by more than the threshold
//!   within a fraction of its 130 Hz period; without the guard a drifted v_r could hold the
//!   estimator in slip for good). Steady sliding without oscillation cannot be told from stick
//!   by accelerometers at all.
//! - Zero-velocity update: in stick v_r is set to 0, and the mean of a_rel (true value 0) is
//!   tracked as the accelerometers' bias with a first-order filter of gain `bias_gain` per
//!   sample; it is subtracted from a_rel everywhere, so an offset error does not integrate into
//!   v_r during the slips.
//!
//! **Thresholds** ([`ContactThresholds::from_breakaway_jump`]): `slip_onset` = J / 2 and
//! `stick_max` = J / 4 with J = (mu_s - mu_k) N / m the breakaway jump. The onset then fires at
//! the first sample after breakaway (|a| starts at J and stays above J / 2 for a quarter of the
//! slip), with a margin of J / 2 over the stick noise. The re-stick asks for |a| <= J / 4: the
//! acceleration has fallen from about J to the stick level (the gap between J / 4 and J / 2 is
//! the hysteresis). Noise and quantisation on a_rel must stay below J / 4 (about 5 m/s^2 for
//! the softest default case): two channels of
//! 0.5 m/s^2 rms noise bounded at 3.46 sigma, plus one count (0.395 m/s^2), give 3.9 m/s^2.
//! `v_tol` = 2 J dt (the velocity two samples of the re-stick acceleration build) and
//! `v_reversal` = 8 J dt, both far below the slip's peak |v_r| of 0.02 to 0.05 m/s. Per sample:
//! no division, no square root.
//!
//! The bias tracking matters. Measured on the six cases (1 s each): without it, a zero error of
//! 5 counts (2 m/s^2) on `pad_x` puts up to 32 % of the samples in the wrong regime (the
//! drifted v_r passes `v_reversal` before the re-stick, and the drift guard ends the slip 5 ms
//! late); with it, zero errors up to +-10 counts leave every sample right and +-20 counts
//! (8 m/s^2) at most 0.5 %.

use crate::scene::Scene;
use crate::stickslip::Regime;

/// The smallest breakaway jump [`ContactThresholds::for_scene`] designs for [m/s^2]: onset
/// 4 m/s^2, stick 2 m/s^2 (10 and 5 counts of the rig's accelerometers).
pub const MIN_DESIGN_JUMP_M_S2: f64 = 8.0;

/// The thresholds of the stick/slip decision (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactThresholds {
    /// |a_rel| above which a sticking pad is taken to slip [m/s^2].
    pub slip_onset_m_s2: f32,
    /// |a_rel| at or below which a slipping pad back at v_r = 0 is taken to stick [m/s^2].
    pub stick_max_m_s2: f32,
    /// v_r counts as back at zero for the re-stick within this of it, on the slip's side [m/s].
    pub v_tol_m_s: f32,
    /// v_r beyond zero by more than this, with |a_rel| above `stick_max`, is a reversal [m/s].
    pub v_reversal_m_s: f32,
    /// Consecutive quiet samples that end a slip whatever v_r says (0: never).
    pub stall_samples: u32,
    /// Gain per sample of the bias tracker in stick [-] (0: no bias tracking).
    pub bias_gain: f32,
}

impl ContactThresholds {
    /// Thresholds for a breakaway jump of `jump_m_s2` [m/s^2] at the sampling rate `fs_hz`:
    /// onset J / 2, stick J / 4, v_tol 2 J dt, v_reversal 8 J dt, drift guard 5 ms, bias time
    /// constant 256 samples.
    pub fn from_breakaway_jump(jump_m_s2: f64, fs_hz: f64) -> Self {
        let dt = 1.0 / fs_hz;
        ContactThresholds {
            slip_onset_m_s2: (0.5 * jump_m_s2) as f32,
            stick_max_m_s2: (0.25 * jump_m_s2) as f32,
            v_tol_m_s: (2.0 * jump_m_s2 * dt) as f32,
            v_reversal_m_s: (8.0 * jump_m_s2 * dt) as f32,
            stall_samples: libm::ceil(5e-3 * fs_hz) as u32,
            bias_gain: 1.0 / 256.0,
        }
    }

    /// The breakaway jump of a scene at its static normal force, J = (mu_s - mu_k) N0 / m
    /// [m/s^2].
    pub fn breakaway_jump(scene: &Scene) -> f64 {
        let n0 = crate::coefficients::Coefficients::of(scene).n0;
        (scene.mu_s - scene.mu_k) * n0 / scene.m
    }

    /// [`Self::from_breakaway_jump`] with the jump of `scene`, but at least
    /// [`MIN_DESIGN_JUMP_M_S2`] (a scene with mu_k = mu_s has no jump at all: its breakaway is
    /// then seen when |a_rel| grows past 4 m/s^2).
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
}

/// The stick/slip estimator (see the module documentation).
#[derive(Clone, Copy, Debug)]
pub struct ContactEstimator {
    th: ContactThresholds,
    dt: f32,
    half_dt: f32,
    regime: Regime,
    v_r: f32,
    a_prev: f32,
    bias: f32,
    quiet: u32,
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
            a_prev: 0.0,
            bias: 0.0,
            quiet: 0,
            sample: 0,
        }
    }

    pub fn thresholds(&self) -> &ContactThresholds {
        &self.th
    }
    pub fn regime(&self) -> Regime {
        self.regime
    }
    /// The tracked bias of a_rel [m/s^2].
    pub fn bias_m_s2(&self) -> f32 {
        self.bias
    }
    /// Index of the next sample.
    pub fn samples(&self) -> u64 {
        self.sample
    }

    /// Takes one sample of a_rel = pad_x - disc_x [m/s^2] (finite: the caller checks).
    #[inline]
    pub fn update(&mut self, a_rel_m_s2: f32) -> ContactSample {
        let th = &self.th;
        let a = a_rel_m_s2 - self.bias;
        let abs_a = a.abs();
        let mut event = None;
        match self.regime {
            Regime::Stick => {
                if abs_a > th.slip_onset_m_s2 {
                    self.regime = if a < 0.0 { Regime::SlipSlower } else { Regime::SlipFaster };
                    self.v_r = self.half_dt * (self.a_prev + a);
                    self.quiet = 0;
                    event = Some(ContactEventKind::StickToSlip);
                } else {
                    self.bias += th.bias_gain * a;
                    self.v_r = 0.0;
                }
            }
            Regime::SlipSlower | Regime::SlipFaster => {
                // s = sign of v_r in this slip
                let s = if self.regime == Regime::SlipSlower { -1.0f32 } else { 1.0f32 };
                let v_new = self.v_r + self.half_dt * (self.a_prev + a);
                let euler = self.v_r + self.dt * self.a_prev;
                let quiet = abs_a <= th.stick_max_m_s2;
                self.quiet = if quiet { self.quiet.saturating_add(1) } else { 0 };
                let back_at_zero = s * v_new <= th.v_tol_m_s || s * euler <= th.v_tol_m_s;
                let stalled = th.stall_samples > 0 && self.quiet >= th.stall_samples;
                if quiet && (back_at_zero || stalled) {
                    self.regime = Regime::Stick;
                    self.v_r = 0.0;
                    event = Some(ContactEventKind::SlipToStick);
                } else if s * v_new < -th.v_reversal_m_s {
                    self.regime = if s < 0.0 { Regime::SlipFaster } else { Regime::SlipSlower };
                    self.v_r = v_new;
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
        }
    }
}
