//! What the firmware compiles for speed: the per-sample call into the shared crate's rig
//! ([`rig_core`]: `stickslip_model::rig::pipeline::Rig` instantiated here) and the estimator
//! task's per-sample log bookkeeping with the log's records as values ([`logbook`]). The
//! records' defmt text is the crate `stickslip-records` (../records).
//!
//! Its own crate for the code generation only: the firmware's release profile builds this
//! crate at opt-level 3 (its per-sample path, and the `#[inline]` functions of
//! `stickslip_model` it calls, are compiled here) and everything else, the f64 set-up included,
//! for size. The host-side tests in `tests/tests/` run it too, built for the host (through the
//! crate `tests/cases`, whose runs the on-target programs print).
#![no_std]

pub mod logbook;
pub mod rig_core;
/// The Cortex-M stack's high-water mark (painted stack), for the firmware and the on-target
/// programs.
#[cfg(target_os = "none")]
pub mod stack;

pub use rig_core::{calibrate_estimate, sample_words};
