//! Cross-crate tests live in `tests/tests/`; the reference simulation they use is
//! `stickslip::numerics::reference` (host/src/numerics/reference.rs).
