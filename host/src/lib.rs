//! The desktop tool of the stick-slip model, as a library: the `stickslip` binary is a thin
//! `main` over these modules, and the cross-crate tests use the reference simulation.

pub mod accuracy;
pub mod builtin;
pub mod cli;
pub mod commands;
pub mod cycles;
pub mod error;
pub mod exp_variants;
pub mod fit;
pub mod map;
pub mod numerics_plots;
pub mod plots;
pub mod recorded;
pub mod reference;
pub mod reference2;
pub mod report;
pub mod run;
pub mod scene_file;
pub mod scene_source;
pub mod series;
pub mod sliding;
pub mod stability;
