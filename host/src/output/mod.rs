//! Output of the scene and numerics commands: number formatting for every command
//! ([`format`]), Markdown tables and JSON of a run and of the six cases ([`report`]), their figures ([`plots`]), and the numerics reports' figures
//! ([`numerics_plots`]); one figure style for every figure of the tool ([`style`]). (`recorded`,
//! `map` and `fit` keep their own output beside their computation, in that style.)

pub mod format;
pub mod numerics_plots;
pub mod plots;
pub mod report;
pub mod style;
