//! Code shared by the on-target test binaries (`digest`, `count`), which run the model on an
//! emulated Cortex-M4F under QEMU. [`scenes`] is also compiled into the host-side test
//! `tests/tests/on_target.rs`, which recomputes the digests on x86-64.
#![no_std]

pub mod scenes;
