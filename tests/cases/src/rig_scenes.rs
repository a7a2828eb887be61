//! The rig cases of the on-target cross-check: frames from the model through the sensor model
//! and the one rig, `stickslip_model::rig::pipeline::Rig` (calibration, estimator with the
//! groan band-pass, window statistics and the armed lockstep model, sequencer), digested by
//! `stickslip_model::harness::replay` (its layout: every output of every frame).
//!
//! Run by the Cortex-M4F program `tests/on-target/src/bin/rig.rs` and by the host-side test
//! `tests/tests/on_target.rs` (this crate's library, built for the host), so both compute the
//! digests with the same code; it uses `core` and `stickslip_model`, nothing else.
//!
//! The cases differ in the rig's parts and the operator's hand (`replay::Script`):
//! - `replay`: the scene's own pad as the model's, pressure transducers, no end-of-stroke
//!   switch, the button at frame 0 (start), recording to the end (`replay::run_frames_digest`);
//! - `core`: the firmware's configuration (`RigConfig::rig`: the default model pad, 100 ms
//!   windows), with both features and an e-stop and a reset, or without either (timed phases).

use core::fmt;

use stickslip_model::rig::pipeline::RigConfig;
use stickslip_model::harness::replay::{run_frames_digest, run_frames_digest_with, ReplaySummary, Script};
use stickslip_model::harness::sensor_model::{Noise, SensorModelConfig};
use stickslip_model::{Caliper, Scene};

/// Frames per case: 0.5 s at 25.6 kHz, five 100 ms windows.
pub const RIG_FRAMES: u64 = 12_800;

/// The noise of the noisy cases: 0.5 m/s^2 rms on each accelerometer (1.3 counts), 0.005 bar
/// on each pressure.
pub const NOISY: Noise = Noise { accel_rms_m_s2: 0.5, pressure_rms_bar: 0.005, seed: 2024, adc_rms_counts: 0.0 };

/// Which rig set-up and script a case runs.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Pipeline {
    /// `replay::run_frames_digest`.
    Replay,
    /// The firmware's configuration with both features (pressure transducers, end-of-stroke
    /// switch), started at frame 0; an e-stop from frame 9 000 to 9 999, reset at frame 11 000.
    CoreDefault,
    /// The firmware's configuration without pressure transducers (timed clamp 50 ms, drive
    /// 30 ms) and without an end-of-stroke switch, started at frame 0.
    CoreNoPressure,
}

/// One rig case.
#[derive(Clone, Copy)]
pub struct RigCase {
    pub name: &'static str,
    pub scene: fn() -> Scene,
    pub noise: Noise,
    pub pipeline: Pipeline,
}

fn push_center() -> Scene {
    Scene::case(Caliper::Push, 0.040)
}
fn pull_center() -> Scene {
    Scene::case(Caliper::Pull, 0.040)
}
fn pull_trail() -> Scene {
    Scene::case(Caliper::Pull, 0.025)
}

/// The cases, in print order.
pub const RIG_CASES: [RigCase; 6] = [
    RigCase { name: "replay_push_center_noisy", scene: push_center, noise: NOISY, pipeline: Pipeline::Replay },
    RigCase { name: "replay_push_center_clean", scene: push_center, noise: Noise::NONE, pipeline: Pipeline::Replay },
    RigCase {
        name: "replay_pull_center_noisy",
        scene: pull_center,
        noise: Noise { seed: 7, ..NOISY },
        pipeline: Pipeline::Replay,
    },
    RigCase { name: "replay_pull_trail_clean", scene: pull_trail, noise: Noise::NONE, pipeline: Pipeline::Replay },
    RigCase { name: "core_push_center_noisy", scene: push_center, noise: NOISY, pipeline: Pipeline::CoreDefault },
    RigCase {
        name: "core_nopressure_pull_center_noisy",
        scene: pull_center,
        noise: Noise { seed: 7, ..NOISY },
        pipeline: Pipeline::CoreNoPressure,
    },
];

/// What a case produced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigRun {
    pub digest: u64,
    pub frames: u64,
    pub windows: u32,
    pub slip_onsets: u64,
    /// The sequencer's state code after the last frame (`SeqState::code`).
    pub final_state: u8,
    /// The sensor model halted and ended the run early.
    pub sensor_halted: bool,
}

/// Why a case could not run (its configuration was refused): a short reason.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigCaseError(pub &'static str);

/// Runs one case. (Never inlined into the caller's frame: the rig is built in the replay's,
/// about 16 KB.)
#[inline(never)]
pub fn run(case: &RigCase) -> Result<RigRun, RigCaseError> {
    let scene = (case.scene)();
    let mut sensor_cfg = SensorModelConfig::RIG;
    sensor_cfg.noise = case.noise;
    let summary = match case.pipeline {
        Pipeline::Replay => run_frames_digest(&scene, RIG_FRAMES, &case.noise),
        Pipeline::CoreDefault => {
            let cfg = RigConfig::rig(25_600.0, true, true);
            let script = Script { button_at: [Some(0), Some(11_000)], estop: Some((9_000, 10_000)) };
            run_frames_digest_with(&scene, RIG_FRAMES, &sensor_cfg, &cfg, &script)
        }
        Pipeline::CoreNoPressure => {
            let mut timing = stickslip_model::rig::pipeline::Timing::RIG;
            timing.clamp_settle_s = 0.05;
            timing.drive_settle_s = 0.03;
            let template = stickslip_model::rig::lockstep::default_template();
            let cfg = RigConfig::for_scene(&template, 25_600.0, false, false, &timing);
            run_frames_digest_with(&scene, RIG_FRAMES, &sensor_cfg, &cfg, &Script::START)
        }
    };
    summary.map(|s| run_of(&s)).map_err(|_| RigCaseError("the rig or the sensor model refused the case"))
}

fn run_of(s: &ReplaySummary) -> RigRun {
    RigRun {
        digest: s.digest,
        frames: s.frames,
        windows: s.windows,
        slip_onsets: s.slip_onsets,
        final_state: s.final_state.code(),
        sensor_halted: s.sensor_halt.is_some(),
    }
}

/// The report line of one case, as printed by the target and rebuilt by the host:
/// `rig_digest <case> <16 hex digits> frames=<n> windows=<n> onsets=<n> final=<state code>`,
/// followed by ` sensor_halt` when the sensor model ended the run early.
pub struct RigReport<'a> {
    pub case: &'a str,
    pub run: &'a RigRun,
}

impl fmt::Display for RigReport<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = self.run;
        write!(
            f,
            "rig_digest {} {:016x} frames={} windows={} onsets={} final={}",
            self.case, r.digest, r.frames, r.windows, r.slip_onsets, r.final_state
        )?;
        if r.sensor_halted {
            write!(f, " sensor_halt")?;
        }
        Ok(())
    }
}
