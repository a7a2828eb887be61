//! A recording as it comes: CSV, UFF dataset 58/58b or WAV, told apart by its first bytes (not
//! its name), read one row at a time. Every reader gives the same rows (time [s], the four
//! accelerations [m/s^2], absent channels 0 and marked absent) and the same one-line errors
//! naming the file, the line, record or sample, and the field.
//!
//! - WAV: the file starts with `RIFF` and has `WAVE` at byte 8 ([`super::wav`]);
//! - UFF: the first non-blank line is `-1` and the next starts with a dataset number
//!   ([`super::uff`]; a file only, not standard input);
//! - CSV otherwise ([`super::csv_in`]).

use std::io::{Cursor, Read};

use super::channels::ChannelMap;
use super::csv_in::{Row, RowReader};
use super::progress::{Counted, Counter};
use super::uff::UffRows;
use super::wav::WavRows;
use crate::error::{HostError, Result};

/// Bytes looked at to tell the format.
const SNIFF_BYTES: usize = 4096;

/// The formats read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Csv,
    Uff,
    Wav,
}

impl Format {
    pub fn name(self) -> &'static str {
        match self {
            Format::Csv => "CSV",
            Format::Uff => "UFF dataset 58",
            Format::Wav => "WAV",
        }
    }

    /// What a row is called in messages: a CSV's line, a UFF's or WAV's sample.
    pub fn row_word(self) -> &'static str {
        match self {
            Format::Csv => "line",
            _ => "sample",
        }
    }
}

/// Tells the format from the first bytes.
pub fn sniff(head: &[u8]) -> Format {
    if head.len() >= 12 && &head[..4] == b"RIFF" && &head[8..12] == b"WAVE" {
        return Format::Wav;
    }
    let text = String::from_utf8_lossy(&head[..head.len().min(SNIFF_BYTES)]);
    let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
    if lines.next() == Some("-1") {
        if let Some(next) = lines.next() {
            let id = next.split_whitespace().next().unwrap_or("");
            let id = id.strip_suffix('b').unwrap_or(id);
            if !id.is_empty() && id.bytes().all(|b| b.is_ascii_digit()) {
                return Format::Uff;
            }
        }
    }
    Format::Csv
}

enum Rows<'a> {
    Csv(RowReader<Box<dyn Read + 'a>>),
    Uff(UffRows),
    Wav(WavRows<Box<dyn Read + 'a>>),
}

/// An opened recording.
pub struct Recording<'a> {
    pub label: String,
    pub format: Format,
    /// disc_x, pad_x, pad_trail, pad_lead: which the file has.
    pub present: [bool; 4],
    /// What the reader assumed (units, ...), for the report.
    pub notes: Vec<String>,
    /// Bytes read so far (all of the file's readers).
    pub counter: Counter,
    /// The file's size [bytes] (0: standard input).
    pub size: u64,
    /// The format's full scale in words, where it has one (an integer WAV's extreme codes:
    /// rows mark the samples at them, `Row::full_scale`).
    pub full_scale: Option<String>,
    rows: Rows<'a>,
}

impl<'a> Recording<'a> {
    /// Opens the file at `path` (`-`: standard input) with the `--channel` mapping `map`.
    pub fn open(path: &str, map: &ChannelMap) -> Result<Self> {
        if path == "-" {
            return Self::from_reader("<stdin>", Box::new(std::io::stdin()), map);
        }
        let f = std::fs::File::open(path).map_err(|e| HostError::Input(format!("{path}: cannot open the recording: {e}")))?;
        let size = f.metadata().map(|m| m.len()).unwrap_or(0);
        Self::build(path, Box::new(f), Some(path), size, map)
    }

    /// A recording read from `input` (CSV or WAV: a universal file needs a path).
    pub fn from_reader(label: &str, input: Box<dyn Read + 'a>, map: &ChannelMap) -> Result<Self> {
        Self::build(label, input, None, 0, map)
    }

    fn build(label: &str, input: Box<dyn Read + 'a>, path: Option<&str>, size: u64, map: &ChannelMap) -> Result<Self> {
        let counter = Counter::default();
        let label = label.to_string();
        let mut input: Box<dyn Read + 'a> = Box::new(Counted::new(input, counter.clone()));
        let mut head = Vec::with_capacity(SNIFF_BYTES);
        (&mut input)
            .take(SNIFF_BYTES as u64)
            .read_to_end(&mut head)
            .map_err(|e| HostError::Input(format!("{label}: cannot read: {e}")))?;
        let format = sniff(&head);
        let rest: Box<dyn Read + 'a> = Box::new(Cursor::new(head).chain(input));
        let mut full_scale = None;
        let (rows, present, notes) = match format {
            Format::Csv => {
                let r = RowReader::with_channels(&label, rest, map)?;
                let p = r.present();
                (Rows::Csv(r), p, Vec::new())
            }
            Format::Wav => {
                let mut r = WavRows::open(&label, rest, map)?;
                let n = std::mem::take(&mut r.notes);
                let p = r.present();
                full_scale = r.full_scale.clone();
                (Rows::Wav(r), p, n)
            }
            Format::Uff => {
                let Some(path) = path else {
                    return Err(HostError::Input(format!(
                        "{label}: a universal file (dataset 58) stores its channels one after another: give it as a file, not on standard input"
                    )));
                };
                drop(rest);
                // the first bytes were read to tell the format: the readers count from 0
                let mut r = UffRows::open(&label, path, map, &counter)?;
                let n = std::mem::take(&mut r.notes);
                let p = r.present();
                (Rows::Uff(r), p, n)
            }
        };
        Ok(Recording { label, format, present, notes, counter, size, full_scale, rows })
    }

    /// The next row, or `None` at the end.
    pub fn next_row(&mut self) -> Result<Option<Row>> {
        match &mut self.rows {
            Rows::Csv(r) => r.next_row(),
            Rows::Uff(r) => r.next_row(),
            Rows::Wav(r) => r.next_row(),
        }
    }

    /// The line of a CSV's header (0 for the other formats).
    pub fn header_line(&self) -> u64 {
        match &self.rows {
            Rows::Csv(r) => r.layout().header_line,
            _ => 0,
        }
    }

    /// An analysis message starting "line N" or "lines N to M" in this format's words.
    pub fn locate(&self, m: &str) -> String {
        if self.format == Format::Csv {
            return m.to_string();
        }
        if let Some(rest) = m.strip_prefix("lines ") {
            format!("samples {rest}")
        } else if let Some(rest) = m.strip_prefix("line ") {
            format!("sample {rest}")
        } else {
            m.to_string()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_by_content() {
        assert_eq!(sniff(b"RIFF\x24\0\0\0WAVEfmt "), Format::Wav);
        assert_eq!(sniff(b"    -1\n    58\nNONE\n"), Format::Uff);
        assert_eq!(sniff(b"\n    -1\r\n    58b     1     2          11        4096     0\n"), Format::Uff);
        assert_eq!(sniff(b"    -1\n   164\n"), Format::Uff);
        assert_eq!(sniff(b"t,disc_x,pad_x\n0,1,2\n"), Format::Csv);
        assert_eq!(sniff(b"-1\n0.5\n"), Format::Csv);
        assert_eq!(sniff(b"RIFF"), Format::Csv);
    }
}
