//! Reading accelerometer recordings as loggers and spreadsheets export them, one row at a
//! time (memory does not grow with the file).
//!
//! **Header.** The first non-blank line that names a time column or one of the four channels
//! is the header (up to [`MAX_PREAMBLE_LINES`] lines of logger preamble before it are
//! skipped); it must name the time column and pad_x (by name, or mapped by `--channel`, see
//! [`super::channels`]); disc_x, pad_trail and pad_lead are read where the header names them
//! (or `--channel` maps them) and are absent otherwise; other columns are ignored. Names are case-insensitive; spaces, dashes and dots count as
//! underscores, leading and trailing underscores are dropped (`Pad Trail`, `pad_trail_`).
//! The time column is `t` or `time`; the channels are `disc_x`, `pad_x`, `pad_trail`,
//! `pad_lead`. A unit may follow the name in brackets or parentheses (`pad_x [m/s^2]`,
//! `pad_x (m/s²)`, `time [s]`), after a space (`time s`), or as a suffix (`t_s`,
//! `pad_x_m_s2`, the tool's own CSV style). Time units: s (default), ms, us; acceleration
//! units: m/s^2 (default, any spelling: `m/s2`, `m s^-2`, `m_per_s2`), mm/s^2, g (9.80665
//! m/s^2). Values are converted to s and m/s^2; another unit on one of these columns is an
//! error.
//!
//! **Separators.** The header line decides: a `;` in it makes the file semicolon-separated,
//! else a tab makes it tab-separated, else it is comma-separated. In semicolon- and
//! tab-separated files a number may use a decimal comma (`1,234`) or a decimal point; in
//! comma-separated files only a point. Fields may be quoted; spaces around a value are
//! ignored; a UTF-8 byte-order mark is skipped; CRLF or LF line ends.
//!
//! **Rows.** Blank lines (also lines of separators only, as spreadsheets write below the
//! data) are skipped anywhere. Every other row must have as many fields as the header
//! (trailing empty fields beyond it are tolerated), and a finite number in the time column
//! and in each channel, within [`PLAUSIBLE_ACCEL_M_S2`]. Any violation is an error that
//! names the file, the line and the column.

use std::io::{BufRead, BufReader, Read};

use stickslip_model::rig::ACCEL_NAMES;

use super::channels::{ChannelMap, ChannelSource};
use super::numbers::{self, Decimal};
use crate::error::{HostError, Result};

/// Lines read while looking for the header.
pub const MAX_PREAMBLE_LINES: u64 = 64;
/// Longest header line accepted [bytes].
pub const MAX_HEADER_BYTES: u64 = 1 << 16;
/// Largest accepted |acceleration| [m/s^2] (1e7 g: anything larger is not a measurement, and
/// the sum of four stays within the rig estimator's plausibility bound of 1e9).
pub const PLAUSIBLE_ACCEL_M_S2: f64 = 1e8;
/// Largest accepted |time| [s].
pub const PLAUSIBLE_TIME_S: f64 = 1e12;

/// Standard gravity [m/s^2].
const G: f64 = 9.806_65;

/// What a header column is.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Role {
    /// The time column; value x scale = seconds.
    Time(f64),
    /// Channel `i` (disc_x, pad_x, pad_trail, pad_lead); value x scale = m/s^2.
    Accel(usize, f64),
    Other,
}

/// Units spelled in one canonical form: lower case, without spaces, `^`, `*`, `·`, braces;
/// `²` as 2, `_per_` and `_` as `/`.
fn canonical_unit(u: &str) -> String {
    let u = u.trim().to_lowercase().replace("_per_", "/").replace("per", "/");
    let mut out = String::with_capacity(u.len());
    for c in u.chars() {
        match c {
            ' ' | '^' | '*' | '·' | '{' | '}' | '.' => {}
            '²' => out.push('2'),
            '_' => out.push('/'),
            c => out.push(c),
        }
    }
    out
}

fn time_unit(u: &str) -> Option<f64> {
    match canonical_unit(u).as_str() {
        "s" | "sec" | "second" | "seconds" => Some(1.0),
        "ms" => Some(1e-3),
        "us" | "µs" | "μs" => Some(1e-6),
        _ => None,
    }
}

fn accel_unit(u: &str) -> Option<f64> {
    match canonical_unit(u).as_str() {
        "m/s2" | "ms-2" | "m/s/s" | "mps2" | "m/ss" => Some(1.0),
        "mm/s2" | "mms-2" => Some(1e-3),
        "g" => Some(G),
        _ => None,
    }
}

/// [`time_unit`] for the other readers: unit text x scale = s.
pub fn time_unit_scale(u: &str) -> Option<f64> {
    time_unit(u)
}

/// [`accel_unit`] for the other readers: unit text x scale = m/s^2.
pub fn accel_unit_scale(u: &str) -> Option<f64> {
    accel_unit(u)
}

/// The channel a name means (`pad_x`, `Pad X`, `pad_x [g]`: 1), if any.
pub fn channel_of_name(name: &str) -> Option<usize> {
    let (bare, _) = name_and_unit(name);
    match base_role(&normal_name(&bare)) {
        Some((false, c)) => Some(c),
        _ => None,
    }
}

/// The base names a column can have: (name, is time, channel index).
fn base_role(name: &str) -> Option<(bool, usize)> {
    match name {
        "t" | "time" => Some((true, 0)),
        _ => ACCEL_NAMES.iter().position(|n| *n == name).map(|i| (false, i)),
    }
}

/// A header cell's name without its unit (`Acc1 [g]` -> `Acc1`), and the unit if one is written
/// in brackets or parentheses.
fn name_and_unit(raw: &str) -> (String, Option<String>) {
    let text = raw.trim().trim_matches('"').trim();
    match text.find(['[', '(']) {
        Some(p) => {
            let unit = text[p + 1..].trim().trim_end_matches([']', ')']).trim().to_string();
            (text[..p].trim().to_string(), Some(unit).filter(|u| !u.is_empty()))
        }
        None => (text.to_string(), None),
    }
}

/// Classifies one header cell.
fn classify(raw: &str) -> std::result::Result<Role, String> {
    let text = raw.trim().trim_matches('"').trim().to_lowercase();
    let (name, unit): (String, Option<String>) = match text.find(['[', '(']) {
        Some(p) => {
            let unit = text[p + 1..].trim().trim_end_matches([']', ')']).trim().to_string();
            (text[..p].to_string(), Some(unit))
        }
        None => match text.split_once(char::is_whitespace) {
            Some((n, u)) if base_role(&normal_name(n)).is_some() => (n.to_string(), Some(u.to_string())),
            _ => (text.clone(), None),
        },
    };
    let mut name = normal_name(&name);
    let mut unit = unit;
    if unit.is_none() && base_role(&name).is_none() {
        // a unit as a suffix: t_s, time_ms, pad_x_m_s2
        for base in ["time", "t"].iter().copied().chain(ACCEL_NAMES.iter().copied()) {
            if let Some(rest) = name.strip_prefix(base).and_then(|r| r.strip_prefix('_')) {
                let is_time = base == "t" || base == "time";
                let known = if is_time { time_unit(rest).is_some() } else { accel_unit(rest).is_some() };
                if known {
                    unit = Some(rest.to_string());
                    name = base.to_string();
                    break;
                }
            }
        }
    }
    let Some((is_time, ch)) = base_role(&name) else { return Ok(Role::Other) };
    let unit = unit.filter(|u| !u.trim().is_empty());
    if is_time {
        match unit {
            None => Ok(Role::Time(1.0)),
            Some(u) => time_unit(&u)
                .map(Role::Time)
                .ok_or_else(|| format!("time column `{}`: unit `{u}` is not a time unit (s, ms, us)", raw.trim())),
        }
    } else {
        match unit {
            None => Ok(Role::Accel(ch, 1.0)),
            Some(u) => accel_unit(&u).map(|s| Role::Accel(ch, s)).ok_or_else(|| {
                format!("column `{}`: unit `{u}` is not an acceleration unit (m/s^2, mm/s^2, g)", raw.trim())
            }),
        }
    }
}

/// Lower case, spaces/dashes/dots as underscores, no leading or trailing underscores.
fn normal_name(n: &str) -> String {
    let s: String = n
        .trim()
        .to_lowercase()
        .chars()
        .map(|c| if c == ' ' || c == '-' || c == '.' { '_' } else { c })
        .collect();
    s.trim_matches('_').to_string()
}

/// Where the columns are, and how to read the numbers.
#[derive(Clone, Debug)]
pub struct Layout {
    pub delimiter: u8,
    /// A decimal comma is accepted (semicolon- and tab-separated files).
    pub decimal_comma: bool,
    /// Line of the header (from 1).
    pub header_line: u64,
    /// Fields in the header.
    pub fields: usize,
    pub time: usize,
    /// Column of disc_x, pad_x, pad_trail, pad_lead; `None`: absent (pad_x never is).
    pub accel: [Option<usize>; 4],
    /// Value x scale = s.
    pub time_scale: f64,
    /// Value x scale = m/s^2.
    pub accel_scale: [f64; 4],
    /// The header's cells as written (for messages).
    pub names: Vec<String>,
}

/// One data row, in s and m/s^2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    /// Line of the row in the file (from 1).
    pub line: u64,
    pub t: f64,
    /// The time column's printed resolution at this row [s] (place value of its last digit).
    pub t_resolution: f64,
    pub accel: [f64; 4],
    /// Per channel (bit c: disc_x, pad_x, pad_trail, pad_lead), the sample is at its format's
    /// extreme codes (an integer WAV's full scale: [`super::wav`]); 0 where the format has no
    /// full scale (CSV, UFF).
    pub full_scale: u8,
}

/// Splits one line into fields with the csv crate (quotes handled).
fn split_line(line: &[u8], delimiter: u8) -> Vec<String> {
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .delimiter(delimiter)
        .flexible(true)
        .from_reader(line);
    let mut rec = csv::ByteRecord::new();
    match rdr.read_byte_record(&mut rec) {
        Ok(true) => rec.iter().map(|f| String::from_utf8_lossy(f).into_owned()).collect(),
        _ => Vec::new(),
    }
}

fn sniff_delimiter(line: &[u8]) -> u8 {
    if line.contains(&b';') {
        b';'
    } else if line.contains(&b'\t') {
        b'\t'
    } else {
        b','
    }
}

fn is_blank(line: &[u8]) -> bool {
    line.iter().all(|&b| b.is_ascii_whitespace() || b == b';' || b == b',' || b == b'\t' || b == b'"')
}

/// The streaming reader: the header is read at construction, then [`RowReader::next_row`]
/// returns one row at a time.
pub struct RowReader<R: Read> {
    label: String,
    layout: Layout,
    rdr: csv::Reader<BufReader<R>>,
    rec: csv::ByteRecord,
    /// Highest column index that must be read.
    last_needed: usize,
}

impl<R: Read> std::fmt::Debug for RowReader<R> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RowReader").field("label", &self.label).field("layout", &self.layout).finish()
    }
}

impl<R: Read> RowReader<R> {
    /// Reads the header of `input`; `label` names the file in messages.
    pub fn new(label: &str, input: R) -> Result<Self> {
        Self::with_channels(label, input, &ChannelMap::default())
    }

    /// Reads the header of `input` with the `--channel` mapping `map`.
    pub fn with_channels(label: &str, input: R, map: &ChannelMap) -> Result<Self> {
        let bad = |msg: String| HostError::Input(format!("{label}: {msg}"));
        let mut br = BufReader::with_capacity(1 << 16, input);
        let mut line_no = 0u64;
        let mut first_nonblank: Option<u64> = None;
        let mut buf = Vec::new();
        let layout = loop {
            buf.clear();
            let n = (&mut br)
                .take(MAX_HEADER_BYTES)
                .read_until(b'\n', &mut buf)
                .map_err(|e| bad(format!("cannot read: {e}")))?;
            if n == 0 {
                return Err(bad(match first_nonblank {
                    None => "empty file: no header line (expected the columns t or time, disc_x, pad_x, pad_trail, pad_lead)".into(),
                    Some(l) => format!(
                        "no header found: lines {l} to {line_no} name none of the columns t or time, disc_x, pad_x, pad_trail, pad_lead"
                    ),
                }));
            }
            line_no += 1;
            if buf.last() != Some(&b'\n') && n as u64 >= MAX_HEADER_BYTES {
                return Err(bad(format!("line {line_no}: longer than {MAX_HEADER_BYTES} bytes before any header{}", if buf.contains(&b'\r') { " (its lines end in CR alone, old Mac style: convert the line endings to LF or CR LF)" } else { "" })));
            }
            let mut line: &[u8] = &buf;
            if line_no == 1 {
                line = line.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(line);
            }
            while let Some((&last, rest)) = line.split_last() {
                if last == b'\n' || last == b'\r' {
                    line = rest;
                } else {
                    break;
                }
            }
            if is_blank(line) {
                continue;
            }
            first_nonblank.get_or_insert(line_no);
            let delimiter = sniff_delimiter(line);
            let names = split_line(line, delimiter);
            let mut time: Option<(usize, f64)> = None;
            let mut accel: [Option<(usize, f64)>; 4] = [None; 4];
            let mut known = 0;
            let mut roles = Vec::with_capacity(names.len());
            for name in names.iter() {
                let (bare, _) = name_and_unit(name);
                let mapped = map.specs.iter().any(|sp| ChannelMap::matches_name(sp, &[name, &bare]));
                // a mapped column is the mapping's: its unit is checked there
                let role = if mapped { Role::Other } else { classify(name).map_err(|m| bad(format!("line {line_no}: {m}")))? };
                roles.push(role);
                if mapped {
                    // a --channel naming the time column would leave the file without one
                    if let Ok(Role::Time(_)) = classify(name) {
                        return Err(bad(format!(
                            "line {line_no}: --channel names the time column `{}`: a channel's source must be another column",
                            name.trim()
                        )));
                    }
                    known += 1;
                }
            }
            for (i, role) in roles.iter().enumerate() {
                match *role {
                    Role::Time(s) => {
                        if let Some((j, _)) = time {
                            return Err(bad(format!(
                                "line {line_no}: columns {} and {} both name the time",
                                j + 1,
                                i + 1
                            )));
                        }
                        time = Some((i, s));
                        known += 1;
                    }
                    Role::Accel(c, s) => {
                        if map.get(c).is_some() {
                            continue; // the key is mapped elsewhere: this column is not it
                        }
                        if let Some((j, _)) = accel[c] {
                            return Err(bad(format!(
                                "line {line_no}: columns {} and {} both name `{}`",
                                j + 1,
                                i + 1,
                                ACCEL_NAMES[c]
                            )));
                        }
                        accel[c] = Some((i, s));
                        known += 1;
                    }
                    Role::Other => {}
                }
            }
            if known == 0 {
                // logger preamble (or data without a header): keep looking, a while
                if line_no >= MAX_PREAMBLE_LINES {
                    return Err(bad(format!(
                        "no header found in the first {MAX_PREAMBLE_LINES} lines: none names the columns t or time, disc_x, pad_x, pad_trail, pad_lead{}",
                        if map.is_empty() { String::new() } else { " or a --channel source".into() }
                    )));
                }
                continue;
            }
            let found: Vec<&str> = names.iter().map(|s| s.trim()).collect();
            let Some((ti, ts)) = time else {
                return Err(bad(format!(
                    "line {line_no}: the header has no column `time (t or time)` (its columns: {})",
                    found.join(", ")
                )));
            };
            // the mapped channels: by name, or #N = the N-th column after time
            for sp in &map.specs {
                let col = match &sp.source {
                    ChannelSource::Name(_) => {
                        let hits: Vec<usize> = (0..names.len())
                            .filter(|&j| {
                                let (bare, _) = name_and_unit(&names[j]);
                                ChannelMap::matches_name(sp, &[&names[j], &bare])
                            })
                            .collect();
                        if hits.len() > 1 {
                            let cols: Vec<String> = hits.iter().map(|&j| format!("{} (`{}`)", j + 1, names[j].trim())).collect();
                            return Err(bad(format!(
                                "line {line_no}: --channel {}: columns {} both match {}: give #N (the N-th column after time) or a name only one has",
                                sp.arg,
                                cols.join(" and "),
                                sp.source_text()
                            )));
                        }
                        hits.first().copied()
                    }
                    ChannelSource::Index(k) => (0..names.len()).filter(|&j| j != ti).nth(k - 1),
                };
                let Some(col) = col else {
                    return Err(bad(format!(
                        "line {line_no}: --channel {}: no column {} in the header (its columns: {}; #N counts the columns after time from 1)",
                        sp.arg,
                        sp.source_text(),
                        found.join(", ")
                    )));
                };
                if col == ti {
                    return Err(bad(format!("line {line_no}: --channel {}: column {} is the time column", sp.arg, col + 1)));
                }
                let scale = match sp.scale {
                    Some(s) => s,
                    None => match name_and_unit(&names[col]).1 {
                        None => 1.0,
                        Some(u) => accel_unit(&u).ok_or_else(|| {
                            bad(format!(
                                "line {line_no}: column {} (`{}`): unit `{u}` is not an acceleration unit (m/s^2, mm/s^2, g): give its SCALE, --channel {}*SCALE",
                                col + 1,
                                names[col].trim(),
                                sp.arg
                            ))
                        })?,
                    },
                };
                if let Some(other) = accel.iter().position(|a| a.is_some_and(|(j, _)| j == col)) {
                    return Err(bad(format!(
                        "line {line_no}: --channel {}: column {} is also {}",
                        sp.arg,
                        col + 1,
                        ACCEL_NAMES[other]
                    )));
                }
                accel[sp.key] = Some((col, scale));
            }
            if accel[1].is_none() {
                return Err(super::channels::pad_x_needed(label, &format!("line {line_no}"), &found.join(", ")));
            }
            break Layout {
                delimiter,
                decimal_comma: delimiter != b',',
                header_line: line_no,
                fields: names.len(),
                time: ti,
                accel: accel.map(|a| a.map(|a| a.0)),
                time_scale: ts,
                accel_scale: accel.map(|a| a.map_or(0.0, |a| a.1)),
                names,
            };
        };
        // Records end at `\n` only (a `\r` before it is trimmed with the other whitespace):
        // with the default CRLF terminator the csv crate ends a record at the `\r` and counts
        // the `\n` into the next record, whose line number then lags by one.
        let rdr = csv::ReaderBuilder::new()
            .has_headers(false)
            .delimiter(layout.delimiter)
            .terminator(csv::Terminator::Any(b'\n'))
            .flexible(true)
            .buffer_capacity(1 << 16)
            .from_reader(br);
        let last_needed = layout.accel.iter().flatten().copied().fold(layout.time, usize::max);
        Ok(RowReader { label: label.to_string(), layout, rdr, rec: csv::ByteRecord::new(), last_needed })
    }

    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// Which of disc_x, pad_x, pad_trail, pad_lead the file has.
    pub fn present(&self) -> [bool; 4] {
        self.layout.accel.map(|a| a.is_some())
    }

    /// The file's name as used in messages.
    pub fn label(&self) -> &str {
        &self.label
    }

    /// The next data row, or `None` at the end of the file.
    pub fn next_row(&mut self) -> Result<Option<Row>> {
        loop {
            let more = match self.rdr.read_byte_record(&mut self.rec) {
                Ok(m) => m,
                Err(e) => {
                    let line = e.position().map(|p| self.layout.header_line + p.line());
                    let at = line.map_or(String::new(), |l| format!("line {l}: "));
                    return Err(HostError::Input(format!("{}: {at}cannot read: {e}", self.label)));
                }
            };
            if !more {
                return Ok(None);
            }
            let line = self.layout.header_line + self.rec.position().map_or(0, |p| p.line());
            let rec = &self.rec;
            if rec.iter().all(is_blank) {
                continue;
            }
            let nf = rec.len();
            let want = self.layout.fields;
            if nf != want && !(nf > want && rec.iter().skip(want).all(|f| f.trim_ascii().is_empty())) {
                return Err(HostError::Input(format!(
                    "{}: line {line}: {nf} field{} where the header (line {}) has {want}: a ragged row",
                    self.label,
                    if nf == 1 { "" } else { "s" },
                    self.layout.header_line
                )));
            }
            debug_assert!(nf > self.last_needed);
            let t = self.cell(line, self.layout.time)?;
            let t_value = t.value * self.layout.time_scale;
            if !(t_value.abs() <= PLAUSIBLE_TIME_S) {
                return Err(self.cell_error(line, self.layout.time, format!("time {} s is beyond +-{PLAUSIBLE_TIME_S:e} s", crate::output::format::short(t_value))));
            }
            let mut accel = [0.0; 4];
            for (c, a) in accel.iter_mut().enumerate() {
                let Some(col) = self.layout.accel[c] else { continue };
                let v = self.cell(line, col)?.value * self.layout.accel_scale[c];
                if !(v.abs() <= PLAUSIBLE_ACCEL_M_S2) {
                    return Err(self.cell_error(
                        line,
                        col,
                        format!("{} m/s^2 is beyond the plausible range +-{PLAUSIBLE_ACCEL_M_S2:e} m/s^2", crate::output::format::short(v)),
                    ));
                }
                *a = v;
            }
            return Ok(Some(Row {
                line,
                t: t_value,
                t_resolution: t.resolution() * self.layout.time_scale,
                accel,
                full_scale: 0,
            }));
        }
    }

    fn cell_error(&self, line: u64, col: usize, msg: String) -> HostError {
        HostError::Input(format!(
            "{}: line {line}, column {} (`{}`): {msg}",
            self.label,
            col + 1,
            self.layout.names[col].trim()
        ))
    }

    #[inline]
    fn cell(&self, line: u64, col: usize) -> Result<Decimal> {
        let raw = &self.rec[col];
        let s = raw.trim_ascii();
        if s.is_empty() {
            return Err(self.cell_error(line, col, "empty cell".into()));
        }
        let s = match s {
            [b'"', inner @ .., b'"'] => inner.trim_ascii(),
            s => s,
        };
        numbers::parse(s, self.layout.decimal_comma).ok_or_else(|| {
            let shown: String = String::from_utf8_lossy(raw).chars().take(40).collect();
            let hint = if !self.layout.decimal_comma && s.contains(&b',') {
                " (a decimal comma needs a semicolon-separated file)"
            } else {
                ""
            };
            self.cell_error(line, col, format!("`{}` is not a number{hint}", shown.trim()))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_cells() {
        assert_eq!(classify("pad_x [m/s^2]"), Ok(Role::Accel(1, 1.0)));
        assert_eq!(classify("Pad_X (m/s²)"), Ok(Role::Accel(1, 1.0)));
        assert_eq!(classify("\"pad trail\""), Ok(Role::Accel(2, 1.0)));
        assert_eq!(classify("pad_trail_"), Ok(Role::Accel(2, 1.0)));
        assert_eq!(classify("pad_lead_m_s2"), Ok(Role::Accel(3, 1.0)));
        assert_eq!(classify("disc_x [g]"), Ok(Role::Accel(0, G)));
        assert_eq!(classify("disc-x m s^-2"), Ok(Role::Accel(0, 1.0)));
        assert_eq!(classify("Time [s]"), Ok(Role::Time(1.0)));
        assert_eq!(classify("t_s"), Ok(Role::Time(1.0)));
        assert_eq!(classify("time (ms)"), Ok(Role::Time(1e-3)));
        assert_eq!(classify("t"), Ok(Role::Time(1.0)));
        assert_eq!(classify("pressure [bar]"), Ok(Role::Other));
        assert_eq!(classify("pad_x_filtered"), Ok(Role::Other));
        assert!(classify("pad_x [V]").is_err());
        assert!(classify("time [h]").is_err());
    }
}
