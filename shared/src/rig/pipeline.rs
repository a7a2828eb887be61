//! The rig's per-sample chain, one type for every caller: [`Rig`] takes one frame (or the ADC
//! words of one frame), the digital inputs and an optional command, and runs calibration,
//! estimator and sequencer, with what a rig does around them: the lockstep model per record,
//! the pressures per window, the noise floor of the clamped phase. The firmware runs it (through
//! the opt-level-3 shim `firmware/rig-core`), and so do the replay digests
//! ([`crate::harness::replay`]), the host == Cortex-M4F cross-checks and the log session of
//! `tests/cases`. A recording (`analyze`, and the virtual rig `sil`, whose frames are
//! calibrated by the same [`Calibrator`]) is played back through the same type: its rows,
//! already calibrated, go through [`Rig::play`], steps 2 and 3 below, of a rig made by
//! [`Rig::for_recording`] (one record from the first row, the floor of the recording's quiet
//! stretch, no sequencer, no model).
//!
//! Per sample ([`Rig::sample`]):
//! 1. [`Calibrator::calibrate`]: counts to m/s^2 and bar, saturation flags;
//! 2. [`Estimator::update`]: contact, groan band-pass, window statistics, lockstep model;
//! 3. the pressures' window statistics (mean, min, max per line) (2 and 3: [`Rig::play`]);
//! 4. [`Sequencer::tick`]: faults, the command, the state's progress, the valves. Without
//!    pressure transducers the sequencer's Clamp and Drive are timed
//!    ([`super::sequencer::PhaseEnd::Timed`]) and the pressure channels read 0 bar;
//! 5. the state's change: Clamp starts the noise floor; Clamp into Drive designs the contact
//!    thresholds from it ([`Rig::take_floor`]); Record starts with a fresh estimator whose model
//!    is already built ("armed", below) and restarts from its initial state; leaving Record
//!    stops the model.
//!
//! **The lockstep model and the sample deadline.** Building a lockstep model is the f64 set-up
//! of [`super::lockstep`] (the exact flows in soft double precision on the Cortex-M4F), far
//! more than one sample's time. [`Rig::init`]
//! therefore builds the model once ("armed"), from the clamp setpoint pressure, in the running
//! estimator, where it stays (one set of tables in the rig), and keeps a fresh estimator
//! without a model beside it; when the sequencer enters Record, the fresh estimator's parts are
//! copied into the running one and its model is restarted from its initial state (a few words
//! of state written, no tables copied; that one sample: the `b_record_start` class of
//! `scripts/count-instructions.sh` counts it). So each record starts with a fresh estimator: contact estimate in stick
//! (with the thresholds the last clamp designed), filters at rest, window statistics from the
//! record's first sample and the model from its initial state (stick, at rest under the load).
//! The model's load is the clamp setpoint's (F_N = p_set A): the sequencer only leaves a
//! pressure-checked Clamp within `clamp_tolerance_bar` of the setpoint (0.1 of 5 bar: 2 % of
//! F_N). A scene the setpoint makes invalid is refused by [`Rig::init`], before any sample.

use core::mem::MaybeUninit;

use super::calibration::{Calibrated, Calibration, Calibrator, Frame, PressureChannel, RIG_CALIBRATION};
use super::contact::ContactThresholds;
use super::estimator::{Estimator, EstimatorConfig, EstimatorSample};
use super::health::{ChannelHealth, HealthReport};
use super::lockstep::{LockstepModel, NoModel};
use super::noise_floor::{FloorReport, A_REL};
use super::sequencer::{
    Command, PhaseEnd, RecordEnd, SeqState, Sequencer, SequencerConfig, SequencerInputs, SequencerOutput,
};
use super::window::WindowReport;
use super::{check, ConfigError, ACCEL_CHANNELS, ACTUATOR, BAND, CHANNELS, PRESSURE_CHANNELS};
use crate::scene::{Scene, SceneError};
use crate::stats::Extremes;

/// The digital inputs of one sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DigitalInputs {
    pub estop: bool,
    pub end_of_stroke: bool,
}

/// Durations of the rig's phases and windows [s] (turned into ticks, one tick per sample, by
/// [`RigConfig::for_scene`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timing {
    /// Window length of the statistics.
    pub window_s: f64,
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
    /// Without pressure transducers: Clamp lasts this long, the actuator line then taken to be
    /// at its setpoint (set it above the rig's measured fill time).
    pub clamp_settle_s: f64,
    /// Without pressure transducers: Drive lasts this long, the band line then taken to be at
    /// the drive pressure.
    pub drive_settle_s: f64,
}

impl Timing {
    /// The rig's defaults: 100 ms windows, the sequencer's own durations
    /// (`SequencerConfig::RIG`: clamp and drive within 2 s, record 1 s, vent 0.5 s), a 3 s
    /// stroke timeout, and 0.5 s / 0.3 s timed fills.
    pub const RIG: Timing = Timing {
        window_s: crate::design::WINDOW_S,
        clamp_timeout_s: 2.0,
        drive_timeout_s: 2.0,
        record_s: 1.0,
        record_timeout_s: 3.0,
        vent_s: 0.5,
        clamp_settle_s: 0.5,
        drive_settle_s: 0.3,
    };
}

/// Whole ticks (samples) in `s` seconds at `fs_hz`, at least one.
pub fn ticks(fs_hz: f64, s: f64) -> u32 {
    let t = s * fs_hz + 0.5;
    if t >= u32::MAX as f64 {
        u32::MAX
    } else if t >= 1.0 {
        t as u32
    } else {
        1
    }
}

/// Everything [`Rig`] needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigConfig {
    pub calibration: Calibration,
    pub estimator: EstimatorConfig,
    /// Its `phase_end` must be [`PhaseEnd::Timed`] without pressure transducers, and its
    /// `record` [`RecordEnd::Ticks`] without the end-of-stroke switch.
    pub sequencer: SequencerConfig,
    /// The two pressure transducers are fitted and sampled (the firmware's feature
    /// `pressure`); without them a frame's pressure channels read 0 bar.
    pub has_pressure: bool,
    /// The end-of-stroke switch is fitted (feature `end-of-stroke`); without it its input is
    /// ignored.
    pub has_end_of_stroke: bool,
    /// The pad the lockstep model runs; its F_N, V and dt are set from the clamp setpoint,
    /// the estimator's band speed and its sampling rate.
    pub model_template: Scene,
}

impl RigConfig {
    /// The rig at `fs_hz` with the lockstep model's default pad
    /// ([`super::lockstep::default_template`]), [`Timing::RIG`] and the nominal calibration.
    pub fn rig(fs_hz: f64, has_pressure: bool, has_end_of_stroke: bool) -> Self {
        Self::for_scene(&super::lockstep::default_template(), fs_hz, has_pressure, has_end_of_stroke, &Timing::RIG)
    }

    /// The rig whose model pad is `template`, at `fs_hz`: the estimator's settings for the
    /// template (its thresholds and band speed) at that rate; `SequencerConfig::RIG`'s
    /// pressures and limits with `timing` in ticks, timed phases without pressure transducers,
    /// and with the end-of-stroke switch a record that lasts until the switch.
    pub fn for_scene(template: &Scene, fs_hz: f64, has_pressure: bool, has_end_of_stroke: bool, timing: &Timing) -> Self {
        let t = |s: f64| ticks(fs_hz, s);
        let mut estimator = EstimatorConfig::for_scene(template);
        estimator.fs_hz = fs_hz;
        estimator.contact = ContactThresholds::for_scene(template, fs_hz);
        estimator.window_samples = t(timing.window_s);
        let mut sequencer = SequencerConfig::RIG;
        sequencer.clamp_timeout_ticks = t(timing.clamp_timeout_s);
        sequencer.drive_timeout_ticks = t(timing.drive_timeout_s);
        sequencer.vent_ticks = t(timing.vent_s);
        sequencer.record = if has_end_of_stroke {
            RecordEnd::EndOfStroke { timeout_ticks: t(timing.record_timeout_s) }
        } else {
            RecordEnd::Ticks(t(timing.record_s))
        };
        sequencer.phase_end = if has_pressure {
            PhaseEnd::Pressure
        } else {
            PhaseEnd::Timed { clamp_ticks: t(timing.clamp_settle_s), drive_ticks: t(timing.drive_settle_s) }
        };
        RigConfig {
            calibration: RIG_CALIBRATION,
            estimator,
            sequencer,
            has_pressure,
            has_end_of_stroke,
            model_template: *template,
        }
    }

    /// A recording's playback ([`Rig::for_recording`]): `estimator` as given, the nominal
    /// calibration, no transducers or switch, timed phases (none of which runs) and the lockstep
    /// model's default pad (never started).
    pub fn recording(estimator: EstimatorConfig) -> Self {
        let mut cfg = Self::rig(estimator.fs_hz, false, false);
        cfg.estimator = estimator;
        cfg
    }

    /// What the parts fitted allow: pressure-checked phases need the transducers, a record
    /// that waits for the end of stroke needs the switch.
    pub fn validate(&self) -> Result<(), ConfigError> {
        check(
            self.has_pressure || self.sequencer.phase_end != PhaseEnd::Pressure,
            "sequencer.phase_end",
            "pressure-checked phases need the pressure transducers (has_pressure); use timed phases",
            0.0,
        )?;
        check(
            self.has_end_of_stroke || !matches!(self.sequencer.record, RecordEnd::EndOfStroke { .. }),
            "sequencer.record",
            "a record until the end of stroke needs the end-of-stroke switch (has_end_of_stroke)",
            0.0,
        )
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
}

/// Why a rig could not be built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RigError {
    Config(ConfigError),
    /// The lockstep model's scene (template at the clamp setpoint) was refused.
    Model(SceneError),
}

impl From<ConfigError> for RigError {
    fn from(e: ConfigError) -> Self {
        RigError::Config(e)
    }
}

impl core::fmt::Display for RigError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            RigError::Config(e) => write!(f, "{e}"),
            RigError::Model(e) => write!(f, "the lockstep model's scene at the clamp setpoint: {e}"),
        }
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
    extremes: Extremes<f32, PRESSURE_CHANNELS>,
}

impl PressureSums {
    const FRESH: PressureSums = PressureSums {
        n: 0,
        sum: [0.0; PRESSURE_CHANNELS],
        extremes: Extremes::<f32, PRESSURE_CHANNELS>::EMPTY,
    };

    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // sum and extremes of the same channel
    fn add(&mut self, p: &[f32; PRESSURE_CHANNELS]) {
        self.n += 1;
        for j in 0..PRESSURE_CHANNELS {
            self.sum[j] += p[j];
            self.extremes.take(j, p[j]);
        }
    }

    #[inline]
    fn report(&self) -> PressureWindow {
        let mut w = PressureWindow::default();
        if self.n > 0 {
            for j in 0..PRESSURE_CHANNELS {
                w.mean_bar[j] = self.sum[j] / self.n as f32;
                w.min_bar[j] = self.extremes.min[j];
                w.max_bar[j] = self.extremes.max[j];
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
    /// [`Rig::take_floor`]. A flag, not the floor itself: the floor copied out with every
    /// sample would put a `memcpy` on the per-sample path (whose instructions
    /// `scripts/count-instructions.sh` counts).
    pub floor_ready: bool,
}

/// The per-sample logic (see the module documentation).
///
/// (`repr(C)`: the fields in this order, the per-sample ones first, the fresh estimator a
/// record starts from last: the per-sample path's offsets as small as they were when the
/// compiler laid out two whole estimators; `scripts/count-instructions.sh`, path B.)
#[derive(Clone, Debug)]
#[repr(C)]
pub struct Rig {
    calibrator: Calibrator,
    /// The running estimator. Its lockstep model (the one set of tables, built once by
    /// [`Self::init`]) runs in the records and is restarted at each record's start.
    estimator: Estimator,
    sequencer: Sequencer,
    has_pressure: bool,
    has_end_of_stroke: bool,
    /// The counts of 0 bar, standing in for the pressure channels that are not sampled.
    zero_bar_counts: [u16; PRESSURE_CHANNELS],
    /// Scans summed per frame (the calibration's `adc.oversample`).
    oversample: usize,
    /// Records started since boot; the windows of the running estimator belong to this one.
    record: u32,
    pressure: PressureSums,
    closed_pressure: PressureWindow,
    /// A window the previous estimator closed and nobody took before a record replaced it.
    pending: Option<ClosedWindow>,
    /// The scene the lockstep model runs in every record.
    model_scene: Scene,
    /// The last clamp's noise floor that designed thresholds, and that design: each record's
    /// estimator starts with its thresholds and a_rel's mean as the bias, the records'
    /// windows are judged against its channels (`window_health`).
    floor: Option<(FloorReport, ContactThresholds)>,
    /// `floor` is new and [`Rig::take_floor`] has not given it out yet.
    floor_unread: bool,
    /// A fresh estimator without a model: copied in at each record's start
    /// ([`Estimator::restart_from`]).
    armed: Estimator<NoModel>,
    /// The lockstep model's normal force at its start [N] (0 without a model).
    model_normal_force: f32,
}

impl Rig {
    /// Builds everything, including the armed lockstep model (the slow f64 set-up, once), in
    /// `slot`, and returns it.
    ///
    /// In place, because of the stack: the model's set-up ([`super::lockstep`]) already moves
    /// its tables by value through several frames of its own, and a `Rig` (two estimators, one
    /// with the model) built by value and moved into a static would add several copies of itself
    /// on top (measured on the emulated Cortex-M4F, bin `rig` of `tests/on-target`, which
    /// prints the stack this takes). The small parts are built first, then one struct literal
    /// is written into the slot, the two estimators built in it; the model is started there, in
    /// the running estimator, and stopped until a record restarts it. On an error the slot may
    /// be left written (a `Rig` owns nothing that would need dropping).
    #[inline(never)]
    pub fn init<'a>(slot: &'a mut MaybeUninit<Rig>, cfg: &RigConfig) -> Result<&'a mut Rig, RigError> {
        Self::build(slot, cfg, true)
    }

    /// Everything, in `slot` (see [`Self::init`]); the lockstep model only if `armed_model`.
    #[inline(always)]
    fn build<'a>(slot: &'a mut MaybeUninit<Rig>, cfg: &RigConfig, armed_model: bool) -> Result<&'a mut Rig, RigError> {
        cfg.validate()?;
        let ecfg = &cfg.estimator;
        let setpoint = cfg.sequencer.clamp_setpoint_bar as f64;
        let adc = &cfg.calibration.adc;
        // frame counts: the sum of the oversampled conversions
        let zero_bar_counts = [
            adc.frame_count(PressureChannel::count_for(&cfg.calibration.pressure[ACTUATOR], adc, 0.0)),
            adc.frame_count(PressureChannel::count_for(&cfg.calibration.pressure[BAND], adc, 0.0)),
        ];
        let model_scene =
            <LockstepModel>::scene(&cfg.model_template, setpoint, ecfg.piston_area_m2, ecfg.band_speed_m_s, ecfg.fs_hz);
        let calibrator = Calibrator::new(&cfg.calibration)?;
        let sequencer = Sequencer::new(&cfg.sequencer)?;
        let groan = Estimator::checked_groan(ecfg)?;
        // One struct literal written into the slot: built in place, the estimators included
        // (`Estimator::fresh` is inlined here), never moved through the stack.
        let rig = slot.write(Rig {
            calibrator,
            estimator: Estimator::fresh(ecfg, groan),
            armed: Estimator::fresh(ecfg, groan),
            model_normal_force: 0.0,
            sequencer,
            has_pressure: cfg.has_pressure,
            has_end_of_stroke: cfg.has_end_of_stroke,
            zero_bar_counts,
            oversample: cfg.calibration.adc.oversample as usize,
            record: 0,
            pressure: PressureSums::FRESH,
            closed_pressure: PressureWindow::default(),
            pending: None,
            model_scene,
            floor: None,
            floor_unread: false,
        });
        if armed_model {
            // built once, where it stays: stopped until a record restarts it
            rig.estimator.start_model(&cfg.model_template, setpoint).map_err(RigError::Model)?;
            rig.model_normal_force = rig.estimator.model().map_or(0.0, |m| m.normal_force());
            rig.estimator.stop_model();
        }
        Ok(rig)
    }

    /// The rig that plays a recording back: a recording is one record, already made, its rows
    /// already in m/s^2 and bar. Its rows go through [`Self::play`], the chain of
    /// [`Self::sample`] between the calibration and the sequencer (the estimator, the window
    /// statistics of the pressures, the window hand-off), from the first row on: record 1
    /// starts here, as [`Self::sample`] starts a record when the sequencer enters Record
    /// (a copy of the armed estimator with the last floor's thresholds). No sequencer runs (the
    /// recording's phases are over) and no lockstep model (a recording has no setpoint).
    /// `floor`: the noise floor and the contact thresholds designed from the recording's quiet
    /// stretch (the clamp's part on the rig), held as the clamp's are (for
    /// [`Self::window_health`] too); `None`: `cfg.estimator.contact` as given. `analyze` and the
    /// virtual rig (`sil`) run their rows through this.
    pub fn for_recording(cfg: &RigConfig, floor: Option<(FloorReport, ContactThresholds)>) -> Result<Rig, RigError> {
        let mut slot = MaybeUninit::uninit();
        let rig = Self::build(&mut slot, cfg, false)?;
        rig.floor = floor;
        rig.start_record();
        Ok(rig.clone())
    }

    /// [`Self::init`] by value (for tests: the value is moved, mind the stack).
    pub fn new(cfg: &RigConfig) -> Result<Self, RigError> {
        let mut slot = MaybeUninit::uninit();
        Ok(Self::init(&mut slot, cfg)?.clone())
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
        self.model_normal_force
    }

    /// One frame from the ADC words of one frame: `oversample` scans of `adc_channels()` words
    /// each (frame order), summed channel by channel (the decimation, see
    /// [`super::calibration`]: a boxcar of N); without pressure transducers the pressure
    /// channels read 0 bar. See [`decimate`] for how the sum is taken.
    #[inline]
    pub fn frame(&self, words: &[u16]) -> Frame {
        let mut counts = [0u16; CHANNELS];
        if self.has_pressure {
            counts = decimate::<CHANNELS, { CHANNELS / 2 }>(words, self.oversample);
        } else {
            counts[..ACCEL_CHANNELS]
                .copy_from_slice(&decimate::<ACCEL_CHANNELS, { ACCEL_CHANNELS / 2 }>(words, self.oversample));
            counts[ACCEL_CHANNELS..].copy_from_slice(&self.zero_bar_counts);
        }
        Frame { counts }
    }

    /// One sample: calibrate, estimate, tick the sequencer (the valves of its output are this
    /// sample's), start or stop the lockstep model with the record.
    #[inline]
    pub fn sample(&mut self, frame: &Frame, digital: &DigitalInputs, command: Option<Command>) -> SampleOut {
        let calibrated = self.calibrator.calibrate(frame);
        let estimate = self.play(&calibrated);
        let before = self.sequencer.state();
        let inputs = SequencerInputs {
            actuator_bar: calibrated.pressure_bar[ACTUATOR],
            band_bar: calibrated.pressure_bar[BAND],
            accel_saturated: calibrated.saturation.any_accel(),
            estop: digital.estop,
            end_of_stroke: self.has_end_of_stroke && digital.end_of_stroke,
            estimator_fault: estimate.fault,
        };
        let sequencer = self.sequencer.tick(&inputs, command);
        let mut record_started = false;
        let mut floor_ready = false;
        if sequencer.changed {
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
        }
        SampleOut { calibrated, estimate, before, sequencer, record_started, floor_ready }
    }

    /// One calibrated sample through the estimator and the pressures' window statistics; a
    /// window that closes waits for [`Self::take_window`]. The part of [`Self::sample`] that does
    /// not depend on where the sample came from: a recording's rows run through it alone
    /// ([`Self::for_recording`]).
    #[inline(always)]
    pub fn play(&mut self, calibrated: &Calibrated) -> EstimatorSample {
        self.pressure.add(&calibrated.pressure_bar);
        let estimate = self.estimator.update(calibrated);
        if estimate.window_ready {
            self.closed_pressure = self.pressure.report();
            self.pressure = PressureSums::FRESH;
        }
        estimate
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
        if design.is_some() {
            self.floor = design;
        }
        self.floor_unread = design.is_some();
        self.floor_unread
    }

    /// The last floor designed (see [`SampleOut::floor_ready`]), once.
    pub fn take_floor(&mut self) -> Option<(FloorReport, ContactThresholds)> {
        if core::mem::take(&mut self.floor_unread) {
            self.floor
        } else {
            None
        }
    }

    /// The accelerometers' health over a closed window ([`super::health`]):
    /// flat channels, and, once a clamp has measured the floor, channels noisier than the
    /// signal. Saturation is not judged here: on the rig it is a sequencer fault (valves
    /// vented, a `state` record with cause `accel_saturation`).
    pub fn window_health(&self, w: &WindowReport) -> HealthReport {
        let floor = self.floor.as_ref().map(|(r, _)| r);
        HealthReport::new(core::array::from_fn(|c| {
            ChannelHealth::assess(w.pp_m_s2[c], w.rms_m_s2[c], false, floor.map(|f| (f.mean_m_s2[c], f.sigma_m_s2[c])))
        }))
    }

    /// The running estimator restarts from the fresh one, its model from its initial state
    /// ([`Estimator::restart_from`]); a window it closed and nobody took yet is kept for
    /// [`Self::take_window`].
    #[inline(never)]
    fn start_record(&mut self) {
        if let Some(report) = self.estimator.take_window() {
            self.pending = Some(ClosedWindow { record: self.record, report, pressure: self.closed_pressure });
        }
        // The fresh estimator's parts copied in (plain data, no model: about 1 KB) and the
        // running estimator's own model restarted from its initial state: its tables stay
        // where they are, no stepper is copied.
        self.estimator.restart_from(&self.armed);
        if let Some((r, th)) = &self.floor {
            self.estimator.set_contact(*th, r.mean_m_s2[A_REL]);
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

/// The sum, channel by channel, of the first `scans` scans of `N` words each in `words` (the
/// decimation of [`Rig::frame`]), two channels per 32-bit addition: channels 2k and 2k + 1 of a
/// scan are packed as the low and high half of one `u32` (`P` = N / 2 of them) and the packed
/// words summed. The halves cannot carry into each other: a converter word is 12 bits at most
/// (the STM32F4's right-aligned data register) and the calibration refuses an `oversample` whose
/// sum could pass 65535 (`adc.oversample`), so each half's sum is the channel's exact sum, as
/// the `u16` additions of one channel at a time give it (`decimation_sums_are_the_channels_own`
/// tests both ways). Half the additions, and the two halves are loaded as one word
/// where the compiler combines the loads.
#[inline(always)]
fn decimate<const N: usize, const P: usize>(words: &[u16], scans: usize) -> [u16; N] {
    let mut sums = [0u32; P];
    for scan in words.chunks_exact(N).take(scans) {
        for (k, s) in sums.iter_mut().enumerate() {
            *s = s.wrapping_add(u32::from(scan[2 * k]) | u32::from(scan[2 * k + 1]) << 16);
        }
    }
    let mut counts = [0u16; N];
    for (k, s) in sums.iter().enumerate() {
        counts[2 * k] = *s as u16;
        counts[2 * k + 1] = (*s >> 16) as u16;
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::decimate;

    /// The packed sums against one channel at a time, over every word a 12-bit converter gives
    /// at the channel's extremes and between, for 1 to 16 scans (the calibration's range).
    #[test]
    fn decimation_sums_are_the_channels_own() {
        let mut words = [0u16; 16 * 6];
        let mut x = 12345u32;
        for trial in 0..200 {
            for w in words.iter_mut() {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                // the rails most often: the sums' worst case
                *w = match trial % 3 {
                    0 => 4095,
                    1 => (x % 4096) as u16,
                    _ => [0, 4095][(x & 1) as usize],
                };
            }
            for scans in 1..=16 {
                let got = decimate::<6, 3>(&words, scans);
                let got4 = decimate::<4, 2>(&words[..scans * 4], scans);
                for c in 0..6 {
                    let want: u32 = (0..scans).map(|s| u32::from(words[6 * s + c])).sum();
                    assert_eq!(u32::from(got[c]), want, "trial {trial}, {scans} scans, channel {c} of 6");
                    if c < 4 {
                        let want4: u32 = (0..scans).map(|s| u32::from(words[4 * s + c])).sum();
                        assert_eq!(u32::from(got4[c]), want4, "trial {trial}, {scans} scans, channel {c} of 4");
                    }
                }
            }
        }
    }
}
