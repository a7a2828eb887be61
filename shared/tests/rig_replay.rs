//! The one rig (`rig::pipeline::Rig`) and the replay digest used by the bit-identity test on
//! the Cortex-M4F: the sequencer drives the armed lockstep model, faults stop it, a
//! configuration the rig's parts cannot run is refused naming its field, and the digest is a
//! pure function of its inputs that sees every output.

use stickslip_model::digest::Fnv1a64;
use stickslip_model::rig::calibration::{Calibrator, Frame, RIG_CALIBRATION};
use stickslip_model::rig::pipeline::{DigitalInputs, Rig, RigError, Timing};
use stickslip_model::harness::replay::{digest_sample, replay_config, run_frames_digest, run_frames_digest_with, Script};
use stickslip_model::harness::sensor_model::{Noise, SensorModel, SensorModelConfig};
use stickslip_model::rig::sequencer::{Command, FaultCause, PhaseEnd, RecordEnd, SeqState, Valves};
use stickslip_model::design::SAMPLE_RATE_HZ;
use stickslip_model::rig::{estimator::Estimator, pipeline::RigConfig};
use stickslip_model::{Caliper, Regime, Scene};

const NOISE: Noise = Noise { accel_rms_m_s2: 0.5, pressure_rms_bar: 0.005, seed: 2024, adc_rms_counts: 0.0 };

#[test]
fn the_digest_is_a_pure_function_of_its_inputs() {
    let s = Scene::case(Caliper::Push, 0.040);
    let a = run_frames_digest(&s, 6000, &NOISE).unwrap();
    let b = run_frames_digest(&s, 6000, &NOISE).unwrap();
    assert_eq!(a, b);
    println!("push_center, 6000 frames, noise seed 2024: digest {:#018x}", a.digest);
    // every input matters
    let other_seed = Noise { seed: 2025, ..NOISE };
    assert_ne!(a.digest, run_frames_digest(&s, 6000, &other_seed).unwrap().digest);
    assert_ne!(a.digest, run_frames_digest(&s, 5999, &NOISE).unwrap().digest);
    assert_ne!(a.digest, run_frames_digest(&Scene::case(Caliper::Pull, 0.040), 6000, &NOISE).unwrap().digest);
    assert_ne!(a.digest, run_frames_digest(&s, 6000, &Noise::NONE).unwrap().digest);
}

#[test]
fn a_replay_records_the_whole_run_and_finds_the_slips() {
    let s = Scene::case(Caliper::Pull, 0.025);
    let r = run_frames_digest(&s, 25_600, &Noise::NONE).unwrap();
    assert_eq!(r.frames, 25_600);
    // start at frame 0, clamp and drive one tick each, then it records to the end; the
    // record's estimator counts its windows from the record's first sample (frame 2): 25 598
    // samples, 9 whole windows of 2 560
    assert_eq!(r.windows, 9);
    assert_eq!(r.sensor_halt, None);
    assert_eq!(r.final_state, SeqState::Record);
    // the estimator's onsets are the model's own (counted here from the stepper)
    let mut m = SensorModel::<f32>::new(&s, &SensorModelConfig::RIG).unwrap();
    let mut onsets = 0;
    for _ in 0..25_600 {
        m.next_frame().unwrap();
        onsets += m.stepper().transitions().iter().filter(|t| t.from == Regime::Stick).count() as u64;
    }
    assert_eq!(r.slip_onsets, onsets);
    println!("pull_trail, 25600 frames, no noise: digest {:#018x}, {} onsets", r.digest, r.slip_onsets);
}

#[test]
fn the_digest_sees_the_outputs_not_only_the_frames() {
    // same frames, a rig with another window length: every frame equal, outputs differ
    let s = Scene::case(Caliper::Pull, 0.040);
    let mut cfg = replay_config(&s, 6000);
    let a = run_frames_digest_with(&s, 6000, &SensorModelConfig::RIG, &cfg, &Script::START).unwrap();
    cfg.estimator.window_samples = 2000;
    let b = run_frames_digest_with(&s, 6000, &SensorModelConfig::RIG, &cfg, &Script::START).unwrap();
    assert_ne!(a.digest, b.digest);
    // the script is an input too
    let never = Script { button_at: [None, None], estop: None };
    let c = run_frames_digest_with(&s, 6000, &SensorModelConfig::RIG, &cfg, &never).unwrap();
    assert_ne!(b.digest, c.digest);
    // never started: the estimator of boot runs all along (6000 / 2000 windows), the model never
    assert_eq!((c.final_state, c.windows), (SeqState::Idle, 3));
    // and one output bit changes the digest of a sample
    let mut rig = Rig::new(&replay_config(&s, 10)).unwrap();
    let frame = Frame { counts: [2048, 2048, 2048, 2048, 2234, 938] };
    let out = rig.sample(&frame, &DigitalInputs::default(), None);
    let (mut d1, mut d2) = (Fnv1a64::new(), Fnv1a64::new());
    digest_sample(&mut d1, &out, None);
    let mut changed = out;
    changed.calibrated.accel_m_s2[3] = f32::from_bits(out.calibrated.accel_m_s2[3].to_bits() ^ 1);
    digest_sample(&mut d2, &changed, None);
    assert_ne!(d1.finish(), d2.finish());
}

#[test]
fn the_pipeline_runs_the_model_during_the_record_only_and_faults_stop_it() {
    let s = Scene::case(Caliper::Pull, 0.040);
    let mut cfg: RigConfig = replay_config(&s, 8000);
    cfg.sequencer.record = RecordEnd::Ticks(5000);
    let mut rig = Rig::new(&cfg).unwrap();
    let mut sensor = SensorModel::<f32>::new(&s, &SensorModelConfig::RIG).unwrap();
    let ok = DigitalInputs::default();
    // idle for a while: no model
    for _ in 0..100 {
        let o = rig.sample(&sensor.next_frame().unwrap(), &ok, None);
        assert_eq!(o.sequencer.state, SeqState::Idle);
        assert!(o.estimate.model.is_none());
    }
    let o = rig.sample(&sensor.next_frame().unwrap(), &ok, Some(Command::Start));
    assert_eq!(o.sequencer.state, SeqState::Clamp);
    assert_eq!(rig.sample(&sensor.next_frame().unwrap(), &ok, None).sequencer.state, SeqState::Drive);
    let o = rig.sample(&sensor.next_frame().unwrap(), &ok, None);
    assert_eq!(o.sequencer.state, SeqState::Record);
    assert!(o.record_started && rig.record() == 1);
    // the model runs from the next sample on, with F_N from the clamp setpoint: 5 bar x 1e5
    // Pa/bar x 3e-4 m^2 = 150 N. It starts at rest: N0 = c_N F_N a_N / K, pull arms
    // d_L = 0.01, d_T = 0.065, a_N = 0.08 - 0.04 m
    let f_n = 5.0 * 1e5 * 3e-4;
    assert_eq!(rig.model_scene().f_n, f_n);
    let (k, c_n) = (1e6 * (0.01f64.powi(2) + 0.065f64.powi(2)), 1e6 * (0.01 + 0.065));
    let n0 = c_n * f_n * 0.04 / k;
    let n = rig.estimator().model().map(|m| m.normal_force()).unwrap() as f64;
    assert!((n - n0).abs() < 1e-5 * n0, "model N0 {n} vs {n0}");
    let mut recorded = 1;
    loop {
        let o = rig.sample(&sensor.next_frame().unwrap(), &ok, None);
        if o.sequencer.state != SeqState::Record {
            assert_eq!(o.sequencer.state, SeqState::Vent);
            break;
        }
        assert!(o.estimate.model.is_some());
        recorded += 1;
    }
    assert_eq!(recorded, 5000);
    assert!(rig.estimator().model().is_none(), "the model stops with the record");

    // a new run, an e-stop in the middle of the record: vented in that tick, model stopped
    let mut rig = Rig::new(&cfg).unwrap();
    rig.sample(&sensor.next_frame().unwrap(), &ok, Some(Command::Start));
    for _ in 0..100 {
        rig.sample(&sensor.next_frame().unwrap(), &ok, None);
    }
    assert_eq!(rig.sequencer().state(), SeqState::Record);
    let o = rig.sample(&sensor.next_frame().unwrap(), &DigitalInputs { estop: true, end_of_stroke: false }, None);
    assert_eq!((o.sequencer.state, o.sequencer.valves), (SeqState::Fault(FaultCause::EStop), Valves::VENTED));
    assert!(rig.estimator().model().is_none());
}

#[test]
fn accelerometer_saturation_in_a_frame_faults_the_rig() {
    let s = Scene::case(Caliper::Pull, 0.040);
    let mut rig = Rig::new(&replay_config(&s, 100)).unwrap();
    let cal = Calibrator::new(&RIG_CALIBRATION).unwrap();
    let ok = DigitalInputs::default();
    let quiet = Frame { counts: [2048, 2048, 2048, 2048, 2234, 938] };
    assert!(!cal.calibrate(&quiet).saturation.any());
    rig.sample(&quiet, &ok, Some(Command::Start));
    rig.sample(&quiet, &ok, None);
    assert_eq!(rig.sample(&quiet, &ok, None).sequencer.state, SeqState::Record);
    let mut hit = quiet;
    hit.counts[2] = 3820; // pad_trail at +700 m/s^2
    let o = rig.sample(&hit, &ok, None);
    assert_eq!((o.sequencer.state, o.sequencer.valves), (SeqState::Fault(FaultCause::AccelSaturation), Valves::VENTED));
    // held: reset refused; cleared: accepted
    assert!(rig.sample(&hit, &ok, Some(Command::Reset)).sequencer.valves.is_vented());
    assert_eq!(rig.sequencer().state(), SeqState::Fault(FaultCause::AccelSaturation));
    assert_eq!(rig.sample(&quiet, &ok, Some(Command::Reset)).sequencer.state, SeqState::Idle);
}

#[test]
fn state_sizes_fit_the_microcontroller() {
    // printed for the firmware's stack and RAM budget (128 KB on the STM32F405)
    let sizes = [
        ("SensorModel<f32>", std::mem::size_of::<SensorModel<f32>>()),
        ("Estimator", std::mem::size_of::<Estimator>()),
    ];
    for (name, n) in sizes {
        println!("{name}: {n} bytes");
        assert!(n < 16 * 1024, "{name}: {n} bytes");
    }
    // the rig: two estimators (the running one and the armed copy) and 1 KB of its own at most
    let (rig, est) = (std::mem::size_of::<Rig>(), std::mem::size_of::<Estimator>());
    println!("Rig: {rig} bytes");
    assert!(rig <= 2 * est + 1024, "Rig: {rig} bytes, estimator {est}");
}

#[test]
fn a_configuration_the_rigs_parts_cannot_run_is_refused_naming_its_field() {
    let s = Scene::case(Caliper::Push, 0.040);
    let field = |cfg: &RigConfig| match Rig::new(cfg) {
        Err(RigError::Config(e)) => e.field,
        Err(RigError::Model(e)) => e.field,
        Ok(_) => "accepted",
    };
    let ok = RigConfig::for_scene(&s, SAMPLE_RATE_HZ, false, false, &Timing::RIG);
    assert_eq!(field(&ok), "accepted");
    assert!(matches!(ok.sequencer.phase_end, PhaseEnd::Timed { clamp_ticks: 12_800, drive_ticks: 7_680 }));
    // pressure-checked phases without transducers would clamp until the timeout
    let mut cfg = ok;
    cfg.sequencer.phase_end = PhaseEnd::Pressure;
    assert_eq!(field(&cfg), "sequencer.phase_end");
    // a record until the end of stroke without the switch
    let mut cfg = ok;
    cfg.sequencer.record = RecordEnd::EndOfStroke { timeout_ticks: 100 };
    assert_eq!(field(&cfg), "sequencer.record");
    // the model's pad off the pad: refused before any sample
    let mut cfg = ok;
    cfg.model_template.beta = 0.095;
    assert_eq!(field(&cfg), "beta");
    // a part's own rule: the sequencer's
    let mut cfg = ok;
    cfg.sequencer.vent_ticks = 0;
    assert_eq!(field(&cfg), "vent_ticks");
}

#[test]
fn without_transducers_the_phases_are_timed_and_the_pressures_read_zero() {
    // the rig's frames carry the actuator line at 5 bar: without transducers they are not read
    let s = Scene::case(Caliper::Push, 0.040);
    let mut timing = Timing::RIG;
    (timing.clamp_settle_s, timing.drive_settle_s) = (0.01, 0.005); // 256 and 128 samples
    let cfg = RigConfig::for_scene(&s, SAMPLE_RATE_HZ, false, false, &timing);
    let mut rig = Rig::new(&cfg).unwrap();
    let mut sensor = SensorModel::<f32>::new(&s, &SensorModelConfig::RIG).unwrap();
    let ok = DigitalInputs::default();
    let mut shown = [0u32; 3];
    for i in 0..1000 {
        let counts = sensor.next_frame().unwrap().counts;
        let o = rig.sample(&rig.frame(&counts), &ok, if i == 0 { Some(Command::Start) } else { None });
        assert!(o.calibrated.pressure_bar.iter().all(|p| p.abs() < 0.01), "{:?}", o.calibrated.pressure_bar);
        match o.sequencer.state {
            SeqState::Clamp => shown[0] += 1,
            SeqState::Drive => shown[1] += 1,
            SeqState::Record => shown[2] += 1,
            other => panic!("{other:?} at frame {i}"),
        }
    }
    assert_eq!(shown, [256, 128, 1000 - 384]);
}

#[test]
fn the_thesis_friction_law_runs_through_the_whole_chain() {
    // mu_k = mu_s: no breakaway jump; the thresholds fall back to their floor and the chain
    // runs (the pad ends up sliding for good, docs/model.md)
    let mut s = Scene::case(Caliper::Push, 0.040);
    s.mu_k = s.mu_s;
    let r = run_frames_digest(&s, 25_600, &NOISE).unwrap();
    assert_eq!(r.frames, 25_600);
    assert_eq!(r.windows, 9, "the record's 25 598 samples");
    assert!(r.slip_onsets >= 1);
}

/// A recording played back (`Rig::for_recording` + `Rig::play`, what `analyze` and `sil` run):
/// the record is the rig's record 1 from the first row, with the floor's thresholds and no
/// model; its windows carry the pressures' statistics (checked against the closed form of a
/// ramp) and are judged against the floor as the clamp's would be.
#[test]
fn a_recording_plays_back_as_the_rigs_record_one_with_its_floor() {
    use stickslip_model::rig::calibration::{Calibrated, Saturation};
    use stickslip_model::rig::contact::ContactThresholds;
    use stickslip_model::rig::estimator::EstimatorConfig;
    use stickslip_model::rig::noise_floor::FloorReport;

    let fs = SAMPLE_RATE_HZ;
    let ecfg = EstimatorConfig { fs_hz: fs, window_samples: 10, ..EstimatorConfig::default() };
    let th = ContactThresholds::from_noise_floor(0.05, 0.01, fs);
    assert_ne!(th, ecfg.contact, "the floor's thresholds must differ from the configuration's for this test");
    let sigma = 0.05f32;
    let floor = FloorReport {
        samples: 512,
        mean_m_s2: core::array::from_fn(|_| 0.0),
        sigma_m_s2: core::array::from_fn(|_| sigma),
        pp_m_s2: core::array::from_fn(|_| 0.3),
    };
    let cfg = RigConfig::recording(ecfg);
    let mut rig = Rig::for_recording(&cfg, Some((floor, th))).unwrap();
    assert_eq!(rig.record(), 1);
    assert_eq!(*rig.estimator().contact().thresholds(), th);
    assert!(rig.estimator().model().is_none(), "a recording has no setpoint: no lockstep model");
    let plain = Rig::for_recording(&cfg, None).unwrap();
    assert_eq!(*plain.estimator().contact().thresholds(), ecfg.contact);

    // 25 rows: the actuator line a ramp of 0.1 bar per row, the band line at 2 bar, every
    // accelerometer +-A (A = sigma: RMS A, under twice the floor's sigma: noisier than the signal)
    let a = sigma;
    let mut closed = vec![];
    for i in 0..25u32 {
        let s = if i % 2 == 0 { a } else { -a };
        let cal = Calibrated {
            accel_m_s2: [s; 4],
            pressure_bar: [0.1 * i as f32, 2.0],
            saturation: Saturation { bits: 0 },
        };
        if rig.play(&cal).window_ready {
            closed.push(rig.take_window().expect("a window closed"));
        }
    }
    assert_eq!(closed.len(), 2, "windows of 10 rows in 25");
    for (k, w) in closed.iter().enumerate() {
        assert_eq!(w.record, 1);
        assert_eq!(w.report.first_sample, 10 * k as u64);
        assert_eq!(w.report.samples, 10);
        // the ramp 0.1 i over i = 10k .. 10k + 9: mean 0.1 (10k + 4.5)
        let mean = 0.1 * (10.0 * k as f64 + 4.5);
        assert!((w.pressure.mean_bar[0] as f64 - mean).abs() < 1e-5, "window {k}: {:?}", w.pressure);
        assert!((w.pressure.min_bar[0] as f64 - 0.1 * (10 * k) as f64).abs() < 1e-6);
        assert!((w.pressure.max_bar[0] as f64 - 0.1 * (10 * k + 9) as f64).abs() < 1e-6);
        assert_eq!((w.pressure.mean_bar[1], w.pressure.min_bar[1], w.pressure.max_bar[1]), (2.0, 2.0, 2.0));
        assert!((w.report.pp_m_s2[1] - 2.0 * a).abs() < 1e-7 && (w.report.rms_m_s2[1] - a).abs() < 1e-7);
        // judged against the floor: pad_x noisier than the signal; without a floor it cannot be
        assert!(rig.window_health(&w.report).channels[1].noisy());
        assert!(!plain.window_health(&w.report).channels[1].noisy());
    }
}
