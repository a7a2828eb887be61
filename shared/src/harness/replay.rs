//! A synthetic rig run, digested: for the bit-identity test of the rig code on the desktop
//! and on the Cortex-M4F (the same digest on both means the same bits everywhere).
//!
//! [`run_frames_digest`] makes `frames` frames of a scene with the [`SensorModel`] (f32 stepper,
//! optional seeded noise) and feeds each to the [`Rig`] (calibration, estimator with the groan
//! filter, window statistics and the armed lockstep model, sequencer), the rig of the firmware.
//! A [`Script`] presses the button and the e-stop at given frames: by default the button at the
//! first frame (start) and nothing else, with the rig's sequencer recording to the end of the
//! run (its record length is the frame count); the sensor model is open loop, so the frames do
//! not depend on the valves. No allocation; the rig (two estimators) is built in place in the
//! caller's frame, the sensor model beside it (their sizes: `cargo test -p stickslip-model
//! --test rig_replay state_sizes -- --nocapture`).
//!
//! Every output of every frame is fed to a [`Fnv1a64`] digest, in this order and layout
//! (f32 as their bits, integers little-endian, see [`crate::digest`]):
//!
//! 1. the frame: six counts, u16 each (2 bytes);
//! 2. the calibrated frame: four accelerations and two pressures (f32), the saturation bits (u16);
//! 3. the estimate: fault (u8), regime (u8), v_r and a_rel (f32), the event (u8: 0 none, else
//!    1 + kind, then its sample index u64), the model (u8: 0 none; else 1, then x'' and the
//!    residual (f32), regime, onset, halted (u8 each)), window_ready (u8);
//! 4. the sequencer: state code, valve bits (actuator 1, band 2), command result code (0 none),
//!    changed (u8 each); the contact estimate's lead samples (u32); the floor designed in this
//!    sample (u8 0/1, then its samples (u32), mean, sigma and peak-to-peak per channel and of
//!    a_rel (f32), the thresholds: slip onset, stick level, v_tol, v_reversal (f32));
//! 5. the state before the tick (its code, u8) and the record-start flag (u8);
//! 6. each window closed (taken after the sample): the record it belongs to (u32), its report:
//!    index (u32), first sample (u64), samples, valid (u32), pp, rms, groan rms (4 x f32 each),
//!    stick fraction, frequency (f32), onsets, saturated, faulted (u32), non_finite (u8), the
//!    model part (u8 0/1, then samples (u32), stick fraction, frequency (f32), onsets (u32),
//!    residual rms (f32), halted (u8)); then the pressures' mean, min and max (2 x f32 each).
//!
//! A sensor model that halts (see [`Halt`]) ends the run early: the digest then takes the tag
//! 0xFF and the frame index (u64).

use core::mem::MaybeUninit;

use crate::rig::contact::{ContactEventKind, ContactThresholds};
use crate::rig::noise_floor::FloorReport;
use crate::rig::pipeline::{ClosedWindow, DigitalInputs, Rig, RigConfig, RigError, SampleOut, Timing};
use super::sensor_model::{Noise, SensorModel, SensorModelConfig, SensorModelError};
use crate::rig::sequencer::{button_command, RecordEnd, SeqState};
use crate::rig::window::WindowReport;
use crate::design::SAMPLE_RATE_HZ;
use crate::digest::Fnv1a64;
use crate::exact::Halt;
use crate::scene::Scene;

/// What a replay produced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReplaySummary {
    /// The FNV-1a digest of every output.
    pub digest: u64,
    /// Frames made and processed.
    pub frames: u64,
    /// Windows closed.
    pub windows: u32,
    /// Stick-to-slip onsets the estimator found.
    pub slip_onsets: u64,
    /// The sequencer's state after the last frame.
    pub final_state: SeqState,
    /// Set if the sensor model halted (a finding of the scene) and ended the run early.
    pub sensor_halt: Option<Halt>,
}

/// Why a replay could not run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReplayError {
    Sensor(SensorModelError),
    Rig(RigError),
}

impl From<SensorModelError> for ReplayError {
    fn from(e: SensorModelError) -> Self {
        ReplayError::Sensor(e)
    }
}
impl From<RigError> for ReplayError {
    fn from(e: RigError) -> Self {
        ReplayError::Rig(e)
    }
}

/// The operator's hand in a replay: the start/stop/reset button and the e-stop, by frame index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Script {
    /// Frames at which the button is pressed (its command is the sequencer's
    /// `button_command` of the state then).
    pub button_at: [Option<u64>; 2],
    /// Frames `[from, to)` over which the e-stop is held.
    pub estop: Option<(u64, u64)>,
}

impl Script {
    /// The button at the first frame (start), nothing else.
    pub const START: Script = Script { button_at: [Some(0), None], estop: None };
}

/// The rig configuration a replay of `frames` frames of `scene` runs with: the rig's
/// ([`RigConfig::for_scene`] at [`SAMPLE_RATE_HZ`], pressure transducers fitted, no
/// end-of-stroke switch) with `scene` as the model's pad, recording `frames` ticks.
pub fn replay_config(scene: &Scene, frames: u64) -> RigConfig {
    let mut cfg = RigConfig::for_scene(scene, SAMPLE_RATE_HZ, true, false, &Timing::RIG);
    cfg.sequencer.record = RecordEnd::Ticks(frames.clamp(1, u32::MAX as u64) as u32);
    cfg
}

/// Makes `frames` frames of `scene` (noise as given), runs them through the rig started at the
/// first frame and digests every output (see the module documentation for the layout).
pub fn run_frames_digest(scene: &Scene, frames: u64, noise: &Noise) -> Result<ReplaySummary, ReplayError> {
    let mut sensor_cfg = SensorModelConfig::RIG;
    sensor_cfg.noise = *noise;
    run_frames_digest_with(scene, frames, &sensor_cfg, &replay_config(scene, frames), &Script::START)
}

/// [`run_frames_digest`] with explicit sensor-model and rig configurations and script. Never
/// inlined: the rig is built in this frame.
#[inline(never)]
pub fn run_frames_digest_with(
    scene: &Scene,
    frames: u64,
    sensor_cfg: &SensorModelConfig,
    rig_cfg: &RigConfig,
    script: &Script,
) -> Result<ReplaySummary, ReplayError> {
    let mut sensor = SensorModel::<f32>::new(scene, sensor_cfg)?;
    let mut slot = MaybeUninit::uninit();
    let rig = Rig::init(&mut slot, rig_cfg)?;
    let mut d = Fnv1a64::new();
    let mut summary = ReplaySummary {
        digest: 0,
        frames: 0,
        windows: 0,
        slip_onsets: 0,
        final_state: SeqState::Idle,
        sensor_halt: None,
    };
    for i in 0..frames {
        let frame = match sensor.next_frame() {
            Ok(f) => f,
            Err(h) => {
                d.write_u8(0xFF);
                d.write_u64(i);
                summary.sensor_halt = Some(h);
                break;
            }
        };
        for c in frame.counts {
            d.write_bytes(&c.to_le_bytes());
        }
        // the six counts as the ADC words of one scan (without pressure transducers the rig
        // reads only the first four, its pressure channels read 0 bar)
        let frame = rig.frame(&frame.counts);
        let digital = DigitalInputs { estop: script.estop.is_some_and(|(a, b)| (a..b).contains(&i)), end_of_stroke: false };
        let command = if script.button_at.contains(&Some(i)) { Some(button_command(rig.state())) } else { None };
        let out = rig.sample(&frame, &digital, command);
        let floor = if out.floor_ready { rig.take_floor() } else { None };
        digest_sample(&mut d, &out, floor.as_ref());
        if let Some(e) = out.estimate.contact.event {
            if e.kind == ContactEventKind::StickToSlip {
                summary.slip_onsets += 1;
            }
        }
        while let Some(w) = rig.take_window() {
            digest_closed_window(&mut d, &w);
            summary.windows += 1;
        }
        summary.frames = i + 1;
        summary.final_state = out.sequencer.state;
    }
    summary.digest = d.finish();
    Ok(summary)
}

/// Feeds one sample's outputs (items 2 to 5 of the module documentation), with the floor this
/// sample designed, if any ([`Rig::take_floor`] after [`SampleOut::floor_ready`]).
pub fn digest_sample(d: &mut Fnv1a64, out: &SampleOut, floor: Option<&(FloorReport, ContactThresholds)>) {
    let c = &out.calibrated;
    for a in c.accel_m_s2 {
        d.write_f32(a);
    }
    for p in c.pressure_bar {
        d.write_f32(p);
    }
    d.write_bytes(&c.saturation.bits.to_le_bytes());
    let e = &out.estimate;
    d.write_u8(e.fault as u8);
    d.write_u8(e.contact.regime as u8);
    d.write_f32(e.contact.v_r_m_s);
    d.write_f32(e.contact.a_rel_m_s2);
    match e.contact.event {
        None => d.write_u8(0),
        Some(ev) => {
            d.write_u8(1 + ev.kind as u8);
            d.write_u64(ev.sample);
        }
    }
    match e.model {
        None => d.write_u8(0),
        Some(m) => {
            d.write_u8(1);
            d.write_f32(m.xdd_m_s2);
            d.write_f32(m.residual_m_s2);
            d.write_u8(m.regime as u8);
            d.write_u8(m.slip_onset as u8);
            d.write_u8(m.halted as u8);
        }
    }
    d.write_u8(e.window_ready as u8);
    let s = &out.sequencer;
    d.write_u8(s.state.code());
    d.write_u8(s.valves.actuator_open as u8 | (s.valves.band_open as u8) << 1);
    d.write_u8(s.command.map_or(0, |r| r.code()));
    d.write_u8(s.changed as u8);
    d.write_u32(e.contact.lead_samples);
    match floor {
        None => d.write_u8(0),
        Some((r, th)) => {
            d.write_u8(1);
            d.write_u32(r.samples);
            for group in [&r.mean_m_s2, &r.sigma_m_s2, &r.pp_m_s2] {
                for v in group {
                    d.write_f32(*v);
                }
            }
            for v in [th.slip_onset_m_s2, th.stick_max_m_s2, th.v_tol_m_s, th.v_reversal_m_s] {
                d.write_f32(v);
            }
        }
    }
    d.write_u8(out.before.code());
    d.write_u8(out.record_started as u8);
}

/// Feeds one closed window (item 6 of the module documentation).
pub fn digest_closed_window(d: &mut Fnv1a64, w: &ClosedWindow) {
    d.write_u32(w.record);
    digest_window(d, &w.report);
    for group in [&w.pressure.mean_bar, &w.pressure.min_bar, &w.pressure.max_bar] {
        for v in group {
            d.write_f32(*v);
        }
    }
}

/// Feeds one window report (the report part of item 6 of the module documentation).
pub fn digest_window(d: &mut Fnv1a64, w: &WindowReport) {
    d.write_u32(w.index);
    d.write_u64(w.first_sample);
    d.write_u32(w.samples);
    d.write_u32(w.valid_samples);
    for group in [&w.pp_m_s2, &w.rms_m_s2, &w.groan_rms_m_s2] {
        for v in group {
            d.write_f32(*v);
        }
    }
    d.write_f32(w.stick_fraction);
    d.write_f32(w.stick_slip_hz);
    d.write_u32(w.slip_onsets);
    d.write_u32(w.saturated_samples);
    d.write_u32(w.faulted_samples);
    d.write_u8(w.non_finite as u8);
    match &w.model {
        None => d.write_u8(0),
        Some(m) => {
            d.write_u8(1);
            d.write_u32(m.samples);
            d.write_f32(m.stick_fraction);
            d.write_f32(m.stick_slip_hz);
            d.write_u32(m.slip_onsets);
            d.write_f32(m.residual_rms_m_s2);
            d.write_u8(m.halt.is_some() as u8);
        }
    }
}
