//! The rig's design constants: the values that every layer of the model crate may read (the
//! scenes' default step, the per-sample chain, the simulation harness, the desktop tool and the
//! firmware). A leaf: it imports nothing.

/// The rig's sampling rate per channel [Hz]: the one design value that the firmware (its ADC
/// trigger), the model's default step (`DEFAULT_SCENE.dt`) and the desktop tool read.
pub const SAMPLE_RATE_HZ: f64 = 25_600.0;
/// The window of the rig's statistics [s]: the firmware's `window` records, the estimator's
/// default (`window::DEFAULT_WINDOW_SAMPLES` at [`SAMPLE_RATE_HZ`]) and `analyze`'s windows.
pub const WINDOW_S: f64 = 0.1;
/// The accelerometers' measuring range, +- [m/s^2] (a Type 4508: 700): the calibration's
/// default and the recorded-data analysis's saturation mark.
pub const ACCEL_RANGE_M_S2: f64 = 700.0;
