//! `stickslip record`: the firmware's defmt log as it arrives, from the board's debug probe
//! (RTT up-channel 0, [`probe`], cargo feature `probe`) or from a file or pipe, through one
//! pipeline:
//!
//! - [`source`]: the bytes as chunks over a channel; each chunk is written to the raw file
//!   before the decoder reads it (the raw file holds every byte decoded, in order);
//! - decode's own [`decode_stream`] reads them as they come (its framing, its loss counts);
//! - [`kind_csv`]: each record goes to its kind's CSV at once, decode's columns;
//! - [`status`]: the status line per window and the lines of state changes and warnings on
//!   stderr;
//! - at the end (the input's end, Ctrl-C, a lost probe), the [`Recording`]: its summary.

pub mod kind_csv;
#[cfg(feature = "probe")]
pub mod probe;
pub mod source;
pub mod status;

use std::fs::{File, OpenOptions};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{sync_channel, Receiver};

use defmt_decoder::Table;

use crate::error::{HostError, Result};
use crate::recorded::decode::{decode_stream, load_table, StreamStats};
use kind_csv::{KindCount, KindFiles};
use source::{Chunk, End, Stop, TeeReader};
use status::{FirmwareLoss, Status};

/// The raw stream's file in the recording's folder.
pub const RAW_FILE: &str = "raw.defmt";

/// What `stickslip record` is asked for.
#[derive(Clone, Copy, Debug)]
pub struct RecordRequest<'a> {
    /// The firmware ELF (its defmt table).
    pub elf: &'a Path,
    /// A file or `-` (standard input) instead of the probe.
    pub input: Option<&'a str>,
    /// The folder (new or empty); `None`: a new folder named by the start time.
    pub out: Option<&'a Path>,
    /// The raw stream's file (new); `None`: DIR/raw.defmt.
    pub raw: Option<&'a Path>,
    /// The chip, as probe-rs names it.
    pub chip: &'a str,
    /// VID:PID[:SERIAL] of the probe to use.
    pub probe: Option<&'a str>,
    /// Flash this ELF (the same file as `elf`) and reset first.
    pub flash: Option<&'a Path>,
    /// Redraw the status line in place (stderr is a terminal).
    pub status_in_place: bool,
}

/// A finished recording.
#[derive(Debug)]
pub struct Recording {
    pub dir: PathBuf,
    pub raw_path: PathBuf,
    /// Bytes in the raw file (every byte the decoder read).
    pub raw_bytes: u64,
    /// decode's counts over the stream.
    pub stats: StreamStats,
    /// The CSV files, per kind in order of first appearance.
    pub kinds: Vec<KindCount>,
    pub firmware: FirmwareLoss,
    /// Why it stopped.
    pub end: End,
    /// The first and last record's timestamp [s].
    pub span_s: Option<(f64, f64)>,
    /// The error that stopped a CSV, if one did.
    pub csv_error: Option<String>,
}

impl Recording {
    /// Why it stopped, in words.
    pub fn end_text(&self) -> String {
        match &self.end {
            End::Input => "the input ended".into(),
            End::Interrupted => "stopped by Ctrl-C".into(),
            End::ReadFailed(m) => format!("the input could not be read: {m}"),
            End::Lost(m) => format!("the probe connection was lost: {m}"),
            End::RawWriteFailed(m) => format!("{}: cannot write the raw stream: {m}", self.raw_path.display()),
            End::CsvWriteFailed => self.csv_error.clone().unwrap_or_else(|| "a CSV could not be written".into()),
        }
    }

    /// The summary: why it stopped, what was saved where, what was lost.
    pub fn summary(&self) -> String {
        let mut s = String::new();
        s.push_str(&format!("record: {}\n", self.end_text()));
        s.push_str(&format!("folder: {}\n", self.dir.display()));
        s.push_str(&format!("raw:    {} ({} bytes)\n", self.raw_path.display(), self.raw_bytes));
        s.push_str(&format!("stream: {}\n", self.stats.summary()));
        match self.span_s {
            Some((a, b)) => s.push_str(&format!("records: timestamps {a} to {b} s\n")),
            None => s.push_str("records: none\n"),
        }
        for k in &self.kinds {
            s.push_str(&format!("  {:<14} {:>8}  {}\n", k.kind, k.rows, k.path.display()));
        }
        let f = &self.firmware;
        if f.windows > 0 {
            s.push_str(&format!(
                "firmware: {} window record{}: {} event record{} and {} window{} not logged (events_dropped, windows_dropped), {} overrun{} since boot\n",
                f.windows,
                crate::recorded::decode::plural(f.windows),
                f.events_dropped,
                crate::recorded::decode::plural(f.events_dropped),
                f.windows_dropped,
                crate::recorded::decode::plural(f.windows_dropped),
                f.overruns,
                crate::recorded::decode::plural(f.overruns),
            ));
        }
        s
    }
}

/// The start time as a folder name's stamp: UTC, `YYYYMMDDTHHMMSSZ`.
pub fn utc_stamp(unix_s: u64) -> String {
    let days = (unix_s / 86_400) as i64;
    let sod = unix_s % 86_400;
    // days since 1970-01-01 to the proleptic Gregorian date (H. Hinnant, civil_from_days)
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}{m:02}{d:02}T{:02}{:02}{:02}Z", sod / 3600, sod / 60 % 60, sod % 60)
}

/// The folder and the raw file, created: `out` (new or empty) or a new folder
/// `rig-STAMP[-N]` in the current directory; `raw` (new) or DIR/raw.defmt.
pub fn create_output(out: Option<&Path>, raw: Option<&Path>) -> Result<(PathBuf, PathBuf, File)> {
    if let Some(r) = raw {
        if r.exists() {
            return Err(HostError::Input(format!("--raw {}: exists: record never overwrites a capture", r.display())));
        }
    }
    let dir = match out {
        Some(d) => {
            std::fs::create_dir_all(d)
                .map_err(|e| HostError::Input(format!("--out {}: cannot create the folder: {e}", d.display())))?;
            let first = std::fs::read_dir(d)
                .map_err(|e| HostError::Input(format!("--out {}: cannot read the folder: {e}", d.display())))?
                .next();
            if let Some(entry) = first {
                let name = entry.map(|e| e.file_name().to_string_lossy().into_owned()).unwrap_or_default();
                return Err(HostError::Input(format!(
                    "--out {}: not empty (it holds {name}): record writes into a new or empty folder",
                    d.display()
                )));
            }
            d.to_path_buf()
        }
        None => {
            let now = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
            let stamp = format!("rig-{}", utc_stamp(now));
            let mut n = 1;
            loop {
                let d = PathBuf::from(if n == 1 { stamp.clone() } else { format!("{stamp}-{n}") });
                match std::fs::create_dir(&d) {
                    Ok(()) => break d,
                    Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && n < 100 => n += 1,
                    Err(e) => {
                        return Err(HostError::Output(format!("{}: cannot create the recording's folder: {e}", d.display())))
                    }
                }
            }
        }
    };
    let raw_path = raw.map_or_else(|| dir.join(RAW_FILE), Path::to_path_buf);
    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&raw_path)
        .map_err(|e| HostError::Input(format!("{}: cannot create the raw stream's file: {e}", raw_path.display())))?;
    Ok((dir, raw_path, file))
}

/// The pipeline: the chunks of `rx` through the raw file and decode into the CSVs of `dir`,
/// the status on `status_out`, until the stream ends.
pub fn record_chunks(
    table: &Table,
    rx: Receiver<Chunk>,
    stop: &Stop,
    (dir, raw_path, raw): (PathBuf, PathBuf, File),
    status_in_place: bool,
    status_out: &mut impl Write,
) -> Recording {
    let mut tee = TeeReader::new(rx, raw, stop.clone());
    let mut files = KindFiles::new(&dir);
    let mut status = Status::new(status_in_place);
    let mut decoded = 0u64;
    let mut csv_error: Option<String> = None;
    let mut span: Option<(f64, f64)> = None;
    let stats = decode_stream(table, &mut tee, |r| {
        if csv_error.is_some() {
            return;
        }
        // frame numbers count the dropped frames: the ones before this one not decoded
        let dropped = r.frame - decoded;
        decoded += 1;
        if let Some(t) = r.timestamp_s {
            span = Some(span.map_or((t, t), |(a, _)| (a, t)));
        }
        if let Err(e) = files.write(&r) {
            csv_error = Some(e.to_string());
            stop.request(End::CsvWriteFailed);
            return;
        }
        status.show(&r, dropped, status_out);
    })
    // the tee never fails a read: its errors end the stream (`tee.end`)
    .unwrap_or_default();
    status.finish(status_out);
    let end = if csv_error.is_some() { End::CsvWriteFailed } else { tee.end.clone().unwrap_or(End::Input) };
    Recording {
        dir,
        raw_path,
        raw_bytes: tee.raw_bytes,
        stats,
        kinds: files.counts(),
        firmware: status.firmware,
        end,
        span_s: span,
        csv_error,
    }
}

/// Records `input` (read in a thread of its own) into `out` (as [`create_output`]); no Ctrl-C
/// handling. The status goes to `status_out`.
pub fn record_reader<R: Read + Send + 'static>(
    table: &Table,
    input: R,
    out: Option<&Path>,
    raw: Option<&Path>,
    status_out: &mut impl Write,
) -> Result<Recording> {
    let output = create_output(out, raw)?;
    let (tx, rx) = sync_channel(source::CHANNEL_CHUNKS);
    let stop = Stop::new(tx.clone());
    source::spawn_reader(input, tx);
    Ok(record_chunks(table, rx, &stop, output, false, status_out))
}

/// `stickslip record`.
pub fn run(a: &RecordRequest) -> Result<String> {
    let elf_label = a.elf.display().to_string();
    let elf = crate::limits::read_bytes(a.elf, "ELF", crate::limits::ELF_FILE_MAX_BYTES)?;
    let table = load_table(&elf_label, &elf)?;
    let (tx, rx) = sync_channel(source::CHANNEL_CHUNKS);
    let stop = Stop::new(tx.clone());
    // the source first: no folder is made for a file that does not open or a probe that is
    // not there
    let from = match a.input {
        Some("-") => {
            source::spawn_reader(std::io::stdin(), tx);
            "standard input".to_string()
        }
        Some(path) => {
            let f = File::open(path).map_err(|e| HostError::Input(format!("{path}: cannot open the stream: {e}")))?;
            // a folder opens on Unix and fails only at the first read, after the output
            // folder was made: refuse it here
            if f.metadata().is_ok_and(|m| m.is_dir()) {
                return Err(HostError::Input(format!("{path}: a folder, not a stream (give the capture's file)")));
            }
            source::spawn_reader(f, tx);
            path.to_string()
        }
        None => probe_source(a, &elf, tx, &stop)?,
    };
    let output = create_output(a.out, a.raw)?;
    // inside the Python module the command has a cancellation token: the interpreter keeps its
    // Ctrl-C (a SIGINT handler of ours would take it from the interpreter for good) and its
    // cancel ends the recording as Ctrl-C does in the binary
    let _watch = match crate::cancel::current() {
        Some(token) => Some(source::stop_on_cancel(&stop, token)),
        None => {
            source::stop_on_ctrl_c(&stop).map_err(HostError::Output)?;
            None
        }
    };
    let mut err = std::io::stderr();
    let _ = writeln!(err, "stickslip: recording {from} into {} (Ctrl-C stops)", output.0.display());
    let rec = record_chunks(&table, rx, &stop, output, a.status_in_place, &mut err);
    let summary = rec.summary();
    let fail = |e: HostError| {
        // the summary says what was saved before the error line
        print!("{summary}");
        let _ = std::io::stdout().flush();
        Err(e)
    };
    // decode's rule for a stream of another build (most frames do not fit the ELF's table):
    // the files stay, the recording is refused as decode refuses it
    if let Err(e) = crate::recorded::decode::check_match(&from, &elf_label, &rec.stats) {
        return fail(e);
    }
    match &rec.end {
        End::Input | End::Interrupted => Ok(summary),
        End::ReadFailed(_) => fail(HostError::Input(format!("{from}: {}", rec.end_text()))),
        End::Lost(_) => fail(HostError::Link(rec.end_text())),
        End::RawWriteFailed(_) | End::CsvWriteFailed => fail(HostError::Output(rec.end_text())),
    }
}

#[cfg(feature = "probe")]
fn probe_source(a: &RecordRequest, elf: &[u8], tx: std::sync::mpsc::SyncSender<Chunk>, stop: &Stop) -> Result<String> {
    if let Some(f) = a.flash {
        let bytes = std::fs::read(f).map_err(|e| HostError::Input(format!("--flash {}: cannot read the ELF: {e}", f.display())))?;
        if bytes != elf {
            return Err(HostError::Input(format!(
                "--flash {}: not the same file as --elf {}: the log would be decoded with another firmware's table",
                f.display(),
                a.elf.display()
            )));
        }
    }
    probe::start(&probe::ProbeRequest { chip: a.chip, probe: a.probe, flash: a.flash, elf }, tx, stop.flag())
}

#[cfg(not(feature = "probe"))]
fn probe_source(_: &RecordRequest, _: &[u8], _: std::sync::mpsc::SyncSender<Chunk>, _: &Stop) -> Result<String> {
    Err(HostError::Input(
        "no --input, and this stickslip was built without the debug probe (cargo feature `probe`: README, At the rig)".into(),
    ))
}

#[cfg(test)]
mod tests {
    use super::utc_stamp;

    #[test]
    fn the_folder_stamp_is_the_utc_date_and_time() {
        // dates worked out by hand: the epoch; 2000-02-29 (a leap day of a year divisible by
        // 400) = 11016 days; 2026-11-26 13:57:12 = 20783 days + 50232 s
        assert_eq!(utc_stamp(0), "19700101T000000Z");
        assert_eq!(utc_stamp(11_016 * 86_400), "20000229T000000Z");
        assert_eq!(utc_stamp(11_016 * 86_400 - 1), "20000228T235959Z");
        assert_eq!(utc_stamp(20_783 * 86_400 + 50_232), "20261126T135712Z");
    }
}
