//! `map` and `map merge`.

use std::path::PathBuf;

use clap::{Args, Subcommand};

use super::RunOptions;

#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct MapArgs {
    #[command(subcommand)]
    pub action: Option<MapAction>,
    /// Built-in scene name (see `stickslip scenes`) or path to a TOML scene file: every key
    /// not swept comes from it
    #[arg(value_name = "SCENE|FILE", required = true)]
    pub scene: Option<String>,
    /// A swept key: KEY=FROM:TO:N (N values, evenly spaced) or KEY=FROM:TO:N:log (geometric);
    /// any numeric scene key (beta, f_n, v, mu_s, mu_k, v_s, k_pivot, c_x, zeta_x, ...) that
    /// acts in SCENE; give one or two; N from 1 to 100000, at most 10000000 cells
    #[arg(long = "sweep", value_name = "KEY=FROM:TO:N[:log]", required = true, allow_hyphen_values = true)]
    pub sweeps: Vec<String>,
    /// The start from sliding: velocity kick relative to the band speed V (x' and y' by kick V,
    /// phi' by kick V / l), 0 < kick <= 0.5
    #[arg(long, value_name = "K", default_value_t = 0.01, allow_hyphen_values = true, value_parser = super::parse::kick)]
    pub kick: f64,
    /// Run only every N-th cell starting at K (0 <= K < N <= 10000000), for a job array; join
    /// the shards' --json with `map merge`
    #[arg(long, value_name = "K/N", allow_hyphen_values = true)]
    pub shard: Option<String>,
    /// Worker threads, 1 to 1024 (default: every core)
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub jobs: Option<u16>,
    /// Step every run as `simulate` does: every step, each sampled, transitions by binary
    /// lifting. By default a thesis-model run jumps over stick where a closed-form bound keeps
    /// the pad stuck (the groan filter's ring-down in closed form), takes its other steps in a
    /// tight loop and, in f64, slip two at a time before the window's samples and locates
    /// transitions by root-finding on the exact flow's Taylor polynomial: the same statistics
    /// to rounding, which a run that amplifies differences can carry further; a model-2 run in
    /// f64 (Stribeck, exponent 1) goes 4 steps at a time in slip and stick and locates
    /// transitions on the guard's quadratic: the statistics to 1e-5, the groan RMS to about
    /// 3e-4 (docs/maps.md, "Statistics at event speed", "Model 2 at event speed")
    #[arg(long)]
    pub step_stick: bool,
    #[command(flatten)]
    pub run: RunOptions,
    #[command(flatten)]
    pub out: MapOutput,
}

#[derive(Debug, Subcommand)]
pub enum MapAction {
    /// Join the --json files of a map's shards into the whole map (and its CSV and figure)
    Merge(MapMergeArgs),
}

#[derive(Debug, Args)]
pub struct MapMergeArgs {
    /// The shards' JSON files (`map ... --shard K/N --json > shard_K.json`)
    #[arg(value_name = "FILE", required = true)]
    pub files: Vec<PathBuf>,
    #[command(flatten)]
    pub out: MapOutput,
}

#[derive(Debug, Args)]
pub struct MapOutput {
    /// Print the map as JSON instead of the Markdown summary
    #[arg(long)]
    pub json: bool,
    /// Write one row per cell to FILE (CSV; with unilateral contact, each run's edges' open fractions at the end)
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Write the figure to FILE (SVG): heat maps with the linear boundary (two sweeps), lines
    /// (one sweep)
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}
