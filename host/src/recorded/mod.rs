//! Recorded and virtual-rig accelerometer data: `analyze` (a logger's CSV export), `sil` (the
//! virtual rig: a scene through the rig's sensor model and estimator), `compare` (model against
//! measurement), `decode` (the firmware's defmt log stream).
//!
//! - [`numbers`]: decimal numbers with a point or a comma, fast and correctly rounded;
//! - [`csv_in`]: the streaming CSV reader (header by name, separators, units, line numbers);
//! - [`analysis`]: the streaming analysis (running statistics, the rig's estimator, Welch
//!   spectra, the figure envelope);
//! - [`spectrum`], [`envelope`]: the Welch estimator and the bounded min/max envelope;
//! - [`sil`]: the virtual rig;
//! - [`report`]: Markdown and JSON of the three analysis commands;
//! - [`windows`]: the estimator's window statistics as CSV (`analyze --windows`);
//! - [`figures`]: the SVG figures;
//! - [`decode`]: the defmt stream decoder;
//! - [`live`]: `record`, the log as it arrives (probe or pipe) into the raw stream and CSVs.
//!
//! Comparisons are written `!(a > b)` on purpose: a NaN then takes the error branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// per-channel arrays are indexed in parallel
#![allow(clippy::needless_range_loop)]

pub mod analysis;
pub mod channels;
pub mod csv_in;
pub mod decode;
pub mod envelope;
pub mod figures;
pub mod live;
pub mod numbers;
pub mod progress;
pub mod quiet;
pub mod report;
pub mod sil;
pub mod source;
pub mod spectrum;
pub mod uff;
pub mod wav;
pub mod windows;

use std::io::Read;

use analysis::{Analysis, AnalysisConfig, Analyzer, FloorSource};
use channels::ChannelMap;
use progress::Progress;
use source::Recording;

use crate::error::{HostError, Result};

/// How a command reads its recordings (`--channel`, `--gaps`), and whether it shows progress.
#[derive(Clone, Debug, Default)]
pub struct ReadOptions {
    pub channels: ChannelMap,
    /// `--gaps split`: analyse the contiguous blocks around jumps in the time column.
    pub split_gaps: bool,
    /// Progress on stderr for a file that takes longer than a second.
    pub progress: bool,
}

/// Rows between progress updates.
const PROGRESS_ROWS: u64 = 1 << 14;

/// An analyser set up for `rec` with `opts`: its channels, its gaps mode, its notes.
pub fn analyzer_for(rec: &Recording, cfg: AnalysisConfig, opts: &ReadOptions) -> Analyzer {
    let mut an = Analyzer::new(cfg);
    an.set_present(rec.present);
    an.split_gaps(opts.split_gaps);
    for n in &rec.notes {
        an.note(n.clone());
    }
    if let Some(w) = &rec.full_scale {
        an.set_full_scale(w.clone());
    }
    an
}

/// Runs every row of `rec` through `an` and finishes it.
fn run(mut rec: Recording, mut an: Analyzer, progress: &mut Progress, done_before: u64) -> Result<Analysis> {
    let label = rec.label.clone();
    while let Some(row) = rec.next_row()? {
        an.push(row.line, row.t, row.t_resolution, &row.accel)
            .map_err(|m| HostError::Input(format!("{label}: {}", rec.locate(&m))))?;
        if row.full_scale != 0 {
            an.at_full_scale(row.t, row.full_scale);
        }
        if an.rows() % PROGRESS_ROWS == 0 {
            progress.update(done_before + rec.counter.get());
        }
    }
    if an.rows() == 0 {
        let header = rec.header_line();
        return Err(HostError::Input(if header > 0 {
            format!("{label}: line {header}: a header and no data rows after it")
        } else {
            format!("{label}: no samples")
        }));
    }
    let mut a = an.finish().map_err(|m| HostError::Input(format!("{label}: {}", rec.locate(&m))))?;
    a.format = rec.format.name();
    Ok(a)
}

/// Analyses a recording read from `input` (CSV or WAV; a universal file needs a path); `label`
/// names it in messages.
pub fn analyze_reader<R: Read>(label: &str, input: R, cfg: AnalysisConfig) -> Result<Analysis> {
    let opts = ReadOptions::default();
    let rec = Recording::from_reader(label, Box::new(input), &opts.channels)?;
    let an = analyzer_for(&rec, cfg, &opts);
    run(rec, an, &mut Progress::new("", 0, false), 0)
}

/// Analyses the recording at `path` (`-`: standard input) with the default read options.
pub fn analyze_path(path: &str, cfg: AnalysisConfig) -> Result<Analysis> {
    analyze_with(path, cfg, &ReadOptions::default())
}

/// Finds the noise floor anywhere in the file at `path` (a first pass): the floor, or why
/// there is none.
pub fn find_floor(path: &str, cfg: &AnalysisConfig, opts: &ReadOptions, progress: &mut Progress) -> Result<(std::result::Result<analysis::FloorOutcome, String>, u64)> {
    let mut rec = Recording::open(path, &opts.channels)?;
    let face = if rec.present[2] && rec.present[3] { cfg.face_coefficient } else { 0.0 };
    let mut q = quiet::QuietSearch::new(face);
    while let Some(row) = rec.next_row()? {
        q.push(row.t, &row.accel);
        if q.rows() % PROGRESS_ROWS == 0 {
            progress.update(rec.counter.get());
        }
    }
    Ok((q.finish(), rec.counter.get()))
}

/// Analyses the recording at `path` (`-`: standard input; a CSV, UFF 58/58b or WAV file, told
/// by its content) with `opts`. With [`FloorSource::Auto`] a file is read twice: first for the
/// noise floor anywhere in it ([`quiet`]), then for the analysis.
pub fn analyze_with(path: &str, mut cfg: AnalysisConfig, opts: &ReadOptions) -> Result<Analysis> {
    let size = if path == "-" { 0 } else { std::fs::metadata(path).map(|m| m.len()).unwrap_or(0) };
    let passes = if cfg.floor == FloorSource::Auto && path != "-" { 2 } else { 1 };
    let mut progress = Progress::new(&format!("reading {path}"), size * passes, opts.progress);
    let mut note = None;
    let mut done = 0;
    if passes == 2 {
        let (found, read) = find_floor(path, &cfg, opts, &mut progress)?;
        done = read;
        match found {
            Ok(f) => cfg.floor = FloorSource::Found(f),
            Err(why) => {
                cfg.floor = FloorSource::Jump;
                note = Some(why);
            }
        }
    }
    let rec = if path == "-" {
        Recording::from_reader("<stdin>", Box::new(std::io::stdin()), &opts.channels)?
    } else {
        Recording::open(path, &opts.channels)?
    };
    let mut an = analyzer_for(&rec, cfg, opts);
    if let Some(why) = note {
        an.note_floor(why);
    }
    let out = run(rec, an, &mut progress, done);
    progress.finish();
    out
}
