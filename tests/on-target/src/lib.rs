//! Code shared by the on-target test binaries (`digest`, `count`, `rig`, `rig_count`), which run
//! the model and the rig's per-sample code on an emulated Cortex-M4F under QEMU. [`scenes`]
//! and [`rig_scenes`] are also compiled into the host-side test `tests/tests/on_target.rs`,
//! which recomputes the digests on x86-64.
#![no_std]

pub mod rig_scenes;
pub mod scenes;

/// The firmware's per-sample logic (`firmware/rig-core`, no HAL): the digests and the
/// instruction counts are of the firmware's own code. ([`rig_scenes`] reaches it as
/// `super::rig_core`, which the host test provides by compiling the same source file.)
pub use stickslip_rig_core::rig_core;
