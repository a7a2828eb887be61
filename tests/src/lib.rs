//! Cross-crate tests live in `tests/tests/`; the reference simulation they use is
//! `stickslip::reference` (host/src/reference.rs).
