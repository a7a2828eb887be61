//! Cross-crate tests live in `tests/tests/`; the reference simulation they use is
//! `stickslip::numerics::reference::thesis` (host/src/numerics/reference/thesis.rs).
