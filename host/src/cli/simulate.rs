//! `simulate`.

use std::path::PathBuf;

use clap::Args;

use super::RunOptions;

#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// Built-in scene name (see `stickslip scenes`) or path to a TOML scene file
    #[arg(value_name = "SCENE|FILE", default_value = super::DEFAULT_SCENE)]
    pub scene: String,
    /// Write the time series to FILE as CSV (one row per step, units in the header)
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Print one JSON object instead of the summary
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub run: RunOptions,
}
