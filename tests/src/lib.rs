//! Cross-crate checks of the model crate. The library part holds the independent reference
//! simulation used by the tests in `tests/tests/`.
pub mod reference;
