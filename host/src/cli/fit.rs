//! `fit`.

use std::path::PathBuf;

use clap::Args;

use super::{RecordOptions, RecordingInput};

#[derive(Debug, Args)]
pub struct FitArgs {
    /// The base scene (built-in name or TOML scene file): every key not freed comes from it
    #[arg(long, value_name = "SCENE|FILE")]
    pub scene: String,
    /// The keys to fit, comma-separated (any numeric scene key but beta, dt, duration,
    /// stats_from; e.g. mu_s,mu_k,v_s,k_b); each starts at SCENE's value, which must be > 0
    #[arg(long, value_name = "KEY[,KEY...]", required = true)]
    pub free: Vec<String>,
    /// Recordings, CASE=FILE (see below)
    #[arg(value_name = "CASE=FILE")]
    pub recordings: Vec<String>,
    #[command(flatten)]
    pub input: RecordingInput,
    /// A table of measured statistics: CSV case,channel,statistic,value[,sigma] (sigma: the
    /// value's standard error in its unit), at most 1 MiB (or the built-in thesis_table_3_1)
    #[arg(long, value_name = "FILE")]
    pub table: Vec<String>,
    /// Cases to leave out of the fit and predict, comma-separated
    #[arg(long, value_name = "CASE[,CASE...]")]
    pub holdout: Vec<String>,
    /// Bounds of a free key, KEY=LO:HI (default: the key's physical range, docs/fit.md)
    #[arg(long, value_name = "KEY=LO:HI")]
    pub bounds: Vec<String>,
    /// Weights of the statistics, STAT=W (0 leaves it out; default 1, peak_hz 0)
    #[arg(long, value_name = "STAT=W[,...]")]
    pub weights: Vec<String>,
    /// Start of a recording's statistics on its time axis [s] (default SCENE's stats_from)
    #[arg(long, value_name = "S", allow_hyphen_values = true, value_parser = super::parse::from_time)]
    pub from: Option<f64>,
    /// Starts of the search, 1 to 1000 (the scene's values, then the best points of a Halton
    /// screen over the bounds; with horizon stages, of a screen of the first horizon)
    #[arg(long, value_name = "N", default_value_t = crate::fit::DEFAULT_STARTS, value_parser = super::parse::starts)]
    pub starts: usize,
    /// Horizon stages before the whole record, in stick-slip periods after each recording's
    /// first slip onset (0: none): each start is fitted to the recordings' first stretch, t = 0
    /// to the first horizon, then to the next, then to the whole record (see below)
    #[arg(long, value_name = "CYCLES[,CYCLES...]", value_delimiter = ',', default_values_t = crate::fit::DEFAULT_HORIZONS, allow_hyphen_values = true, value_parser = super::parse::horizon)]
    pub horizons: Vec<f64>,
    /// What recordings are compared by: waveform (pad_x sample by sample, multiple shooting over
    /// the cycles: 1-DOF scenes), statistics (the whole record's), or auto (waveform where it
    /// applies: recordings alone, every case a 1-DOF scene)
    #[arg(long, value_name = "auto|waveform|statistics", default_value = "auto")]
    pub cost: String,
    /// Iteration limit of each start's Nelder-Mead run (and evaluation budget of its
    /// Levenberg-Marquardt run), 1 to 1000000
    #[arg(long, value_name = "N", default_value_t = crate::fit::DEFAULT_MAX_ITERS, value_parser = super::parse::max_iters)]
    pub max_iters: u64,
    /// Bootstrap resamples over the recordings' windows, 0 (none) to 100000
    #[arg(long, value_name = "N", default_value_t = crate::fit::DEFAULT_BOOTSTRAP, value_parser = super::parse::bootstrap)]
    pub bootstrap: usize,
    /// Seed of the bootstrap's resampling
    #[arg(long, value_name = "N", default_value_t = 1, allow_hyphen_values = true)]
    pub seed: u32,
    /// No search: the cost along one free key, N values (2 to 1000) log-spaced from LO to HI
    /// (both finite, 0 < LO < HI), the other free keys at SCENE's values (the basin's width, a
    /// flat direction, a jump where the cycle changes)
    #[arg(long, value_name = "KEY=LO:HI:N")]
    pub profile: Option<String>,
    /// Write the fitted scene as a scene file (for simulate, sil, compare)
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Print one JSON object instead of the Markdown report
    #[arg(long)]
    pub json: bool,
    /// Write an SVG of model against measured, per statistic and case
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    pub record: RecordOptions,
}
