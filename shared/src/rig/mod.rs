//! The rig: from the ADC counts of one sample instant to stick-slip statistics, and the
//! sequencer of its two valves. Pure logic, tick-driven, `no_std`, no allocation: the firmware
//! calls it once per sample, the desktop tool and the tests call the same code.
//!
//! Signal path, one call per sample (fs = 25.6 kHz, six channels):
//!
//! ```text
//! Frame (6 x u16 counts)
//!   -> calibration::Calibrator::calibrate     4 accelerations [m/s^2], 2 pressures [bar], saturation
//!   -> estimator::Estimator::update           contact (stick/slip, v_r, events), groan band-pass,
//!                                             lockstep model, window statistics
//!   -> sequencer::Sequencer::tick             valve outputs, faults
//! ```
//!
//! [`pipeline::Rig`] strings the three together with what the rig does around them (the armed
//! lockstep model per record, timed phases without pressure transducers, per-window pressures,
//! the noise floor): the one per-sample chain, run by the firmware, the replay digests and the
//! host == Cortex-M4F cross-checks. The simulation harness, in its own folder
//! ([`crate::harness`]): `sensor_model::SensorModel` runs the other way (model
//! motion to counts) for tests and the virtual rig; `replay` digests a whole synthetic run
//! through the rig for the bit-identity test on the Cortex-M4F. The recorded-data tools (`sil`,
//! `analyze`) play their calibrated rows back through the same type
//! ([`pipeline::Rig::for_recording`], [`pipeline::Rig::play`]: the chain after the calibration,
//! without the sequencer): a recording has neither ADC words nor valves.
//!
//! Channel order in a [`calibration::Frame`]: the four accelerometers `disc_x`, `pad_x`,
//! `pad_trail`, `pad_lead` (the thesis's names, Table 3.1), then the actuator (normal-load) line
//! pressure and the band-drive cylinder line pressure.
//!
//! Modules:
//! - [`calibration`]: counts to SI, saturation flags; the inverse used by the sensor model.
//! - [`pneumatics`]: actuator pressure to normal load.
//! - [`geometry`]: where the pad's y accelerometers sit and which way they read.
//! - [`bandpass`]: Butterworth band-pass as a biquad cascade (bilinear transform).
//! - [`contact`]: stick/slip decision and relative velocity from the accelerations.
//! - [`lockstep`]: the model stepped alongside the measurement, its residual.
//! - [`noise_floor`]: each channel's bias and noise while nothing moves; the contact
//!   thresholds designed from it.
//! - [`window`]: per-window statistics.
//! - [`estimator`]: the per-sample analysis (contact, band-pass, lockstep, window).
//! - [`sequencer`]: the valve sequencer and its faults.
//! - [`pipeline`]: the rig, calibration + estimator + sequencer in one call per sample.

pub mod bandpass;
pub mod calibration;
pub mod contact;
pub mod estimator;
pub mod geometry;
pub mod health;
pub mod lockstep;
pub mod noise_floor;
pub mod pipeline;
pub mod pneumatics;
pub mod sequencer;
pub mod window;

/// The design constants (sample rate, window, accelerometer range) live in the leaf module
/// [`crate::design`]; re-exported here under their old paths for the rig's users.
pub use crate::design::{ACCEL_RANGE_M_S2, SAMPLE_RATE_HZ, WINDOW_S};

/// Accelerometer channels per frame.
pub const ACCEL_CHANNELS: usize = 4;
/// Pressure channels per frame.
pub const PRESSURE_CHANNELS: usize = 2;
/// Channels per frame.
pub const CHANNELS: usize = ACCEL_CHANNELS + PRESSURE_CHANNELS;

/// Frame / accelerometer index of the band's x accelerometer (`disc_x`).
pub const DISC_X: usize = 0;
/// Frame / accelerometer index of the pad's x accelerometer (`pad_x`).
pub const PAD_X: usize = 1;
/// Frame / accelerometer index of the y accelerometer near the pad's trailing edge (`pad_trail`).
pub const PAD_TRAIL: usize = 2;
/// Frame / accelerometer index of the y accelerometer near the pad's leading edge (`pad_lead`).
pub const PAD_LEAD: usize = 3;
/// Pressure index of the actuator (normal-load) line (frame index `ACCEL_CHANNELS + ACTUATOR`).
pub const ACTUATOR: usize = 0;
/// Pressure index of the band-drive cylinder line (frame index `ACCEL_CHANNELS + BAND`).
pub const BAND: usize = 1;

/// Accelerometer names, in frame order (as in the thesis's Table 3.1).
pub const ACCEL_NAMES: [&str; ACCEL_CHANNELS] = ["disc_x", "pad_x", "pad_trail", "pad_lead"];
/// Pressure channel names, in frame order.
pub const PRESSURE_NAMES: [&str; PRESSURE_CHANNELS] = ["actuator", "band"];

/// A rig configuration value that breaks a rule: which field, which rule, what value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConfigError {
    pub field: &'static str,
    pub rule: &'static str,
    pub value: f64,
}

impl core::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "rig setting `{}` = {}: {}", self.field, self.value, self.rule)
    }
}

/// `Ok` if `ok`, else the error naming `field`, `rule` and `value`.
pub(crate) fn check(ok: bool, field: &'static str, rule: &'static str, value: f64) -> Result<(), ConfigError> {
    if ok {
        Ok(())
    } else {
        Err(ConfigError { field, rule, value })
    }
}
