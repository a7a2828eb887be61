//! `cases`.

use std::path::PathBuf;

use clap::Args;

use super::RunOptions;

#[derive(Debug, Args)]
pub struct CasesArgs {
    /// Which six cases: `thesis` (the thesis model, no damping), `rig` (model 2: Stribeck
    /// friction, the band as a mass, a few percent damping; mu_k, v_s, k_b fitted to Table
    /// 3.1), `rig-float` (the rig set with the face and a floating pad, its own fit) or
    /// `rig-built` (model 3: rig-float with the soft band of the pneumatic drive, unilateral
    /// edges and contact exponent 1.5, mu_k and k_b fitted to Table 3.1, 3 s runs; f64 only)
    #[arg(long, value_enum, default_value = "thesis")]
    pub set: CaseSet,
    /// Print {"cases": [...]} as JSON instead of the Markdown table
    #[arg(long)]
    pub json: bool,
    /// Write the 8 SVG figures (like the thesis's Fig. 2.5 to 2.12) into DIR
    #[arg(long, value_name = "DIR")]
    pub plots: Option<PathBuf>,
    /// Start of the plotted window [s] (default: the statistics window start)
    #[arg(long, value_name = "S", allow_hyphen_values = true, requires = "plots")]
    pub plot_from: Option<f64>,
    /// End of the plotted window [s] (default: plot start + 0.1 s, at most the run length)
    #[arg(long, value_name = "S", allow_hyphen_values = true, requires = "plots")]
    pub plot_to: Option<f64>,
    #[command(flatten)]
    pub run: RunOptions,
}

/// The six-case sets of `cases --set`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum CaseSet {
    Thesis,
    Rig,
    /// The rig set with friction-face kinematics and the floating pad (model 2, part 2)
    RigFloat,
    /// The floating set with model 3: the soft band, unilateral edges, contact exponent 1.5,
    /// its own Table 3.1 fit (f64 only)
    RigBuilt,
}
