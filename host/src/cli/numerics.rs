//! The numerics reports: `accuracy` and `stability`.

use std::path::PathBuf;

use clap::Args;

#[derive(Debug, Args)]
pub struct AccuracyArgs {
    /// The short version (3 steps, 3 tolerances, 1 repeat), as CI runs it
    #[arg(long, display_order = 1)]
    pub quick: bool,
    /// Write the log-log figure (error against run time) to FILE (SVG)
    #[arg(long, value_name = "FILE", display_order = 3)]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    pub report: ReportOptions,
    /// Timing repeats, 1 to 100; the minimum is kept (default 3, --quick 1)
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u8).range(1..=100), display_order = 5)]
    pub repeats: Option<u8>,
}

#[derive(Debug, Args)]
pub struct StabilityArgs {
    /// The short version (0.1 s runs), as CI runs it
    #[arg(long, display_order = 1)]
    pub quick: bool,
    /// Write the outcome map to FILE (SVG)
    #[arg(long, value_name = "FILE", display_order = 3)]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    pub report: ReportOptions,
}

/// The options both reports share: JSON instead of Markdown, and the bounds checked. Their
/// place in `--help` (after --quick, around --plot) is kept by `display_order`.
#[derive(Debug, Args)]
pub struct ReportOptions {
    /// Print JSON instead of the Markdown tables
    #[arg(long, display_order = 2)]
    pub json: bool,
    /// Exit with code 3 if a bound fails (see below)
    #[arg(long, display_order = 4)]
    pub check: bool,
}
