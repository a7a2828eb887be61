//! `analyze --windows` against the firmware's own windows, line by line: a run of the sensor
//! model through the one rig (`stickslip_model::rig::pipeline::Rig`, as the firmware runs it:
//! the button at frame 0, the record to the end) gives the `window` records the firmware would
//! log; the same record's calibrated accelerations, written as a CSV recording (f32 values in
//! their shortest form, time k / 25.6 kHz), go through `stickslip analyze`'s analysis with the
//! rig's thresholds (the scene's breakaway jump), where a `Rig` made for the recording plays
//! them back (`Rig::for_recording`, `Rig::play`: no sequencer, no calibration). Every statistic of every window must be the
//! same to the bit: pp, RMS and groan RMS per channel, stick fraction, stick-slip frequency,
//! onsets, sample counts. (The lockstep model's part is the rig's alone: a recording has no
//! model.)

use std::fmt::Write as _;
use std::mem::MaybeUninit;

use stickslip::recorded::analysis::FloorSource;
use stickslip::recorded::{analyze_path, sil};
use stickslip_model::rig::contact::{ContactThresholds, MIN_DESIGN_JUMP_M_S2};
use stickslip_model::rig::pipeline::{DigitalInputs, Rig};
use stickslip_model::harness::replay::replay_config;
use stickslip_model::harness::sensor_model::{Noise, SensorModel, SensorModelConfig};
use stickslip_model::rig::sequencer::Command;
use stickslip_model::rig::window::WindowReport;
use stickslip_model::{Caliper, Scene};

/// Samples of the record: t = 0 .. 0.5 s exactly at 25.6 kHz (the analysis's rate from the
/// time column is then 25 600 Hz to the bit), five whole windows of 2 560.
const RECORD: usize = 12_801;

fn check(scene: &Scene, noise: Noise) {
    let mut sensor_cfg = SensorModelConfig::RIG;
    sensor_cfg.noise = noise;
    let mut sensor = SensorModel::<f32>::new(scene, &sensor_cfg).unwrap();
    // clamp and drive take one frame each: the record's estimator starts after frame 2
    let frames = 3 + RECORD as u64;
    let mut slot = MaybeUninit::uninit();
    let rig = Rig::init(&mut slot, &replay_config(scene, frames)).unwrap();
    let mut csv = String::from("t_s,disc_x_m_s2,pad_x_m_s2,pad_trail_m_s2,pad_lead_m_s2\n");
    let mut rig_windows: Vec<WindowReport> = vec![];
    let mut k = 0usize;
    for i in 0..frames {
        let counts = sensor.next_frame().unwrap().counts;
        let out = rig.sample(&rig.frame(&counts), &DigitalInputs::default(), (i == 0).then_some(Command::Start));
        if rig.record() == 1 && !out.record_started {
            let a = out.calibrated.accel_m_s2;
            writeln!(csv, "{},{},{},{},{}", k as f64 / 25_600.0, a[0], a[1], a[2], a[3]).unwrap();
            k += 1;
        }
        while let Some(w) = rig.take_window() {
            if w.record == 1 {
                rig_windows.push(WindowReport { model: None, ..w.report });
            }
        }
    }
    assert_eq!(k, RECORD);
    assert_eq!(rig_windows.len(), 5);
    assert!(rig_windows.iter().map(|w| w.slip_onsets).sum::<u32>() >= 10, "the run stick-slips: {rig_windows:?}");

    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("analyze_windows_vs_rig");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{:?}_{}.csv", scene.caliper, noise.seed));
    std::fs::write(&path, csv).unwrap();
    let mut cfg = sil::analysis_config(scene, f64::NEG_INFINITY, None, false);
    cfg.floor = FloorSource::Jump;
    cfg.breakaway_jump_m_s2 = ContactThresholds::breakaway_jump(scene).max(MIN_DESIGN_JUMP_M_S2);
    cfg.spectra = false;
    cfg.windows = true;
    let an = analyze_path(path.to_str().unwrap(), cfg).unwrap();
    assert_eq!(an.sample_rate_hz, 25_600.0);
    let analyzed: Vec<WindowReport> = an.windows.iter().map(|w| w.report).collect();
    assert_eq!(analyzed.len(), rig_windows.len());
    for (a, r) in analyzed.iter().zip(&rig_windows) {
        assert_eq!(a, r, "window {}: analyze against the rig", r.index);
    }
}

#[test]
fn analyze_windows_equal_the_rigs_push_center_noisy() {
    let noise = Noise { accel_rms_m_s2: 0.5, pressure_rms_bar: 0.005, seed: 2024, adc_rms_counts: 0.0 };
    check(&Scene::case(Caliper::Push, 0.040), noise);
}

#[test]
fn analyze_windows_equal_the_rigs_pull_trail_clean() {
    check(&Scene::case(Caliper::Pull, 0.025), Noise::NONE);
}
