//! The independent reference simulations, the yardsticks of the tests and the adaptive baseline
//! of `stickslip accuracy`: one event-driven DOP853 driver ([`driver`]) over a small trait for a
//! hybrid system, and one right-hand side per model, each written from docs/model.md and
//! sharing no code with `stickslip_model`: the thesis model ([`thesis`]), model 2
//! ([`model2`]) and model 3's pneumatic band drive ([`pneumatic`]: model 2's pad from the
//! model-2 reference, its own band, air column, throttle and seal). They share only what
//! docs/model.md states once for all ([`common`]): the pad's constants, the transition table
//! and the window statistics.

pub mod common;
pub mod driver;
pub mod model2;
pub mod pneumatic;
pub mod thesis;

pub use common::{Regime, WindowStats};
pub use driver::Tolerances;
