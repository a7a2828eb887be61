//! The command line (clap derive). Help texts state units and defaults; keep them true.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

use crate::scenes::run::Precision;

const AFTER_HELP: &str = "\
With no subcommand, runs `simulate push_center`.

Scene files are TOML: the keys are `name`, `description` (optional) and the model's scene
fields caliper (\"push\"/\"pull\"), m, inertia, l, w, l_cl, l_ct, k_l, k_t, k_g, f_n, beta, v,
mu_s, mu_k, c_x, c_phi, rotation, dt, duration, stats_from, all in SI units; model 2 adds
friction (\"coulomb\"/\"stribeck\"), v_s, stribeck_exponent, band (true/false), m_b, k_b, c_b,
face (true/false: friction-face kinematics), k_pivot (inf: the hinge; finite: the pad translates
normal to the band too), c_y, and damping ratios zeta_x, zeta_phi, zeta_b instead of c_x, c_phi, c_b. Keys left out take the
default pad's value (the built-in push_center, the thesis model); unknown keys are an error.
Start from `stickslip scenes show push_center > my.toml` (or rig_push_center for model 2),
which lists every key with its unit.

Exit codes: 0 success (a run that halts, e.g. on contact loss or sprag, is a finding and still
exits 0, with the outcome reported); 2 bad input (unknown scene, unreadable or invalid scene
file or recording, bad option value), with one line on stderr naming the file or option, the
field (or line and column) and the rule; 1 an output file could not be written; 3 a bound of
`accuracy --check` or `stability --check` failed (the report is still printed); 4 the debug
probe's connection was lost while `record` recorded (what was saved is summarized).

Limits: files read whole are at most 1 MiB (scene files, `fit --table`), 64 MiB (a `map merge`
shard, the `decode --elf` firmware); recordings and defmt streams are streamed. A run's work is
budgeted: substeps per step (the exact steppers' quarter-radian rule) x steps at most 2^27
(134217728: a 5000 s run at 25.6 kHz), and fewer than 4096 substeps per step;
a run over it is not stepped and ends with the outcome `budget` and its cause (exit 0, as any
classified halt). Counts given on the command line are capped as each option's help says.";

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
    /// oracle_1dof, pull_center and push_center, and of the model-2 stepper on the Stribeck
    /// scenes (f32 with each of the three exponentials), with the adaptive DOP853 baseline
    #[command(after_help = ACCURACY_AFTER)]
    Accuracy(AccuracyArgs),
    /// Stability sweeps of stiff and extreme cases around push_center, every method, f32 and
    /// f64, each run classified bounded / sprag / contact_loss / method_unstable
    #[command(after_help = STABILITY_AFTER)]
    Stability(StabilityArgs),
    /// Analyse an accelerometer recording (CSV, UFF 58/58b or WAV: time [s]; disc_x, pad_x,
    /// pad_trail, pad_lead [m/s^2], pad_x required): peak-to-peak, RMS, spectral peak,
    /// groan-band RMS per channel, and the rig estimator's stick fraction and stick-slip
    /// frequency
    #[command(after_help = [ANALYZE_AFTER, "\n\n", RECORDING_AFTER].concat())]
    Analyze(AnalyzeArgs),
    /// The virtual rig: a scene's motion through the rig's sensor model (100 mV/g, noise,
    /// 12-bit ADC, 700 m/s^2 clipping) into the rig's estimator; estimated against true stick
    /// fraction, stick-slip frequency and peak-to-peak
    #[command(after_help = SIL_AFTER)]
    Sil(SilArgs),
    /// Model against measurement: a scene through the virtual rig and a recording through the
    /// same analysis, per channel side by side, with the ratios measured / model
    #[command(after_help = [COMPARE_AFTER, "\n\n", RECORDING_AFTER].concat())]
    Compare(CompareArgs),
    /// Regime map: sweep one or two scene keys; per cell the linear stability of steady sliding,
    /// a run from perturbed steady sliding and one from rest, each classified (steady sliding,
    /// stick-slip, ...); in parallel on every core, shardable (`map merge` joins the shards)
    #[command(after_help = MAP_AFTER)]
    Map(MapArgs),
    /// Identify a rig: fit free scene keys (mu_s, mu_k, v_s, k_b, ...) so that the virtual rig
    /// reproduces recordings (CASE=FILE) or a table of measured statistics (--table), with
    /// standard errors, correlations, flat directions and held-out cases
    #[command(after_help = [FIT_AFTER, "\n\n", RECORDING_AFTER].concat())]
    Fit(FitArgs),
    /// Decode the firmware's raw defmt log stream (RTT capture or defmt-semihosting output)
    /// with the firmware ELF into CSV or JSON records
    #[command(after_help = DECODE_AFTER)]
    Decode(DecodeArgs),
    /// Record the firmware's log as it arrives, from the board's debug probe (RTT) or from a
    /// stream (--input): the raw stream, one CSV per record kind (decode's), a status line per
    /// window, a summary of what was recorded and lost
    #[command(after_help = RECORD_AFTER)]
    Record(RecordArgs),
}

const ANALYZE_AFTER: &str = "\
The CSV: a header naming the time column (t or time) and the channels disc_x, pad_x, pad_trail,
pad_lead in any order (case-insensitive; other columns are ignored; up to 64 preamble lines
before the header are skipped). Units may follow a name: `pad_x [m/s^2]`, `pad_x (m/s²)`,
`time [s]`, `t_s`, `pad_x_m_s2`; time in s (default), ms or us, accelerations in m/s^2
(default), mm/s^2 or g (9.80665 m/s^2). Separator: `;` if the header has one (then numbers may
use a decimal comma, 1,234), else tab, else `,` (decimal point only). Quotes, spaces around
values, blank lines and lines of separators only are accepted.

The time column must increase strictly and be uniform: each interval within 1 % of the mean
interval of the rows before it, plus half the printed resolution of each of its two rows. The
sample rate is (rows - 1) / (t_last - t_first); it must exceed 1000 Hz (the groan band's 500 Hz
edge). Memory does not grow with the file: running statistics, the estimator per sample, Welch
spectra over fixed segments, a 2048-bucket envelope for the figures, the floor search's
histogram (256 KB). A file is read twice (the noise floor, then the analysis); from standard
input the floor is searched in the first 2^18 rows (10.2 s at 25.6 kHz, about 10 MB), which
are held back. Progress goes to stderr when reading takes longer than a second.

Per channel, over the rows at t >= --from: peak-to-peak (max - min, as in the thesis's Table
3.1) and RMS (about zero) [m/s^2]; spectral peak [Hz]: the largest bin above 0 Hz of a Welch
PSD (periodic Hann window, 50 % overlap, each segment's mean removed; the samples after the
last complete segment are left out; a record shorter than a segment is one segment), good to
one bin; groan-band RMS [m/s^2]: RMS of the rig's 100-500 Hz
band-pass (4th-order Butterworth, the rig's coefficients) run on the channel minus its first
sample (the filter starts as if the record had held its first value: a constant gives 0).
Stick fraction [-] and stick-slip frequency [Hz]:
from the rig's estimator, run by the firmware's rig type (shared::rig::pipeline::Rig, made
for the recording: every row goes through the chain the firmware runs after its calibration)
fed every row as calibrated accelerations: samples estimated in stick / samples; (n - 1) / (t_last onset -
t_first onset) over its n stick-to-slip onsets (null with fewer than two); each onset dated
back to where a_rel first left the noise. Its thresholds come from the noise floor of the
record's quiet rows: --quiet FROM:TO (a stretch where nothing moves), else found anywhere in
the record: a_rel in blocks of 32 rows, the blocks whose variance is at most 4 x the 1 %
quantile of all blocks' (its stick phases, wherever they are: a record that starts inside the
stick-slip cycle needs no flag), checked to be quiet (a block 16 x louder exists, 256 quiet
rows or more, and the quiet blocks lie at one level: their variance about their common mean at
most 4 x their within-block variance). Slip onset =
max(6 sigma of a_rel = pad_x - disc_x (+ the face term), 2 counts, 1e-4 m/s^2), stick at half
of it, then adaptive: 1/16 of the slips' mean peak |a_rel|, at most 4 x the designed onset
(shared::rig::contact). Without quiet rows (the summary says why), or with --breakaway-jump J: fixed thresholds
from J (onset J/2, stick J/4; J = (mu_s - mu_k) N0 / m of --scene, push_center: 33.2 m/s^2).
The estimator starts in stick, as the rig's does (its pad is clamped before the band moves): it
is started at the first 16 rows in a row whose a_rel is within its stick level, so a record
that starts inside a slip counts its first, partial slip as slip (its estimator windows start
there too).

Channel health (the rig's rule, shared::rig::health): a channel is flat (no sample changed),
saturated (samples at the range), or noisier than the signal (RMS about the floor's mean below
2 sigma of its floor; never said of disc_x, which has no signal of its own when the band runs
steadily, nor of pad_trail and pad_lead with a floor found in the stick phases, where the pad
still rotates). With pad_x any of these, or disc_x saturated, the estimator cannot decide: the
summary says why and the stick fraction and frequency are null. `compare` and `fit` apply the
same verdict to the recordings they read: an unhealthy channel is not compared (its ratios
null, the words beside) nor fitted (its statistics skipped, the words as the reason), and the
stick fraction, frequency and first slip of an undecided recording neither.

--json prints {\"file\", \"channels\": {\"disc_x\": {\"pp\", \"rms\", \"peak_hz\", \"groan_rms\",
\"mean\", \"min\", \"max\"}, \"pad_x\": ..., \"pad_trail\": ..., \"pad_lead\": ...},
\"stick_fraction\", \"stick_slip_hz\", \"slip_onsets\", \"sample_rate_hz\", \"samples\" (analysed),
\"rows\", \"duration_s\" (samples / rate), \"from_s\", \"t_first_s\", \"t_last_s\",
\"time_resolution_s\" (printed resolution of the time column), \"samples_at_range\" (any channel
at or beyond 700 m/s^2), \"spectrum\": {\"method\", \"window\", \"overlap\", \"segment_samples\",
\"segments\", \"resolution_hz\"}, \"estimator\": {\"breakaway_jump_m_s2\", \"slip_onset_m_s2\",
\"stick_max_m_s2\", \"setup_rate_hz\", \"thresholds_from\" (\"floor\" or \"jump\"), \"floor\": null or
{\"from_s\", \"to_s\", \"chosen\" (\"auto\" or \"given\"), \"samples\", \"sigma_m_s2\" (per channel),
\"a_rel_sigma_m_s2\", \"a_rel_mean_m_s2\", \"quantum_m_s2\", \"quiet_blocks\"}, \"floor_note\" (null or
why no floor was found), \"undecided\" (null or why), \"health\" (per channel, a list of
words)}, \"format\" (CSV, UFF dataset 58, WAV), \"present\" (per channel, true or false),
\"gaps\": [{\"line\", \"t_before_s\", \"t_after_s\", \"intervals\"}], \"notes\"}; an absent channel's
entry in \"channels\" is null; m/s^2, Hz, s.

--plots DIR writes disc_x.svg, pad_x.svg, pad_trail.svg, pad_lead.svg (acceleration [m/s^2]
against time [s], like the thesis's Fig. 3.2 to 3.5) and spectra.svg (the four PSDs
[(m/s^2)^2/Hz], 0 to 2000 Hz, groan band shaded).

Bad input (no pad_x, an empty or non-numeric cell, a ragged row, a time column that repeats,
goes back, drops rows or jumps, an empty file, a header without rows, a UFF record or WAV
header that cannot be read) exits with code 2 and one line naming the file, the line, record
or sample, and the column or field.";

const SIL_AFTER: &str = "\
Per sample (t = (i + 1) dt, one exact step of the scene; the rig's rate 25.6 kHz for the
default dt): the model's motion gives pad_x = x'', pad_trail and pad_lead = r phi'' at sensors
5 mm in from each edge of the pad (r: lever arm about the pivot edge; plus the pad's y'' where
it floats, k_pivot finite), disc_x = the band's x_b'' (band = true; else 0: the band runs at
constant speed); then seeded white noise (--noise, bounded at 3.46 sigma), clipping at +-700
m/s^2, 100 mV/g through a front-end gain of 0.2 into the 12-bit ADC (0.395 m/s^2 per count),
calibration back to m/s^2, and the same analysis as `analyze` (the rig's estimator with its
thresholds from the noise floor of the --quiet-lead phase, default 0.1 s of quiet frames before
t = 0; with --quiet-lead 0, the scene's breakaway jump; --breakaway-jump fixes them).
--gain sets the front-end gain per channel (the amplifier option of the rig's wiring: the
calibration divides it out). Statistics over t >= stats_from (default 0.5 s of a 1 s run).

Truth from the model run itself: its regime at each sample (stick fraction), the exact times
of its stick-to-slip transitions ((n - 1) / (t_n - t_1)), the noise-free accelerations before
clipping and the ADC (peak-to-peak). Error = (estimated - true) / true; null where the truth is
0 (disc_x). Each peak-to-peak comes with its hard error bound [m/s^2]: one ADC count (each
extreme rounded by at most half a count) plus 2 x 3.46 sigma of noise; a channel spanning few
counts cannot be estimated closer than that (pad_trail of push_trail: 15 counts, bound 7 %).

--json prints {\"scene\", \"caliper\", \"beta\" [m], \"sample_rate_hz\", \"stats_from\" [s],
\"samples\", \"steps\", \"outcome\", \"halt_t_s\", \"noise_m_s2\", \"seed\", \"saturated_frames\",
\"stick_fraction\", \"stick_slip_hz\", \"slip_onsets\": {\"estimated\", \"true\", \"error\"},
\"channels\": {\"disc_x\": {\"pp\": {\"estimated\", \"true\", \"error\"}, \"pp_bound\" [m/s^2], \"rms\",
\"peak_hz\", \"groan_rms\"}, ...}}.

Channel health (`analyze`'s rule and words: flat, saturated, noisier than the signal) applies
to the virtual recording, with a channel at its range or an ADC rail in any frame of the window
saturated: where the estimator cannot decide, the stick fraction, frequency and onsets are not
estimated (null) and the summary says why; a saturated channel's peak-to-peak is not estimated.
--json then adds \"undecided\" (why) and \"health\" (per channel, a list of words).

--csv FILE writes every sample's calibrated channels: t_s,disc_x_m_s2,pad_x_m_s2,
pad_trail_m_s2,pad_lead_m_s2 (values that read back to the same numbers), which `analyze` and
`compare` accept. --plots DIR writes the figures of `analyze --plots` for the window.";

const COMPARE_AFTER: &str = "\
The model side is `sil SCENE` (same options): the four channels the virtual rig records over
t >= stats_from. The measured side is `analyze FILE` over t >= --from, with the scene's
breakaway jump unless --breakaway-jump is given (it applies to the measured side, and to the
model side only when the scene has no jump of its own: mu_s = mu_k). Per
channel: peak-to-peak and RMS [m/s^2], spectral peak [Hz]; and the stick fraction [-] and the
stick-slip frequency [Hz]; each as measured, model, and measured / model (null when the model
value is 0 or missing).

--json prints {\"scene\", \"file\", \"channels\": {\"disc_x\": {\"pp\", \"peak_hz\", \"rms\",
\"groan_rms\": {\"measured\", \"model\", \"ratio\"}}, ...}, \"stick_fraction\": {...},
\"stick_slip_hz\": {...}, \"measured\": {\"sample_rate_hz\", \"samples\", \"duration_s\", \"from_s\",
\"resolution_hz\"}, \"model\": {...}, \"model_outcome\", \"model_noise_m_s2\", \"health\" (the measured
channels' words, as analyze gives them), \"undecided\" (null or why the measured stick fraction
and frequency cannot be told)}. The measured side gets analyze's channel-health verdict: a
measured channel that is flat, saturated or noisier than the signal has null ratios (its words
are printed beside), an absent one null values, and an undecided recording no measured stick
fraction or frequency.

`sil SCENE --csv run.csv` then `compare SCENE run.csv --from <stats_from>` gives ratios of 1.";

/// How a recording is read, shared by every command that reads one (`analyze`, `compare`,
/// `fit`): written once, flattened into each.
#[derive(Debug, Args, Clone, Default)]
pub struct RecordingInput {
    /// Which column (CSV), record (UFF: any of its ID lines) or channel is which of the rig's
    /// accelerometers: KEY=SOURCE[*SCALE], KEY one of disc_x, pad_x, pad_trail, pad_lead;
    /// SOURCE a name or #N (the N-th column after time, record or WAV channel, from 1); SCALE
    /// multiplies the values into m/s^2 (replacing a unit in the file; a WAV needs one: the
    /// acceleration at full scale). Repeat it per channel; unmapped channels are still found
    /// by name. pad_x is required, the others may be absent
    #[arg(long = "channel", value_name = "KEY=SOURCE[*SCALE]", allow_hyphen_values = true)]
    pub channels: Vec<String>,
    /// A jump forward in the time column (rows missing, a gap): `error` (one line naming it,
    /// exit 2) or `split` (analyse the contiguous blocks: the estimator and filters restart
    /// after each gap, the stick-slip frequency pools the blocks' onset intervals; the gaps
    /// are listed). A time that repeats or goes back is always an error
    #[arg(long, value_name = "error|split", default_value = "error", value_parser = ["error", "split"])]
    pub gaps: String,
}

const RECORDING_AFTER: &str = "\
Recordings (analyze, compare, fit): the format is told from the content, not the name: a CSV,
a universal file with dataset 58 records (ASCII 58 or binary 58b, real single or double,
even abscissa: B&K PULSE, Siemens Test.Lab, pyuff), or a WAV file (integer PCM 8 to 32 bits
or 32-bit float, any channel count; no units and no names: map each channel by --channel
KEY=#N*SCALE, SCALE the acceleration at full scale in m/s^2, required unless the file is float
in m/s^2). A UFF record is one channel: named by any of its ID lines or #N, its time axis
from record 7 (abscissa minimum and increment, record 8's units), its unit from record 9's
units label (m/s^2, mm/s^2, g; none with specific data type 12: m/s^2); UFF needs a file (not
standard input). Logger columns: --channel pad_x='Acc1 [g]' --channel disc_x=#3*9.80665.

Which statistic needs which channel: pad_x is required (the stick fraction and stick-slip
frequency come from a_rel = pad_x - disc_x, and pad_x's health decides whether they can be
told); without disc_x, a_rel = pad_x alone (the band taken at constant speed: the summary says
so); without pad_trail or pad_lead the estimator's face term is left out. Peak-to-peak, RMS,
spectral peak and groan-band RMS are per channel: an absent channel's are absent (null in
JSON, `absent` in the table), never 0.

The time axis is checked at full precision: each interval within 1 % of the mean interval
plus half the printed resolution of each of its two rows; a time that repeats or goes back, a
drop of rows or a gap is named by its line (--gaps split analyses around gaps instead).";

/// Options of the analysis shared by `analyze` and `compare`.
#[derive(Debug, Args)]
pub struct RecordOptions {
    /// Welch segment length [samples], even, 16 to 1048576 (default: the smallest power of two
    /// with a resolution of 2 Hz or finer, 16384 at 25.6 kHz, at most 65536)
    #[arg(long, value_name = "N")]
    pub segment: Option<usize>,
    /// Fixed contact thresholds from a breakaway jump J [m/s^2], 0 < J <= 1e6: slip onset above
    /// J/2, stick at most J/4 (default: thresholds from the noise floor of the record's quiet
    /// rows)
    #[arg(long, value_name = "M_S2", allow_hyphen_values = true)]
    pub breakaway_jump: Option<f64>,
}

#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    /// The recording: a CSV, UFF (dataset 58/58b) or WAV file, or `-` for standard input
    #[arg(value_name = "FILE")]
    pub file: String,
    #[command(flatten)]
    pub input: RecordingInput,
    /// Print one JSON object instead of the Markdown summary
    #[arg(long)]
    pub json: bool,
    /// Write the SVG figures (each channel against time, the spectra) into DIR
    #[arg(long, value_name = "DIR")]
    pub plots: Option<PathBuf>,
    /// Write the estimator's own window statistics (100 ms windows from the first row, the
    /// keys of the firmware's `window` record: pp, rms, groan_rms per channel, stick, ss_hz,
    /// onsets...) to FILE as CSV, one row per window
    #[arg(long, value_name = "FILE")]
    pub windows: Option<PathBuf>,
    /// Start of the statistics on the file's time axis [s] (default: the first row); earlier
    /// rows only run through the estimator and its filters
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub from: Option<f64>,
    /// Scene whose band speed and face geometry set up the estimator, and whose breakaway
    /// jump is the starting value (built-in name or TOML file)
    #[arg(long, value_name = "SCENE|FILE", default_value = "push_center")]
    pub scene: String,
    /// The quiet stretch (nothing moves) whose noise floor sets the contact thresholds, on the
    /// file's time axis [s] (default: the quiet rows of a_rel found anywhere in the record, its
    /// stick phases; none found: the scene's breakaway jump)
    #[arg(long, value_name = "FROM:TO", allow_hyphen_values = true)]
    pub quiet: Option<String>,
    #[command(flatten)]
    pub record: RecordOptions,
}

/// The virtual rig's sensor noise.
#[derive(Debug, Args)]
pub struct SilNoise {
    /// White noise on each accelerometer [m/s^2 rms], 0 (none) to 10000 (bounded at 3.46 sigma)
    #[arg(long, value_name = "M_S2", default_value_t = crate::recorded::sil::DEFAULT_NOISE_M_S2, allow_hyphen_values = true)]
    pub noise: f64,
    /// Seed of the noise generator
    #[arg(long, value_name = "N", default_value_t = crate::recorded::sil::DEFAULT_SEED, allow_hyphen_values = true)]
    pub seed: u32,
    /// Front-end gain of the accelerometers [V/V], 0.001 to 1000: one value for all four, or
    /// four (disc_x,pad_x,pad_trail,pad_lead). 0.2 spans +-809 m/s^2 at 0.395 m/s^2 per count;
    /// 10 spans +-16 m/s^2 at 7.9 mm/s^2 per count (Table 3.1's levels)
    #[arg(long, value_name = "G[,G,G,G]", value_delimiter = ',', allow_hyphen_values = true)]
    pub gain: Vec<f64>,
    /// The clamped, band-still phase before the run [s], 0 to 60: quiet frames written before
    /// t = 0, whose noise floor sets the contact thresholds (0: none, the scene's breakaway jump)
    #[arg(long, value_name = "S", default_value_t = crate::recorded::sil::DEFAULT_QUIET_S, allow_hyphen_values = true)]
    pub quiet_lead: f64,
    /// Conversions summed per frame, 1 to 16 (the firmware's oversampling: 4; 1: none): each
    /// frame count is the sum of N conversions of the same frame
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=16))]
    pub oversample: u32,
    /// The converter's own noise on each conversion [counts rms], 0 (none) to 4096 (it dithers
    /// the oversampled conversions, the sensor's noise is drawn once per frame)
    #[arg(long, value_name = "COUNTS", default_value_t = 0.0, allow_hyphen_values = true)]
    pub adc_noise: f64,
}

#[derive(Debug, Args)]
pub struct SilArgs {
    /// Built-in scene name (see `stickslip scenes`) or path to a TOML scene file
    #[arg(value_name = "SCENE|FILE", default_value = "push_center")]
    pub scene: String,
    /// Print one JSON object instead of the Markdown summary
    #[arg(long)]
    pub json: bool,
    /// Write every sample's calibrated channels to FILE (CSV, `analyze` reads it)
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Write the SVG figures of the statistics window into DIR
    #[arg(long, value_name = "DIR")]
    pub plots: Option<PathBuf>,
    /// Write the rig's estimator's window statistics (100 ms windows from the first frame, the
    /// quiet lead's included; the columns of `analyze --windows`) to FILE as CSV
    #[arg(long, value_name = "FILE")]
    pub windows: Option<PathBuf>,
    /// The front end: rig (noise, 700 m/s^2 clipping, 12-bit ADC, calibration: the rig as
    /// built) or ideal (the accelerations plus the noise only: a high-resolution logger)
    #[arg(long, value_name = "rig|ideal", default_value = "rig", value_parser = ["rig", "ideal"])]
    pub front_end: String,
    #[command(flatten)]
    pub record: RecordOptions,
    #[command(flatten)]
    pub noise: SilNoise,
    #[command(flatten)]
    pub run: RunOptions,
}

#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The model: built-in scene name or TOML scene file
    #[arg(value_name = "SCENE|FILE")]
    pub scene: String,
    /// The measurement: a recording as `analyze` reads it (`-`: standard input)
    #[arg(value_name = "FILE")]
    pub file: String,
    #[command(flatten)]
    pub input: RecordingInput,
    /// Print one JSON object instead of the Markdown table
    #[arg(long)]
    pub json: bool,
    /// Start of the statistics on the recording's time axis [s] (default: its first row)
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub from: Option<f64>,
    /// The quiet stretch (nothing moves) whose noise floor sets the contact thresholds, on the
    /// file's time axis [s] (default: the quiet rows of a_rel found anywhere in the record, its
    /// stick phases; none found: the scene's breakaway jump)
    #[arg(long, value_name = "FROM:TO", allow_hyphen_values = true)]
    pub quiet: Option<String>,
    #[command(flatten)]
    pub record: RecordOptions,
    #[command(flatten)]
    pub noise: SilNoise,
    #[command(flatten)]
    pub run: RunOptions,
}

#[derive(Debug, Args)]
pub struct DecodeArgs {
    /// The firmware ELF the stream came from (its .defmt section and symbols), at most 64 MiB
    #[arg(long, value_name = "FIRMWARE_ELF")]
    pub elf: PathBuf,
    /// The raw defmt byte stream (`-` or nothing: standard input)
    #[arg(value_name = "FILE|-", default_value = "-")]
    pub input: String,
    /// Print one JSON object instead of CSV
    #[arg(long)]
    pub json: bool,
    /// CSV of one kind of record only, with its fields as columns (window, event, state,
    /// command, ...: see below)
    #[arg(long, value_name = "KIND", conflicts_with = "json")]
    pub kind: Option<String>,
}

const DECODE_AFTER: &str = "\
The stream: the raw bytes the firmware's defmt logger sent (rzCOBS frames, each ending with
0x00), as saved from the RTT up-channel by a debug-probe tool, or as defmt-semihosting prints
them under QEMU (`qemu-system-arm ... -semihosting-config enable=on,target=native > log.defmt`).
A truncated or corrupted stream decodes what can be recovered: a frame that does not decode is
dropped and its bytes skipped, bytes after the last frame separator are an incomplete frame;
stderr gets one line with the counts (frames decoded and dropped, bytes skipped, incomplete
bytes). defmt has no checksum, but a frame must fit its format: a frame whose format (named by
its index in the ELF's table) does not use exactly its bytes is dropped, and a stream of 8
frames or more of which more than half are dropped is refused (exit 2): it is not from this
ELF's build (another build's indices name other formats) or is damaged beyond use. A corrupted
frame that still fits its format gives a wrong record.

Kinds: the records of the firmware's log (see firmware/README.md, Log records): boot, armed,
config_error, start, state, command, event, window, overrun, stall, input, panic. Each is laid
out as `name key={..} key={..} ...` and decodes to kind `name` with its keys as fields (an
array `[a, b, c, d]` as a JSON array, in CSV as key_0 ... key_3); any other line: kind log
(fields arg0, arg1, ...).

CSV (default): frame,offset,timestamp_s,level,kind,message, one row per decoded frame.
--kind KIND: only that kind, columns frame,timestamp_s and its fields (exit 2 if the stream
has none).
--json prints {\"records\": [{\"frame\", \"offset\", \"timestamp\", \"timestamp_s\", \"level\", \"kind\",
\"message\", \"fields\": {...}}...], \"stream\": {\"encoding\", \"bytes\", \"frames_decoded\",
\"frames_dropped\", \"bytes_skipped\", \"incomplete_bytes\"}}.

Exit codes: 0 (also when frames were lost: the counts say so), 2 an unreadable or defmt-less
ELF (at most 64 MiB), a stream that does not fit the ELF's table (see above), a --kind with
no record, an unreadable stream.";

#[derive(Debug, Args)]
pub struct RecordArgs {
    /// The firmware ELF that runs on the board (its .defmt table decodes the log)
    #[arg(long, value_name = "FIRMWARE_ELF")]
    pub elf: PathBuf,
    /// Read the raw defmt stream from FILE (`-`: standard input, e.g. a pipe) instead of a probe
    #[arg(long, value_name = "FILE|-", conflicts_with_all = ["probe", "flash"])]
    pub input: Option<String>,
    /// The folder for raw.defmt and the CSVs, new or empty (default: a new folder
    /// rig-YYYYMMDDTHHMMSSZ, the start time in UTC, in the current directory)
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Write the raw stream to FILE (a new file) instead of DIR/raw.defmt
    #[arg(long, value_name = "FILE")]
    pub raw: Option<PathBuf>,
    /// The target chip, as probe-rs names it
    #[arg(long, value_name = "CHIP", default_value = "STM32F407VGTx")]
    pub chip: String,
    /// The debug probe when several are connected: USB vendor and product id in hex, and its
    /// serial number (e.g. 0483:374b:066DFF535155878281123456)
    #[arg(long, value_name = "VID:PID[:SERIAL]")]
    pub probe: Option<String>,
    /// Flash this ELF (it must be the --elf file) and reset the chip before recording; without
    /// it, attach to the firmware that runs
    #[arg(long, value_name = "ELF")]
    pub flash: Option<PathBuf>,
}

const RECORD_AFTER: &str = "\
Sources: the board through a debug probe (probe-rs: attach to CHIP, or --flash and reset; the
RTT control block found from the ELF's _SEGGER_RTT symbol or by a scan of RAM; up-channel 0,
the firmware's defmt log, read raw), or --input FILE|- (a saved stream, or a pipe such as QEMU's
semihosting output). The probe needs this tool built with the cargo feature `probe` (README,
At the rig).

Written as the records arrive, in DIR: raw.defmt (or --raw FILE), every byte read, in order:
`stickslip decode --elf ELF DIR/raw.defmt` decodes it again; KIND.csv for every record kind
seen (window, event, state, command, floor, health, boot, ...; kind log for other lines), each
equal to `stickslip decode --elf ELF DIR/raw.defmt --kind KIND` (columns frame, timestamp_s
[s], then the record's keys, arrays as key_0...), one line written per record: a crash or a
pulled cable loses at most the record in flight. Decoding is decode's own: a frame that does
not decode is dropped and counted, a cut frame at the end is counted as incomplete.

stderr: a status line per window record: the record and window number, stick fraction [-],
stick-slip frequency [Hz], pad_x peak-to-peak [m/s^2], the valves (actuator/band open, from
the last state record) and the sequencer state, and the frames dropped so far; a line per
state and command record and per warn or error record. On a terminal the status line is
redrawn in place.

Stops at the end of the input, on Ctrl-C (SIGINT: the files are complete; a second Ctrl-C
exits at once), or when the probe connection is lost. stdout then gets the summary: why it
stopped, the raw bytes, decode's counts (frames decoded and dropped, bytes skipped,
incomplete bytes), the records per kind with their files, and what the firmware itself
reports as not logged (the window records' events_dropped, windows_dropped, overruns).

Exit codes: 0 the input ended or Ctrl-C (also when frames were lost: the summary counts
them); 2 bad input: an unreadable or defmt-less ELF (at most 64 MiB), a stream that does not
fit the ELF's table (as decode refuses it; the files stay, the summary is printed), an
unreadable --input, --out not empty,
--raw exists, --flash not the --elf file, no probe attached, a probe or chip that cannot be
opened or attached, no RTT control block, or a tool built without the feature `probe` asked
for one; 1 a file could not be written (the summary says what was saved); 4 the probe
connection was lost while recording (the summary says what was saved).";

const ACCURACY_AFTER: &str = "\
Steps 1e-6, 1e-5, 1/25600, 1e-4, 2.5e-4 and 1e-3 s (--quick: 1/25600, 2.5e-4, 1e-3 s); methods
exact, explicit_euler, symplectic_euler, rk4_karnopp, moreau_jean; DOP853 at rtol 1e-5 to 1e-13
(--quick: 1e-6, 1e-8, 1e-10). Error: for the periodic oracle_1dof and pull_center, the larger
relative error of the period and the x amplitude (the final-state error, over each quantity's
peak-to-peak, is reported beside it: phase drift accumulated over the run); for the irregular push_center, the largest relative error of the four
peak-to-peak values and the stick-slip frequency, and the absolute stick-fraction error.
References: the closed form (oracle_1dof); the exact method in f64 at 1/25600 s, cross-checked
against DOP853 at rtol 1e-12 (2-DOF scenes). Model 2 (oracle_stribeck, pull_center_stribeck,
rig_pull_center): method model2 in f64, f32 (the model's own exp), \"f32 libm exp\" and \"f32
micromath exp\" (the firmware's alternative exponentials, same stepper), against the model-2
reference (DOP853 at rtol 1e-12, its own right-hand side); the exponentials' own errors over
exp(-y), y in [0, 20], are listed. Cost: minimum wall time over --repeats of the plain
stepping loop; ns per step = that time / steps. Timings depend on the machine and its load.

--json prints {\"rows\": [{\"scene\", \"method\", \"precision\", \"dt\" [s] (null: adaptive),
\"error\" (null: the run halted), \"ns_per_step\", \"run_s\", \"steps\", \"outcome\", \"rtol\",
\"error_period\", \"error_amplitude\", \"error_final\"}...], \"speedup_at_equal_error\",
\"reference_check\", \"checks\", \"exp_f32\": [{\"exp\", \"precision\", \"max_rel_error\",
\"at_y\"}...]}.

--check exits with code 3 if a bound fails: oracle_1dof exact error at 1/25600 s <= 1e-9 (f64)
and <= 1e-5 (f32); pull_center exact f64 at least 10x faster than DOP853 at error <= 1e-6;
oracle_stribeck model2 error at 1/25600 s <= 1e-6 (f64) and <= 1e-4 (f32).";

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

const FIT_AFTER: &str = "\
Targets: a recording CASE=FILE (a CSV, UFF or WAV file as `analyze` reads it, --channel and
--gaps as there, its time zero at the band's start,
as `sil --csv` writes it) gives, over t >= --from, every statistic `analyze` computes: per
channel pp, rms, groan_rms [m/s^2] and peak_hz [Hz]; per case stick_fraction [-],
stick_slip_hz [Hz] and first_slip_s [s] (the estimator's first slip onset in the whole file:
it carries the friction level, which the accelerations alone do not). A table (--table FILE)
is CSV `case,channel,statistic,value` with that header (channel empty for a per-case
statistic); `--table thesis_table_3_1` is the thesis's Table 3.1 (24 peak-to-peak values).
CASE is one of push_trail, push_center, push_lead, pull_trail, pull_center, pull_lead (SCENE
with that case's caliper and beta, c_phi at SCENE's damping ratio) or SCENE's own name.

Cost (--cost): with recordings alone of a 1-DOF scene (rotation = false, band = false), the
default is the time-domain cost (waveform): the recorded pad_x sample by sample against the
model's, by multiple shooting: the recording is cut at its re-sticks, and in each segment the
model's cycle (the slip integrated from the breakaway state x_s = (mu_s N - c_x V) / k_g,
x' = V, its re-stick located inside the step) is placed on the recorded re-stick, shifted by
at most 2 samples to fit best; 3 samples either side of each re-stick are left out; one more
residual holds the first re-stick's time from the band's start (the friction level). Residual
= (recorded - model) / noise. A global stage fits the cycles' features first (first re-stick,
period, extremes, mean square). Otherwise (statistics) the model of each case runs through the
virtual rig's ideal sensor path (no noise, no ADC) into the same analysis, with the estimator's breakaway jump of SCENE (or --breakaway-jump) on
both sides. Residual = sqrt(weight) ln(model / measured); default weight 1, peak_hz 0 (one
Welch bin is too coarse). A recording's pp is fitted only with --weights pp=W: a sampled
extreme depends on where the samples fall on the waveform's sharpest part (with falling
friction, the last slip samples before a re-stick), not only on the parameters.
Search: from each of --starts starts (in parallel) Nelder-Mead (argmin) on ln(value), then
Levenberg-Marquardt from its best point; the lowest cost wins. Bounds default to a physical
range per key (docs/fit.md: mu 0.05..1.5, v_s 1e-5..1 m/s, stiffnesses, masses, damping as
ratios 1e-4..1 of critical; other keys start / 10 .. start x 10); --bounds overrides. The
starts after SCENE's values are the best of a global screen of Halton points over the whole
box of the bounds (256 per free key on the features of the time-domain cost, 24 per key on a
table's statistics). With statistics of recordings, each start is first fitted to the recordings' first stretch, from
t = 0 to the first slip onset + the first of --horizons stick-slip periods (each recording in
its own periods; default 1.5, then 4.5: a horizon in mid-stick, not at an onset), from there
to the next horizon, then to the whole record: a record's statistics jump wherever the kind of
stick-slip cycle changes, its first cycles' do not (--horizons 0: none). The starts after
SCENE's values are then the best of a screen of the first horizon (64 Halton points per free
key over a factor 2 either way).
Goodness: chi^2 per degree of freedom against the noise: the recording's own (the RMS of its
samples where the fitted model is in stick) for the time-domain cost; for statistics, each log
ratio's spread over its recording's windows, or an assumed 0.25 in ln(value) where none is
stated (a table's). Verdict: fits (chi^2 / dof within 1 + 3 sqrt(2 / dof) + 0.1), misfit (above,
and two starts agree on the cost: the model family does not fit), not_converged (above, and no
start confirms the best); converged is true only with fits. Intervals (time-domain cost): 95 %
profile likelihood per free key (the others re-fitted along it; threshold Delta chi^2 = 3.84 x
max(1, chi^2 / dof)); null on a side where the profile does not close inside the bounds.
Standard errors: central-difference Jacobian at the optimum, scaled by the residual variance;
a direction of the parameters known to no better than about +-35 % is reported as flat (not
identifiable). Recordings add a bootstrap over 8 windows each (a linearised refit per
resample). --holdout fits without those cases and reports the fitted model's prediction of
them. --profile KEY=LO:HI:N runs no search: it prints the cost at N values of KEY log-spaced
from LO to HI (the other free keys at SCENE's values) with the statistic furthest off at each,
to see a basin's width, a flat direction or a jump where the stick-slip cycle changes; with
--json {\"scene\", \"key\", \"others\", \"statistics\", \"points\": [{\"value\", \"cost\",
\"rms_log_ratio\", \"worst\", \"worst_log_ratio\", \"error\"}], \"seconds\"}.

--json prints {\"scene\", \"parameters\": {KEY: {\"value\", \"std\", \"std_bootstrap\", \"start\",
\"lo\", \"hi\", \"interval\": [lo|null, hi|null]}}, \"residuals\": [{\"case\", \"channel\",
\"statistic\", \"measured\", \"model\", \"log_ratio\", \"weight\", \"source\"}], \"holdout\": [...],
\"converged\", \"goodness\": {\"chi2_per_dof\", \"dof\", \"noise\", \"noise_source\", \"chi2_limit\",
\"starts_agreeing\", \"verdict\"}, \"cost_kind\", \"identifiable\",
\"flat_directions\", \"correlation\", \"cost\", \"residual_variance\", \"rms_log_ratio_fitted\",
\"rms_log_ratio_holdout\", \"weights\", \"breakaway_jump_m_s2\", \"bootstrap_resamples\",
\"evaluations\", \"seconds\", \"starts\", \"stages\": [{\"cycles\", \"horizons_s\", \"statistics\",
\"values\", \"cost\", \"converged\"}], \"skipped\", \"notes\"}. Progress goes to stderr.
Bad targets (unknown case, a free key that is not numeric, a table row with an unknown channel
or statistic, a recording that does not parse) exit 2 with one line naming them.";

const MAP_AFTER: &str = "\
Each cell is SCENE with the swept values (a damping ratio zeta_x, zeta_phi, zeta_b is set after
the other keys, with the cell's stiffness). Per cell:
- linear: steady sliding at the band speed linearised with the model's own matrices (the
  falling friction slope as negative damping, the floating pad's friction-coupled stiffness);
  eigenvalues by nalgebra: stable (every mode decays or is neutral), the largest growth rate
  [1/s], the unstable mode's frequency [Hz]; or no steady sliding (sprag, contact_loss);
- from_sliding: a run from steady sliding with a velocity kick (--kick), and from_rest: a run
  from the default stuck start. Each run's regime: stick_slip (a breakaway in the statistics
  window), stuck (stick and no breakaway in the window), steady_sliding (never in stick, the
  sliding velocity's peak-to-peak <= 4 kick V), sliding_oscillation (never in stick, larger),
  sprag, contact_loss, method_unstable (another halt); stick fraction, stick-slip frequency
  [Hz], pad_x peak-to-peak and groan-band (100 to 500 Hz) RMS [m/s^2] over the window.
Cells where from_sliding is steady and from_rest stick-slips are bistable (a subcritical Hopf
band). A cell whose scene is invalid is reported as such (its reason in `invalid`).

--json prints {\"scene\", \"scene_toml\", \"sweeps\", \"duration_s\", \"stats_from_s\", \"dt_s\",
\"precision\", \"kick\", \"steady_pp_over_kick_v\", \"cells_total\", \"shard\", \"cells\": [{\"index\",
\"params\": {KEY: value}, \"invalid\", \"linear\": {\"stable\", \"max_growth_rate\", \"unstable_hz\",
\"no_steady_sliding\", \"modes\"}, \"from_sliding\": {\"regime\", \"stick_fraction\", \"stick_slip_hz\",
\"pad_x_pp\", \"groan_rms\", \"slide_v_pp\", \"halt_s\"}, \"from_rest\": {...}}]}; null where a
value does not exist. Cell index i = i_1 + n_1 i_2 (the first sweep runs fastest).

A progress bar with the time left, and the steps per second at the end, go to stderr. On a
cluster: run `map ... --shard K/N --json > shard_K.json` for K = 0..N-1 as a job array, then
`map merge shard_*.json` (it checks that every cell is there once; the result equals the unsplit
map). Bad sweeps (unknown key, N = 0, FROM > TO with log, a value that makes every cell it is in
invalid) exit 2 with one line naming the sweep.";

const SIMULATE_AFTER: &str = "\
The summary gives the peak-to-peak values of x [m], x' [m/s], phi [rad] and phi' [rad/s] over the
statistics window [stats_from, duration] (exact extremes of the continuous motion), the stick
fraction, the stick-slip frequency [Hz] with their cycle-to-cycle spread, the transitions, the
first slip time and the outcome; for a model-2 scene also the linear stability of steady
sliding at the band speed (the model's own linearisation: stable, neutral, or the growth rate
[1/s] and frequency of the fastest-growing mode), and for a pad that is not hinged (finite
k_pivot) the kinetic friction at which steady Coulomb sliding turns unstable by mode coupling
(flutter).

--json prints one object with the keys name, caliper, beta [m], x_pp [m], xdot_pp [m/s],
phi_pp [rad], phidot_pp [rad/s], stick_fraction [-], stick_slip_hz [Hz], precision, dt [s],
duration [s], steps, stats_from [s] (window start used: the nearest step boundary), outcome
(completed | contact_loss | diverged | sprag | non_finite | transition_storm), halt_t_s [s],
first_slip_s [s], transitions (whole run), slip_onsets (window), cycles (complete cycles in the
window, onset to onset), period_mean_s [s] and period_sd_s [s] (their period: mean and sample
standard deviation; stick_slip_hz = 1 / period_mean_s), cycle_stick_fraction_mean [-] and
cycle_stick_fraction_sd [-] (stick fraction of each complete cycle), and for a model-2 scene
linear: {stable, max_growth_rate [1/s], unstable_hz [Hz], invalid (why steady sliding does not
exist, or null), flutter_mu_k (finite k_pivot only)}. A value that does not exist (statistics of
a run that halted before the window, a spread of fewer than two cycles) is null.

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
    #[arg(long, value_name = "K", default_value_t = 0.01, allow_hyphen_values = true)]
    pub kick: f64,
    /// Run only every N-th cell starting at K (0 <= K < N <= 10000000), for a job array; join
    /// the shards' --json with `map merge`
    #[arg(long, value_name = "K/N", allow_hyphen_values = true)]
    pub shard: Option<String>,
    /// Worker threads, 1 to 1024 (default: every core)
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub jobs: Option<u16>,
    #[command(flatten)]
    pub run: RunOptions,
    #[command(flatten)]
    pub out: MapOutput,
}

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
    /// A table of measured statistics: CSV case,channel,statistic,value, at most 1 MiB (or the
    /// built-in thesis_table_3_1)
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
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub from: Option<f64>,
    /// Starts of the search, 1 to 1000 (the scene's values, then points spread over +-30 %;
    /// with horizon stages, the best points of a screen of the first horizon)
    #[arg(long, value_name = "N", default_value_t = crate::fit::DEFAULT_STARTS)]
    pub starts: usize,
    /// Horizon stages before the whole record, in stick-slip periods after each recording's
    /// first slip onset (0: none): each start is fitted to the recordings' first stretch, t = 0
    /// to the first horizon, then to the next, then to the whole record (see below)
    #[arg(long, value_name = "CYCLES[,CYCLES...]", value_delimiter = ',', default_values_t = crate::fit::DEFAULT_HORIZONS, allow_hyphen_values = true)]
    pub horizons: Vec<f64>,
    /// What recordings are compared by: waveform (pad_x sample by sample, multiple shooting over
    /// the cycles: 1-DOF scenes), statistics (the whole record's), or auto (waveform where it
    /// applies: recordings alone, every case a 1-DOF scene)
    #[arg(long, value_name = "auto|waveform|statistics", default_value = "auto")]
    pub cost: String,
    /// Iteration limit of each start's Nelder-Mead run (and evaluation budget of its
    /// Levenberg-Marquardt run), 1 to 1000000
    #[arg(long, value_name = "N", default_value_t = crate::fit::DEFAULT_MAX_ITERS)]
    pub max_iters: u64,
    /// Bootstrap resamples over the recordings' windows, 0 (none) to 100000
    #[arg(long, value_name = "N", default_value_t = crate::fit::DEFAULT_BOOTSTRAP)]
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
    /// Write one row per cell to FILE (CSV)
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Write the figure to FILE (SVG): heat maps with the linear boundary (two sweeps), lines
    /// (one sweep)
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
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
    /// Which six cases: `thesis` (the thesis model, no damping), `rig` (model 2: Stribeck
    /// friction, the band as a mass, a few percent damping; mu_k, v_s, k_b fitted to Table
    /// 3.1) or `rig-float` (the rig set with the face and a floating pad, its own fit)
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
