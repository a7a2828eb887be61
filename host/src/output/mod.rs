//! Output of the scene and numerics commands: Markdown tables and JSON of a run and of the six
//! cases ([`report`]), their figures ([`plots`]), and the numerics reports' figures
//! ([`numerics_plots`]). (`recorded`, `map` and `fit` keep their own output beside their
//! computation.)

pub mod numerics_plots;
pub mod plots;
pub mod report;
