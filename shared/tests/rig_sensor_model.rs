//! The sensor model against the equations of motion written out here (docs/model.md), the
//! accelerometer geometry worked out by hand, and hand-computed counts; its noise and its
//! clipping at the sensor's range.

use stickslip_model::rig::calibration::{Calibrator, RIG_CALIBRATION};
use stickslip_model::harness::prng::UNIT_NOISE_BOUND;
use stickslip_model::harness::sensor_model::{Noise, SensorGeometry, SensorModel, SensorModelConfig};
use stickslip_model::rig::{DISC_X, PAD_LEAD, PAD_TRAIL, PAD_X};
use stickslip_model::{catalogue::CASE_BETAS, Caliper, Regime, Scene};

/// Counts per m/s^2 by hand: 0.1 V/g x 0.2 / 9.80665 per (3.3 / 4096 V per count).
const COUNTS_PER_M_S2: f64 = 0.1 * 0.2 / 9.80665 / (3.3 / 4096.0);

/// x'' and phi'' from the equations of motion, with the arms of docs/model.md written out.
fn accelerations(s: &Scene, regime: Regime, z: [f64; 4]) -> (f64, f64) {
    let (d_l, d_t, a_n, sign) = match s.caliper {
        Caliper::Push => (s.l + s.l_cl, s.l - s.l_ct, s.beta, 1.0),
        Caliper::Pull => (s.l - s.l_cl, s.l + s.l_ct, 2.0 * s.l - s.beta, -1.0),
    };
    let k = s.k_l * d_l * d_l + s.k_t * d_t * d_t;
    let c_n = s.k_l * d_l + s.k_t * d_t;
    let n = c_n * z[2];
    let f_f = match regime {
        Regime::Stick => s.k_g * z[0],
        Regime::SlipSlower => s.mu_k * n,
        Regime::SlipFaster => -s.mu_k * n,
    };
    let xdd = if regime == Regime::Stick { 0.0 } else { (f_f - s.k_g * z[0]) / s.m };
    let phidd = (s.f_n * a_n + sign * s.w * f_f - k * z[2]) / s.inertia;
    (xdd, phidd)
}

#[test]
#[allow(clippy::needless_range_loop)]
fn channels_follow_the_equations_of_motion_and_the_sensor_geometry() {
    for caliper in [Caliper::Push, Caliper::Pull] {
        for (name, beta) in CASE_BETAS {
            let s = Scene::case(caliper, beta);
            let mut m = SensorModel::<f64>::new(&s, &SensorModelConfig::RIG).unwrap();
            // sensors 5 mm in from each edge; the pivot is the trailing edge (push) or the
            // leading edge (pull) of the 80 mm pad
            let (arm_trail, arm_lead) = match caliper {
                Caliper::Push => (0.005, 0.075),
                Caliper::Pull => (0.075, 0.005),
            };
            let (mut slips, mut sticks) = (0, 0);
            for _ in 0..(0.3 * 25600.0) as usize {
                let frame = m.next_frame().unwrap();
                let regime = m.stepper().regime();
                let z = m.stepper().state().to_array();
                let (xdd, phidd) = accelerations(&s, regime, z);
                let t = m.truth();
                assert_eq!(t.regime, Some(regime));
                let want = [0.0, xdd, arm_trail * phidd, arm_lead * phidd];
                for i in 0..4 {
                    let got = t.accel_m_s2[i];
                    assert!(
                        (got - want[i]).abs() <= 1e-9 * (1.0 + want[i].abs()),
                        "{}_{name} ch {i}: {got} vs {}",
                        caliper.name(),
                        want[i]
                    );
                    // the count, rounded half up from the hand-computed gain
                    let c = (2048.0 + want[i] * COUNTS_PER_M_S2 + 0.5).floor() as i64;
                    assert!(
                        (frame.counts[i] as i64 - c).abs() <= 1,
                        "{}_{name} ch {i}: count {} vs {c}",
                        caliper.name(),
                        frame.counts[i]
                    );
                }
                assert_eq!(frame.counts[DISC_X], 2048);
                if regime == Regime::Stick {
                    sticks += 1;
                    assert_eq!(t.accel_m_s2[PAD_X], 0.0, "stick: the pad moves with the band");
                    assert_eq!(frame.counts[PAD_X], 2048);
                } else {
                    slips += 1;
                }
                // 5 bar and 0.65 bar by hand: 1.8 V and 0.756 V at the pin
                assert_eq!(frame.counts[4], 2234);
                assert_eq!(frame.counts[5], 938);
            }
            assert!(slips > 100 && sticks > 100, "{}_{name}: both regimes seen", caliper.name());
        }
    }
}

#[test]
fn y_polarity_and_positions_are_configurable() {
    let s = Scene::case(Caliper::Push, 0.040);
    let mut cfg = SensorModelConfig::RIG;
    cfg.geometry =
        SensorGeometry { trail_from_trailing_edge_m: 0.02, lead_from_trailing_edge_m: 0.06, y_polarity: -1.0 };
    let mut flipped = SensorModel::<f64>::new(&s, &cfg).unwrap();
    let mut plain = SensorModel::<f64>::new(&s, &SensorModelConfig::RIG).unwrap();
    for _ in 0..3000 {
        flipped.next_frame().unwrap();
        plain.next_frame().unwrap();
        let (a, b) = (flipped.truth().accel_m_s2, plain.truth().accel_m_s2);
        // push: arms are the positions; lead sensor 0.075 -> 0.06, trail 0.005 -> 0.02
        assert!((a[PAD_LEAD] + b[PAD_LEAD] * 0.06 / 0.075).abs() <= 1e-9 * (1.0 + b[PAD_LEAD].abs()));
        assert!((a[PAD_TRAIL] + b[PAD_TRAIL] * 0.02 / 0.005).abs() <= 1e-9 * (1.0 + b[PAD_TRAIL].abs()));
    }
    cfg.geometry.lead_from_trailing_edge_m = 0.09; // off the 80 mm pad
    assert!(SensorModel::<f64>::new(&s, &cfg).is_err());
    cfg.geometry = SensorGeometry { y_polarity: 0.5, ..SensorGeometry::RIG };
    assert!(SensorModel::<f64>::new(&s, &cfg).is_err());
}

#[test]
fn noise_is_white_enough_bounded_and_repeatable() {
    // the first 40 ms of every case are stick: all true accelerations of disc_x and pad_x are 0
    let s = Scene::case(Caliper::Push, 0.040);
    let sigma = 1.0;
    let mut cfg = SensorModelConfig::RIG;
    cfg.noise = Noise { accel_rms_m_s2: sigma, pressure_rms_bar: 0.0, seed: 12345, adc_rms_counts: 0.0 };
    let cal = Calibrator::new(&RIG_CALIBRATION).unwrap();
    let lsb = 1.0 / COUNTS_PER_M_S2;
    let run = |seed: u32| {
        let mut c = cfg;
        c.noise.seed = seed;
        let mut m = SensorModel::<f32>::new(&s, &c).unwrap();
        (0..1000).map(|_| m.next_frame().unwrap()).collect::<Vec<_>>()
    };
    let frames = run(12345);
    assert_eq!(frames, run(12345), "same seed, same frames");
    assert_ne!(frames, run(54321), "another seed, other frames");
    let v: Vec<f64> = frames.iter().map(|f| cal.calibrate(f).accel_m_s2[DISC_X] as f64).collect();
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
    // quantisation adds lsb^2 / 12 to the variance
    let want = (sigma * sigma + lsb * lsb / 12.0).sqrt();
    assert!(mean.abs() < 4.0 * want / n.sqrt(), "mean {mean}");
    assert!((var.sqrt() - want).abs() < 0.1 * want, "std {} vs {want}", var.sqrt());
    let peak = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    assert!(peak <= UNIT_NOISE_BOUND * sigma + 0.5 * lsb + 1e-6, "peak {peak}");
    // lag-1 correlation of white noise is ~0
    let r1 = v.windows(2).map(|w| (w[0] - mean) * (w[1] - mean)).sum::<f64>() / (n - 1.0) / var;
    assert!(r1.abs() < 0.1, "lag-1 correlation {r1}");
}

#[test]
fn accelerometers_clip_at_their_range_and_are_flagged() {
    // a 4000 N load: breakaway jump (mu_s - mu_k) N / m of about 880 m/s^2, beyond 700; a
    // 0.1 m/s band brings the first slip (t1 ~ mu_s N0 / (k_g V)) to about 60 ms
    let mut s = Scene::case(Caliper::Push, 0.040);
    s.f_n = 4000.0;
    s.v = 0.1;
    let mut cfg = SensorModelConfig::RIG;
    cfg.band_line_bar = 0.65;
    cfg.piston_area_m2 = 4000.0 / 5e5; // keep the actuator line at 5 bar
    let mut m = SensorModel::<f32>::new(&s, &cfg).unwrap();
    let cal = Calibrator::new(&RIG_CALIBRATION).unwrap();
    let (mut over, mut flagged) = (0, 0);
    for _ in 0..25600 {
        let f = m.next_frame().unwrap();
        let true_pad_x = m.truth().accel_m_s2[PAD_X] as f64;
        let c = cal.calibrate(&f);
        // never beyond the counts of +-700 m/s^2 (3820 and 276, by hand)
        assert!(f.counts[PAD_X] <= 3820 && f.counts[PAD_X] >= 276);
        if true_pad_x.abs() >= 700.0 {
            over += 1;
            assert!(c.saturation.range(PAD_X) && c.saturation.any_accel(), "{true_pad_x} m/s^2 not flagged");
            assert!((c.accel_m_s2[PAD_X].abs() as f64 - 700.0).abs() <= 0.5 / COUNTS_PER_M_S2);
        }
        if c.saturation.range(PAD_X) {
            flagged += 1;
            assert!(true_pad_x.abs() >= 700.0 - 0.5 / COUNTS_PER_M_S2, "flag at {true_pad_x}");
        }
        assert!(!c.saturation.rail(PAD_X));
    }
    assert!(over > 0 && flagged >= over, "over {over} flagged {flagged}");
}
