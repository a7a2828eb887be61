//! Calibration against counts worked out by hand from the data-sheet figures, and the
//! saturation flags at both rails and at the sensor's range (700 m/s^2).
//!
//! Hand figures (rig defaults): one count = 3.3 V / 4096 = 0.0008056640625 V. Accelerometer
//! 100 mV/g through a gain of 0.2: 1 g -> 0.1 V -> 0.02 V at the pin -> 24.824 counts above the
//! mid-scale 2048, so +1 g reads count 2073 and -1 g count 2023. 700 m/s^2 = 71.380 g -> 1.42760 V
//! -> 1772.0 counts -> count 3820 (and 276 for -700). Pressure transducer 1..5 V for 0..10 bar
//! through 0.6: 0 bar -> 0.6 V -> 744.73 -> count 745; 5 bar -> 1.8 V -> 2234.18 -> count 2234.

use stickslip_model::rig::calibration::{
    AccelChannel, Adc, Calibration, Calibrator, Frame, PressureChannel, RIG_CALIBRATION, STANDARD_GRAVITY,
};
use stickslip_model::rig::{ACCEL_CHANNELS, CHANNELS, PAD_X};

const VOLT_PER_COUNT: f64 = 3.3 / 4096.0;

fn frame_with(channel: usize, count: u16) -> Frame {
    // everything else at a quiet mid-scale / 5 bar
    let mut f = Frame { counts: [2048, 2048, 2048, 2048, 2234, 2234] };
    f.counts[channel] = count;
    f
}

#[test]
fn one_g_gives_the_hand_computed_count_and_back() {
    let adc = Adc::RIG;
    let ch = AccelChannel::RIG;
    assert_eq!(ch.count_for(&adc, STANDARD_GRAVITY), 2073);
    assert_eq!(ch.count_for(&adc, -STANDARD_GRAVITY), 2023);
    assert_eq!(ch.count_for(&adc, 0.0), 2048);
    // a gain of 1: 0.1 V = 124.12 counts
    let g1 = AccelChannel { front_end_gain: 1.0, ..ch };
    assert_eq!(g1.count_for(&adc, STANDARD_GRAVITY), 2172);

    let cal = Calibrator::new(&RIG_CALIBRATION).unwrap();
    // count 2073 is 25 counts = 25 x 0.805664 mV at the pin = 0.0201416 V / 0.2 = 0.100708 V
    // at the sensor = 1.00708 g
    let expected = 25.0 * VOLT_PER_COUNT / 0.2 / 0.1 * 9.80665;
    for i in 0..ACCEL_CHANNELS {
        let c = cal.calibrate(&frame_with(i, 2073));
        let a = c.accel_m_s2[i] as f64;
        assert!((a - expected).abs() < 1e-5 * expected, "channel {i}: {a} vs {expected}");
        assert_eq!(c.saturation.bits, 0);
        let c = cal.calibrate(&frame_with(i, 2023));
        assert!((c.accel_m_s2[i] as f64 + expected).abs() < 1e-5 * expected);
    }
    // mid-scale is exactly zero
    assert_eq!(cal.calibrate(&frame_with(PAD_X, 2048)).accel_m_s2[PAD_X], 0.0);
}

#[test]
fn round_trip_is_within_half_a_count_over_the_range() {
    let cal = Calibrator::new(&RIG_CALIBRATION).unwrap();
    let ch = AccelChannel::RIG;
    let lsb = VOLT_PER_COUNT / (0.2 * 0.1 / 9.80665); // m/s^2 per count, by hand
    for k in -700..=700 {
        let a = k as f64 * 0.997;
        let c = ch.count_for(&Adc::RIG, a);
        let back = cal.calibrate(&frame_with(0, c)).accel_m_s2[0] as f64;
        assert!((back - a).abs() <= 0.5 * lsb * (1.0 + 1e-6), "{a} -> {c} -> {back}");
    }
}

#[test]
fn pressures_from_hand_computed_counts() {
    let adc = Adc::RIG;
    let p = PressureChannel::RIG;
    assert_eq!(p.count_for(&adc, 0.0), 745);
    assert_eq!(p.count_for(&adc, 5.0), 2234);
    let cal = Calibrator::new(&RIG_CALIBRATION).unwrap();
    let c = cal.calibrate(&frame_with(4, 2234));
    // 2234 counts = 1.79985 V at the pin; (1.79985 - 0.6) / 0.24 bar
    let expected = (2234.0 * VOLT_PER_COUNT - 0.6) / 0.24;
    assert!((c.pressure_bar[0] as f64 - expected).abs() < 1e-5, "{} vs {expected}", c.pressure_bar[0]);
    assert!((expected - 5.0).abs() < 0.5 * VOLT_PER_COUNT / 0.24);
    let c = cal.calibrate(&frame_with(5, 745));
    let expected = (745.0 * VOLT_PER_COUNT - 0.6) / 0.24;
    assert!((c.pressure_bar[1] as f64 - expected).abs() < 1e-5);
    // a broken wire reads 0 V: -2.5 bar (and a rail)
    let c = cal.calibrate(&frame_with(4, 0));
    assert!((c.pressure_bar[0] as f64 + 2.5).abs() < 1e-5);
    assert!(c.saturation.rail(4));
}

#[test]
fn range_flag_at_700_m_s2_both_signs() {
    let cal = Calibrator::new(&RIG_CALIBRATION).unwrap();
    assert_eq!(AccelChannel::RIG.count_for(&Adc::RIG, 700.0), 3820);
    assert_eq!(AccelChannel::RIG.count_for(&Adc::RIG, -700.0), 276);
    for i in 0..ACCEL_CHANNELS {
        for (count, flagged) in [(3820u16, true), (3821, true), (3819, false), (276, true), (275, true), (277, false)] {
            let s = cal.calibrate(&frame_with(i, count)).saturation;
            assert_eq!(s.range(i), flagged, "channel {i} count {count}");
            assert_eq!(s.any_accel(), flagged);
            for j in 0..ACCEL_CHANNELS {
                if j != i {
                    assert!(!s.range(j));
                }
            }
            assert!(!s.rail(i), "count {count} is not a rail");
        }
    }
}

#[test]
fn rail_flags_at_both_rails_on_every_channel() {
    let cal = Calibrator::new(&RIG_CALIBRATION).unwrap();
    for j in 0..CHANNELS {
        for (count, rail) in [(0u16, true), (4095, true), (1, false), (4094, false), (5000, true)] {
            let s = cal.calibrate(&frame_with(j, count)).saturation;
            assert_eq!(s.rail(j), rail, "channel {j} count {count}");
            for k in 0..CHANNELS {
                if k != j {
                    assert!(!s.rail(k));
                }
            }
            if j < ACCEL_CHANNELS && rail {
                // a rail of an accelerometer is beyond its range here (+-809 m/s^2 span)
                assert!(s.range(j) && s.any_accel());
            }
            if j >= ACCEL_CHANNELS {
                assert!(!s.any_accel(), "a pressure rail is not an accelerometer saturation");
                assert_eq!(s.any(), rail);
            }
        }
    }
}

#[test]
fn with_high_gain_the_rails_come_before_the_range() {
    // gain 1: the ADC spans +-1.65 V / 0.0102 V per m/s^2 = +-161.8 m/s^2 < 700
    let mut cal = RIG_CALIBRATION;
    cal.accel[0].front_end_gain = 1.0;
    let c = Calibrator::new(&cal).unwrap();
    let s = c.calibrate(&frame_with(0, 4095)).saturation;
    assert!(s.rail(0) && !s.range(0));
    let a = c.calibrate(&frame_with(0, 4095)).accel_m_s2[0] as f64;
    let span = 2047.0 * VOLT_PER_COUNT / 0.1 * 9.80665;
    assert!((a - span).abs() < 1e-4 * span, "{a} vs {span}");
}

#[test]
fn invalid_calibrations_are_refused_by_name() {
    let mut bad: Calibration = RIG_CALIBRATION;
    bad.accel[2].sensitivity_mv_per_g = 0.0;
    assert_eq!(Calibrator::new(&bad).unwrap_err().field, "accel.sensitivity_mv_per_g");
    let mut bad = RIG_CALIBRATION;
    bad.adc.bits = 0;
    assert_eq!(Calibrator::new(&bad).unwrap_err().field, "adc.bits");
    let mut bad = RIG_CALIBRATION;
    bad.pressure[1].full_scale_v = bad.pressure[1].zero_v;
    assert_eq!(Calibrator::new(&bad).unwrap_err().field, "pressure.full_scale_v");
    let mut bad = RIG_CALIBRATION;
    bad.accel[0].offset_counts = f64::NAN;
    assert!(Calibrator::new(&bad).is_err());
}
