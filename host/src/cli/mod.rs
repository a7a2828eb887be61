//! The command line (clap derive). Help texts state units and defaults; keep them true.
//!
//! One module per command family; the long help texts (`after_help`) are the text files in
//! `help/`, each without a final newline (clap prints them as they are).

use clap::{Args, Parser, Subcommand};

use crate::scenes::run::Precision;

mod cases;
mod fit;
pub mod invoke;
mod map;
mod numerics;
pub mod parse;
mod recordings;
mod scenes;
mod simulate;

pub use cases::{CaseSet, CasesArgs};
pub use fit::FitArgs;
pub use map::{MapAction, MapArgs, MapMergeArgs, MapOutput};
pub use numerics::{AccuracyArgs, StabilityArgs};
pub use recordings::{AnalyzeArgs, CompareArgs, DecodeArgs, RecordArgs, SilArgs, SilNoise};
pub use scenes::{ScenesAction, ScenesArgs};
pub use simulate::SimulateArgs;

/// The scene a command runs when none is named (the thesis model's push caliper, load at the
/// centre).
pub const DEFAULT_SCENE: &str = "push_center";

#[derive(Debug, Parser)]
#[command(
    name = "stickslip",
    version,
    about = "Stick-slip of a 2-DOF brake pad on a moving band: run scenes, the six thesis cases, plots",
    after_help = include_str!("help/top.txt")
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run one scene and print a summary (the default command)
    #[command(after_help = include_str!("help/simulate.txt"))]
    Simulate(SimulateArgs),
    /// Run the six cases (push/pull caliper x load near the trailing edge, centre, leading edge)
    /// and print a Markdown table like the thesis's Table 2.1
    #[command(after_help = include_str!("help/cases.txt"))]
    Cases(CasesArgs),
    /// List the built-in scenes, or print one as a scene file (`scenes show NAME`)
    Scenes(ScenesArgs),
    /// Work-precision report: error against run time of every method, in f32 and f64, on
    /// oracle_1dof, pull_center and push_center, and of the model-2 stepper on the Stribeck
    /// scenes (f32 with each of the three exponentials), with the adaptive DOP853 baseline
    #[command(after_help = include_str!("help/accuracy.txt"))]
    Accuracy(AccuracyArgs),
    /// Stability sweeps of stiff and extreme cases around push_center, every method, f32 and
    /// f64, each run classified bounded / sprag / contact_loss / method_unstable
    #[command(after_help = include_str!("help/stability.txt"))]
    Stability(StabilityArgs),
    /// Analyse an accelerometer recording (CSV, UFF 58/58b or WAV: time [s]; disc_x, pad_x,
    /// pad_trail, pad_lead [m/s^2], pad_x required): peak-to-peak, RMS, spectral peak,
    /// groan-band RMS per channel, and the rig estimator's stick fraction and stick-slip
    /// frequency
    #[command(after_help = [include_str!("help/analyze.txt"), "\n\n", include_str!("help/recording.txt")].concat())]
    Analyze(AnalyzeArgs),
    /// The virtual rig: a scene's motion through the rig's sensor model (100 mV/g, noise,
    /// 12-bit ADC, 700 m/s^2 clipping) into the rig's estimator; estimated against true stick
    /// fraction, stick-slip frequency and peak-to-peak
    #[command(after_help = include_str!("help/sil.txt"))]
    Sil(SilArgs),
    /// Model against measurement: a scene through the virtual rig and a recording through the
    /// same analysis, per channel side by side, with the ratios measured / model
    #[command(after_help = [include_str!("help/compare.txt"), "\n\n", include_str!("help/recording.txt")].concat())]
    Compare(CompareArgs),
    /// Regime map: sweep one or two scene keys; per cell the linear stability of steady sliding,
    /// a run from perturbed steady sliding and one from rest, each classified (steady sliding,
    /// stick-slip, ...); in parallel on every core, shardable (`map merge` joins the shards)
    #[command(after_help = include_str!("help/map.txt"))]
    Map(MapArgs),
    /// Identify a rig: fit free scene keys (mu_s, mu_k, v_s, k_b, ...) so that the virtual rig
    /// reproduces recordings (CASE=FILE) or a table of measured statistics (--table), with
    /// standard errors, correlations, flat directions and held-out cases
    #[command(after_help = [include_str!("help/fit.txt"), "\n\n", include_str!("help/recording.txt")].concat())]
    Fit(FitArgs),
    /// Decode the firmware's raw defmt log stream (RTT capture or defmt-semihosting output)
    /// with the firmware ELF into CSV or JSON records
    #[command(after_help = include_str!("help/decode.txt"))]
    Decode(DecodeArgs),
    /// Record the firmware's log as it arrives, from the board's debug probe (RTT) or from a
    /// stream (--input): the raw stream, one CSV per record kind (decode's), a status line per
    /// window, a summary of what was recorded and lost
    #[command(after_help = include_str!("help/record.txt"))]
    Record(RecordArgs),
}

/// How a recording is read, shared by every command that reads one (`analyze`, `compare`,
/// `fit`): written once, flattened into each.
#[derive(Debug, Args, Clone, Default)]
pub struct RecordingInput {
    /// Which column (CSV), record (UFF: any of its ID lines) or channel is which of the rig's
    /// accelerometers: KEY=SOURCE[*SCALE], KEY one of disc_x, pad_x, pad_trail, pad_lead;
    /// SOURCE a name or #N (the N-th column after time, record or WAV channel, from 1); SCALE
    /// multiplies the values into m/s^2 (replacing a unit in the file; a WAV needs one: the
    /// acceleration at full scale). Repeat it per channel; unmapped channels are still found
    /// by name. A name that matches several columns or records, or two columns or records
    /// found by name for one channel, is an error naming them (give #N). pad_x is required,
    /// the others may be absent
    #[arg(long = "channel", value_name = "KEY=SOURCE[*SCALE]", allow_hyphen_values = true)]
    pub channels: Vec<String>,
    /// A jump forward in the time column (rows missing, a gap): `error` (one line naming it,
    /// exit 2) or `split` (analyse the contiguous blocks: the estimator and filters restart
    /// after each gap, the stick-slip frequency pools the blocks' onset intervals; the gaps
    /// are listed). A time that repeats or goes back is always an error
    #[arg(long, value_name = "error|split", default_value = "error", value_parser = ["error", "split"])]
    pub gaps: String,
}

/// Options of the analysis shared by `analyze` and `compare`.
#[derive(Debug, Args)]
pub struct RecordOptions {
    /// Welch segment length [samples], even, 16 to 1048576 (default: the smallest power of two
    /// with a resolution of 2 Hz or finer, 16384 at 25.6 kHz, at most 65536)
    #[arg(long, value_name = "N", value_parser = parse::segment)]
    pub segment: Option<usize>,
    /// Fixed contact thresholds from a breakaway jump J [m/s^2], 0 < J <= 1e6: slip onset above
    /// J/2, stick at most J/4 (default: thresholds from the noise floor of the record's quiet
    /// rows)
    #[arg(long, value_name = "M_S2", allow_hyphen_values = true, value_parser = parse::breakaway_jump)]
    pub breakaway_jump: Option<f64>,
}

/// Where the contact thresholds of a measured recording come from (a quiet stretch or a fixed
/// breakaway jump), with the analysis options: shared by `analyze` and `compare`.
#[derive(Debug, Args)]
pub struct FloorOptions {
    /// The quiet stretch (nothing moves) whose noise floor sets the contact thresholds, on the
    /// file's time axis [s] (default: the quiet rows of a_rel found anywhere in the record, its
    /// stick phases; none found: the scene's breakaway jump)
    #[arg(long, value_name = "FROM:TO", allow_hyphen_values = true)]
    pub quiet: Option<String>,
    #[command(flatten)]
    pub record: RecordOptions,
}

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
