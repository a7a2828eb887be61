//! What a fit is fitted to: recordings (`CASE=FILE`, a CSV as `analyze` reads it) and tables
//! of measured statistics (`--table FILE`: CSV `case,channel,statistic,value`, optionally with
//! a fifth column `sigma`: the value's standard error in its own unit, empty where unknown).
//!
//! A recording gives every statistic of [`super::stat::Stat`] over its analysed stretch
//! (`--from` on), and the same statistics over [`WINDOWS`] equal windows of that stretch for
//! the bootstrap. A table gives what it lists. Values must be finite and > 0: a fit compares
//! log ratios. A recording's statistic that is 0 or missing (a dead channel, no onset) is
//! left out and named in the report.

use std::path::Path;

use crate::error::{HostError, Result};
use crate::output::format::short;
use crate::recorded::analysis::{Analysis, AnalysisConfig, Analyzer};
use crate::recorded::source;
use crate::recorded::ReadOptions;

use super::stat::{channel_index, recording_keys, Stat, StatKey};

/// A recording's peak-to-peak is fitted only if it spans at least this many of its amplitude
/// steps (`ChannelStats::step`, one ADC count of a quantised record): its two extremes are each
/// off by up to half a step, so the peak-to-peak by up to 5 % here.
pub const MIN_STEPS_PP: f64 = 20.0;
/// An RMS (plain or groan-band) is fitted only if it is at least this many amplitude steps
/// (quantisation adds step^2 / 12 to the mean square: 0.5 % of it here).
pub const MIN_STEPS_RMS: f64 = 3.0;

/// Windows of a recording's analysed stretch for the bootstrap.
pub const WINDOWS: usize = 8;

/// The thesis's Table 3.1 (peak-to-peak accelerations measured on the rig, 6 cases x 4
/// channels, m/s^2), shipped as data: `--table thesis_table_3_1`.
pub const THESIS_TABLE_3_1_NAME: &str = "thesis_table_3_1";
pub const THESIS_TABLE_3_1: &str = include_str!("../../data/thesis_table_3_1.csv");

/// One measured value.
#[derive(Clone, Debug)]
pub struct Measured {
    pub key: StatKey,
    pub value: f64,
    /// Where it came from: "FILE" or "FILE line N".
    pub source: String,
    /// The value in each window of its recording (empty for a table row or where a window
    /// has none): the bootstrap's resampling units.
    pub windows: Vec<f64>,
    /// A table's stated standard error of the value, in its unit (its `sigma` column).
    pub sigma: Option<f64>,
}

/// A recording's statistic that is not fitted, and why.
#[derive(Clone, Debug)]
pub struct Skipped {
    pub key: StatKey,
    pub source: String,
    pub why: String,
}

/// A recording target as given on the command line, `CASE=FILE`.
pub fn parse_recording_arg(arg: &str) -> Result<(String, String)> {
    match arg.split_once('=') {
        Some((case, file)) if !case.trim().is_empty() && !file.is_empty() => Ok((case.trim().to_string(), file.to_string())),
        _ => Err(HostError::Input(format!(
            "target `{arg}`: a recording target is CASE=FILE (e.g. pull_center=run.csv); a table is --table FILE"
        ))),
    }
}

/// The values a measured statistic can have [lo, hi] and its unit: a stick fraction is a
/// fraction (at most 1); accelerations from 1 um/s^2 (below any accelerometer's noise) to 1e6
/// m/s^2 (beyond any accelerometer's range); frequencies from 1 mHz to 1 MHz; the first slip
/// within a day of the start.
fn sane_range(stat: Stat) -> (f64, f64, &'static str) {
    match stat {
        Stat::StickFraction => (1e-9, 1.0, "(a fraction, > 0 and <= 1)"),
        Stat::Pp | Stat::Rms | Stat::GroanRms => (1e-6, 1e6, "m/s^2"),
        Stat::PeakHz | Stat::StickSlipHz => (1e-3, 1e6, "Hz"),
        Stat::FirstSlipS => (1e-9, 86_400.0, "s"),
    }
}

/// The line (from 1) of the record that starts at `byte` of `text`, or after it: the blank
/// and comment lines the reader skipped before it are passed over (the CSV reader's own line
/// count is one short after a blank line and on CRLF files).
fn line_at(text: &str, byte: u64) -> u64 {
    let bytes = text.as_bytes();
    let mut at = (byte as usize).min(bytes.len());
    loop {
        let end = bytes[at..].iter().position(|&b| b == b'\n').map_or(bytes.len(), |p| at + p);
        let line = &text[at..end];
        let skipped = line.trim().is_empty() || line.trim_start().starts_with('#');
        if !skipped || end >= bytes.len() {
            break;
        }
        at = end + 1;
    }
    bytes[..at].iter().filter(|&&b| b == b'\n').count() as u64 + 1
}

/// Reads a table of measured statistics. `label` names it in errors; errors name the line.
pub fn read_table(label: &str, text: &str) -> Result<Vec<Measured>> {
    let bad = |line: u64, m: String| HostError::Input(format!("{label}: line {line}: {m}"));
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .flexible(true)
        .from_reader(text.as_bytes());
    let mut out: Vec<Measured> = Vec::new();
    let mut header_seen = false;
    // the header's fields: 4, or 5 with `sigma`
    let mut fields = 4;
    for rec in rdr.records() {
        let rec = rec.map_err(|e| {
            let line = e.position().map_or(0, |p| line_at(text, p.byte()));
            bad(line, format!("not CSV: {e}"))
        })?;
        let line = rec.position().map_or(0, |p| line_at(text, p.byte()));
        if !header_seen {
            let h: Vec<&str> = rec.iter().collect();
            if h != ["case", "channel", "statistic", "value"] && h != ["case", "channel", "statistic", "value", "sigma"] {
                return Err(bad(
                    line,
                    format!("the header must be `case,channel,statistic,value` or `case,channel,statistic,value,sigma`, not `{}`", h.join(",")),
                ));
            }
            fields = h.len();
            header_seen = true;
            continue;
        }
        if rec.len() != fields {
            let names = if fields == 5 { "case,channel,statistic,value,sigma" } else { "case,channel,statistic,value" };
            return Err(bad(line, format!("{} fields where the header has {fields} ({names})", rec.len())));
        }
        let (case, channel, statistic, value) = (&rec[0], &rec[1], &rec[2], &rec[3]);
        if case.is_empty() {
            return Err(bad(line, "the case is empty".into()));
        }
        let stat = Stat::parse(statistic).ok_or_else(|| {
            let names: Vec<&str> = Stat::ALL.iter().map(|s| s.name()).collect();
            bad(line, format!("unknown statistic `{statistic}` (the statistics: {})", names.join(", ")))
        })?;
        let channel = if stat.per_channel() {
            Some(channel_index(channel).ok_or_else(|| {
                bad(
                    line,
                    format!(
                        "unknown channel `{channel}` (the channels: {}; {} needs one)",
                        stickslip_model::rig::ACCEL_NAMES.join(", "),
                        stat.name()
                    ),
                )
            })?)
        } else if channel.is_empty() {
            None
        } else {
            return Err(bad(line, format!("{} is a statistic of the case: leave the channel empty, not `{channel}`", stat.name())));
        };
        // a decimal comma is a separator here: the table is comma-separated
        let v: f64 = value.parse().map_err(|_| bad(line, format!("value `{value}` is not a number")))?;
        if !(v.is_finite() && v > 0.0) {
            return Err(bad(line, format!("value {}: must be finite and > 0 (a fit compares log ratios)", short(v))));
        }
        let (lo, hi, unit) = sane_range(stat);
        if !(lo..=hi).contains(&v) {
            return Err(bad(
                line,
                format!("{} value {}: outside the range a measurement can have, {} to {} {unit}", stat.name(), short(v), short(lo), short(hi)),
            ));
        }
        let sigma = match rec.get(4) {
            None | Some("") => None,
            Some(s) => {
                let e: f64 = s.parse().map_err(|_| bad(line, format!("sigma `{s}` is not a number")))?;
                if !(e.is_finite() && e > 0.0) {
                    return Err(bad(line, format!("sigma {}: must be finite and > 0 (leave it empty where the error is unknown)", short(e))));
                }
                Some(e)
            }
        };
        let key = StatKey { case: case.to_string(), channel, stat };
        if let Some(prev) = out.iter().find(|m| m.key == key) {
            return Err(bad(line, format!("{} is given twice (also {})", key.label(), prev.source)));
        }
        out.push(Measured { key, value: v, source: format!("{label} line {line}"), windows: Vec::new(), sigma });
    }
    if !header_seen {
        return Err(HostError::Input(format!("{label}: empty: a table is CSV `case,channel,statistic,value` with that header")));
    }
    if out.is_empty() {
        return Err(HostError::Input(format!("{label}: a header and no rows")));
    }
    Ok(out)
}

/// Reads `--table ARG`: the built-in [`THESIS_TABLE_3_1_NAME`] or a file.
pub fn load_table(arg: &str) -> Result<Vec<Measured>> {
    if arg == THESIS_TABLE_3_1_NAME && !Path::new(arg).exists() {
        return read_table(THESIS_TABLE_3_1_NAME, THESIS_TABLE_3_1);
    }
    let text = crate::limits::read_text(Path::new(arg), "table", crate::limits::TABLE_FILE_MAX_BYTES)?;
    read_table(arg, &text)
}

/// One pass over the recording at `path` (any format `analyze` reads, read with `opts`), each
/// row given to `f`.
fn each_row(
    path: &str,
    opts: &ReadOptions,
    mut f: impl FnMut(u64, f64, f64, &[f64; 4]) -> std::result::Result<(), String>,
) -> Result<()> {
    let mut rows = source::Recording::open(path, &opts.channels)?;
    while let Some(row) = rows.next_row()? {
        f(row.line, row.t, row.t_resolution, &row.accel).map_err(|m| HostError::Input(format!("{path}: {}", rows.locate(&m))))?;
    }
    Ok(())
}

/// An analyser for the recording at `path` as `opts` read it (its channels, its gaps mode).
fn analyzer(path: &str, cfg: AnalysisConfig, opts: &ReadOptions) -> Result<Analyzer> {
    let rec = source::Recording::open(path, &opts.channels)?;
    Ok(crate::recorded::analyzer_for(&rec, cfg, opts))
}

/// A recording analysed as a whole and in [`WINDOWS`] windows.
pub struct Recording {
    pub case: String,
    pub path: String,
    /// How it is read (`--channel`, `--gaps`).
    pub read: ReadOptions,
    pub analysis: Analysis,
    pub windows: Vec<Analysis>,
}

/// Analyses the recording at `path` for `case` with `cfg` (two passes: the whole stretch,
/// then its windows, each window analysed on its own rows).
pub fn read_recording(case: &str, path: &str, cfg: &AnalysisConfig, opts: &ReadOptions) -> Result<Recording> {
    if path == "-" {
        return Err(HostError::Input(format!(
            "{case}=-: a fit reads each recording twice (the whole, then its windows for the bootstrap): give a file"
        )));
    }
    let analysis = crate::recorded::analyze_with(path, cfg.clone(), opts)?;
    let (t0, t1) = (analysis.t_first, analysis.t_last);
    let span = (t1 - t0) / WINDOWS as f64;
    let mut windows: Vec<Analyzer> = (0..WINDOWS)
        .map(|k| analyzer(path, AnalysisConfig { from_s: t0 + k as f64 * span, figures: false, ..cfg.clone() }, opts))
        .collect::<Result<_>>()?;
    let half_sample = 0.25 / analysis.sample_rate_hz;
    each_row(path, opts, |line, t, res, a| {
        if t < t0 - half_sample {
            return Ok(());
        }
        let k = (((t - t0) / span).floor().max(0.0) as usize).min(WINDOWS - 1);
        windows[k].push(line, t, res, a)
    })?;
    let windows = windows
        .into_iter()
        .enumerate()
        .map(|(k, w)| w.finish().map_err(|m| HostError::Input(format!("{path}: window {} of {WINDOWS}: {m}", k + 1))))
        .collect::<Result<Vec<_>>>()?;
    Ok(Recording { case: case.to_string(), path: path.to_string(), read: opts.clone(), analysis, windows })
}

impl Recording {
    /// The end of its horizon `cycles` stick-slip periods after its first slip onset [s]:
    /// t_first_onset + cycles / stick_slip_hz, `None` where the recording has no onset or no
    /// frequency, or where the horizon reaches its last row (the whole record, not a start).
    pub fn horizon_s(&self, cycles: f64) -> Option<f64> {
        let a = &self.analysis;
        let h = a.first_onset_s? + cycles / a.stick_slip_hz?;
        (h > 0.0 && h < a.t_last).then_some(h)
    }

    /// The recording's start, t = 0 (the band's start, as `sil --csv` writes it) to
    /// `horizon_s`, analysed with `cfg` (its `from_s` replaced by 0): the rows after the horizon
    /// are left out as if the file ended there. No windows: a horizon is not bootstrapped.
    pub fn head(&self, cfg: &AnalysisConfig, horizon_s: f64) -> Result<Recording> {
        let mut an = analyzer(&self.path, AnalysisConfig { from_s: 0.0, figures: false, ..cfg.clone() }, &self.read)?;
        let end = horizon_s + 0.25 / self.analysis.sample_rate_hz;
        each_row(&self.path, &self.read, |line, t, res, a| if t <= end { an.push(line, t, res, a) } else { Ok(()) })?;
        let analysis = an
            .finish()
            .map_err(|m| HostError::Input(format!("{}: its start to t = {horizon_s} s: {m}", self.path)))?;
        Ok(Recording { case: self.case.clone(), path: self.path.clone(), read: self.read.clone(), analysis, windows: Vec::new() })
    }

    /// Whether every window holds at least two slip onsets (a stick-slip cycle or more): only
    /// then do the windows resample the record's statistics.
    pub fn windows_hold_cycles(&self) -> bool {
        self.windows.iter().all(|w| w.slip_onsets >= 2)
    }

    /// Its statistics as measured values, and those left out.
    pub fn measured(&self) -> (Vec<Measured>, Vec<Skipped>) {
        let (mut keep, mut skip) = (Vec::new(), Vec::new());
        let cycles = self.windows_hold_cycles();
        for key in recording_keys(&self.case) {
            // the channel-health verdict, as `analyze` gives it: an absent or unhealthy channel,
            // or a contact estimate that cannot be told, is not a measurement to fit
            let verdict = match key.channel {
                Some(c) if !self.analysis.present[c] => Some("the recording has no such channel".to_string()),
                Some(c) if !self.analysis.health[c].is_empty() => {
                    Some(format!("{} {}", stickslip_model::rig::ACCEL_NAMES[c], self.analysis.health[c].join(", ")))
                }
                None if matches!(key.stat, Stat::StickFraction | Stat::StickSlipHz | Stat::FirstSlipS) => {
                    self.analysis.undecided.as_ref().map(|u| format!("cannot decide: {u}"))
                }
                _ => None,
            };
            if let Some(why) = verdict {
                skip.push(Skipped { key, source: self.path.clone(), why });
                continue;
            }
            let step = key.channel.map_or(0.0, |c| self.analysis.channels[c].step);
            let min_steps = match key.stat {
                Stat::Pp => MIN_STEPS_PP,
                Stat::Rms | Stat::GroanRms => MIN_STEPS_RMS,
                _ => 0.0,
            };
            match key.stat.of(&self.analysis, key.channel) {
                Some(v) if v.is_finite() && v > 0.0 && v < min_steps * step => skip.push(Skipped {
                    key,
                    source: self.path.clone(),
                    why: format!("measured {v}: fewer than {min_steps} of the recording's amplitude steps ({step} m/s^2)"),
                }),
                Some(v) if v.is_finite() && v > 0.0 => {
                    let windows = self
                        .windows
                        .iter()
                        .filter_map(|w| key.stat.of(w, key.channel))
                        .filter(|v| v.is_finite() && *v > 0.0)
                        .collect::<Vec<_>>();
                    // the first onset is one event of the whole record: windows do not resample it
                    let whole = cycles && windows.len() == self.windows.len() && key.stat != Stat::FirstSlipS;
                    let windows = if whole { windows } else { Vec::new() };
                    keep.push(Measured { key, value: v, source: self.path.clone(), windows, sigma: None });
                }
                Some(v) => skip.push(Skipped { key, source: self.path.clone(), why: format!("measured {v}: not > 0") }),
                None => skip.push(Skipped { key, source: self.path.clone(), why: "not in the recording".into() }),
            }
        }
        (keep, skip)
    }
}
