//! The desktop tool of the stick-slip model, as a library: the `stickslip` binary is a thin
//! `main` over these modules, and the cross-crate tests use the reference simulation.
//!
//! By concern:
//! - [`scenes`]: the scenes (built-in, files, overrides) and their runs (series, cycles, the
//!   linear stability of steady sliding): `simulate`, `cases`, `scenes`;
//! - [`numerics`]: the work-precision and stability reports and the independent references
//!   they measure against: `accuracy`, `stability`;
//! - [`recorded`]: recorded data and the virtual rig: `analyze`, `sil`, `compare`, `decode`;
//! - [`map`]: regime maps: `map`;
//! - [`fit`]: identification: `fit`;
//! - [`output`]: the tables, JSON and figures of the scene and numerics commands;
//! - [`limits`]: the size of every file read whole, the caps on counts, the work budget;
//! - [`cli`] parses, [`commands`] dispatches, [`error`] is what a command returns on failure.
//!   [`cancel`] stops a command from outside (the Python module's Ctrl-C).

pub mod cancel;
pub mod cli;
pub mod commands;
pub mod error;
pub mod fit;
pub mod limits;
pub mod map;
pub mod numerics;
pub mod output;
pub mod recorded;
pub mod scenes;

/// The tool's version (the host crate's, as `stickslip --version` prints it).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
