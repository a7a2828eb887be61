//! The runs that the emulated Cortex-M4F and the host both compute, from this one crate: the
//! on-target programs (`tests/on-target`: bins `digest`, `rig`, `records`) print what they give
//! on the target, the host's cross-checks (`tests/tests/on_target.rs`,
//! `tests/tests/records_on_target.rs`) recompute them on x86-64 and compare.
//!
//! - [`scenes`]: the model's runs, digested step by step (the exact stepper in f32 and f64,
//!   each model-2 composition in f32);
//! - [`rig_scenes`]: the rig cases, frames through the one rig
//!   (`stickslip_model::rig::pipeline::Rig`, which the firmware runs), digested;
//! - [`records_session`]: a rig session played without the hardware, for the log
//!   ([`logbook`]'s records).
#![no_std]

pub mod records_session;
pub mod rig_scenes;
pub mod scenes;

/// The firmware's per-sample call at its code generation (`firmware/rig-core`, no HAL): the
/// instruction counts are of the firmware's own code.
pub use stickslip_rig_core::rig_core;

/// The records of the firmware's log as values, and its log bookkeeping (`firmware/rig-core`).
pub use stickslip_rig_core::logbook;
