//! The firmware's per-sample logic, without the HAL: ADC words to a frame, calibration,
//! estimator, sequencer, and what the firmware does around them (the lockstep model per
//! record, timed clamp/drive phases without pressure transducers, per-window pressure
//! statistics, the start/stop/reset button).
//!
//! The firmware calls [`RigCore::sample_words`] once per frame; the on-target programs of
//! `tests/on-target` count its instructions (bin `rig_count`, with the firmware's code
//! generation settings) and digest its outputs on the Cortex-M4F and on x86-64 (bin `rig`, and
//! the host test `tests/tests/on_target.rs`, with this crate built for the host). It uses
//! nothing but `core` and `stickslip_model` (no HAL, no logging); the Cargo features of the
//! firmware reach it as the runtime flags of [`CoreConfig`].
//!
//! **The lockstep model and the sample deadline.** Building a lockstep model is the f64 set-up
//! of `stickslip_model::rig::lockstep` (the exact flows: some 13 million instructions of soft
//! double precision, about 0.1 s), far more than one sample's time. [`RigCore::init`] therefore
//! builds, once at boot, a second estimator whose model is already started ("armed") from the
//! clamp setpoint pressure; when the sequencer enters Record, the running estimator is replaced
//! by a copy of the armed one (one `memcpy` of about 8 KB: some 10 000 instructions, that one
//! sample). So each record starts with a fresh
//! estimator: contact estimate in stick, filters at rest, window statistics from the record's
//! first sample and the model from its initial state (stick, at rest under the load). The
//! model's load is the clamp setpoint's (F_N = p_set A), not the pressure measured during Drive
//! as `stickslip_model::rig::pipeline::Rig` does: the sequencer only leaves Clamp within
//! `clamp_tolerance_bar` of the setpoint (0.1 of 5 bar: 2 % of F_N). The model stops when the
//! record ends.

use core::mem::MaybeUninit;
use core::ptr::addr_of_mut;

use stickslip_model::rig::calibration::{
    Adc, Calibrated, Calibration, Calibrator, Frame, PressureChannel, RIG_CALIBRATION,
};
use stickslip_model::rig::contact::ContactThresholds;
use stickslip_model::rig::estimator::{Estimator, EstimatorConfig, EstimatorSample};
use stickslip_model::rig::lockstep::LockstepModel;
use stickslip_model::rig::pipeline::DigitalInputs;
use stickslip_model::rig::sequencer::{
    Command, RecordEnd, SeqState, Sequencer, SequencerConfig, SequencerInputs, SequencerOutput,
};
use stickslip_model::rig::health::{ChannelHealth, HealthReport};
use stickslip_model::rig::noise_floor::{FloorReport, A_REL};
use stickslip_model::rig::window::WindowReport;
use stickslip_model::rig::{ConfigError, ACCEL_CHANNELS, ACTUATOR, BAND, CHANNELS, PRESSURE_CHANNELS};
use stickslip_model::{Scene, SceneError};

/// `f` (a function pointer), through a value the optimiser cannot see through: a call of the
/// result is never inlined. For the set-up calls into `stickslip_model` (the f64 set-up of the exact flows,
/// the band-pass design, validation). This crate is compiled for speed (opt-level 3, for the
/// per-sample path), the model crate for size; at the link-time pass a function called once
/// is inlined into its caller whatever its size and then optimised as the caller is, so
/// without this the whole set-up would be unrolled into [`RigCore::init`] (12 KB of flash
/// instead of about 3: the firmware's flash budget is 64 KB).
#[inline(always)]
fn cold<F: Copy>(f: F) -> F {
    core::hint::black_box(f)
}

/// Durations of the sequencer's phases [s] (converted to ticks, one tick per sample).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timing {
    /// Clamp must reach its setpoint within this.
    pub clamp_timeout_s: f64,
    /// The band line must reach the drive pressure within this.
    pub drive_timeout_s: f64,
    /// Record length without an end-of-stroke switch (set it below the band's stroke time).
    pub record_s: f64,
    /// With an end-of-stroke switch: the record lasts until the switch, which must come within
    /// this (else the sequencer faults with "record timeout").
    pub record_timeout_s: f64,
    /// Vent before Idle.
    pub vent_s: f64,
    /// Without pressure transducers: the actuator line is taken to be at its setpoint this long
    /// after the clamp valve opened (set it above the rig's measured fill time).
    pub clamp_settle_s: f64,
    /// Without pressure transducers: the band line is taken to be at the drive pressure this
    /// long after the band valve opened.
    pub drive_settle_s: f64,
}

impl Timing {
    /// The rig's defaults: the sequencer's own (`SequencerConfig::RIG`: clamp and drive within
    /// 2 s, record 1 s, vent 0.5 s), a 3 s stroke timeout, and 0.5 s / 0.3 s timed fills.
    pub const RIG: Timing = Timing {
        clamp_timeout_s: 2.0,
        drive_timeout_s: 2.0,
        record_s: 1.0,
        record_timeout_s: 3.0,
        vent_s: 0.5,
        clamp_settle_s: 0.5,
        drive_settle_s: 0.3,
    };
}

/// Everything [`RigCore`] needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoreConfig {
    /// Sampling rate per channel [Hz] (the rate the trigger timer really gives).
    pub fs_hz: f64,
    /// Window length [s] (rounded to whole samples).
    pub window_s: f64,
    /// The two pressure transducers are fitted and sampled (feature `pressure`).
    pub has_pressure: bool,
    /// The end-of-stroke switch is fitted (feature `end-of-stroke`).
    pub has_end_of_stroke: bool,
    pub calibration: Calibration,
    /// The pad the lockstep model runs (its F_N, V and dt are set from the clamp setpoint, the
    /// band speed and `fs_hz`).
    pub model_template: Scene,
    pub timing: Timing,
}

impl CoreConfig {
    /// The rig at `fs_hz`, 100 ms windows, the nominal calibration and the default scene.
    pub fn rig(fs_hz: f64, has_pressure: bool, has_end_of_stroke: bool) -> Self {
        CoreConfig {
            fs_hz,
            window_s: 0.1,
            has_pressure,
            has_end_of_stroke,
            calibration: RIG_CALIBRATION,
            model_template: stickslip_model::rig::lockstep::default_template(),
            timing: Timing::RIG,
        }
    }

    /// ADC words per frame: the calibration's `adc.oversample` scans of [`Self::adc_channels`]
    /// words.
    pub fn frame_words(&self) -> usize {
        self.calibration.adc.oversample as usize * self.adc_channels()
    }

    /// ADC words per scan: six, or the four accelerometers without pressure transducers.
    pub fn adc_channels(&self) -> usize {
        if self.has_pressure {
            CHANNELS
        } else {
            ACCEL_CHANNELS
        }
    }

    /// Whole ticks (samples) in `s` seconds, at least one.
    pub fn ticks(&self, s: f64) -> u32 {
        let t = s * self.fs_hz + 0.5;
        if t >= u32::MAX as f64 {
            u32::MAX
        } else if t >= 1.0 {
            t as u32
        } else {
            1
        }
    }

    /// The estimator's settings: the template's thresholds and band speed at `fs_hz`.
    pub fn estimator(&self) -> EstimatorConfig {
        let for_scene: fn(&Scene) -> EstimatorConfig = cold(EstimatorConfig::for_scene);
        let thresholds: fn(&Scene, f64) -> ContactThresholds = cold(ContactThresholds::for_scene);
        let mut e = for_scene(&self.model_template);
        e.fs_hz = self.fs_hz;
        e.contact = thresholds(&self.model_template, self.fs_hz);
        e.window_samples = self.ticks(self.window_s);
        e
    }

    /// The sequencer's settings: `SequencerConfig::RIG`'s pressures and limits, [`Timing`] in
    /// ticks; with the end-of-stroke switch a record lasts until the switch.
    pub fn sequencer(&self) -> SequencerConfig {
        let t = &self.timing;
        let mut s = SequencerConfig::RIG;
        s.clamp_timeout_ticks = self.ticks(t.clamp_timeout_s);
        s.drive_timeout_ticks = self.ticks(t.drive_timeout_s);
        s.vent_ticks = self.ticks(t.vent_s);
        s.record = if self.has_end_of_stroke {
            RecordEnd::EndOfStroke { timeout_ticks: self.ticks(t.record_timeout_s) }
        } else {
            RecordEnd::Ticks(self.ticks(t.record_s))
        };
        s
    }
}

/// Why the core could not be built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CoreError {
    Config(ConfigError),
    /// The lockstep model's scene (template at the clamp setpoint) was refused.
    Model(SceneError),
}

impl From<ConfigError> for CoreError {
    fn from(e: ConfigError) -> Self {
        CoreError::Config(e)
    }
}

/// Pressure statistics of one window [bar] (calibrated values; about 0 without transducers).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PressureWindow {
    /// Actuator line, band line.
    pub mean_bar: [f32; PRESSURE_CHANNELS],
    pub min_bar: [f32; PRESSURE_CHANNELS],
    pub max_bar: [f32; PRESSURE_CHANNELS],
}

#[derive(Clone, Copy, Debug)]
struct PressureSums {
    n: u32,
    sum: [f32; PRESSURE_CHANNELS],
    min: [f32; PRESSURE_CHANNELS],
    max: [f32; PRESSURE_CHANNELS],
}

impl PressureSums {
    const FRESH: PressureSums = PressureSums {
        n: 0,
        sum: [0.0; PRESSURE_CHANNELS],
        min: [f32::INFINITY; PRESSURE_CHANNELS],
        max: [f32::NEG_INFINITY; PRESSURE_CHANNELS],
    };

    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // sum, min and max of the same channel
    fn add(&mut self, p: &[f32; PRESSURE_CHANNELS]) {
        self.n += 1;
        for j in 0..PRESSURE_CHANNELS {
            self.sum[j] += p[j];
            if p[j] < self.min[j] {
                self.min[j] = p[j];
            }
            if p[j] > self.max[j] {
                self.max[j] = p[j];
            }
        }
    }

    fn report(&self) -> PressureWindow {
        let mut w = PressureWindow::default();
        if self.n > 0 {
            for j in 0..PRESSURE_CHANNELS {
                w.mean_bar[j] = self.sum[j] / self.n as f32;
                w.min_bar[j] = self.min[j];
                w.max_bar[j] = self.max[j];
            }
        }
        w
    }
}

/// A closed window: the record it belongs to (0 before the first record), the estimator's
/// report and the pressures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosedWindow {
    pub record: u32,
    pub report: WindowReport,
    pub pressure: PressureWindow,
}

/// What one sample produced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleOut {
    pub calibrated: Calibrated,
    pub estimate: EstimatorSample,
    /// The sequencer's state before this sample's tick.
    pub before: SeqState,
    pub sequencer: SequencerOutput,
    /// This sample entered Record: the estimator was replaced by a fresh one with the model.
    pub record_started: bool,
    /// This sample ended Clamp into Drive with a floor long enough to design from: the noise
    /// floor measured while clamped and the contact thresholds designed from it (they hold
    /// from here on, and in every record until the next clamp measures again) wait for
    /// [`RigCore::take_floor`]. A flag, not the floor itself: the 100 bytes of the floor copied
    /// out with every sample cost 160 instructions per sample (the `memcpy`).
    pub floor_ready: bool,
}

/// The command the single start/stop/reset button gives in a state: the sequencer's
/// (`stickslip_model::rig::sequencer::button_command`), re-exported for the firmware.
pub use stickslip_model::rig::sequencer::button_command;

/// The per-sample logic (see the module documentation).
#[derive(Debug)]
pub struct RigCore {
    calibrator: Calibrator,
    estimator: Estimator,
    /// A fresh estimator with the lockstep model started: copied in at each record's start.
    armed: Estimator,
    sequencer: Sequencer,
    has_pressure: bool,
    has_end_of_stroke: bool,
    /// The counts of 0 bar, standing in for the pressure channels that are not sampled.
    zero_bar_counts: [u16; PRESSURE_CHANNELS],
    /// Scans summed per frame (the calibration's `adc.oversample`).
    oversample: usize,
    clamp_setpoint_bar: f32,
    drive_start_bar: f32,
    clamp_settle_ticks: u32,
    drive_settle_ticks: u32,
    /// Outputs made in the sequencer's current state (its entering tick counts as 1).
    ticks_in_state: u32,
    /// Records started since boot; the windows of the running estimator belong to this one.
    record: u32,
    pressure: PressureSums,
    closed_pressure: PressureWindow,
    /// A window the previous estimator closed and nobody took before a record replaced it.
    pending: Option<ClosedWindow>,
    /// The scene the lockstep model runs in every record.
    model_scene: Scene,
    /// The contact thresholds and a_rel bias the last clamp's noise floor designed (each
    /// record's estimator starts with them).
    floor_design: Option<(ContactThresholds, f32)>,
    /// The last floor and its design, until [`RigCore::take_floor`].
    floor_out: Option<(FloorReport, ContactThresholds)>,
    /// The last floor designed from (for the channels' health in the records' windows).
    floor_last: Option<FloorReport>,
}

impl RigCore {
    /// Builds everything, including the armed lockstep model (the slow f64 set-up, once), in
    /// `slot`, and returns it.
    ///
    /// In place, because of the stack: the model's set-up (in `stickslip_model`) already moves
    /// its tables by value through several frames of its own, and a `RigCore` (about 16 KB, two
    /// estimators) built by value and moved into a static would add several copies of itself
    /// on top (measured on the emulated Cortex-M4F, bin `rig` of `tests/on-target`, which
    /// prints the stack this takes). Each part is written into its field once; the helpers are
    /// never inlined, so that their frames exist only while they run. On an error the slot is
    /// left uninitialised (a `RigCore` owns nothing that would need dropping).
    #[inline(never)]
    pub fn init<'a>(slot: &'a mut MaybeUninit<RigCore>, cfg: &CoreConfig) -> Result<&'a mut RigCore, CoreError> {
        let ecfg = cfg.estimator();
        let scfg = cfg.sequencer();
        let setpoint = scfg.clamp_setpoint_bar as f64;
        let count_for: fn(&PressureChannel, &Adc, f64) -> u16 = cold(PressureChannel::count_for);
        let scene: fn(&Scene, f64, f64, f64, f64) -> Scene = cold(<LockstepModel>::scene);
        let new_calibrator: fn(&Calibration) -> Result<Calibrator, ConfigError> = cold(Calibrator::new);
        let new_sequencer: fn(&SequencerConfig) -> Result<Sequencer, ConfigError> = cold(Sequencer::new);
        let start_model: fn(&mut Estimator, &Scene, f64) -> Result<(), SceneError> = cold(Estimator::start_model);
        let adc = &cfg.calibration.adc;
        // frame counts: the sum of the oversampled conversions
        let zero_bar_counts = [
            adc.frame_count(count_for(&cfg.calibration.pressure[ACTUATOR], adc, 0.0)),
            adc.frame_count(count_for(&cfg.calibration.pressure[BAND], adc, 0.0)),
        ];
        let model_scene = scene(&cfg.model_template, setpoint, ecfg.piston_area_m2, ecfg.band_speed_m_s, ecfg.fs_hz);
        let calibrator = new_calibrator(&cfg.calibration)?;
        let sequencer = new_sequencer(&scfg)?;
        let p = slot.as_mut_ptr();
        // SAFETY: `p` points to `slot`, valid for writes and exclusively ours. Every field is
        // written exactly once through a raw pointer (`all_fields` below fails to compile when
        // a field is added, as a reminder to write it here) before any reference to it is made,
        // and `assume_init_mut` comes after the last field; the one reference made before it
        // (`&mut (*p).armed`) is to a field already written. No field has drop glue, so an
        // early return (`?`) leaking the written fields is harmless.
        unsafe {
            addr_of_mut!((*p).calibrator).write(calibrator);
            addr_of_mut!((*p).sequencer).write(sequencer);
            addr_of_mut!((*p).has_pressure).write(cfg.has_pressure);
            addr_of_mut!((*p).has_end_of_stroke).write(cfg.has_end_of_stroke);
            addr_of_mut!((*p).zero_bar_counts).write(zero_bar_counts);
            addr_of_mut!((*p).oversample).write(cfg.calibration.adc.oversample as usize);
            addr_of_mut!((*p).clamp_setpoint_bar).write(scfg.clamp_setpoint_bar);
            addr_of_mut!((*p).drive_start_bar).write(scfg.drive_start_bar);
            addr_of_mut!((*p).clamp_settle_ticks).write(cfg.ticks(cfg.timing.clamp_settle_s));
            addr_of_mut!((*p).drive_settle_ticks).write(cfg.ticks(cfg.timing.drive_settle_s));
            addr_of_mut!((*p).ticks_in_state).write(0);
            addr_of_mut!((*p).record).write(0);
            addr_of_mut!((*p).pressure).write(PressureSums::FRESH);
            addr_of_mut!((*p).closed_pressure).write(PressureWindow::default());
            addr_of_mut!((*p).pending).write(None);
            addr_of_mut!((*p).model_scene).write(model_scene);
            addr_of_mut!((*p).floor_design).write(None);
            addr_of_mut!((*p).floor_out).write(None);
            addr_of_mut!((*p).floor_last).write(None);
            write_new_estimator(addr_of_mut!((*p).estimator), &ecfg)?;
            copy_estimator(addr_of_mut!((*p).armed), addr_of_mut!((*p).estimator));
            start_model(&mut (*p).armed, &cfg.model_template, setpoint).map_err(CoreError::Model)?;
            Ok(slot.assume_init_mut())
        }
    }

    /// Names every field (no `..`): a field added to `RigCore` breaks the build here until
    /// [`Self::init`] writes it too.
    #[allow(dead_code)]
    fn all_fields(&self) {
        let RigCore {
            calibrator: _,
            estimator: _,
            armed: _,
            sequencer: _,
            has_pressure: _,
            has_end_of_stroke: _,
            zero_bar_counts: _,
            oversample: _,
            clamp_setpoint_bar: _,
            drive_start_bar: _,
            clamp_settle_ticks: _,
            drive_settle_ticks: _,
            ticks_in_state: _,
            record: _,
            pressure: _,
            closed_pressure: _,
            pending: _,
            model_scene: _,
            floor_design: _,
            floor_out: _,
            floor_last: _,
        } = self;
    }

    /// [`Self::init`] by value (for tests: the value is moved, mind the stack).
    pub fn new(cfg: &CoreConfig) -> Result<Self, CoreError> {
        let mut slot = MaybeUninit::uninit();
        Self::init(&mut slot, cfg)?;
        // SAFETY: `init` returned Ok: every field is written.
        Ok(unsafe { slot.assume_init() })
    }

    pub fn estimator(&self) -> &Estimator {
        &self.estimator
    }
    pub fn sequencer(&self) -> &Sequencer {
        &self.sequencer
    }
    pub fn state(&self) -> SeqState {
        self.sequencer.state()
    }
    /// Records started since boot.
    pub fn record(&self) -> u32 {
        self.record
    }
    /// The scene the lockstep model runs in every record (F_N from the clamp setpoint).
    pub fn model_scene(&self) -> &Scene {
        &self.model_scene
    }
    /// The lockstep model's normal force at its start [N].
    pub fn model_normal_force(&self) -> f32 {
        self.armed.model().map_or(0.0, |m| m.normal_force())
    }

    /// One frame from the ADC words of one frame: `oversample` scans of `adc_channels()` words
    /// each (frame order), summed channel by channel (the decimation, see
    /// [`stickslip_model::rig::calibration`]: a boxcar of N; N - 1 additions per channel);
    /// without pressure transducers the pressure channels read 0 bar. A 12-bit word summed
    /// 16 times at most cannot overflow (the calibration's validation).
    #[inline]
    pub fn frame(&self, words: &[u16]) -> Frame {
        let mut counts = [0u16; CHANNELS];
        if self.has_pressure {
            counts.copy_from_slice(&words[..CHANNELS]);
            for scan in words[CHANNELS..].chunks_exact(CHANNELS).take(self.oversample - 1) {
                for (c, w) in counts.iter_mut().zip(scan) {
                    *c = c.wrapping_add(*w);
                }
            }
        } else {
            counts[..ACCEL_CHANNELS].copy_from_slice(&words[..ACCEL_CHANNELS]);
            for scan in words[ACCEL_CHANNELS..].chunks_exact(ACCEL_CHANNELS).take(self.oversample - 1) {
                for (c, w) in counts[..ACCEL_CHANNELS].iter_mut().zip(scan) {
                    *c = c.wrapping_add(*w);
                }
            }
            counts[ACCEL_CHANNELS..].copy_from_slice(&self.zero_bar_counts);
        }
        Frame { counts }
    }

    /// Without transducers, the pressures the sequencer is given: the actuator line at its
    /// setpoint `clamp_settle` after the clamp valve opened, the band line at the drive
    /// pressure `drive_settle` after the band valve opened; 0 bar on a vented line.
    #[inline(always)]
    fn timed_pressures(&self, state: SeqState) -> (f32, f32) {
        let t = self.ticks_in_state;
        match state {
            SeqState::Clamp => (if t >= self.clamp_settle_ticks { self.clamp_setpoint_bar } else { 0.0 }, 0.0),
            SeqState::Drive => {
                (self.clamp_setpoint_bar, if t >= self.drive_settle_ticks { self.drive_start_bar } else { 0.0 })
            }
            SeqState::Record => (self.clamp_setpoint_bar, self.drive_start_bar),
            SeqState::Idle | SeqState::Vent | SeqState::Fault(_) => (0.0, 0.0),
        }
    }

    /// What the firmware calls per frame: [`Self::frame`] and [`Self::sample`] of the ADC words
    /// of one frame (`CoreConfig::frame_words`). Never inlined: it is compiled (with everything it inlines) in this crate,
    /// at this crate's optimisation level.
    #[inline(never)]
    pub fn sample_words(&mut self, words: &[u16], digital: &DigitalInputs, command: Option<Command>) -> SampleOut {
        let frame = self.frame(words);
        self.sample(&frame, digital, command)
    }

    /// One sample: calibrate, estimate, tick the sequencer (the valves of its output are this
    /// sample's), start or stop the lockstep model with the record.
    #[inline]
    pub fn sample(&mut self, frame: &Frame, digital: &DigitalInputs, command: Option<Command>) -> SampleOut {
        let calibrated = self.calibrator.calibrate(frame);
        let estimate = self.estimator.update(&calibrated);
        self.pressure.add(&calibrated.pressure_bar);
        if estimate.window_ready {
            self.closed_pressure = self.pressure.report();
            self.pressure = PressureSums::FRESH;
        }
        let before = self.sequencer.state();
        let (actuator_bar, band_bar) = if self.has_pressure {
            (calibrated.pressure_bar[ACTUATOR], calibrated.pressure_bar[BAND])
        } else {
            self.timed_pressures(before)
        };
        let inputs = SequencerInputs {
            actuator_bar,
            band_bar,
            accel_saturated: calibrated.saturation.any_accel(),
            estop: digital.estop,
            end_of_stroke: self.has_end_of_stroke && digital.end_of_stroke,
            estimator_fault: estimate.fault,
        };
        let sequencer = self.sequencer.tick(&inputs, command);
        let mut record_started = false;
        let mut floor_ready = false;
        if sequencer.changed {
            self.ticks_in_state = 1;
            if sequencer.state == SeqState::Clamp {
                self.estimator.start_floor();
            } else if before == SeqState::Clamp {
                floor_ready = self.end_floor(sequencer.state == SeqState::Drive);
            }
            if sequencer.state == SeqState::Record {
                self.start_record();
                record_started = true;
            } else if before == SeqState::Record {
                self.estimator.stop_model();
            }
        } else {
            self.ticks_in_state = self.ticks_in_state.saturating_add(1);
        }
        SampleOut { calibrated, estimate, before, sequencer, record_started, floor_ready }
    }

    /// Clamp ended: into Drive, the floor designs the contact thresholds (kept for the
    /// records' estimators, and for [`Self::take_floor`]); otherwise it is dropped. True if a
    /// design was made.
    #[inline(never)]
    fn end_floor(&mut self, into_drive: bool) -> bool {
        if !into_drive {
            self.estimator.cancel_floor();
            return false;
        }
        let design = self.estimator.finish_floor(self.calibrator.a_rel_quantum_m_s2());
        if let Some((r, th)) = design {
            self.floor_design = Some((th, r.mean_m_s2[A_REL]));
            self.floor_last = Some(r);
        }
        self.floor_out = design;
        design.is_some()
    }

    /// The last floor designed (see [`SampleOut::floor_ready`]), once.
    pub fn take_floor(&mut self) -> Option<(FloorReport, ContactThresholds)> {
        self.floor_out.take()
    }

    /// The accelerometers' health over a closed window ([`stickslip_model::rig::health`]):
    /// flat channels, and, once a clamp has measured the floor, channels noisier than the
    /// signal. Saturation is not judged here: on the rig it is a sequencer fault (valves
    /// vented, a `state` record with cause `accel_saturation`).
    pub fn window_health(&self, w: &WindowReport) -> HealthReport {
        let floor = self.floor_last.as_ref();
        HealthReport::new(core::array::from_fn(|c| {
            ChannelHealth::assess(w.pp_m_s2[c], w.rms_m_s2[c], false, floor.map(|f| (f.mean_m_s2[c], f.sigma_m_s2[c])))
        }))
    }

    /// The running estimator gives way to a copy of the armed one; a window it closed and
    /// nobody took yet is kept for [`Self::take_window`].
    #[inline(never)]
    fn start_record(&mut self) {
        if let Some(report) = self.estimator.take_window() {
            self.pending = Some(ClosedWindow { record: self.record, report, pressure: self.closed_pressure });
        }
        // SAFETY: two distinct fields of `self`: valid, aligned, not overlapping.
        unsafe { copy_estimator(&mut self.estimator, &self.armed) };
        if let Some((th, bias)) = self.floor_design {
            self.estimator.set_contact(th, bias);
        }
        self.pressure = PressureSums::FRESH;
        self.record = self.record.wrapping_add(1);
    }

    /// The last closed window, once (the window's divisions and square roots are taken here:
    /// call it outside the per-sample loop, before the next window closes).
    #[inline(never)]
    pub fn take_window(&mut self) -> Option<ClosedWindow> {
        if let Some(w) = self.pending.take() {
            return Some(w);
        }
        let pressure = self.closed_pressure;
        self.estimator.take_window().map(|report| ClosedWindow { record: self.record, report, pressure })
    }

    /// Closed windows replaced before they were taken (of the running estimator).
    pub fn windows_dropped(&self) -> u32 {
        self.estimator.windows_dropped()
    }
}

/// Writes `Estimator::new(cfg)` to `dst`, in a frame of its own (see [`RigCore::init`]), built
/// in place (`Estimator::new_in`): returned by value and then written, it went through copies on
/// the stack (a 41.7 KB frame with the `model2` lockstep model, 81.9 KB once its stepper had
/// the near operators; now under 1 KB, `arm-none-eabi-objdump -d` of bin `rig`).
///
/// # Safety
/// `dst` must be valid for writes.
#[inline(never)]
unsafe fn write_new_estimator(dst: *mut Estimator, cfg: &EstimatorConfig) -> Result<(), ConfigError> {
    // SAFETY: the caller's promise; MaybeUninit<Estimator> has Estimator's layout.
    let slot = unsafe { &mut *(dst as *mut core::mem::MaybeUninit<Estimator>) };
    Estimator::new_in(slot, cfg).map(|_| ())
}

/// Copies the estimator at `src` to `dst`, bit for bit: what `Clone` does for it (it is plain
/// data: numbers, arrays, enums and options of them; no references, no heap, no drop glue,
/// which the assertion below keeps checking), in one `memcpy` of about 8 KB instead of a
/// field-by-field clone through a temporary (1.8 KB of code, and twice the copying at the
/// start of every record).
///
/// # Safety
/// `src` must be valid for reads, `dst` valid for writes, both aligned, not overlapping.
#[inline(never)]
unsafe fn copy_estimator(dst: *mut Estimator, src: *const Estimator) {
    const _: () = assert!(!core::mem::needs_drop::<Estimator>(), "Estimator must stay plain data");
    // SAFETY: the caller's promise; a bitwise copy of plain data is a valid value.
    unsafe { core::ptr::copy_nonoverlapping(src, dst, 1) };
}

/// The decimation of one frame's ADC words ([`RigCore::frame`]), its calibration and one
/// estimator update: the per-sample path without the sequencer and without the lockstep model
/// (the instruction count's path A; `RigCore::sample_words` makes the same calls). `core` only
/// lends its frame layout (oversampling, pressure channels). Never inlined: compiled in this
/// crate, like `sample_words`.
#[inline(never)]
pub fn calibrate_estimate(
    core: &RigCore,
    calibrator: &Calibrator,
    estimator: &mut Estimator,
    words: &[u16],
) -> (Calibrated, EstimatorSample) {
    let frame = core.frame(words);
    let calibrated = calibrator.calibrate(&frame);
    let estimate = estimator.update(&calibrated);
    (calibrated, estimate)
}
