//! The independent reference simulations, the yardsticks of the tests and the adaptive baseline
//! of `stickslip accuracy`: one event-driven DOP853 driver ([`driver`]) over a small trait for a
//! hybrid system, and one right-hand side per model, each written from docs/model.md and
//! sharing no code with `stickslip_model`'s steppers or with each other: the thesis model
//! ([`thesis`]) and model 2, part 1 ([`model2`]).

pub mod driver;
pub mod model2;
pub mod thesis;

pub use driver::Tolerances;
