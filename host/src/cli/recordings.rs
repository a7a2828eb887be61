//! The commands of recordings and the rig: `analyze`, `sil`, `compare`, `decode`, `record`.

use std::path::PathBuf;

use clap::Args;

use super::{FloorOptions, RecordOptions, RecordingInput, RunOptions};

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
    #[arg(long, value_name = "S", allow_hyphen_values = true, value_parser = super::parse::from_time)]
    pub from: Option<f64>,
    /// Scene whose band speed and face geometry set up the estimator, and whose breakaway
    /// jump is the starting value (built-in name or TOML file)
    #[arg(long, value_name = "SCENE|FILE", default_value = super::DEFAULT_SCENE)]
    pub scene: String,
    #[command(flatten)]
    pub floor: FloorOptions,
}

/// The virtual rig's sensor noise.
#[derive(Debug, Args)]
pub struct SilNoise {
    /// White noise on each accelerometer [m/s^2 rms], 0 (none) to 10000 (bounded at 3.46 sigma)
    #[arg(long, value_name = "M_S2", default_value_t = crate::recorded::sil::DEFAULT_NOISE_M_S2, allow_hyphen_values = true, value_parser = super::parse::noise)]
    pub noise: f64,
    /// Seed of the noise generator
    #[arg(long, value_name = "N", default_value_t = crate::recorded::sil::DEFAULT_SEED, allow_hyphen_values = true)]
    pub seed: u32,
    /// Front-end gain of the accelerometers [V/V], 0.001 to 1000: one value for all four, or
    /// four (disc_x,pad_x,pad_trail,pad_lead). 0.2 spans +-809 m/s^2 at 0.395 m/s^2 per count;
    /// 10 spans +-16 m/s^2 at 7.9 mm/s^2 per count (Table 3.1's levels)
    #[arg(long, value_name = "G[,G,G,G]", value_delimiter = ',', allow_hyphen_values = true, value_parser = super::parse::gain)]
    pub gain: Vec<f64>,
    /// The clamped, band-still phase before the run [s], 0 to 60: quiet frames written before
    /// t = 0, whose noise floor sets the contact thresholds (0: none, the scene's breakaway jump)
    #[arg(long, value_name = "S", default_value_t = crate::recorded::sil::DEFAULT_QUIET_S, allow_hyphen_values = true, value_parser = super::parse::quiet_lead)]
    pub quiet_lead: f64,
    /// Conversions summed per frame, 1 to 16 (the firmware's oversampling: 4; 1: none): each
    /// frame count is the sum of N conversions of the same frame
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=16))]
    pub oversample: u32,
    /// The converter's own noise on each conversion [counts rms], 0 (none) to 4096 (it dithers
    /// the oversampled conversions, the sensor's noise is drawn once per frame)
    #[arg(long, value_name = "COUNTS", default_value_t = 0.0, allow_hyphen_values = true, value_parser = super::parse::adc_noise)]
    pub adc_noise: f64,
}

#[derive(Debug, Args)]
pub struct SilArgs {
    /// Built-in scene name (see `stickslip scenes`) or path to a TOML scene file
    #[arg(value_name = "SCENE|FILE", default_value = super::DEFAULT_SCENE)]
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
    #[arg(long, value_name = "S", allow_hyphen_values = true, value_parser = super::parse::from_time)]
    pub from: Option<f64>,
    #[command(flatten)]
    pub floor: FloorOptions,
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
