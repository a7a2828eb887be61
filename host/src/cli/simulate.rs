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
    /// Step on the sample grid even without --csv. By default a model-2 scene in f64 without
    /// --csv whose fastest mode turns at most 0.005 rad per sample (e.g. oracle_stribeck)
    /// runs event-driven: exact flows between events, Dormand-Prince 5(4) in Stribeck slip at
    /// rtol 1e-10, the same statistics of the same motion (the summary's precision line then
    /// names the method). The thesis model, f32, --csv and any run the event path gives back
    /// (a halt) step on the grid
    #[arg(long, conflicts_with = "events")]
    pub grid: bool,
    /// Run event-driven wherever the event path covers the scene (a model-2 scene in f64
    /// without --csv), also where the grid is cheaper (the rig sets)
    #[arg(long)]
    pub events: bool,
    #[command(flatten)]
    pub run: RunOptions,
}
