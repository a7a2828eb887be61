//! Channel health: is an accelerometer channel fit to decide stick from slip with? One rule for
//! the rig (the firmware's `health` record, per window of a record) and for `analyze` (its
//! "cannot decide" line), so that both say the same of the same signal.
//!
//! A channel is
//! - **flat**: no sample changed over the stretch (peak-to-peak 0): dead, unplugged, or a signal
//!   below one count of its converter;
//! - **saturated**: samples at the accelerometer's range or at an ADC rail;
//! - **noisier than the signal**: its RMS about the floor's mean is below
//!   [`NOISY_RMS_FACTOR`] times the noise sigma the floor measured (the signal's power is below
//!   3 times the noise's: a contact decision on it would be a guess).
//!
//! The band's accelerometer (disc_x) is never "noisier than the signal": a band that runs
//! steadily (or a rigid one) has no signal of its own, and its noise only widens a_rel's floor,
//! which the contact thresholds are designed from. The contact estimate (a_rel = pad_x -
//! disc_x, [`super::contact`]) cannot be decided when pad_x is any of the three, or when disc_x
//! is saturated. A flat disc_x does not stop it (a steady band below one count).

use super::{ACCEL_CHANNELS, DISC_X, PAD_X};

/// "Noisier than the signal": RMS (about the floor's mean) below this many noise sigmas.
pub const NOISY_RMS_FACTOR: f32 = 2.0;

/// What is wrong with one channel (bits; 0: nothing).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ChannelHealth(pub u8);

impl ChannelHealth {
    pub const FLAT: u8 = 1;
    pub const SATURATED: u8 = 2;
    pub const NOISY: u8 = 4;

    /// The health of a channel over a stretch: its peak-to-peak and RMS (about 0) [m/s^2],
    /// whether any sample was at the range, and the floor's mean and sigma [m/s^2] if a floor
    /// was measured (without one, "noisier than the signal" cannot be judged).
    pub fn assess(pp_m_s2: f32, rms_m_s2: f32, saturated: bool, floor_mean_sigma_m_s2: Option<(f32, f32)>) -> Self {
        let mut bits = 0;
        if pp_m_s2 == 0.0 {
            bits |= Self::FLAT;
        }
        if saturated {
            bits |= Self::SATURATED;
        }
        if let Some((mean, sigma)) = floor_mean_sigma_m_s2 {
            // RMS about the floor's mean: rms^2 - mean^2 (the mean square about 0 minus the
            // bias's share), not below 0
            let ac2 = (rms_m_s2 * rms_m_s2 - mean * mean).max(0.0);
            let limit = NOISY_RMS_FACTOR * sigma;
            if sigma > 0.0 && ac2 < limit * limit {
                bits |= Self::NOISY;
            }
        }
        ChannelHealth(bits)
    }

    pub fn ok(self) -> bool {
        self.0 == 0
    }
    pub fn flat(self) -> bool {
        self.0 & Self::FLAT != 0
    }
    pub fn saturated(self) -> bool {
        self.0 & Self::SATURATED != 0
    }
    pub fn noisy(self) -> bool {
        self.0 & Self::NOISY != 0
    }

    /// The words for each bit set, in the order flat, saturated, noisy.
    pub fn words(self) -> impl Iterator<Item = &'static str> {
        [(Self::FLAT, "flat"), (Self::SATURATED, "saturated"), (Self::NOISY, "noisier than the signal")]
            .into_iter()
            .filter(move |(b, _)| self.0 & b != 0)
            .map(|(_, w)| w)
    }
}

/// The channel health of the four accelerometers, with the contact verdict.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HealthReport {
    pub channels: [ChannelHealth; ACCEL_CHANNELS],
}

impl HealthReport {
    /// The report of four channels' [`ChannelHealth::assess`]: disc_x's noise verdict dropped
    /// (see the module documentation).
    pub fn new(mut channels: [ChannelHealth; ACCEL_CHANNELS]) -> Self {
        channels[DISC_X].0 &= !ChannelHealth::NOISY;
        HealthReport { channels }
    }

    /// Nothing wrong with any channel.
    pub fn ok(&self) -> bool {
        self.channels.iter().all(|c| c.ok())
    }

    /// The contact estimate cannot be decided on these channels (see the module documentation).
    pub fn undecidable(&self) -> bool {
        !self.channels[PAD_X].ok() || self.channels[DISC_X].saturated()
    }

    /// Bit `i` set where channel `i` has `bit` (one of [`ChannelHealth`]'s constants).
    pub fn mask(&self, bit: u8) -> u8 {
        self.channels.iter().enumerate().fold(0, |m, (i, c)| if c.0 & bit != 0 { m | 1 << i } else { m })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_kind_and_the_verdict() {
        let floor = Some((0.0, 0.1));
        // a signal 10 sigma strong: fine
        assert!(ChannelHealth::assess(3.0, 1.0, false, floor).ok());
        // dead
        assert!(ChannelHealth::assess(0.0, 0.0, false, floor).flat());
        // 1.5 sigma: noisier than the signal; 2.5 sigma is not
        assert!(ChannelHealth::assess(0.6, 0.15, false, floor).noisy());
        assert!(!ChannelHealth::assess(0.9, 0.25, false, floor).noisy());
        // a bias of 1 m/s^2 does not pass for a signal: rms 1.005 about 0 is 0.1 about the mean
        assert!(ChannelHealth::assess(0.6, 1.005, false, Some((1.0, 0.1))).noisy());
        // no floor: no noise verdict
        assert!(ChannelHealth::assess(0.6, 0.15, false, None).ok());
        assert!(ChannelHealth::assess(5.0, 2.0, true, floor).saturated());

        let mut h = HealthReport::default();
        assert!(h.ok() && !h.undecidable());
        h.channels[DISC_X] = ChannelHealth(ChannelHealth::FLAT);
        assert!(!h.ok() && !h.undecidable(), "a flat band alone decides");
        h.channels[DISC_X] = ChannelHealth(ChannelHealth::SATURATED);
        assert!(h.undecidable());
        let quiet_band = HealthReport::new([ChannelHealth(ChannelHealth::NOISY), ChannelHealth::default(), ChannelHealth::default(), ChannelHealth::default()]);
        assert!(quiet_band.ok(), "a band with no signal of its own is not reported");
        h.channels[DISC_X] = ChannelHealth::default();
        h.channels[DISC_X] = ChannelHealth::default();
        h.channels[PAD_X] = ChannelHealth(ChannelHealth::FLAT);
        assert!(h.undecidable());
        assert_eq!(h.mask(ChannelHealth::FLAT), 1 << PAD_X);
        assert_eq!(ChannelHealth(ChannelHealth::FLAT | ChannelHealth::NOISY).words().count(), 2);
    }
}
