//! ADC counts to SI units, and the saturation flags.
//!
//! **Accelerometers** (Type 4508 class: 100 mV/g, range 700 m/s^2, IEPE). The front end removes
//! the IEPE bias, applies a voltage gain G and shifts zero acceleration to `offset_counts`
//! (mid-scale, 2048 for 12 bits). With sensitivity S = (mV/g) 1e-3 / 9.80665 [V per m/s^2] and
//! an ADC of reference V_ref and b bits (one count = V_ref / 2^b volts):
//!
//! ```text
//! count = offset + a S G 2^b / V_ref            (the ADC, rounded to the nearest count)
//! a     = (count - offset) * V_ref / (2^b S G)  [m/s^2]
//! ```
//!
//! **Pressure transducers** (linear): the transducer gives `zero_v` at 0 bar (gauge) and
//! `full_scale_v` at `full_scale_bar`; the front end scales it by `front_end_gain` to the ADC pin:
//!
//! ```text
//! pin volts = G (zero_v + p (full_scale_v - zero_v) / full_scale_bar)
//! p         = (count - c0) * V_ref / (2^b G span_v_per_bar),   c0 = G zero_v 2^b / V_ref
//! ```
//!
//! Every channel is therefore `value = (count - offset) * scale`, with `offset` and `scale`
//! worked out once in f64 and rounded to f32: two operations per channel and sample.
//!
//! **Saturation flags.** *Range*: the accelerometer reached its measuring range, |a| >= 700
//! m/s^2. It is tested on counts, against the counts the ADC returns for +-700 m/s^2, so a
//! sensor clipped exactly at its range is flagged whatever the rounding. *Rail*: a channel sits
//! at an ADC rail (count 0 or 2^b - 1, or a count above the ADC's span, which a real ADC cannot
//! produce). With the default front-end gain the ADC spans about +-809 m/s^2, so the range flag
//! fires before the rails; with a higher gain (more resolution) the rails come first and the
//! range flag can never fire.
//!
//! **Oversampling** ([`Adc::oversample`] = N, 1 to 16). The firmware converts each channel N
//! times per frame (the regular sequence triggered at N fs) and a frame's count is the *sum* of
//! the N conversions (the decimation: a boxcar of N at N fs, then one sample in N; its first
//! null is at fs, its gain at 500 Hz is 1 - 2e-4 for N = 4 at fs = 25.6 kHz; the anti-alias is
//! the sensors' own 8 kHz bandwidth and the front end's low-pass below fs / 2). A frame count
//! spans 0 to N (2^b - 1); every formula above holds for it with the count and the offset
//! multiplied by N: the calibrator uses N offset and scale / N, the range flags N times a
//! conversion's range count, the rails 0 and N (2^b - 1). With N = 1 (the default) nothing
//! changes, bit for bit. The sum gains resolution only where the converter's own noise dithers
//! the N conversions (the sensor's noise, band-limited to 8 kHz, is nearly the same in all N):
//! `sil --oversample N --adc-noise C` measures it.

use super::{check, ConfigError, ACCEL_CHANNELS, CHANNELS, PRESSURE_CHANNELS};

/// Standard gravity [m/s^2], the g of a sensitivity given in mV/g.
pub const STANDARD_GRAVITY: f64 = 9.806_65;

/// The raw counts of one sample instant: `disc_x`, `pad_x`, `pad_trail`, `pad_lead`, actuator
/// pressure, band pressure (see [`super`] for the indices).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Frame {
    pub counts: [u16; CHANNELS],
}

/// Saturation flags of one frame: bit `i` (0..4) range of accelerometer `i`, bit `4 + j`
/// (0..6) rail of frame channel `j`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Saturation {
    pub bits: u16,
}

impl Saturation {
    const RANGE_MASK: u16 = (1 << ACCEL_CHANNELS) - 1;
    const RAIL_SHIFT: u32 = ACCEL_CHANNELS as u32;
    /// Rails of the accelerometer channels.
    const ACCEL_RAIL_MASK: u16 = ((1 << ACCEL_CHANNELS) - 1) << ACCEL_CHANNELS;

    /// Accelerometer `i` at its measuring range.
    pub fn range(self, i: usize) -> bool {
        i < ACCEL_CHANNELS && self.bits & (1 << i) != 0
    }
    /// Frame channel `j` at an ADC rail.
    pub fn rail(self, j: usize) -> bool {
        j < CHANNELS && self.bits & (1 << (Self::RAIL_SHIFT as usize + j)) != 0
    }
    /// Any accelerometer at its range or at a rail.
    #[inline(always)]
    pub fn any_accel(self) -> bool {
        self.bits & (Self::RANGE_MASK | Self::ACCEL_RAIL_MASK) != 0
    }
    /// Any flag at all.
    pub fn any(self) -> bool {
        self.bits != 0
    }
}

/// One calibrated frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Calibrated {
    /// `disc_x`, `pad_x`, `pad_trail`, `pad_lead` [m/s^2].
    pub accel_m_s2: [f32; ACCEL_CHANNELS],
    /// Actuator line, band line [bar] (gauge).
    pub pressure_bar: [f32; PRESSURE_CHANNELS],
    pub saturation: Saturation,
}

/// The analog-to-digital converter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adc {
    /// Reference voltage: the input of the (non-existent) count 2^bits [V].
    pub vref_v: f64,
    /// Resolution [bits], 1..=16.
    pub bits: u32,
    /// Conversions summed per frame, 1..=16, with oversample (2^bits - 1) <= 65535 (see the
    /// module documentation; 1: none).
    pub oversample: u32,
}

impl Adc {
    /// The rig's STM32F4 ADC: 12 bits on a 3.3 V reference.
    pub const RIG: Adc = Adc { vref_v: 3.3, bits: 12, oversample: 1 };

    pub fn validate(&self) -> Result<(), ConfigError> {
        check(self.vref_v.is_finite() && self.vref_v > 0.0, "adc.vref_v", "reference must be > 0 V", self.vref_v)?;
        check(self.bits >= 1 && self.bits <= 16, "adc.bits", "resolution must be 1..=16 bits", self.bits as f64)?;
        check(
            self.oversample >= 1 && self.oversample <= 16 && self.oversample * self.max_count() as u32 <= u16::MAX as u32,
            "adc.oversample",
            "must be 1..=16 with oversample x (2^bits - 1) <= 65535",
            self.oversample as f64,
        )
    }
    /// The top of a frame count (the sum of `oversample` conversions at the upper rail).
    pub fn frame_max_count(&self) -> u16 {
        (self.oversample.clamp(1, 16) * self.max_count() as u32).min(u16::MAX as u32) as u16
    }
    /// The frame count of `oversample` equal conversions of `count`.
    pub fn frame_count(&self, count: u16) -> u16 {
        (self.oversample.clamp(1, 16) * count as u32).min(u16::MAX as u32) as u16
    }
    /// Volts per count, V_ref / 2^bits [V].
    pub fn volts_per_count(&self) -> f64 {
        self.vref_v / (1u32 << self.bits.min(16)) as f64
    }
    /// The top count (the upper rail), 2^bits - 1.
    pub fn max_count(&self) -> u16 {
        ((1u32 << self.bits.min(16)) - 1) as u16
    }
    /// The count for a voltage at the ADC pin: nearest count (half up), clamped to the rails.
    pub fn count_for_volts(&self, volts: f64) -> u16 {
        count_from_fractional(volts / self.volts_per_count(), self.max_count() as f64)
    }
}

/// Nearest count (half up) to a fractional count, clamped to [0, max]; NaN gives 0.
#[inline(always)]
pub(crate) fn count_from_fractional(c: f64, max: f64) -> u16 {
    let c = if c > max { max } else { c };
    if !(c > 0.0) {
        return 0;
    }
    (c + 0.5) as u16
}

/// One accelerometer channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AccelChannel {
    /// Sensitivity [mV/g], g = 9.80665 m/s^2 (100 for a Type 4508).
    pub sensitivity_mv_per_g: f64,
    /// Front-end voltage gain from the sensor output to the ADC pin [V/V].
    pub front_end_gain: f64,
    /// ADC count at zero acceleration [counts]; may be fractional (a measured offset).
    pub offset_counts: f64,
    /// Measuring range of the sensor, +- [m/s^2] (700 for a Type 4508).
    pub range_m_s2: f64,
}

impl AccelChannel {
    /// A Type 4508-class accelerometer on the rig's front end: 100 mV/g, +-700 m/s^2, gain 0.2,
    /// zero at mid-scale (the ADC then spans about +-809 m/s^2, 0.395 m/s^2 per count).
    pub const RIG: AccelChannel =
        AccelChannel { sensitivity_mv_per_g: 100.0, front_end_gain: 0.2, offset_counts: 2048.0, range_m_s2: crate::design::ACCEL_RANGE_M_S2 };

    /// Sensitivity S [V per m/s^2].
    pub fn sensitivity_v_per_m_s2(&self) -> f64 {
        self.sensitivity_mv_per_g * 1e-3 / STANDARD_GRAVITY
    }
    /// Counts per m/s^2 at the ADC: S G / (volts per count).
    pub fn counts_per_m_s2(&self, adc: &Adc) -> f64 {
        self.sensitivity_v_per_m_s2() * self.front_end_gain / adc.volts_per_count()
    }
    /// The count the ADC returns for an acceleration [m/s^2] (no clipping at the sensor range).
    pub fn count_for(&self, adc: &Adc, a_m_s2: f64) -> u16 {
        count_from_fractional(self.offset_counts + a_m_s2 * self.counts_per_m_s2(adc), adc.max_count() as f64)
    }

    /// The frame counts of -range and +range (lo, hi): each rounded like the ADC rounds (half
    /// up), times the conversions summed per frame. They may lie outside the ADC span.
    pub fn range_counts(&self, adc: &Adc) -> (i32, i32) {
        let cpu = self.counts_per_m_s2(adc);
        let at = |a: f64| adc.oversample as i32 * libm::floor(self.offset_counts + a * cpu + 0.5) as i32;
        (at(-self.range_m_s2), at(self.range_m_s2))
    }

    fn validate(&self, adc: &Adc) -> Result<(), ConfigError> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        check(
            ok(self.sensitivity_mv_per_g),
            "accel.sensitivity_mv_per_g",
            "must be > 0 mV/g",
            self.sensitivity_mv_per_g,
        )?;
        check(ok(self.front_end_gain), "accel.front_end_gain", "must be > 0", self.front_end_gain)?;
        check(ok(self.range_m_s2), "accel.range_m_s2", "must be > 0 m/s^2", self.range_m_s2)?;
        check(
            self.offset_counts.is_finite() && self.offset_counts >= 0.0 && self.offset_counts <= adc.max_count() as f64,
            "accel.offset_counts",
            "zero must lie inside the ADC span",
            self.offset_counts,
        )
    }
}

/// One pressure channel (a linear transducer and its front end).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PressureChannel {
    /// Transducer output at 0 bar (gauge) [V].
    pub zero_v: f64,
    /// Transducer output at `full_scale_bar` [V].
    pub full_scale_v: f64,
    /// Pressure of `full_scale_v` [bar].
    pub full_scale_bar: f64,
    /// Front-end voltage gain from the transducer output to the ADC pin [V/V].
    pub front_end_gain: f64,
}

impl PressureChannel {
    /// A 0..10 bar, 1..5 V transducer through a 0.6 divider: 0.6 V to 3.0 V at the pin,
    /// 0.24 V/bar, 0.00336 bar per count. A broken wire (0 V) reads -2.5 bar.
    pub const RIG: PressureChannel =
        PressureChannel { zero_v: 1.0, full_scale_v: 5.0, full_scale_bar: 10.0, front_end_gain: 0.6 };

    /// Volts at the ADC pin per bar.
    pub fn pin_volts_per_bar(&self) -> f64 {
        self.front_end_gain * (self.full_scale_v - self.zero_v) / self.full_scale_bar
    }
    /// The count at 0 bar (fractional).
    pub fn zero_counts(&self, adc: &Adc) -> f64 {
        self.front_end_gain * self.zero_v / adc.volts_per_count()
    }
    /// The count the ADC returns for a pressure [bar].
    pub fn count_for(&self, adc: &Adc, bar: f64) -> u16 {
        let c = self.zero_counts(adc) + bar * self.pin_volts_per_bar() / adc.volts_per_count();
        count_from_fractional(c, adc.max_count() as f64)
    }

    fn validate(&self) -> Result<(), ConfigError> {
        let fin = |v: f64| v.is_finite();
        check(fin(self.zero_v), "pressure.zero_v", "must be a finite voltage", self.zero_v)?;
        check(fin(self.full_scale_v), "pressure.full_scale_v", "must be a finite voltage", self.full_scale_v)?;
        check(
            fin(self.full_scale_bar) && self.full_scale_bar > 0.0,
            "pressure.full_scale_bar",
            "must be > 0 bar",
            self.full_scale_bar,
        )?;
        check(
            fin(self.front_end_gain) && self.front_end_gain > 0.0,
            "pressure.front_end_gain",
            "must be > 0",
            self.front_end_gain,
        )?;
        check(self.full_scale_v != self.zero_v, "pressure.full_scale_v", "span must not be 0 V", self.full_scale_v)
    }
}

/// The calibration of the whole rig: the ADC and the six channels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Calibration {
    pub adc: Adc,
    pub accel: [AccelChannel; ACCEL_CHANNELS],
    pub pressure: [PressureChannel; PRESSURE_CHANNELS],
}

/// The rig's nominal calibration ([`AccelChannel::RIG`], [`PressureChannel::RIG`], [`Adc::RIG`]).
pub const RIG_CALIBRATION: Calibration = Calibration {
    adc: Adc::RIG,
    accel: [AccelChannel::RIG; ACCEL_CHANNELS],
    pressure: [PressureChannel::RIG; PRESSURE_CHANNELS],
};

impl Default for Calibration {
    fn default() -> Self {
        RIG_CALIBRATION
    }
}

impl Calibration {
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.adc.validate()?;
        for a in &self.accel {
            a.validate(&self.adc)?;
        }
        for p in &self.pressure {
            p.validate()?;
        }
        Ok(())
    }
}

/// The per-sample form of a [`Calibration`]: f32 offsets and scales, count thresholds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Calibrator {
    /// value = (count - offset) * scale, per frame channel.
    offset: [f32; CHANNELS],
    scale: [f32; CHANNELS],
    /// Range flags, count >= range_hi or count <= range_lo (the counts of +-range, which may
    /// lie outside the ADC span: then the flag cannot fire), as one unsigned comparison per
    /// channel ([`range_test`]): flagged iff count - `range_from`, wrapped, >= `range_span`.
    range_from: [u32; ACCEL_CHANNELS],
    range_span: [u32; ACCEL_CHANNELS],
    /// Rail flags, count == 0 or count >= the frame's top count, as one comparison: count - 1,
    /// wrapped, >= `rail_span` (the top count - 1).
    rail_span: u32,
}

/// The range flag's one comparison for the bounds `lo`, `hi` (flag: count <= lo or count >=
/// hi): (`from`, `span`) such that a count c in 0..=65535 is flagged iff
/// `c.wrapping_sub(from) >= span`. The bounds are first clamped to -1..=65536 (the same flags
/// for every u16 count); then from = lo + 1 (0..=65537) and span = hi - lo - 1, at least 0: a
/// count below `from` wraps to at least 2^32 - 65537, above any span.
pub(crate) fn range_test(lo: i32, hi: i32) -> (u32, u32) {
    let lo = lo.clamp(-1, 65_536);
    let hi = hi.clamp(-1, 65_536);
    ((lo + 1) as u32, (hi - lo - 1).max(0) as u32)
}

impl Calibrator {
    pub fn new(cal: &Calibration) -> Result<Self, ConfigError> {
        cal.validate()?;
        let adc = &cal.adc;
        let vpc = adc.volts_per_count();
        // frame counts are sums of n conversions (1: the conversions themselves, bit for bit)
        let n = adc.oversample as f64;
        let mut offset = [0.0f32; CHANNELS];
        let mut scale = [0.0f32; CHANNELS];
        let mut range_from = [0u32; ACCEL_CHANNELS];
        let mut range_span = [0u32; ACCEL_CHANNELS];
        for (i, a) in cal.accel.iter().enumerate() {
            let cpu = a.counts_per_m_s2(adc);
            offset[i] = (n * a.offset_counts) as f32;
            scale[i] = (1.0 / (n * cpu)) as f32;
            // the counts of +-range, rounded like the ADC rounds (half up), n of them
            let (lo, hi) = a.range_counts(adc);
            (range_from[i], range_span[i]) = range_test(lo, hi);
        }
        for (j, p) in cal.pressure.iter().enumerate() {
            offset[ACCEL_CHANNELS + j] = (n * p.zero_counts(adc)) as f32;
            scale[ACCEL_CHANNELS + j] = (vpc / (n * p.pin_volts_per_bar())) as f32;
        }
        Ok(Calibrator { offset, scale, range_from, range_span, rail_span: u32::from(adc.frame_max_count()).saturating_sub(1) })
    }

    /// m/s^2 (accelerometers) or bar (pressures) per frame count, per frame channel.
    pub fn scale(&self) -> &[f32; CHANNELS] {
        &self.scale
    }
    /// The resolution of a_rel = pad_x - disc_x [m/s^2]: the larger count of the two (what
    /// [`super::estimator::Estimator::finish_floor`] designs the onset's floor of 2 quanta from).
    pub fn a_rel_quantum_m_s2(&self) -> f32 {
        self.scale[super::PAD_X].max(self.scale[super::DISC_X])
    }
    /// Counts at zero, per frame channel.
    pub fn offset(&self) -> &[f32; CHANNELS] {
        &self.offset
    }

    /// Calibrates one frame: (count - offset) * scale per channel, and the saturation flags.
    #[inline]
    #[allow(clippy::needless_range_loop)] // parallel per-channel arrays
    pub fn calibrate(&self, frame: &Frame) -> Calibrated {
        let c = &frame.counts;
        let mut out = Calibrated::default();
        let mut bits = 0u16;
        for i in 0..ACCEL_CHANNELS {
            out.accel_m_s2[i] = (c[i] as f32 - self.offset[i]) * self.scale[i];
            if u32::from(c[i]).wrapping_sub(self.range_from[i]) >= self.range_span[i] {
                bits |= 1 << i;
            }
        }
        for j in 0..PRESSURE_CHANNELS {
            let k = ACCEL_CHANNELS + j;
            out.pressure_bar[j] = (c[k] as f32 - self.offset[k]) * self.scale[k];
        }
        for (j, &cj) in c.iter().enumerate() {
            if u32::from(cj).wrapping_sub(1) >= self.rail_span {
                bits |= 1 << (ACCEL_CHANNELS + j);
            }
        }
        out.saturation = Saturation { bits };
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The calibrator's one-comparison range and rail flags against the two comparisons they
    /// stand for (count <= lo or count >= hi; count == 0 or count >= the top count), for every
    /// u16 count: the rig's channel, oversampled, a gain whose range passes the ADC's span, one
    /// whose range lies inside it off-centre, and bounds past the u16 span either way.
    #[test]
    fn one_comparison_flags_are_the_two_comparisons() {
        let settings = [(0.2, 2048.0, 1), (0.2, 2048.0, 4), (2.0, 2048.0, 16), (0.05, 1000.0, 1), (0.2, 0.0, 1), (0.2, 4095.0, 3)];
        let cals = settings.map(|(gain, offset, oversample)| {
            let mut c = RIG_CALIBRATION;
            c.adc.oversample = oversample;
            for a in c.accel.iter_mut() {
                a.front_end_gain = gain;
                a.offset_counts = offset;
            }
            c
        });
        for cal in &cals {
            let k = Calibrator::new(cal).unwrap();
            let top = cal.adc.frame_max_count();
            let (lo, hi) = cal.accel[0].range_counts(&cal.adc);
            for c in 0..=u16::MAX {
                let frame = Frame { counts: [c; CHANNELS] };
                let bits = k.calibrate(&frame).saturation.bits;
                let range = i32::from(c) <= lo || i32::from(c) >= hi;
                let rail = c == 0 || c >= top;
                assert_eq!(bits & 1 != 0, range, "count {c}, range {lo}..{hi}");
                assert_eq!(bits & (1 << ACCEL_CHANNELS) != 0, rail, "count {c}, top {top}");
            }
        }
        // bounds past the u16 span, and empty ranges
        for (lo, hi) in [(-70_000, 70_000), (-5, 3), (100, 101), (100, 100), (200, 100), (65_535, 65_540), (-1, 0), (i32::MIN, i32::MAX)] {
            let (from, span) = range_test(lo, hi);
            for c in 0..=u16::MAX {
                let want = i32::from(c) <= lo || i32::from(c) >= hi;
                assert_eq!(u32::from(c).wrapping_sub(from) >= span, want, "count {c}, bounds {lo}, {hi}");
            }
        }
    }
}
