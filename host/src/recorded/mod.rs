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
pub mod csv_in;
pub mod decode;
pub mod envelope;
pub mod figures;
pub mod live;
pub mod numbers;
pub mod report;
pub mod sil;
pub mod spectrum;
pub mod windows;

use std::io::Read;

use analysis::{Analysis, AnalysisConfig, Analyzer};
use csv_in::RowReader;

use crate::error::{HostError, Result};

/// Analyses a CSV recording read from `input`; `label` names it in messages.
pub fn analyze_reader<R: Read>(label: &str, input: R, cfg: AnalysisConfig) -> Result<Analysis> {
    let mut rows = RowReader::new(label, input)?;
    let mut an = Analyzer::new(cfg);
    while let Some(row) = rows.next_row()? {
        an.push(row.line, row.t, row.t_resolution, &row.accel)
            .map_err(|m| HostError::Input(format!("{label}: {m}")))?;
    }
    let header = rows.layout().header_line;
    if an.rows() == 0 {
        return Err(HostError::Input(format!("{label}: line {header}: a header and no data rows after it")));
    }
    an.finish().map_err(|m| HostError::Input(format!("{label}: {m}")))
}

/// Analyses the CSV file at `path` (`-`: standard input).
pub fn analyze_path(path: &str, cfg: AnalysisConfig) -> Result<Analysis> {
    if path == "-" {
        return analyze_reader("<stdin>", std::io::stdin().lock(), cfg);
    }
    let f = std::fs::File::open(path).map_err(|e| HostError::Input(format!("{path}: cannot open the recording: {e}")))?;
    analyze_reader(path, f, cfg)
}
