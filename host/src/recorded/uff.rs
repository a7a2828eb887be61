//! The Universal File Format's dataset 58 (function at nodal DOF) as B&K PULSE, Siemens
//! Test.Lab and pyuff write time data: one record per channel, ASCII (`58`) or binary (`58b`),
//! written against the format's published layout (UC-SDRL):
//!
//! ```text
//!     -1
//!     58            (58b: `    58b     1     2          11       40960     0 ...`:
//!                    byte order 1 little / 2 big endian, float format 2 IEEE 754,
//!                    11 ASCII lines, bytes of binary data following them)
//! record 1-5   ID lines 1 to 5 (80 characters each; line 1 usually the channel's name)
//! record 6     function type (1: time response), ids, response and reference node/direction
//! record 7     (3I10,3E13.5) ordinate data type (2 real single, 4 real double), number of
//!              values, abscissa spacing (1 even), abscissa minimum, increment, z value
//! record 8     (I10,3I5,2(1X,A20)) abscissa: specific data type, unit exponents, axis label,
//!              units label
//! record 9     the same for the ordinate (specific data type 12: acceleration)
//! record 10-11 ordinate denominator, z axis
//! record 12    the values: ASCII 6E13.5 (single) or 4E20.12 (double), any number per line
//!              here; binary: the raw values, no line ends, then `    -1`
//!     -1
//! ```
//!
//! Read here: real single and double values on an even abscissa (record 7 fields 1 and 3);
//! the time axis is abscissa minimum + i x increment (record 8's units label: s, ms, us, or
//! none: s). The ordinate's unit is record 9's units label (m/s^2, mm/s^2, g), or m/s^2 when
//! it has none and its specific data type is 12 (acceleration); `--channel KEY=SOURCE*SCALE`
//! overrides it. Records are named by any of their five ID lines. Streaming: a first pass
//! finds each record's values (a binary record's are skipped by seeking), then one file handle
//! per channel reads its values in step with the others; memory does not grow with the file.
//! Standard input cannot be read this way (the channels lie one after another): give a file.

use std::fs::File;
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};

use super::channels::{fold, ChannelMap, ChannelSource};
use super::csv_in::{accel_unit_scale, channel_of_name, time_unit_scale, Row, PLAUSIBLE_ACCEL_M_S2};
use super::numbers;
use crate::error::{HostError, Result};
use crate::recorded::progress::Counted;

/// Longest line read while scanning [bytes] (records are 80 characters; data lines of 6 E13.5
/// are 78).
const MAX_LINE: u64 = 1 << 12;

/// How a record's values are stored.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Storage {
    Ascii,
    /// Binary, little endian (else big), 8-byte doubles (else 4-byte singles).
    Binary { little: bool, double: bool },
}

/// One dataset-58 record as the scan found it.
#[derive(Clone, Debug)]
pub struct Record {
    /// Its place among the file's dataset-58 records (from 1).
    pub index: usize,
    /// Line of its `58` line in the file (from 1).
    pub line: u64,
    pub ids: [String; 5],
    func_type: i64,
    ord_type: i64,
    pub values: u64,
    even: bool,
    x0: f64,
    dx: f64,
    /// Abscissa units label x scale = s (`None`: not a time unit).
    time_scale: Option<f64>,
    abscissa_units: String,
    ordinate_type: i64,
    ordinate_units: String,
    storage: Storage,
    /// Byte offset of the first value (binary) or of the first data line (ASCII).
    offset: u64,
    /// Line of the first data line (ASCII; binary: the line after the header).
    data_line: u64,
}

impl Record {
    /// How messages name it: `record 2 (`pad_x`)`.
    pub fn name(&self) -> String {
        format!("record {} (`{}`)", self.index, self.ids[0].trim())
    }
}

fn field(line: &str, from: usize, to: usize) -> &str {
    let b = line.as_bytes();
    let to = to.min(b.len());
    if from >= to {
        return "";
    }
    // the records are ASCII; a multi-byte character makes the slice invalid: no field then
    line.get(from..to).unwrap_or("").trim()
}

/// Scans the file: every dataset-58 record's header and where its values are.
pub fn scan(label: &str, path: &str) -> Result<Vec<Record>> {
    let bad = |line: u64, m: String| HostError::Input(format!("{label}: line {line}: {m}"));
    let f = File::open(path).map_err(|e| HostError::Input(format!("{label}: cannot open the recording: {e}")))?;
    let mut r = BufReader::with_capacity(1 << 16, f);
    let mut pos: u64 = 0;
    let mut line_no: u64 = 0;
    let mut buf = Vec::new();
    let mut records = Vec::new();
    // one line without its end; `None` at the end of the file
    let mut next_line = |r: &mut BufReader<File>, pos: &mut u64, line_no: &mut u64| -> Result<Option<String>> {
        buf.clear();
        let n = r.by_ref().take(MAX_LINE).read_until(b'\n', &mut buf).map_err(|e| bad(*line_no + 1, format!("cannot read: {e}")))?;
        if n == 0 {
            return Ok(None);
        }
        *pos += n as u64;
        *line_no += 1;
        if buf.last() != Some(&b'\n') && n as u64 >= MAX_LINE {
            return Err(bad(*line_no, format!("longer than {MAX_LINE} bytes: not a universal file's line")));
        }
        while matches!(buf.last(), Some(b'\n' | b'\r')) {
            buf.pop();
        }
        Ok(Some(String::from_utf8_lossy(&buf).into_owned()))
    };
    let is_delimiter = |l: &str| l.trim() == "-1" && l.trim_end().len() <= 6;
    loop {
        // the opening `-1`
        let Some(l) = next_line(&mut r, &mut pos, &mut line_no)? else { break };
        if l.trim().is_empty() {
            continue;
        }
        if !is_delimiter(&l) {
            return Err(bad(line_no, format!("`{}`: a dataset must start with a line `    -1`", l.trim().chars().take(40).collect::<String>())));
        }
        let Some(id_line) = next_line(&mut r, &mut pos, &mut line_no)? else {
            return Err(bad(line_no, "the file ends after `-1`: a dataset number must follow".into()));
        };
        let id_at = line_no;
        let toks: Vec<&str> = id_line.split_whitespace().collect();
        let first = toks.first().copied().unwrap_or("");
        let (num, binary) = match first.strip_suffix('b') {
            Some(n) => (n, true),
            None => (first, false),
        };
        if num != "58" {
            if binary {
                return Err(bad(id_at, format!("dataset `{first}`: a binary dataset other than 58b cannot be skipped")));
            }
            if num.parse::<u32>().is_err() {
                return Err(bad(id_at, format!("`{}`: a dataset number must follow `-1`", id_line.trim())));
            }
            // another dataset (units, geometry, ...): skipped to its closing `-1`
            loop {
                match next_line(&mut r, &mut pos, &mut line_no)? {
                    Some(l) if is_delimiter(&l) => break,
                    Some(_) => {}
                    None => return Err(bad(line_no, format!("dataset {num} (line {id_at}) has no closing `-1`"))),
                }
            }
            continue;
        }
        let storage = if binary {
            let int = |i: usize, what: &str| -> Result<i64> {
                toks.get(i).and_then(|t| t.parse::<i64>().ok()).ok_or_else(|| {
                    bad(id_at, format!("58b line: field {} ({what}) missing or not a number", i + 1))
                })
            };
            let order = int(1, "byte ordering")?;
            let format = int(2, "floating-point format")?;
            let lines = int(3, "ASCII lines")?;
            if !(order == 1 || order == 2) {
                return Err(bad(id_at, format!("58b line: byte ordering {order}: 1 (little endian) or 2 (big endian)")));
            }
            if format != 2 {
                return Err(bad(id_at, format!("58b line: floating-point format {format}: only 2 (IEEE 754) is read")));
            }
            if lines != 11 {
                return Err(bad(id_at, format!("58b line: {lines} ASCII lines: dataset 58 has 11")));
            }
            Some((order == 1, int(4, "bytes of binary data")?))
        } else {
            None
        };
        let mut recs = Vec::with_capacity(11);
        for k in 0..11 {
            match next_line(&mut r, &mut pos, &mut line_no)? {
                Some(l) => recs.push(l),
                None => return Err(bad(line_no, format!("dataset 58 at line {id_at}: the file ends in record {}", k + 1))),
            }
        }
        let index = records.len() + 1;
        let rec_line = |k: usize| id_at + k as u64;
        let ids: [String; 5] = std::array::from_fn(|k| recs[k].trim().to_string());
        let name = format!("record {index} (`{}`)", ids[0]);
        let num_err = |k: usize, f: usize, what: &str, v: &str| {
            bad(rec_line(k), format!("{name}, record {k}, field {f} ({what}): `{v}` is not a number"))
        };
        // record 6: function type first
        let r6 = recs[5].split_whitespace().next().unwrap_or("");
        let func_type: i64 = r6.parse().map_err(|_| num_err(6, 1, "function type", r6))?;
        // record 7: 3I10,3E13.5 (whitespace-separated in practice; fixed columns otherwise)
        let r7: Vec<String> = {
            let w: Vec<&str> = recs[6].split_whitespace().collect();
            if w.len() >= 6 {
                w.iter().map(|s| s.to_string()).collect()
            } else {
                let l = &recs[6];
                [(0, 10), (10, 20), (20, 30), (30, 43), (43, 56), (56, 69)].iter().map(|&(a, b)| field(l, a, b).to_string()).collect()
            }
        };
        let i7 = |f: usize, what: &str| -> Result<i64> { r7[f - 1].parse::<i64>().map_err(|_| num_err(7, f, what, &r7[f - 1])) };
        let x7 = |f: usize, what: &str| -> Result<f64> {
            let s = r7[f - 1].replace(['D', 'd'], "E");
            numbers::parse(s.as_bytes(), false).map(|d| d.value).ok_or_else(|| num_err(7, f, what, &r7[f - 1]))
        };
        let ord_type = i7(1, "ordinate data type")?;
        let values = i7(2, "number of values")?;
        let even = i7(3, "abscissa spacing")? == 1;
        let x0 = x7(4, "abscissa minimum")?;
        let dx = x7(5, "abscissa increment")?;
        if values < 0 {
            return Err(bad(rec_line(7), format!("{name}, record 7, field 2 (number of values): {values} is negative")));
        }
        let units = |k: usize| {
            let u = field(&recs[k - 1], 47, 67).to_string();
            if u.eq_ignore_ascii_case("none") { String::new() } else { u }
        };
        let abscissa_units = units(8);
        let ordinate_units = units(9);
        let ordinate_type = recs[8].split_whitespace().next().and_then(|t| t.parse::<i64>().ok()).unwrap_or(0);
        let time_scale = if abscissa_units.is_empty() { Some(1.0) } else { time_unit_scale(&abscissa_units) };
        let storage = match storage {
            Some((little, bytes)) => {
                let width: i64 = if matches!(ord_type, 4 | 6) { 8 } else { 4 };
                let per_value = match ord_type {
                    5 | 6 => 2,
                    _ => 1,
                } * if even { 1 } else { 2 };
                let want = values.checked_mul(per_value * width);
                if want != Some(bytes) {
                    return Err(bad(
                        id_at,
                        format!("{name}: the 58b line gives {bytes} bytes where record 7 gives {values} values of {width} bytes"),
                    ));
                }
                let offset = pos;
                r.seek_relative(bytes).map_err(|e| bad(line_no, format!("{name}: cannot skip its {bytes} bytes: {e}")))?;
                pos += bytes as u64;
                let rec = Record {
                    index,
                    line: id_at,
                    ids: ids.clone(),
                    func_type,
                    ord_type,
                    values: values as u64,
                    even,
                    x0,
                    dx,
                    time_scale,
                    abscissa_units: abscissa_units.clone(),
                    ordinate_type,
                    ordinate_units: ordinate_units.clone(),
                    storage: Storage::Binary { little, double: width == 8 },
                    offset,
                    data_line: line_no + 1,
                };
                // the closing `-1` (a line end before it is tolerated)
                loop {
                    match next_line(&mut r, &mut pos, &mut line_no)? {
                        Some(l) if l.trim().is_empty() => {}
                        Some(l) if is_delimiter(&l) => break,
                        Some(l) => {
                            return Err(bad(
                                line_no,
                                format!("{name}: `{}` after its {bytes} bytes of values: the closing `    -1` must follow them", l.trim().chars().take(20).collect::<String>()),
                            ))
                        }
                        None => return Err(bad(line_no, format!("{name}: the file ends within its binary values or before its closing `-1`"))),
                    }
                }
                records.push(rec);
                continue;
            }
            None => Storage::Ascii,
        };
        let offset = pos;
        let data_line = line_no + 1;
        loop {
            match next_line(&mut r, &mut pos, &mut line_no)? {
                Some(l) if is_delimiter(&l) => break,
                Some(_) => {}
                None => return Err(bad(line_no, format!("{name} (line {id_at}) has no closing `-1`"))),
            }
        }
        records.push(Record {
            index,
            line: id_at,
            ids,
            func_type,
            ord_type,
            values: values as u64,
            even,
            x0,
            dx,
            time_scale,
            abscissa_units,
            ordinate_type,
            ordinate_units,
            storage,
            offset,
            data_line,
        });
    }
    if records.is_empty() {
        return Err(HostError::Input(format!("{label}: a universal file without a dataset 58 (time data): nothing to analyse")));
    }
    Ok(records)
}

/// One channel's values, read in step with the others.
struct ChannelReader {
    r: BufReader<Counted<File>>,
    storage: Storage,
    /// Values of the current ASCII line not yet taken.
    pending: std::collections::VecDeque<f64>,
    line: u64,
    line_buf: Vec<u8>,
    /// Values x scale = m/s^2.
    scale: f64,
    name: String,
}

impl ChannelReader {
    fn next(&mut self, label: &str) -> Result<f64> {
        let v = match self.storage {
            Storage::Binary { little, double } => {
                let mut b = [0u8; 8];
                let w = if double { 8 } else { 4 };
                self.r.read_exact(&mut b[..w]).map_err(|e| HostError::Input(format!("{label}: {}: cannot read its values: {e}", self.name)))?;
                match (double, little) {
                    (true, true) => f64::from_le_bytes(b),
                    (true, false) => f64::from_be_bytes(b),
                    (false, true) => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    (false, false) => f32::from_be_bytes([b[0], b[1], b[2], b[3]]) as f64,
                }
            }
            Storage::Ascii => loop {
                if let Some(v) = self.pending.pop_front() {
                    break v;
                }
                self.line_buf.clear();
                let n = self
                    .r
                    .by_ref()
                    .take(MAX_LINE)
                    .read_until(b'\n', &mut self.line_buf)
                    .map_err(|e| HostError::Input(format!("{label}: line {}: {}: cannot read: {e}", self.line, self.name)))?;
                if n == 0 {
                    return Err(HostError::Input(format!("{label}: {}: the file ends before its values do", self.name)));
                }
                self.line += 1;
                let text = String::from_utf8_lossy(&self.line_buf);
                if text.trim() == "-1" {
                    return Err(HostError::Input(format!(
                        "{label}: line {}: {}: its values end before record 7's number of values",
                        self.line, self.name
                    )));
                }
                for (k, tok) in text.split_whitespace().enumerate() {
                    let t = tok.replace(['D', 'd'], "E");
                    let v = numbers::parse(t.as_bytes(), false).map(|d| d.value).ok_or_else(|| {
                        HostError::Input(format!(
                            "{label}: line {}: {}, value {} of the line: `{}` is not a number",
                            self.line,
                            self.name,
                            k + 1,
                            tok.chars().take(24).collect::<String>()
                        ))
                    })?;
                    self.pending.push_back(v);
                }
            },
        };
        Ok(v * self.scale)
    }
}

/// The rows of a universal file: one value of each mapped record per row.
pub struct UffRows {
    label: String,
    channels: [Option<ChannelReader>; 4],
    present: [bool; 4],
    i: u64,
    n: u64,
    x0: f64,
    dx: f64,
    /// What was assumed, for the report.
    pub notes: Vec<String>,
    /// The sampling interval [s].
    pub dt_s: f64,
}

impl UffRows {
    pub fn present(&self) -> [bool; 4] {
        self.present
    }

    /// Opens `path` with `map`; `counter` counts the bytes read (progress).
    pub fn open(label: &str, path: &str, map: &ChannelMap, counter: &super::progress::Counter) -> Result<Self> {
        let records = scan(label, path)?;
        let listing = || records.iter().map(|r| format!("#{} `{}`", r.index, r.ids[0])).collect::<Vec<_>>().join(", ");
        let mut chosen: [Option<(&Record, Option<f64>)>; 4] = [None; 4];
        for sp in &map.specs {
            let rec = match &sp.source {
                ChannelSource::Index(k) => records.get(k - 1),
                ChannelSource::Name(_) => {
                    let hits: Vec<&Record> =
                        records.iter().filter(|r| ChannelMap::matches_name(sp, &r.ids.iter().map(String::as_str).collect::<Vec<_>>())).collect();
                    if hits.len() > 1 {
                        let which: Vec<String> = hits.iter().map(|r| format!("#{} `{}`", r.index, r.ids[0])).collect();
                        return Err(HostError::Input(format!(
                            "{label}: --channel {} matches records {}: give #N or a text that names one",
                            sp.arg,
                            which.join(", ")
                        )));
                    }
                    hits.first().copied()
                }
            };
            let rec = rec.ok_or_else(|| {
                HostError::Input(format!("{label}: --channel {}: no dataset-58 record {} (the records: {})", sp.arg, sp.source_text(), listing()))
            })?;
            chosen[sp.key] = Some((rec, sp.scale));
        }
        for rec in &records {
            for id in &rec.ids {
                if let Some(c) = channel_of_name(id) {
                    let mapped = map.specs.iter().any(|sp| match &sp.source {
                        ChannelSource::Index(k) => *k == rec.index,
                        ChannelSource::Name(n) => rec.ids.iter().any(|i| fold(i) == fold(n)),
                    });
                    if map.get(c).is_some() || mapped {
                        continue;
                    }
                    match chosen[c] {
                        None => chosen[c] = Some((rec, None)),
                        Some((other, _)) if other.index != rec.index => {
                            return Err(HostError::Input(format!(
                                "{label}: records #{} (`{}`) and #{} (`{}`) both name `{}`: map one with --channel {}=#N",
                                other.index,
                                other.ids[0],
                                rec.index,
                                rec.ids[0],
                                super::channels::key_name(c),
                                super::channels::key_name(c)
                            )))
                        }
                        Some(_) => {}
                    }
                }
            }
        }
        if chosen[1].is_none() {
            return Err(super::channels::pad_x_needed(label, "the dataset-58 records", &listing()));
        }
        let first = chosen.iter().flatten().map(|c| c.0).min_by_key(|r| r.index).expect("pad_x is there");
        let mut notes = Vec::new();
        let mut channels: [Option<ChannelReader>; 4] = Default::default();
        for (key, ch) in chosen.iter().enumerate() {
            let Some((rec, scale)) = ch else { continue };
            let name = rec.name();
            let at = |m: String| HostError::Input(format!("{label}: line {}: {name}: {m}", rec.line));
            if rec.func_type != 1 {
                return Err(at(format!("record 6, field 1 (function type) {}: not a time response (1)", rec.func_type)));
            }
            if !matches!(rec.ord_type, 2 | 4) {
                return Err(at(format!("record 7, field 1 (ordinate data type) {}: only real single (2) or real double (4) values are read", rec.ord_type)));
            }
            if !rec.even {
                return Err(at("record 7, field 3 (abscissa spacing): uneven: only an even abscissa (1) is read".into()));
            }
            if !(rec.dx.is_finite() && rec.dx > 0.0 && rec.x0.is_finite()) {
                return Err(at(format!("record 7, fields 4 and 5 (abscissa minimum, increment) {:.4e}, {:.4e}: the increment must be > 0", rec.x0, rec.dx)));
            }
            if rec.time_scale.is_none() {
                return Err(at(format!("record 8 (abscissa): units `{}` are not a time unit (s, ms, us)", rec.abscissa_units)));
            }
            let s = match scale {
                Some(s) => *s,
                None if rec.ordinate_units.is_empty() && rec.ordinate_type == 12 => {
                    notes.push(format!("{name}: no units label, specific data type 12 (acceleration): taken as m/s^2"));
                    1.0
                }
                None => accel_unit_scale(&rec.ordinate_units).ok_or_else(|| {
                    at(format!(
                        "record 9 (ordinate): units `{}` are not an acceleration unit (m/s^2, mm/s^2, g): give its SCALE, --channel {}=#{}*SCALE",
                        rec.ordinate_units,
                        super::channels::key_name(key),
                        rec.index
                    ))
                })?,
            };
            let tx = |r: &Record| (r.x0 * r.time_scale.unwrap_or(1.0), r.dx * r.time_scale.unwrap_or(1.0));
            let (x0, dx) = tx(rec);
            let (f0, fdx) = tx(first);
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(fdx);
            if rec.values != first.values || !close(x0, f0) || !close(dx, fdx) {
                return Err(at(format!(
                    "{} values from {:.6e} s every {:.6e} s where {} has {} from {:.6e} s every {:.6e} s: the channels must share one time axis",
                    rec.values,
                    x0,
                    dx,
                    first.name(),
                    first.values,
                    f0,
                    fdx
                )));
            }
            let f = File::open(path).map_err(|e| HostError::Input(format!("{label}: cannot open the recording: {e}")))?;
            let mut r = BufReader::with_capacity(1 << 16, Counted::new(f, counter.clone()));
            r.seek(SeekFrom::Start(rec.offset)).map_err(|e| at(format!("cannot seek to its values: {e}")))?;
            channels[key] = Some(ChannelReader {
                r,
                storage: rec.storage,
                pending: Default::default(),
                line: rec.data_line - 1,
                line_buf: Vec::new(),
                scale: s,
                name,
            });
        }
        let ts = first.time_scale.unwrap_or(1.0);
        let present = std::array::from_fn(|c| channels[c].is_some());
        Ok(UffRows {
            label: label.to_string(),
            channels,
            present,
            i: 0,
            n: first.values,
            x0: first.x0 * ts,
            dx: first.dx * ts,
            notes,
            dt_s: first.dx * ts,
        })
    }

    /// The next row (its `line` is the sample's number, from 1), or `None` after the last.
    pub fn next_row(&mut self) -> Result<Option<Row>> {
        if self.i >= self.n {
            return Ok(None);
        }
        let mut accel = [0.0; 4];
        for (c, ch) in self.channels.iter_mut().enumerate() {
            if let Some(ch) = ch {
                let v = ch.next(&self.label)?;
                if !(v.abs() <= PLAUSIBLE_ACCEL_M_S2) {
                    return Err(HostError::Input(format!(
                        "{}: {}, value {}: {v:.4e} m/s^2 is beyond the plausible range +-{PLAUSIBLE_ACCEL_M_S2:e} m/s^2",
                        self.label,
                        ch.name,
                        self.i + 1
                    )));
                }
                accel[c] = v;
            }
        }
        let t = self.x0 + self.i as f64 * self.dx;
        self.i += 1;
        Ok(Some(Row { line: self.i, t, t_resolution: 0.0, accel, full_scale: 0 }))
    }
}
