//! The estimator's window statistics of an analysis as CSV (`analyze --windows FILE`): one row
//! per window the estimator closed, with the keys of the firmware's `window` record
//! (firmware/README.md, "Log records"; `decode` reads them from the rig's log), so that a
//! recording's windows and the rig's can be set side by side line by line. On the same samples
//! with the rig's thresholds they are the same to the bit: `tests/tests/analyze_windows_vs_rig.rs`
//! runs a record through the firmware's rig and its calibrated channels through `analyze`.
//!
//! Columns, named as `decode --kind window` names the record's fields: `idx` (the
//! window's number from 0), `first` (its first sample, counting the recording's rows from 0),
//! `samples`, `valid` (the samples that passed the input check), `pp_0`..`pp_3`,
//! `rms_0`..`rms_3`, `groan_rms_0`..`groan_rms_3` [m/s^2] (channels 0 to 3: disc_x, pad_x,
//! pad_trail, pad_lead), `stick` (stick fraction), `ss_hz` (stick-slip frequency within the
//! window, 0 with fewer than two onsets), `onsets`, `saturated`, `faulted`, `nonfinite`; then
//! what only a recording has, `t_end_s` (the time column at the window's last sample [s]). The
//! f32 statistics are written in their shortest form that reads back to the same f32.

use std::path::Path;

use super::analysis::EstimatorWindow;
use crate::error::{HostError, Result};

/// The header row.
fn header() -> Vec<String> {
    let mut h: Vec<String> = ["idx", "first", "samples", "valid"].map(String::from).to_vec();
    for stat in ["pp", "rms", "groan_rms"] {
        h.extend((0..4).map(|c| format!("{stat}_{c}")));
    }
    h.extend(["stick", "ss_hz", "onsets", "saturated", "faulted", "nonfinite", "t_end_s"].map(String::from));
    h
}

/// One window's row, in the order of [`header`].
fn row(w: &EstimatorWindow) -> Vec<String> {
    let r = &w.report;
    let mut v = vec![
        r.index.to_string(),
        r.first_sample.to_string(),
        r.samples.to_string(),
        r.valid_samples.to_string(),
    ];
    for group in [&r.pp_m_s2, &r.rms_m_s2, &r.groan_rms_m_s2] {
        v.extend(group.iter().map(f32::to_string));
    }
    v.extend([
        r.stick_fraction.to_string(),
        r.stick_slip_hz.to_string(),
        r.slip_onsets.to_string(),
        r.saturated_samples.to_string(),
        r.faulted_samples.to_string(),
        r.non_finite.to_string(),
        // + 0.0: a time of -0 (the last sample of a quiet lead ending at t = 0) prints as 0
        (w.t_end_s + 0.0).to_string(),
    ]);
    v
}

/// Writes `windows` to `path` as CSV.
pub fn write_csv(path: &Path, windows: &[EstimatorWindow]) -> Result<()> {
    let err = |e: csv::Error| HostError::Output(format!("{}: cannot write the windows: {e}", path.display()));
    let mut w = csv::Writer::from_path(path).map_err(err)?;
    w.write_record(header()).map_err(err)?;
    for win in windows {
        w.write_record(row(win)).map_err(err)?;
    }
    w.flush().map_err(|e| HostError::Output(format!("{}: cannot write the windows: {e}", path.display())))
}
