//! The per-sample analysis of calibrated frames: one fixed step per sample (dt = 1 / fs).
//!
//! For each [`Calibrated`] frame, [`Estimator::update`]:
//! 1. checks the input: the sum of the magnitudes of the six values must be finite and at most
//!    [`PLAUSIBLE_SUM_LIMIT`]; one comparison catches a NaN or infinity anywhere, and a bound
//!    this size keeps every square and sum downstream finite. A refused sample sets the
//!    sample's `fault` flag, is counted in the window, and touches no state (filters, v_r,
//!    statistics): a non-finite value is never propagated;
//! 2. estimates the contact from a_rel = pad_x - disc_x ([`super::contact`]);
//! 3. filters the four accelerometers through the groan band-pass ([`super::bandpass`]);
//! 4. steps the lockstep model, if started ([`super::lockstep`]);
//! 5. adds the sample to the window statistics ([`super::window`]); when a window closes its
//!    sums wait for [`Estimator::take_window`] (the sample's `window_ready` flag says so), which
//!    takes the window's divisions and square roots: call it outside the sample deadline,
//!    before the next window closes.
//!
//! Cost per sample (Cortex-M4F, single-precision FPU): no division and no square root; four
//! band-pass cascades of two sections (three multiplies each), the contact update, the
//! per-channel min/max and squares. `scripts/count-instructions.sh` counts it as executed
//! instructions under QEMU (`netduinoplus2`), with the calibration of the six channels (path
//! A) and with the lockstep model and the sequencer as well (path B, the firmware's
//! `stickslip_rig_core::sample_words` on [`super::pipeline::Rig`]); firmware/README.md, "Per-sample cost", holds the figures (the
//! firmware issue's bound for path A is 1,500). A lockstep step with a transition costs
//! several thousand more (the stepper's in-step transition search).

use super::bandpass::{BandPass, CascadeState, GROAN_BAND_HZ, GROAN_SECTIONS};
use super::calibration::Calibrated;
use super::contact::{ContactEstimator, ContactEventKind, ContactSample, ContactThresholds};
use super::lockstep::{LockstepModel, ModelSample, ModelSlot, NoModel};
use super::noise_floor::{FloorReport, NoiseFloor, A_REL, MIN_FLOOR_SAMPLES};
use super::pneumatics::RIG_PISTON_AREA_M2;
use super::geometry::SensorGeometry;
use super::window::{SampleStats, WindowAccumulator, WindowReport, DEFAULT_WINDOW_SAMPLES};
use super::{check, ConfigError, ACCEL_CHANNELS, DISC_X, PAD_LEAD, PAD_TRAIL, PAD_X};
use crate::design::SAMPLE_RATE_HZ;
use crate::catalogue::DEFAULT_SCENE;
use crate::scene::{Scene, SceneError};
use crate::stickslip::Regime;

/// Largest accepted sum of |value| over the six calibrated values of a frame (m/s^2 and bar
/// mixed: a plausibility bound, about 1e6 times the accelerometers' range).
pub const PLAUSIBLE_SUM_LIMIT: f32 = 1e9;

/// The estimator's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EstimatorConfig {
    /// Sampling rate [Hz].
    pub fs_hz: f64,
    pub contact: ContactThresholds,
    /// Window length [samples].
    pub window_samples: u32,
    /// Groan band edges [Hz].
    pub groan_band_hz: (f64, f64),
    /// Actuator piston area [m^2], for the lockstep model's F_N.
    pub piston_area_m2: f64,
    /// Band speed for the lockstep model [m/s] (the rig does not measure it).
    pub band_speed_m_s: f64,
    /// Friction-face term of the relative acceleration [-]: a_rel = pad_x - disc_x +
    /// `face_coefficient` (pad_lead - pad_trail). With face kinematics the face slides at
    /// x' + s w phi' against the band, and phi'' = (pad_lead - pad_trail) / (r_lead - r_trail)
    /// from the edge sensors (a floating pad's y'' cancels in the difference), so the
    /// coefficient is s w / (r_lead - r_trail); 0 without the face (the thesis's pivot).
    pub face_coefficient: f32,
}

impl EstimatorConfig {
    /// Settings for a rig whose pad is `scene`: thresholds from its breakaway jump, its band
    /// speed, the rig's rate, window, groan band and piston area.
    pub fn for_scene(scene: &Scene) -> Self {
        EstimatorConfig {
            fs_hz: SAMPLE_RATE_HZ,
            contact: ContactThresholds::for_scene(scene, SAMPLE_RATE_HZ),
            window_samples: DEFAULT_WINDOW_SAMPLES,
            groan_band_hz: GROAN_BAND_HZ,
            piston_area_m2: RIG_PISTON_AREA_M2,
            band_speed_m_s: scene.v,
            face_coefficient: Self::face_coefficient_for(scene, &SensorGeometry::RIG) as f32,
        }
    }

    /// s w / (r_lead - r_trail) for a scene with face kinematics and rotation, 0 otherwise (or
    /// where the sensors' geometry is invalid for the scene, or both sit at one lever arm).
    pub fn face_coefficient_for(scene: &Scene, geometry: &SensorGeometry) -> f64 {
        if !(scene.face && scene.rotation) {
            return 0.0;
        }
        match geometry.arms(scene) {
            Ok((r_trail, r_lead)) if r_lead != r_trail => {
                crate::coefficients::Coefficients::of(scene).s * scene.w / (r_lead - r_trail)
            }
            _ => 0.0,
        }
    }

    pub fn validate(&self) -> Result<(), ConfigError> {
        check(self.fs_hz.is_finite() && self.fs_hz > 0.0, "fs_hz", "must be > 0 Hz", self.fs_hz)?;
        let c = &self.contact;
        let pos = |v: f32| v.is_finite() && v > 0.0;
        check(pos(c.slip_onset_m_s2), "contact.slip_onset_m_s2", "must be > 0", c.slip_onset_m_s2 as f64)?;
        check(
            pos(c.stick_max_m_s2) && c.stick_max_m_s2 <= c.slip_onset_m_s2,
            "contact.stick_max_m_s2",
            "must satisfy 0 < stick_max <= slip_onset",
            c.stick_max_m_s2 as f64,
        )?;
        check(c.v_tol_m_s.is_finite() && c.v_tol_m_s >= 0.0, "contact.v_tol_m_s", "must be >= 0", c.v_tol_m_s as f64)?;
        check(
            c.v_reversal_m_s.is_finite() && c.v_reversal_m_s >= c.v_tol_m_s,
            "contact.v_reversal_m_s",
            "must satisfy v_reversal >= v_tol",
            c.v_reversal_m_s as f64,
        )?;
        check(
            c.bias_gain.is_finite() && c.bias_gain >= 0.0 && c.bias_gain < 1.0,
            "contact.bias_gain",
            "must satisfy 0 <= gain < 1",
            c.bias_gain as f64,
        )?;
        check(
            c.onset_fraction.is_finite() && c.onset_fraction >= 0.0 && c.onset_fraction < 1.0,
            "contact.onset_fraction",
            "must satisfy 0 <= fraction < 1",
            c.onset_fraction as f64,
        )?;
        check(
            c.onset_max_factor.is_finite() && c.onset_max_factor >= 1.0,
            "contact.onset_max_factor",
            "must be >= 1",
            c.onset_max_factor as f64,
        )?;
        check(
            c.stick_ratio.is_finite() && c.stick_ratio > 0.0 && c.stick_ratio <= 1.0,
            "contact.stick_ratio",
            "must satisfy 0 < ratio <= 1",
            c.stick_ratio as f64,
        )?;
        check(
            self.face_coefficient.is_finite(),
            "face_coefficient",
            "must be finite",
            self.face_coefficient as f64,
        )?;
        check(self.window_samples >= 1, "window_samples", "must be >= 1", self.window_samples as f64)?;
        check(
            self.piston_area_m2.is_finite() && self.piston_area_m2 > 0.0,
            "piston_area_m2",
            "must be > 0 m^2",
            self.piston_area_m2,
        )?;
        check(
            self.band_speed_m_s.is_finite() && self.band_speed_m_s > 0.0,
            "band_speed_m_s",
            "must be > 0 m/s",
            self.band_speed_m_s,
        )
    }
}

impl Default for EstimatorConfig {
    fn default() -> Self {
        Self::for_scene(&DEFAULT_SCENE)
    }
}

/// The estimate after one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EstimatorSample {
    /// Index of this sample (from 0).
    pub sample: u64,
    /// The input was refused (non-finite or implausible): the contact estimate below is the
    /// previous one, held, and nothing was accumulated.
    pub fault: bool,
    pub contact: ContactSample,
    /// The lockstep model's prediction, when it runs.
    pub model: Option<ModelSample>,
    /// A window closed with this sample: its report is in [`Estimator::take_window`].
    pub window_ready: bool,
}

/// The per-sample analysis (see the module documentation). `M`: where its lockstep model is
/// kept, a [`LockstepModel`] (the default), or [`NoModel`] for the rig's fresh estimator that a
/// record starts from ([`Estimator::restart_from`]).
#[derive(Clone, Copy, Debug)]
pub struct Estimator<M: ModelSlot = LockstepModel> {
    cfg: EstimatorConfig,
    contact: ContactEstimator,
    last_contact: ContactSample,
    groan: BandPass<GROAN_SECTIONS>,
    groan_state: [CascadeState<GROAN_SECTIONS>; ACCEL_CHANNELS],
    last_groan: [f32; ACCEL_CHANNELS],
    window: WindowAccumulator,
    model: M,
    model_halt_seen: bool,
    /// The noise floor being measured (between [`Estimator::start_floor`] and
    /// [`Estimator::finish_floor`]).
    floor: Option<NoiseFloor>,
    sample: u64,
}

impl Estimator {
    pub fn new(cfg: &EstimatorConfig) -> Result<Self, ConfigError> {
        Ok(Self::fresh(cfg, Self::checked_groan(cfg)?))
    }

    /// [`Self::new`] written into `slot` (e.g. a `static`'s memory): the estimator carries the
    /// lockstep model's stepper (kilobytes with model 2 in f32: `core::mem::size_of`), which a Cortex-M4F's stack
    /// should not hold while it is moved. On an error `slot` is not written.
    pub fn new_in<'a>(slot: &'a mut core::mem::MaybeUninit<Self>, cfg: &EstimatorConfig) -> Result<&'a mut Self, ConfigError> {
        Ok(slot.write(Self::fresh(cfg, Self::checked_groan(cfg)?)))
    }

    /// Validates `cfg` and designs its groan band-pass.
    pub(crate) fn checked_groan(cfg: &EstimatorConfig) -> Result<BandPass<GROAN_SECTIONS>, ConfigError> {
        cfg.validate()?;
        BandPass::butterworth(cfg.groan_band_hz.0, cfg.groan_band_hz.1, cfg.fs_hz)
    }

    /// The lockstep model, while it runs.
    pub fn model(&self) -> Option<&LockstepModel> {
        if self.model.is_running() {
            Some(&self.model)
        } else {
            None
        }
    }

    /// Starts (or restarts) the lockstep model from the measured actuator pressure [bar]:
    /// `template` with F_N = p A and the configured band speed. Set-up work in f64 (the exact
    /// flows): call it between samples, not inside a tight sample deadline.
    pub fn start_model(&mut self, template: &Scene, actuator_bar: f64) -> Result<(), SceneError> {
        self.model_halt_seen = false;
        self.window.set_model_halt(None);
        self.model.start(template, actuator_bar, self.cfg.piston_area_m2, self.cfg.band_speed_m_s, self.cfg.fs_hz)
    }

    /// Stops the lockstep model (its stepper is kept: [`LockstepModel::restart`]).
    pub fn stop_model(&mut self) {
        self.model.stop();
    }

    /// A record's start: every part of `fresh` (the rig's fresh estimator, which carries no
    /// model) copied in, and this estimator's own lockstep model restarted from its initial
    /// state with its tables kept ([`LockstepModel::restart`]): a few words of the model
    /// written, no stepper copied. The same estimator as a copy of a fresh one whose model was
    /// just started for the same scene.
    #[inline(always)]
    pub(crate) fn restart_from(&mut self, fresh: &Estimator<NoModel>) {
        let Estimator {
            cfg,
            contact,
            last_contact,
            groan,
            groan_state,
            last_groan,
            window,
            model: NoModel,
            model_halt_seen,
            floor,
            sample,
        } = fresh;
        self.cfg = *cfg;
        self.contact = *contact;
        self.last_contact = *last_contact;
        self.groan = *groan;
        self.groan_state = *groan_state;
        self.last_groan = *last_groan;
        self.window = *window;
        self.model_halt_seen = *model_halt_seen;
        self.floor = *floor;
        self.sample = *sample;
        self.model.restart();
    }
}

impl<M: ModelSlot> Estimator<M> {
    /// A new estimator for `cfg` (validated) with its groan filter: written where it is used
    /// (inlined into [`Self::new`], [`Self::new_in`] and `Rig::init`).
    #[inline(always)]
    pub(crate) fn fresh(cfg: &EstimatorConfig, groan: BandPass<GROAN_SECTIONS>) -> Self {
        Estimator {
            cfg: *cfg,
            contact: ContactEstimator::new(cfg.contact, cfg.fs_hz),
            last_contact: ContactSample { regime: Regime::Stick, v_r_m_s: 0.0, a_rel_m_s2: 0.0, event: None, lead_samples: 0 },
            groan,
            groan_state: [CascadeState::<GROAN_SECTIONS>::ZERO; ACCEL_CHANNELS],
            last_groan: [0.0; ACCEL_CHANNELS],
            window: WindowAccumulator::new(cfg.window_samples, cfg.fs_hz),
            model: M::stopped(),
            model_halt_seen: false,
            floor: None,
            sample: 0,
        }
    }

    pub fn config(&self) -> &EstimatorConfig {
        &self.cfg
    }
    /// The groan band-pass in use.
    pub fn groan_filter(&self) -> &BandPass<GROAN_SECTIONS> {
        &self.groan
    }
    /// The band-passed accelerations of the last valid sample [m/s^2].
    pub fn last_groan(&self) -> &[f32; ACCEL_CHANNELS] {
        &self.last_groan
    }
    pub fn contact(&self) -> &ContactEstimator {
        &self.contact
    }
    /// Starts measuring the noise floor (the clamped, band-still phase): every valid sample
    /// until [`Self::finish_floor`] adds to it. Restarts a floor already under way.
    pub fn start_floor(&mut self) {
        self.floor = Some(NoiseFloor::new());
    }

    /// Ends the floor and, if it has at least [`MIN_FLOOR_SAMPLES`], designs the contact
    /// thresholds from it ([`ContactThresholds::from_noise_floor`] with a_rel's sigma and
    /// `quantum_m_s2`, the larger count of pad_x and disc_x [m/s^2]; 0 for a continuous
    /// input), restarts the contact estimator in stick with a_rel's mean as its bias, and
    /// returns the floor with the thresholds. `None` (nothing changed) without a floor or with
    /// too few samples. Takes a square root per value and a few divisions: between samples.
    pub fn finish_floor(&mut self, quantum_m_s2: f32) -> Option<(FloorReport, ContactThresholds)> {
        let f = self.floor.take()?;
        if f.samples() < MIN_FLOOR_SAMPLES {
            return None;
        }
        let r = f.report();
        let th = ContactThresholds::from_noise_floor(r.sigma_m_s2[A_REL] as f64, quantum_m_s2 as f64, self.cfg.fs_hz);
        self.set_contact(th, r.mean_m_s2[A_REL]);
        Some((r, th))
    }

    /// Replaces the contact thresholds and restarts the contact estimator in stick with
    /// `bias_m_s2` as the bias of a_rel.
    pub fn set_contact(&mut self, th: ContactThresholds, bias_m_s2: f32) {
        self.cfg.contact = th;
        self.contact = ContactEstimator::new(th, self.cfg.fs_hz);
        self.contact.set_bias_m_s2(bias_m_s2);
    }

    /// Drops the floor under way, if any (the clamped phase ended without the band starting).
    pub fn cancel_floor(&mut self) {
        self.floor = None;
    }

    /// The report of the last closed window, once. Takes the window's divisions and square
    /// roots (its Cortex-M4F instructions: the window-closing samples of
    /// `scripts/count-instructions.sh`): call it outside the sample deadline.
    pub fn take_window(&mut self) -> Option<WindowReport> {
        self.window.take_report()
    }

    /// Closed windows replaced before [`Self::take_window`] took them.
    pub fn windows_dropped(&self) -> u32 {
        self.window.windows_dropped()
    }

    /// One sample. Always inlined: it is the per-sample path, compiled where it is called (the
    /// firmware's `stickslip_rig_core::sample_words`, at opt-level 3); left to the inliner, a program with
    /// two callers (tests/on-target's `rig_count`) gets one out-of-line copy compiled at this
    /// crate's "s", with more instructions per sample (`scripts/count-instructions.sh`).
    #[inline(always)]
    pub fn update(&mut self, c: &Calibrated) -> EstimatorSample {
        let sample = self.sample;
        self.sample = self.sample.wrapping_add(1);
        let a = &c.accel_m_s2;
        let sum = a[0].abs() + a[1].abs() + a[2].abs() + a[3].abs() + c.pressure_bar[0].abs() + c.pressure_bar[1].abs();
        if !(sum <= PLAUSIBLE_SUM_LIMIT) {
            // keep the model in time with the samples, but compare it with nothing
            let model = self.model.step(0.0).map(|mut s| {
                s.residual_m_s2 = 0.0;
                s
            });
            self.note_halt();
            let ready = self.window.add_faulted(model.is_some());
            let mut contact = self.last_contact;
            contact.event = None;
            return EstimatorSample { sample, fault: true, contact, model, window_ready: ready };
        }
        let a_rel = a[PAD_X] - a[DISC_X] + self.cfg.face_coefficient * (a[PAD_LEAD] - a[PAD_TRAIL]);
        if let Some(f) = &mut self.floor {
            f.add(a, a_rel);
        }
        let contact = self.contact.update(a_rel);
        self.last_contact = contact;
        let mut groan = [0.0f32; ACCEL_CHANNELS];
        for (i, g) in groan.iter_mut().enumerate() {
            *g = self.groan.run(&mut self.groan_state[i], a[i]);
        }
        self.last_groan = groan;
        // the check before the call: a stopped model (outside the records) costs a load and a
        // branch, not the step's call and register saves (15 instructions per sample, path A
        // of scripts/count-instructions.sh)
        let model = if self.model.is_running() { self.model.step(a[PAD_X]) } else { None };
        self.note_halt();
        let onset = matches!(contact.event, Some(e) if e.kind == ContactEventKind::StickToSlip);
        let ready = self.window.add(&SampleStats {
            accel_m_s2: a,
            groan_m_s2: &groan,
            stick: contact.regime == Regime::Stick,
            slip_onset: onset,
            onset_lead: contact.lead_samples,
            saturated: c.saturation.any_accel(),
            model: model.as_ref(),
        });
        EstimatorSample { sample, fault: false, contact, model, window_ready: ready }
    }

    #[inline(always)]
    fn note_halt(&mut self) {
        if !self.model_halt_seen {
            if let Some(h) = self.model.halt() {
                self.window.set_model_halt(Some(h));
                self.model_halt_seen = true;
            }
        }
    }
}
