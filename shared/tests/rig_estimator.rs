//! The estimator on frames made by the sensor model from the six cases (1 s at 25.6 kHz, with
//! and without noise), against the truth the model itself gives: its regime at each sample and
//! its transition times (never the estimator's own output).
//!
//! Per 100 ms window: stick fraction (truth: samples in stick / samples) and stick-slip
//! frequency (truth: (n - 1) / (t_last - t_first) over the exact stick-to-slip times of the
//! window) within 2 % of the truth; the peak-to-peak of each channel against the peak-to-peak
//! of the noise-free signal the sensor model generated, within one count plus the noise's hard
//! bound (2 x 3.46 sigma). Run with `--nocapture` to see the measured figures.

use stickslip_model::rig::calibration::{Calibrated, Calibrator, RIG_CALIBRATION};
use stickslip_model::rig::contact::{ContactEventKind, ContactThresholds};
use stickslip_model::rig::estimator::{Estimator, EstimatorConfig};
use stickslip_model::harness::prng::UNIT_NOISE_BOUND;
use stickslip_model::harness::sensor_model::{Noise, SensorModel, SensorModelConfig};
use stickslip_model::rig::window::WindowReport;
use stickslip_model::rig::{ACCEL_NAMES, PAD_X};
use stickslip_model::{catalogue::CASE_BETAS, Caliper, Regime, Scene};

const FS: f64 = 25_600.0;
const SAMPLES: usize = 25_600;
const WINDOW: usize = 2_560;
/// m/s^2 per count, by hand: 3.3 V / 4096 / (0.1 V/g x 0.2) x 9.80665.
const LSB: f64 = 3.3 / 4096.0 / 0.02 * 9.80665;

/// The model's truth over one window.
#[derive(Default, Clone)]
struct TrueWindow {
    stick: usize,
    onsets: Vec<f64>,
    min: [f64; 4],
    max: [f64; 4],
    n: usize,
}

impl TrueWindow {
    fn stick_fraction(&self) -> f64 {
        self.stick as f64 / self.n as f64
    }
    fn hz(&self) -> f64 {
        if self.onsets.len() >= 2 {
            (self.onsets.len() - 1) as f64 / (self.onsets[self.onsets.len() - 1] - self.onsets[0])
        } else {
            0.0
        }
    }
}

struct Outcome {
    truth: Vec<TrueWindow>,
    est: Vec<WindowReport>,
    /// Samples whose estimated regime (stick, slip slower, slip faster) is the model's.
    samples_agreeing: usize,
    faults: usize,
    /// Slip reversals: the model's (slip to slip transitions) and the estimator's.
    true_reversals: usize,
    reversals: usize,
}

/// Runs a case through sensor model -> calibrator -> estimator and collects both sides.
fn run(scene: &Scene, noise: Noise, est_cfg: &EstimatorConfig, calibration_offset_error: f64) -> Outcome {
    let mut sensor_cfg = SensorModelConfig::RIG;
    sensor_cfg.noise = noise;
    let mut sensor = SensorModel::<f32>::new(scene, &sensor_cfg).unwrap();
    // the calibrator may believe in a slightly wrong zero for pad_x (an offset the estimator
    // has to track as a bias)
    let mut cal = RIG_CALIBRATION;
    cal.accel[PAD_X].offset_counts += calibration_offset_error;
    let cal = Calibrator::new(&cal).unwrap();
    let mut est = Estimator::new(est_cfg).unwrap();
    let mut out =
        Outcome { truth: vec![], est: vec![], samples_agreeing: 0, faults: 0, true_reversals: 0, reversals: 0 };
    let mut w = TrueWindow { min: [f64::INFINITY; 4], max: [f64::NEG_INFINITY; 4], ..Default::default() };
    for _ in 0..SAMPLES {
        let frame = sensor.next_frame().unwrap();
        let truth = *sensor.truth();
        for tr in sensor.stepper().transitions() {
            if tr.from == Regime::Stick {
                w.onsets.push(tr.t);
            }
            if tr.from != Regime::Stick && tr.to != Regime::Stick {
                out.true_reversals += 1;
            }
        }
        let true_stick = truth.regime == Some(Regime::Stick);
        w.stick += true_stick as usize;
        for i in 0..4 {
            let a = truth.accel_m_s2[i] as f64;
            w.min[i] = w.min[i].min(a);
            w.max[i] = w.max[i].max(a);
        }
        w.n += 1;
        let s = est.update(&cal.calibrate(&frame));
        out.faults += s.fault as usize;
        out.samples_agreeing += (Some(s.contact.regime) == truth.regime) as usize;
        out.reversals += matches!(s.contact.event, Some(e) if e.kind == ContactEventKind::Reversal) as usize;
        if s.window_ready {
            out.est.push(est.take_window().unwrap());
            out.truth.push(std::mem::replace(
                &mut w,
                TrueWindow { min: [f64::INFINITY; 4], max: [f64::NEG_INFINITY; 4], ..Default::default() },
            ));
        }
    }
    out
}

/// Checks every window; returns the worst relative errors (stick fraction, frequency).
#[allow(clippy::needless_range_loop)]
fn check(name: &str, o: &Outcome, sigma: f64) -> (f64, f64) {
    assert_eq!(o.est.len(), SAMPLES / WINDOW, "{name}: windows");
    assert_eq!(o.faults, 0);
    // beyond the 2 % of the statistics: the regime, slip direction included, is right at
    // (nearly) every sample, and there are no reversals the model does not have
    assert!(o.samples_agreeing as f64 >= 0.999 * SAMPLES as f64, "{name}: {} samples agree", o.samples_agreeing);
    assert_eq!(o.reversals, o.true_reversals, "{name}: reversals");
    let (mut worst_sf, mut worst_hz) = (0.0f64, 0.0f64);
    for (t, e) in o.truth.iter().zip(&o.est) {
        assert_eq!(e.samples as usize, t.n);
        let (sf, hz) = (t.stick_fraction(), t.hz());
        let err_sf = (e.stick_fraction as f64 - sf).abs() / sf;
        assert!(err_sf <= 0.02, "{name} window {}: stick fraction {} vs true {sf}", e.index, e.stick_fraction);
        if hz == 0.0 {
            assert_eq!(e.stick_slip_hz, 0.0, "{name} window {}: frequency without two true onsets", e.index);
        } else {
            let err_hz = (e.stick_slip_hz as f64 - hz).abs() / hz;
            assert!(err_hz <= 0.02, "{name} window {}: {} Hz vs true {hz} Hz", e.index, e.stick_slip_hz);
            worst_hz = worst_hz.max(err_hz);
        }
        assert_eq!(e.slip_onsets as usize, t.onsets.len(), "{name} window {}: onsets", e.index);
        worst_sf = worst_sf.max(err_sf);
        // pp against the noise-free generated signal: one count of quantisation, plus the
        // noise's hard bound at both extremes
        let tol = LSB * (1.0 + 1e-4) + 2.0 * UNIT_NOISE_BOUND * sigma;
        for i in 0..4 {
            let true_pp = t.max[i] - t.min[i];
            let pp = e.pp_m_s2[i] as f64;
            assert!(
                (pp - true_pp).abs() <= tol,
                "{name} window {} {}: pp {pp} vs true {true_pp}",
                e.index,
                ACCEL_NAMES[i]
            );
        }
        assert!(!e.non_finite);
    }
    (worst_sf, worst_hz)
}

#[test]
fn six_cases_without_noise() {
    for caliper in [Caliper::Push, Caliper::Pull] {
        for (name, beta) in CASE_BETAS {
            let s = Scene::case(caliper, beta);
            let o = run(&s, Noise::NONE, &EstimatorConfig::for_scene(&s), 0.0);
            let label = format!("{}_{name}", caliper.name());
            let (sf, hz) = check(&label, &o, 0.0);
            println!(
                "{label:12} no noise: samples agreeing {}/{SAMPLES}, worst window error: stick fraction {sf:.1e}, frequency {hz:.1e}",
                o.samples_agreeing
            );
        }
    }
}

#[test]
fn six_cases_with_a_little_noise() {
    // 0.5 m/s^2 rms on every accelerometer (1.3 counts), 0.005 bar on the pressures
    let sigma = 0.5;
    for caliper in [Caliper::Push, Caliper::Pull] {
        for (name, beta) in CASE_BETAS {
            let s = Scene::case(caliper, beta);
            let noise = Noise { accel_rms_m_s2: sigma, pressure_rms_bar: 0.005, seed: 0xC0FFEE, adc_rms_counts: 0.0 };
            let o = run(&s, noise, &EstimatorConfig::for_scene(&s), 0.0);
            let label = format!("{}_{name}", caliper.name());
            let (sf, hz) = check(&label, &o, sigma);
            println!(
                "{label:12} noise {sigma} m/s^2: samples agreeing {}/{SAMPLES}, worst window error: stick fraction {sf:.1e}, frequency {hz:.1e}",
                o.samples_agreeing
            );
        }
    }
}

#[test]
fn fixed_thresholds_work_for_every_case() {
    // one set of thresholds for all six (the softest case's jump is 20.7 m/s^2): the decision
    // does not need the scene's friction coefficients
    let cfg =
        EstimatorConfig { contact: ContactThresholds::from_breakaway_jump(20.0, FS), ..EstimatorConfig::default() };
    for caliper in [Caliper::Push, Caliper::Pull] {
        for (name, beta) in CASE_BETAS {
            let s = Scene::case(caliper, beta);
            let noise = Noise { accel_rms_m_s2: 0.5, pressure_rms_bar: 0.0, seed: 99, adc_rms_counts: 0.0 };
            let o = run(&s, noise, &cfg, 0.0);
            check(&format!("{}_{name} fixed", caliper.name()), &o, 0.5);
        }
    }
}

#[test]
fn a_zero_offset_error_is_tracked_as_a_bias() {
    // the calibrator's zero for pad_x is off by `off` counts: a constant error of off x 0.395
    // m/s^2 on a_rel, which the zero-velocity updates must learn in the stick phases
    for (caliper, beta) in [(Caliper::Pull, 0.040), (Caliper::Push, 0.025)] {
        let s = Scene::case(caliper, beta);
        let cfg = EstimatorConfig::for_scene(&s);
        for off in [-10.0, -1.5, 5.0, 10.0] {
            let label = format!("{}_{beta} offset {off}", caliper.name());
            let o = run(&s, Noise::NONE, &cfg, off);
            // the pp of pad_x is unchanged by a constant offset
            check(&label, &o, 0.0);
            // and the estimate of it, after 1 s of mostly stick
            let mut sensor = SensorModel::<f32>::new(&s, &SensorModelConfig::RIG).unwrap();
            let mut cal = RIG_CALIBRATION;
            cal.accel[PAD_X].offset_counts += off;
            let cal = Calibrator::new(&cal).unwrap();
            let mut est = Estimator::new(&cfg).unwrap();
            for _ in 0..SAMPLES {
                est.update(&cal.calibrate(&sensor.next_frame().unwrap()));
            }
            let want = -off * LSB;
            let got = est.contact().bias_m_s2() as f64;
            assert!((got - want).abs() < 0.02 * want.abs(), "{label}: bias {got} vs {want}");
        }
    }
}

#[test]
fn non_finite_inputs_are_refused_and_not_propagated() {
    let s = Scene::case(Caliper::Pull, 0.025);
    let mut sensor = SensorModel::<f32>::new(&s, &SensorModelConfig::RIG).unwrap();
    let cal = Calibrator::new(&RIG_CALIBRATION).unwrap();
    let mut est = Estimator::new(&EstimatorConfig::for_scene(&s)).unwrap();
    est.start_model(&s, 5.0).unwrap();
    let bad = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e30];
    let mut windows = vec![];
    let mut refused = 0;
    for k in 0..SAMPLES {
        let mut c: Calibrated = cal.calibrate(&sensor.next_frame().unwrap());
        let true_stick = sensor.truth().regime == Some(Regime::Stick);
        if k % 1000 == 500 {
            // a bad value in a different channel each time, pressures included
            let which = (k / 1000) % 6;
            let v = bad[(k / 1000) % bad.len()];
            if which < 4 {
                c.accel_m_s2[which] = v;
            } else {
                c.pressure_bar[which - 4] = v;
            }
        }
        let out = est.update(&c);
        if k % 1000 == 500 {
            assert!(out.fault, "sample {k} refused");
            assert!(out.contact.event.is_none());
            refused += 1;
        } else {
            assert!(!out.fault);
            assert!(out.contact.v_r_m_s.is_finite());
            // the bad samples did not disturb the contact estimate (they fall in stick or
            // slip alike; a skipped slip sample costs at most one sample of v_r)
            if k % 1000 > 502 && k % 1000 < 998 {
                assert_eq!(out.contact.regime == Regime::Stick, true_stick, "sample {k}");
            }
        }
        if let Some(m) = out.model {
            assert!(m.xdd_m_s2.is_finite() && m.residual_m_s2.is_finite());
        }
        if out.window_ready {
            windows.push(est.take_window().unwrap());
        }
    }
    assert_eq!(refused, 26);
    let faulted: u32 = windows.iter().map(|w| w.faulted_samples).sum();
    assert_eq!(faulted, 26);
    for w in &windows {
        assert!(!w.non_finite);
        assert_eq!(w.valid_samples + w.faulted_samples, w.samples);
        for v in w.pp_m_s2.iter().chain(&w.rms_m_s2).chain(&w.groan_rms_m_s2) {
            assert!(v.is_finite() && *v < 1e4, "window {}: {v}", w.index);
        }
        let m = w.model.unwrap();
        assert!(m.residual_rms_m_s2.is_finite());
    }
    assert!(est.last_groan().iter().all(|g| g.is_finite()));
}

#[test]
fn lockstep_model_follows_the_truth_on_the_periodic_cases() {
    // the estimator fed with the sensor model's own noise-free accelerations and the exact
    // load: its lockstep model is the same model, so its x'' and stick fraction must match
    for (name, beta) in CASE_BETAS {
        let s = Scene::case(Caliper::Pull, beta);
        let mut sensor = SensorModel::<f32>::new(&s, &SensorModelConfig::RIG).unwrap();
        let mut est = Estimator::new(&EstimatorConfig::for_scene(&s)).unwrap();
        est.start_model(&s, 5.0).unwrap(); // 5 bar x 3e-4 m^2 = 150 N
        let (mut res_sq, mut pad_sq, mut stick_true, mut stick_model, mut n) = (0.0f64, 0.0f64, 0u32, 0u32, 0u32);
        for _ in 0..SAMPLES {
            sensor.next_frame().unwrap();
            let t = *sensor.truth();
            let c = Calibrated { accel_m_s2: t.accel_m_s2, pressure_bar: [5.0, 0.65], ..Default::default() };
            let out = est.update(&c);
            let m = out.model.unwrap();
            assert!(!m.halted);
            res_sq += (m.residual_m_s2 as f64).powi(2);
            pad_sq += (t.accel_m_s2[PAD_X] as f64).powi(2);
            stick_true += (t.regime == Some(Regime::Stick)) as u32;
            stick_model += (m.regime == Regime::Stick) as u32;
            n += 1;
            if out.window_ready {
                let w = est.take_window().unwrap();
                let mw = w.model.unwrap();
                assert_eq!(mw.samples, 2560);
                // the model's own window statistics agree with the measured ones
                assert!((mw.stick_fraction - w.stick_fraction).abs() <= 2.0 / 2560.0, "pull_{name}");
                assert_eq!(mw.slip_onsets, w.slip_onsets);
            }
        }
        let rel = (res_sq / pad_sq).sqrt();
        println!("pull_{name}: lockstep residual rms / pad_x rms = {rel:.1e}; stick samples {stick_model} vs {stick_true} of {n}");
        assert!(rel < 1e-3, "pull_{name}: residual {rel}");
        assert_eq!(stick_model, stick_true);
    }
}

#[test]
fn a_reversal_is_reported_as_such() {
    // a_rel made by hand: stick, breakaway into slip with the pad slower (a < 0), v_r comes
    // back through zero with a staying large: the slip reverses (pad faster), then it slows,
    // and re-sticks when v_r returns to zero with a at rest
    let th = ContactThresholds::from_breakaway_jump(40.0, FS);
    let mut c = stickslip_model::rig::contact::ContactEstimator::new(th, FS);
    let mut events = vec![];
    let mut push = |a: f32, c: &mut stickslip_model::rig::contact::ContactEstimator| {
        let s = c.update(a);
        if let Some(e) = s.event {
            events.push((e.kind, e.sample, s.regime));
        }
        s
    };
    for _ in 0..100 {
        push(0.0, &mut c);
    }
    for _ in 0..100 {
        push(-40.0, &mut c); // v_r -> -0.156 m/s
    }
    for _ in 0..200 {
        push(40.0, &mut c); // through zero at sample 300 and on to +0.156
    }
    // v_r is now about 4000 dt (the trapezoid adds half-samples at the joins); -30 m/s^2 for
    // 133 samples brings it back to within 10 dt of zero, where a drops to 0: stick
    for _ in 0..133 {
        push(-30.0, &mut c);
    }
    assert_eq!(c.regime(), Regime::SlipFaster);
    push(0.0, &mut c);
    assert_eq!(c.regime(), Regime::Stick);
    let kinds: Vec<_> = events.iter().map(|e| (e.0, e.2)).collect();
    assert_eq!(
        kinds,
        vec![
            (ContactEventKind::StickToSlip, Regime::SlipSlower),
            (ContactEventKind::Reversal, Regime::SlipFaster),
            (ContactEventKind::SlipToStick, Regime::Stick)
        ],
        "{events:?}"
    );
    assert_eq!(events[0].1, 100);
    // v_r crosses zero at sample 300 and the reversal needs it beyond zero by the larger of
    // v_reversal = 8 J dt and half the slip's peak |v_r| (100 samples of a = J): 50 samples
    assert!(events[1].1 >= 348 && events[1].1 <= 352, "{events:?}");
    assert_eq!(events[2].1, 533); // 100 + 100 + 200 + 133: the sample where a drops to 0
}

#[test]
fn a_window_not_taken_before_the_next_closes_is_replaced_and_counted() {
    let cfg = EstimatorConfig { window_samples: 100, ..EstimatorConfig::default() };
    let mut est = Estimator::new(&cfg).unwrap();
    let c = Calibrated { accel_m_s2: [1.0, 1.0, -2.0, 3.0], pressure_bar: [5.0, 0.65], ..Default::default() };
    let mut ready = 0;
    for _ in 0..300 {
        ready += est.update(&c).window_ready as u32;
    }
    assert_eq!(ready, 3);
    assert_eq!(est.windows_dropped(), 2);
    let w = est.take_window().unwrap();
    assert_eq!((w.index, w.first_sample, w.samples), (2, 200, 100));
    // constant inputs: pp 0, rms = |value|
    assert_eq!(w.pp_m_s2, [0.0; 4]);
    for (rms, v) in w.rms_m_s2.iter().zip([1.0f32, 1.0, 2.0, 3.0]) {
        assert!((rms - v).abs() < 1e-6 * v, "{rms} vs {v}");
    }
    assert!(est.take_window().is_none(), "taken once");
}
