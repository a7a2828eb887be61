//! Code shared by the on-target test binaries (`digest`, `count`, `rig`, `rig_count`,
//! `records`, `count_model2`, `stack_overflow`), which run the model and the rig firmware's
//! HAL-free code on an emulated Cortex-M4F under QEMU. What they run and print is in
//! `tests/cases` (crate `stickslip-crosscheck-cases`), which the host-side cross-checks run too.
#![no_std]

/// The runs both sides compute (`tests/cases`): the host's cross-checks recompute them.
pub use stickslip_crosscheck_cases::{records_session, rig_scenes, scenes};

/// The firmware's per-sample logic (`firmware/rig-core`, no HAL): the digests and the
/// instruction counts are of the firmware's own code.
pub use stickslip_rig_core::rig_core;

/// The records of the firmware's log as values, and its log bookkeeping (`firmware/rig-core`).
pub use stickslip_rig_core::logbook;

/// The painted stack's high-water mark (`firmware/rig-core/src/stack.rs`), as the firmware
/// measures it.
pub use stickslip_rig_core::stack;
