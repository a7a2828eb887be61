//! The rig firmware's per-sample logic, without the HAL (see [`rig_core`]; everything is
//! re-exported here).
//!
//! Its own crate for the code generation: the firmware's release profile builds this crate at
//! opt-level 3 (its per-sample path, and the `#[inline]` functions of `stickslip_model` it
//! calls, are compiled here) and everything else, the f64 set-up included, for size. The code
//! itself lives in `src/rig_core.rs`, which the host-side test `tests/tests/on_target.rs`
//! also compiles as a module (through `#[path]`): keep it free of crate-level attributes and
//! `crate::` paths.
#![no_std]

pub mod rig_core;

pub use rig_core::*;
