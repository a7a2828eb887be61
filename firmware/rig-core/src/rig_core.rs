//! The per-sample call at the firmware's code generation: the one rig is
//! [`stickslip_model::rig::pipeline::Rig`]; this module only instantiates its `#[inline]`
//! per-sample functions ([`Rig::frame`], [`Rig::sample`], and the calibration and estimator
//! calls they make) in this crate, which the firmware's release profile compiles at opt-level 3
//! while everything else, the rig's set-up included, is compiled for size.
//!
//! The firmware calls [`sample_words`] once per frame; the on-target program `rig_count`
//! counts its instructions (and [`calibrate_estimate`]'s: the path without the sequencer) with
//! the firmware's code generation settings.

use stickslip_model::rig::calibration::{Calibrated, Calibrator};
use stickslip_model::rig::estimator::{Estimator, EstimatorSample};
use stickslip_model::rig::pipeline::{DigitalInputs, Rig, SampleOut};
use stickslip_model::rig::sequencer::Command;

/// [`Rig::frame`] and [`Rig::sample`] of the ADC words of one frame (`RigConfig::frame_words`):
/// what the firmware calls per frame. Never inlined: compiled, with everything it inlines, in
/// this crate, at this crate's optimisation level.
#[inline(never)]
pub fn sample_words(rig: &mut Rig, words: &[u16], digital: &DigitalInputs, command: Option<Command>) -> SampleOut {
    let frame = rig.frame(words);
    rig.sample(&frame, digital, command)
}

/// The decimation of one frame's ADC words ([`Rig::frame`]), its calibration and one estimator
/// update: the per-sample path without the sequencer and without the lockstep model (the
/// instruction count's path A; [`sample_words`] makes the same calls). `rig` only lends its
/// frame layout (oversampling, pressure channels). Never inlined: compiled in this crate, like
/// `sample_words`.
#[inline(never)]
pub fn calibrate_estimate(
    rig: &Rig,
    calibrator: &Calibrator,
    estimator: &mut Estimator,
    words: &[u16],
) -> (Calibrated, EstimatorSample) {
    let frame = rig.frame(words);
    let calibrated = calibrator.calibrate(&frame);
    let estimate = estimator.update(&calibrated);
    (calibrated, estimate)
}
