//! The command line (clap derive). Help texts state units and defaults; keep them true.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

use crate::run::Precision;

const AFTER_HELP: &str = "\
With no subcommand, runs `simulate push_center`.

Scene files are TOML: the keys are `name`, `description` (optional) and the model's scene
fields caliper (\"push\"/\"pull\"), m, inertia, l, w, l_cl, l_ct, k_l, k_t, k_g, f_n, beta, v,
mu_s, mu_k, c_x, c_phi, rotation, dt, duration, stats_from, all in SI units. Keys left out take
the default pad's value (the built-in push_center); unknown keys are an error. Start from
`stickslip scenes show push_center > my.toml`, which lists every key with its unit.

Exit codes: 0 success (a run that halts, e.g. on contact loss or sprag, is a finding and still
exits 0, with the outcome reported); 2 bad input (unknown scene, unreadable or invalid scene
file, bad option value), with one line on stderr naming the file or option, the field and the
rule; 1 an output file could not be written; 3 a bound of `accuracy --check` or
`stability --check` failed (the report is still printed).";

#[derive(Debug, Parser)]
#[command(
    name = "stickslip",
    version,
    about = "Stick-slip of a 2-DOF brake pad on a moving band: run scenes, the six thesis cases, plots",
    after_help = AFTER_HELP
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run one scene and print a summary (the default command)
    #[command(after_help = SIMULATE_AFTER)]
    Simulate(SimulateArgs),
    /// Run the six cases (push/pull caliper x load near the trailing edge, centre, leading edge)
    /// and print a Markdown table like the thesis's Table 2.1
    #[command(after_help = CASES_AFTER)]
    Cases(CasesArgs),
    /// List the built-in scenes, or print one as a scene file (`scenes show NAME`)
    Scenes(ScenesArgs),
    /// Work-precision report: error against run time of every method, in f32 and f64, on
    /// oracle_1dof, pull_center and push_center, with the adaptive DOP853 baseline
    #[command(after_help = ACCURACY_AFTER)]
    Accuracy(AccuracyArgs),
    /// Stability sweeps of stiff and extreme cases around push_center, every method, f32 and
    /// f64, each run classified bounded / sprag / contact_loss / method_unstable
    #[command(after_help = STABILITY_AFTER)]
    Stability(StabilityArgs),
}

const ACCURACY_AFTER: &str = "\
Steps 1e-6, 1e-5, 1/25600, 1e-4, 2.5e-4 and 1e-3 s (--quick: 1/25600, 2.5e-4, 1e-3 s); methods
exact, explicit_euler, symplectic_euler, rk4_karnopp, moreau_jean; DOP853 at rtol 1e-5 to 1e-13
(--quick: 1e-6, 1e-8, 1e-10). Error: for the periodic oracle_1dof and pull_center, the larger
relative error of the period and the x amplitude (the final-state error, over each quantity's
peak-to-peak, is reported beside it: phase drift accumulated over the run); for the irregular push_center, the largest relative error of the four
peak-to-peak values and the stick-slip frequency, and the absolute stick-fraction error.
References: the closed form (oracle_1dof); the exact method in f64 at 1/25600 s, cross-checked
against DOP853 at rtol 1e-12 (2-DOF scenes). Cost: minimum wall time over --repeats of the plain
stepping loop; ns per step = that time / steps. Timings depend on the machine and its load.

--json prints {\"rows\": [{\"scene\", \"method\", \"precision\", \"dt\" [s] (null: adaptive),
\"error\" (null: the run halted), \"ns_per_step\", \"run_s\", \"steps\", \"outcome\", \"rtol\",
\"error_period\", \"error_amplitude\", \"error_final\"}...], \"speedup_at_equal_error\",
\"reference_check\", \"checks\"}.

--check exits with code 3 if a bound fails: oracle_1dof exact error at 1/25600 s <= 1e-9 (f64)
and <= 1e-5 (f32); pull_center exact f64 at least 10x faster than DOP853 at error <= 1e-6.";

const STABILITY_AFTER: &str = "\
Sweeps, one parameter at a time around push_center (0.2 s runs; --quick 0.1 s): contact
stiffness k_l = k_t 1e4..1e10 N/m, k_g 1e3..1e9 N/m, mu_s 0..2 and 4, 8 (mu_k = 0.78 mu_s), V 1e-6..10
m/s, beta 0..0.08 m, F_N 0..1e4 N, damping ratio 0..1 (of both modes), dt 1e-7..1e-2 s.
Outcomes: bounded; sprag (the model diverges, or self-locks in stick: stiffness margin given);
contact_loss (N < 0, outside the model's validity); method_unstable (the method halted where
the exact f64 run of the same scene does not: omega_max dt and the method's limit given).

--json prints {\"rows\": [{\"sweep\", \"method\", \"precision\", \"dt\", \"contact_stiffness\",
\"k_g\", \"mu_s\", \"mu_k\", \"v\", \"beta\", \"f_n\", \"damping_ratio\", \"omega_dt\",
\"omega_dt_limit\", \"outcome\", \"t_halt\", \"stiffness_margin\", \"detail\"}...], \"duration_s\"}.

--check exits with code 3 unless the exact method is bounded at contact stiffness 1e10 N/m in
both precisions, every row is classified and no value is NaN or infinite.";

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
    /// Timing repeats; the minimum is kept (default 3, --quick 1)
    #[arg(long, value_name = "N")]
    pub repeats: Option<usize>,
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

const SIMULATE_AFTER: &str = "\
The summary gives the peak-to-peak values of x [m], x' [m/s], phi [rad] and phi' [rad/s] over the
statistics window [stats_from, duration] (exact extremes of the continuous motion), the stick
fraction, the stick-slip frequency [Hz] with their cycle-to-cycle spread, the transitions, the
first slip time and the outcome.

--json prints one object with the keys name, caliper, beta [m], x_pp [m], xdot_pp [m/s],
phi_pp [rad], phidot_pp [rad/s], stick_fraction [-], stick_slip_hz [Hz], precision, dt [s],
duration [s], steps, stats_from [s] (window start used: the nearest step boundary), outcome
(completed | contact_loss | diverged | sprag | non_finite | transition_storm), halt_t_s [s],
first_slip_s [s], transitions (whole run), slip_onsets (window), cycles (complete cycles in the
window, onset to onset), period_mean_s [s] and period_sd_s [s] (their period: mean and sample
standard deviation; stick_slip_hz = 1 / period_mean_s), cycle_stick_fraction_mean [-] and
cycle_stick_fraction_sd [-] (stick fraction of each complete cycle). A value that does not exist
(statistics of a run that halted before the window, a spread of fewer than two cycles) is null.

--csv FILE writes one row per completed step, the state at the end of the step:
t_s,x_m,xdot_m_per_s,phi_rad,phidot_rad_per_s,n_N,f_f_N,regime (regime: stick, slip_slower,
slip_faster; F_f is the friction force on the pad along the band's direction).";

const CASES_AFTER: &str = "\
--json prints {\"precision\", \"dt\" [s], \"duration\" [s], \"stats_from\" [s], \"cases\": [...]}; each
case has exactly the keys name, caliper (\"push\"/\"pull\"), beta [m], x_pp [m], xdot_pp [m/s],
phi_pp [rad], phidot_pp [rad/s], stick_fraction [-], stick_slip_hz [Hz], plus \"outcome\" only
for a case whose run halted (contact_loss | diverged | sprag | non_finite | transition_storm).

--plots DIR writes 8 SVG figures (created if missing): {push,pull}_{displacement,velocity,
angular_displacement,angular_velocity}.svg, the three load positions as three lines. By default
they show the readable window t = stats_from to stats_from + 0.1 s; --plot-from 0 --plot-to
<duration> plots the whole run. Figures use mm, mm/s, mrad and rad/s; the caption names the
window.";

/// Run settings shared by `simulate` and `cases`.
#[derive(Debug, Args)]
pub struct RunOptions {
    /// Time step [s], replaces the scene's dt (six cases: 1/25600 s)
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub dt: Option<f64>,
    /// Run length [s], replaces the scene's duration (six cases: 1 s)
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub duration: Option<f64>,
    /// Start of the statistics window [s], replaces the scene's stats_from (six cases: 0.5 s)
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub stats_from: Option<f64>,
    /// Floating-point type of the stepper
    #[arg(long, value_enum, default_value = "f64")]
    pub precision: Precision,
}

#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// Built-in scene name (see `stickslip scenes`) or path to a TOML scene file
    #[arg(value_name = "SCENE|FILE", default_value = "push_center")]
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

#[derive(Debug, Args)]
pub struct CasesArgs {
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

#[derive(Debug, Args)]
pub struct ScenesArgs {
    #[command(subcommand)]
    pub action: Option<ScenesAction>,
}

#[derive(Debug, Subcommand)]
pub enum ScenesAction {
    /// Print a scene as a complete TOML scene file (every key, with unit and meaning), which
    /// `simulate FILE` accepts unchanged
    Show {
        /// Built-in scene name, or a scene file to print in full
        #[arg(value_name = "NAME|FILE")]
        name: String,
    },
}
