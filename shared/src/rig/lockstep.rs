//! The model run alongside the measurement, one exact step per sample: the prediction the
//! measured `pad_x` is compared with.
//!
//! The scene is the configured pad (a template [`Scene`]) with the *measured* normal load,
//! F_N = p_actuator A (see [`super::pneumatics`]), and the configured band speed V; its step is
//! the sampling interval. Building it computes the exact flows in f64 (about 75 matrix
//! exponentials): a set-up cost paid once per record, not per sample. Per sample it is one
//! [`ExactStepper::step`] in f32 and x'' from the regime's row of the system matrix (five
//! multiply-adds, no division: the same x'' as `Plant::accelerations`, to f32 rounding):
//! measured 200 to 230 Cortex-M4F instructions in all without a transition, 4,400 to 4,900
//! for a step with one (see [`super::estimator`]); at 168 MHz and 25.6 kHz a sample has 6,560
//! cycles, so a transition step takes most of a sample's time.
//!
//! The model starts from its own initial state (stick, x = 0, at rest under the load), so it
//! is meaningful from the moment the band starts moving. The push cases are irregular (their
//! event times depend on round-off), so the residual there grows after a few cycles while the
//! statistics still agree; the pull cases settle to a periodic cycle.
//!
//! A model that halts (a finding: sprag, contact loss; see [`Halt`]) stops predicting; the
//! halt is kept and reported, and no value of the halted step is passed on.

use super::pneumatics::normal_load_n;
use crate::exact::{ExactStepper, Halt};
use crate::scene::{Scene, SceneError};
use crate::stickslip::Regime;

/// The model's prediction at one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelSample {
    /// The model's pad acceleration x'' [m/s^2] (0 once halted).
    pub xdd_m_s2: f32,
    /// Measured pad_x minus the model's x'' [m/s^2] (0 once halted).
    pub residual_m_s2: f32,
    pub regime: Regime,
    /// A stick-to-slip transition happened in this sample's step.
    pub slip_onset: bool,
    /// The model has halted (at this step or before).
    pub halted: bool,
}

/// The exact stepper in lockstep with the samples.
#[derive(Clone, Debug)]
pub struct LockstepModel {
    stepper: ExactStepper<f32>,
    halt: Option<Halt>,
}

impl LockstepModel {
    /// The scene the model runs: `template` with F_N = `actuator_bar` x `piston_area_m2`, band
    /// speed `band_speed_m_s` and step 1 / `fs_hz`.
    pub fn scene(template: &Scene, actuator_bar: f64, piston_area_m2: f64, band_speed_m_s: f64, fs_hz: f64) -> Scene {
        let mut s = *template;
        s.f_n = normal_load_n(actuator_bar, piston_area_m2);
        s.v = band_speed_m_s;
        s.dt = 1.0 / fs_hz;
        if !(s.duration >= s.dt) {
            s.duration = s.dt;
        }
        if !(s.stats_from < s.duration) {
            s.stats_from = 0.0;
        }
        s
    }

    /// Builds the model for [`Self::scene`]; a scene that does not validate (e.g. a negative or
    /// non-finite measured pressure) is refused with the reason.
    pub fn new(
        template: &Scene,
        actuator_bar: f64,
        piston_area_m2: f64,
        band_speed_m_s: f64,
        fs_hz: f64,
    ) -> Result<Self, SceneError> {
        let scene = Self::scene(template, actuator_bar, piston_area_m2, band_speed_m_s, fs_hz);
        Ok(LockstepModel { stepper: ExactStepper::new(&scene)?, halt: None })
    }

    pub fn stepper(&self) -> &ExactStepper<f32> {
        &self.stepper
    }
    pub fn halt(&self) -> Option<Halt> {
        self.halt
    }

    /// One step; compares the model's x'' with the measured `pad_x_m_s2`.
    #[inline]
    pub fn step(&mut self, pad_x_m_s2: f32) -> ModelSample {
        if self.halt.is_none() {
            if let Err(h) = self.stepper.step() {
                self.halt = Some(h);
            }
        }
        let regime = self.stepper.regime();
        if self.halt.is_some() {
            return ModelSample { xdd_m_s2: 0.0, residual_m_s2: 0.0, regime, slip_onset: false, halted: true };
        }
        let z = self.stepper.state().to_array();
        let (xdd, _) = self.stepper.propagator().accelerations(regime, &z);
        let slip_onset = self.stepper.transitions().iter().any(|t| t.from == Regime::Stick);
        ModelSample { xdd_m_s2: xdd, residual_m_s2: pad_x_m_s2 - xdd, regime, slip_onset, halted: false }
    }
}
