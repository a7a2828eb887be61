//! Code shared by the on-target test binaries (`digest`, `count`, `rig`, `rig_count`,
//! `records`), which run the model and the rig firmware's HAL-free code on an emulated
//! Cortex-M4F under QEMU. [`scenes`] and [`rig_scenes`] are also compiled into the host-side
//! test `tests/tests/on_target.rs`, which recomputes the digests on x86-64, and
//! [`records_session`] into `tests/tests/records_on_target.rs`, which decodes the log.
#![no_std]

pub mod records_session;
pub mod rig_scenes;
pub mod scenes;

/// The firmware's per-sample logic (`firmware/rig-core`, no HAL): the digests and the
/// instruction counts are of the firmware's own code. ([`rig_scenes`] reaches it as
/// `super::rig_core`, which the host test provides by compiling the same source file.)
pub use stickslip_rig_core::rig_core;

/// The records of the firmware's log as values, and its log bookkeeping (`firmware/rig-core`),
/// which [`records_session`] reaches as `super::logbook`.
pub use stickslip_rig_core::logbook;

/// The painted stack's high-water mark (`firmware/rig-core/src/stack.rs`), as the firmware
/// measures it.
pub use stickslip_rig_core::stack;
