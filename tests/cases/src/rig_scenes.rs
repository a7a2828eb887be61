//! The rig cases of the on-target cross-check: frames from the model through the sensor model,
//! calibration, estimator (contact, groan band-pass, window statistics, lockstep model) and
//! sequencer, digested.
//!
//! Run by the Cortex-M4F program `tests/on-target/src/bin/rig.rs` and by the host-side test
//! `tests/tests/on_target.rs` (this crate's library, built for the host), so both compute the
//! digests with the same code; it uses `core`, `stickslip_model` and the firmware's per-sample
//! logic, `crate::rig_core` (`firmware/rig-core/src/rig_core.rs`), and nothing else.
//!
//! Two kinds of case:
//! - `replay`: `stickslip_model::rig::replay::run_frames_digest` as it is (the shared
//!   pipeline `Rig::tick`, started at the first frame, recording to the end);
//! - `core`: the same frames through the firmware's `RigCore::sample` (the lockstep model
//!   swapped in at the record's start, timed phases without pressure transducers, the per-window
//!   pressures, the button and the e-stop), digested with the replay's own layout
//!   (`replay::digest_tick`, `replay::digest_window`) plus what the core adds: per frame the
//!   state before the tick and the record-start flag (u8 each); per window the record number
//!   (u32) and the pressure mean, min and max (2 x f32 each).

use core::fmt;
use core::mem::MaybeUninit;

use stickslip_model::digest::Fnv1a64;
use stickslip_model::rig::pipeline::{DigitalInputs, TickOutput};
use stickslip_model::rig::replay::{digest_tick, digest_window, run_frames_digest};
use stickslip_model::rig::sensor_model::{Noise, SensorModel, SensorModelConfig};
use stickslip_model::rig::sequencer::Command;
use stickslip_model::{Caliper, Scene};

use crate::rig_core::{button_command, CoreConfig, RigCore};

/// Frames per case: 0.5 s at 25.6 kHz, five 100 ms windows.
pub const RIG_FRAMES: u64 = 12_800;

/// The noise of the noisy cases: 0.5 m/s^2 rms on each accelerometer (1.3 counts), 0.005 bar
/// on each pressure.
pub const NOISY: Noise = Noise { accel_rms_m_s2: 0.5, pressure_rms_bar: 0.005, seed: 2024, adc_rms_counts: 0.0 };

/// Which pipeline a case runs.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Pipeline {
    /// `replay::run_frames_digest`.
    Replay,
    /// The firmware's `RigCore` with both features (pressure transducers, end-of-stroke switch),
    /// started at frame 0; an e-stop from frame 9 000 to 9 999, reset at frame 11 000.
    CoreDefault,
    /// The firmware's `RigCore` without pressure transducers (timed clamp 50 ms, drive 30 ms)
    /// and without an end-of-stroke switch, started at frame 0.
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

/// Runs one case. (The pipelines run in frames of their own, never inlined into the caller's:
/// their set-up takes tens of KB of stack, see `RigCore::init`.)
#[inline(never)]
pub fn run(case: &RigCase) -> Result<RigRun, RigCaseError> {
    let scene = (case.scene)();
    match case.pipeline {
        Pipeline::Replay => run_replay(&scene, &case.noise),
        Pipeline::CoreDefault => {
            let cfg = CoreConfig::rig(25_600.0, true, true);
            run_core(&scene, &case.noise, &cfg, true)
        }
        Pipeline::CoreNoPressure => {
            let mut cfg = CoreConfig::rig(25_600.0, false, false);
            cfg.timing.clamp_settle_s = 0.05;
            cfg.timing.drive_settle_s = 0.03;
            run_core(&scene, &case.noise, &cfg, false)
        }
    }
}

#[inline(never)]
fn run_replay(scene: &Scene, noise: &Noise) -> Result<RigRun, RigCaseError> {
    let s = run_frames_digest(scene, RIG_FRAMES, noise).map_err(|_| RigCaseError("replay refused"))?;
    Ok(RigRun {
        digest: s.digest,
        frames: s.frames,
        windows: s.windows,
        slip_onsets: s.slip_onsets,
        final_state: s.final_state.code(),
        sensor_halted: s.sensor_halt.is_some(),
    })
}

/// The frames of `scene` through `RigCore`: the button at frame 0 (start) and, with `estop`,
/// an e-stop held over frames 9 000..10 000 and the button again at frame 11 000 (reset).
#[inline(never)]
fn run_core(scene: &Scene, noise: &Noise, cfg: &CoreConfig, estop: bool) -> Result<RigRun, RigCaseError> {
    let mut sensor_cfg = SensorModelConfig::RIG;
    sensor_cfg.noise = *noise;
    let mut sensor = SensorModel::<f32>::new(scene, &sensor_cfg).map_err(|_| RigCaseError("sensor model refused"))?;
    let mut slot = MaybeUninit::uninit();
    let core = RigCore::init(&mut slot, cfg).map_err(|_| RigCaseError("rig core refused"))?;
    let mut d = Fnv1a64::new();
    let mut run = RigRun { digest: 0, frames: 0, windows: 0, slip_onsets: 0, final_state: 0, sensor_halted: false };
    for i in 0..RIG_FRAMES {
        let frame = match sensor.next_frame() {
            Ok(f) => f,
            Err(_) => {
                d.write_u8(0xFF);
                d.write_u64(i);
                run.sensor_halted = true;
                break;
            }
        };
        for c in frame.counts {
            d.write_bytes(&c.to_le_bytes());
        }
        let words = frame.counts;
        let frame = core.frame(&words);
        let digital = DigitalInputs { estop: estop && (9_000..10_000).contains(&i), end_of_stroke: false };
        let command: Option<Command> =
            if i == 0 || (estop && i == 11_000) { Some(button_command(core.state())) } else { None };
        let out = core.sample(&frame, &digital, command);
        let floor = if out.floor_ready { core.take_floor() } else { None };
        let tick = TickOutput {
            calibrated: out.calibrated,
            estimate: out.estimate,
            sequencer: out.sequencer,
            model_refused: None,
            floor,
        };
        digest_tick(&mut d, &tick);
        d.write_u8(out.before.code());
        d.write_u8(out.record_started as u8);
        if let Some(e) = out.estimate.contact.event {
            if e.kind == stickslip_model::rig::contact::ContactEventKind::StickToSlip {
                run.slip_onsets += 1;
            }
        }
        while let Some(w) = core.take_window() {
            d.write_u32(w.record);
            digest_window(&mut d, &w.report);
            for group in [&w.pressure.mean_bar, &w.pressure.min_bar, &w.pressure.max_bar] {
                for v in group {
                    d.write_f32(*v);
                }
            }
            run.windows += 1;
        }
        run.frames = i + 1;
        run.final_state = out.sequencer.state.code();
    }
    run.digest = d.finish();
    Ok(run)
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
