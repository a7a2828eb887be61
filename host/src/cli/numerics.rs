//! The numerics reports: `accuracy` and `stability`.

use std::path::PathBuf;

use clap::Args;

#[derive(Debug, Args)]
pub struct AccuracyArgs {
    /// The short version (3 steps, 3 tolerances, 1 repeat), as CI runs it
    #[arg(long)]
    pub quick: bool,
    /// Print JSON instead of the Markdown tables
    #[arg(long)]
    pub json: bool,
    /// Write the log-log figure (error against run time) to FILE (SVG)
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Exit with code 3 if a bound fails (see below)
    #[arg(long)]
    pub check: bool,
    /// Timing repeats, 1 to 100; the minimum is kept (default 3, --quick 1)
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u8).range(1..=100))]
    pub repeats: Option<u8>,
}

#[derive(Debug, Args)]
pub struct StabilityArgs {
    /// The short version (0.1 s runs), as CI runs it
    #[arg(long)]
    pub quick: bool,
    /// Print JSON instead of the Markdown tables
    #[arg(long)]
    pub json: bool,
    /// Write the outcome map to FILE (SVG)
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Exit with code 3 if a bound fails (see below)
    #[arg(long)]
    pub check: bool,
}
