//! The whole per-sample chain in one call: calibration, estimator, sequencer.
//!
//! [`Rig::tick`] takes one [`Frame`], the digital inputs and an optional command, and returns
//! everything the firmware needs for that sample: the calibrated values, the estimate and the
//! valve outputs. The sequencer ticks once per sample, so its durations are in samples.
//!
//! The contact thresholds come from the measurement: while the sequencer is in Clamp (the pad
//! clamped, the band still) the estimator measures the noise floor; when Clamp ends into Drive
//! it designs the thresholds from it (`Estimator::finish_floor`, with the larger count of
//! pad_x and disc_x as the quantum) and reports them in that tick's [`TickOutput::floor`].
//!
//! The lockstep model is tied to the record: when the sequencer enters Record, the model is
//! built from the mean actuator pressure measured during Drive (the clamp load the band starts
//! under; the current sample's if Drive had none) and the configured band speed; it stops when
//! the record ends. Building it is the f64 set-up of [`super::lockstep`]: that one tick takes
//! much longer than the others.

use super::calibration::{Calibrated, Calibration, Calibrator, Frame};
use super::estimator::{Estimator, EstimatorConfig, EstimatorSample};
use super::sequencer::{Command, SeqState, Sequencer, SequencerConfig, SequencerInputs, SequencerOutput};
use super::contact::ContactThresholds;
use super::noise_floor::FloorReport;
use super::{ConfigError, ACTUATOR, BAND};
use crate::scene::{Scene, SceneError};

/// Everything the rig needs to run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigConfig {
    pub calibration: Calibration,
    pub estimator: EstimatorConfig,
    pub sequencer: SequencerConfig,
    /// The pad the lockstep model runs (its F_N, V and dt are replaced by the measured load,
    /// the configured band speed and the sampling interval).
    pub model_template: Scene,
}

/// The digital inputs of one sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DigitalInputs {
    pub estop: bool,
    pub end_of_stroke: bool,
}

/// The outputs of one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TickOutput {
    pub calibrated: Calibrated,
    pub estimate: EstimatorSample,
    pub sequencer: SequencerOutput,
    /// The lockstep model could not be started at the record's start (the measured load gave
    /// an invalid scene, e.g. a negative pressure): the reason.
    pub model_refused: Option<SceneError>,
    /// The clamped phase ended into Drive with this sample: the noise floor it measured and
    /// the contact thresholds designed from it (`None` if it was too short: the thresholds
    /// stay as configured).
    pub floor: Option<(FloorReport, ContactThresholds)>,
}

/// Calibration + estimator + sequencer.
#[derive(Clone, Debug)]
pub struct Rig {
    calibrator: Calibrator,
    estimator: Estimator,
    sequencer: Sequencer,
    template: Scene,
    drive_bar_sum: f32,
    drive_samples: u32,
}

impl Rig {
    pub fn new(cfg: &RigConfig) -> Result<Self, ConfigError> {
        Ok(Rig {
            calibrator: Calibrator::new(&cfg.calibration)?,
            estimator: Estimator::new(&cfg.estimator)?,
            sequencer: Sequencer::new(&cfg.sequencer)?,
            template: cfg.model_template,
            drive_bar_sum: 0.0,
            drive_samples: 0,
        })
    }

    pub fn estimator(&self) -> &Estimator {
        &self.estimator
    }
    pub fn estimator_mut(&mut self) -> &mut Estimator {
        &mut self.estimator
    }
    pub fn sequencer(&self) -> &Sequencer {
        &self.sequencer
    }

    /// One sample.
    pub fn tick(&mut self, frame: &Frame, digital: &DigitalInputs, command: Option<Command>) -> TickOutput {
        let calibrated = self.calibrator.calibrate(frame);
        let estimate = self.estimator.update(&calibrated);
        let inputs = SequencerInputs {
            actuator_bar: calibrated.pressure_bar[ACTUATOR],
            band_bar: calibrated.pressure_bar[BAND],
            accel_saturated: calibrated.saturation.any_accel(),
            estop: digital.estop,
            end_of_stroke: digital.end_of_stroke,
            estimator_fault: estimate.fault,
        };
        let before = self.sequencer.state();
        let sequencer = self.sequencer.tick(&inputs, command);
        let mut model_refused = None;
        let mut floor = None;
        if sequencer.state == SeqState::Drive {
            if before != SeqState::Drive {
                self.drive_bar_sum = 0.0;
                self.drive_samples = 0;
            }
            if !estimate.fault {
                self.drive_bar_sum += inputs.actuator_bar;
                self.drive_samples = self.drive_samples.saturating_add(1);
            }
        }
        if sequencer.changed {
            if sequencer.state == SeqState::Clamp {
                self.estimator.start_floor();
            } else if before == SeqState::Clamp {
                if sequencer.state == SeqState::Drive {
                    floor = self.estimator.finish_floor(self.calibrator.a_rel_quantum_m_s2());
                } else {
                    self.estimator.cancel_floor();
                }
            }
            if sequencer.state == SeqState::Record {
                let bar = if self.drive_samples > 0 {
                    self.drive_bar_sum as f64 / self.drive_samples as f64
                } else {
                    inputs.actuator_bar as f64
                };
                if let Err(e) = self.estimator.start_model(&self.template, bar) {
                    model_refused = Some(e);
                }
            } else if before == SeqState::Record {
                self.estimator.stop_model();
            }
        }
        TickOutput { calibrated, estimate, sequencer, model_refused, floor }
    }
}
