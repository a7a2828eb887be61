//! The firmware's defmt log stream, decoded with the firmware ELF's defmt table
//! (defmt-decoder 1.x, matching the firmware's defmt 1.x) into records.
//!
//! **Framing.** The firmware's defmt uses the rzCOBS encoding (the default of defmt 1.x, as
//! the ELF's `_defmt_encoding_` symbol says): every frame ends with a 0x00 byte, so a stream
//! can be cut anywhere and decoding resumes at the next frame. Each byte run between two zero
//! bytes is one frame; a frame that does not decode (corrupted bytes, a frame cut by a lost
//! buffer, a frame of another firmware) is dropped and its bytes counted as skipped; bytes
//! after the last zero are an incomplete frame (a truncated capture). Runs of zeros are
//! separators, not data. A run of more than [`MAX_FRAME_BYTES`] bytes without a zero is
//! skipped as garbage. The raw encoding (`encoding-raw`) has no separators: decoding stops at
//! the first frame that does not decode and the rest is counted as skipped.
//!
//! defmt has no checksum, but a frame must fit its format: the decoded frame's bytes must be
//! exactly its format's (index, timestamp, arguments) plus the rzCOBS padding, or it is
//! dropped; a stream of which most frames are dropped is refused ([`check_match`]): it is not
//! this ELF's build. A corrupted frame that still fits its format gives a wrong record.
//! defmt-decoder 1.2 reserves memory for a format slice (`{=[?]}`) before reading its
//! elements, so a corrupted frame whose format has one could ask for gigabytes; the rig
//! firmware's table has no format slice.
//!
//! **Records.** Each frame gives: its number in the stream (from 0, dropped frames included),
//! the byte offset of its first byte, the timestamp (the firmware's `{=u64:us}` uptime,
//! printed in seconds), the level, the message, and its parameters as fields. A line laid out
//! as `name key={..} key={..} ...` (every record of the firmware's log: firmware/records, listed
//! in firmware/README.md, "Log records") is kind `name` with its keys as fields; any other
//! line (embassy-stm32's own defmt lines, say) is kind `log` with fields `arg0`, `arg1`...
//!
//! `stickslip record` (`recorded::live`) decodes with [`decode_stream`] as the bytes arrive and
//! writes its per-kind CSVs with [`extend_kind_columns`], [`kind_header`] and [`kind_row`],
//! the functions of `--kind` here.

use std::io::Read;

use defmt_decoder::{DecodeError, Encoding, Table};
use defmt_parser::{Fragment, Type};
use serde::Serialize;
use serde_json::Value;

use crate::error::{HostError, Result};

/// Longest frame accepted [bytes] (the firmware's longest, a `window` record, is about 140).
pub const MAX_FRAME_BYTES: usize = 1 << 16;

/// One decoded frame.
#[derive(Clone, Debug, Serialize)]
pub struct Record {
    /// Frame number in the stream, from 0 (dropped frames counted).
    pub frame: u64,
    /// Byte offset of the frame's first byte.
    pub offset: u64,
    /// The timestamp as the firmware's format prints it.
    pub timestamp: Option<String>,
    /// The timestamp in seconds, when it is a number.
    pub timestamp_s: Option<f64>,
    pub level: Option<&'static str>,
    pub kind: String,
    pub message: String,
    /// The parameters, named, in the order of the message.
    #[serde(serialize_with = "ordered_map")]
    pub fields: Vec<(String, Value)>,
}

impl Record {
    /// The field `name`, if the record has it.
    pub fn field(&self, name: &str) -> Option<&Value> {
        self.fields.iter().find(|(k, _)| k == name).map(|(_, v)| v)
    }
}

fn ordered_map<S: serde::Serializer>(fields: &[(String, Value)], s: S) -> std::result::Result<S::Ok, S::Error> {
    s.collect_map(fields.iter().map(|(k, v)| (k, v)))
}

/// `name key={..} key={..} ...`: the record layout of firmware/records/src/lib.rs. Returns the
/// name and the keys, or `None` if the format does not follow it.
fn key_value_layout(fragments: &[Fragment<'_>]) -> Option<(String, Vec<String>)> {
    let word = |w: &str| !w.is_empty() && w.bytes().all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_');
    let mut name: Option<String> = None;
    let mut keys = Vec::new();
    let mut lit = String::new();
    for f in fragments {
        match f {
            Fragment::Literal(l) => lit.push_str(l),
            Fragment::Parameter(_) => {
                let text = std::mem::take(&mut lit);
                let key_part = match &name {
                    None => {
                        let (n, rest) = text.split_once(' ')?;
                        if !word(n) {
                            return None;
                        }
                        name = Some(n.to_string());
                        rest.to_string()
                    }
                    Some(_) => text.strip_prefix(' ')?.to_string(),
                };
                let key = key_part.strip_suffix('=')?;
                if !word(key) {
                    return None;
                }
                keys.push(key.to_string());
            }
        }
    }
    match name {
        Some(n) if lit.is_empty() => Some((n, keys)),
        None if word(&lit) => Some((lit, keys)),
        _ => None,
    }
}

/// What the stream held.
#[derive(Clone, Debug, Default, Serialize, PartialEq, Eq)]
pub struct StreamStats {
    pub encoding: &'static str,
    pub bytes: u64,
    pub frames_decoded: u64,
    pub frames_dropped: u64,
    pub bytes_skipped: u64,
    /// Bytes after the last frame separator (an incomplete frame).
    pub incomplete_bytes: u64,
}

impl StreamStats {
    /// One line for stderr.
    pub fn summary(&self) -> String {
        format!(
            "decoded {} frame{} from {} bytes; dropped {} frame{} ({} bytes skipped); {} bytes of an incomplete frame at the end",
            self.frames_decoded,
            if self.frames_decoded == 1 { "" } else { "s" },
            self.bytes,
            self.frames_dropped,
            if self.frames_dropped == 1 { "" } else { "s" },
            self.bytes_skipped,
            self.incomplete_bytes
        )
    }
}

fn level_name(l: defmt_parser::Level) -> &'static str {
    use defmt_parser::Level::*;
    match l {
        Trace => "trace",
        Debug => "debug",
        Info => "info",
        Warn => "warn",
        Error => "error",
    }
}

fn is_number_type(t: &Type) -> bool {
    matches!(
        t,
        Type::I8
            | Type::I16
            | Type::I32
            | Type::I64
            | Type::I128
            | Type::Isize
            | Type::U8
            | Type::U16
            | Type::U32
            | Type::U64
            | Type::U128
            | Type::Usize
            | Type::F32
            | Type::F64
    )
}

/// A parameter's displayed value as JSON: numbers as numbers, booleans as booleans, the rest
/// as strings.
fn field_value(ty: &Type, shown: &str) -> Value {
    if is_number_type(ty) || matches!(ty, Type::Bool) {
        if let Ok(v) = serde_json::from_str::<Value>(shown) {
            if v.is_number() || v.is_boolean() {
                return v;
            }
        }
        if let Ok(x) = shown.parse::<f64>() {
            if let Some(n) = serde_json::Number::from_f64(x) {
                return Value::Number(n);
            }
        }
    }
    if matches!(ty, Type::Format) && shown.starts_with('[') {
        // a defmt array of numbers, `[a, b, c, d]`
        if let Ok(v @ Value::Array(_)) = serde_json::from_str::<Value>(shown) {
            return v;
        }
        // with a NaN or an infinity among them (not JSON numbers): each element apart, a
        // non-finite one as its text ("NaN", "inf", "-inf"), as a scalar field shows it, so that
        // the array keeps its shape and its finite values (a window's rms with one NaN became one
        // string before, its CSV cells rms_0.. empty)
        if let Some(inner) = shown.strip_prefix('[').and_then(|x| x.strip_suffix(']')) {
            let parts: Vec<Option<Value>> = inner
                .split(',')
                .map(|e| {
                    let e = e.trim();
                    match serde_json::from_str::<Value>(e) {
                        Ok(v) if v.is_number() => Some(v),
                        _ => e.parse::<f64>().ok().filter(|x| !x.is_finite()).map(|_| Value::String(e.to_string())),
                    }
                })
                .collect();
            if !inner.trim().is_empty() && parts.iter().all(Option::is_some) {
                return Value::Array(parts.into_iter().flatten().collect());
            }
        }
    }
    Value::String(shown.to_string())
}

/// The record of a decoded frame.
fn record(frame: &defmt_decoder::Frame<'_>, number: u64, offset: u64) -> Record {
    let fragments = frame.fragments();
    let (kind, names) = key_value_layout(&fragments).unwrap_or_else(|| ("log".to_string(), Vec::new()));
    let mut fields = Vec::new();
    let mut k = 0;
    for (frag, shown) in fragments.iter().zip(frame.display_fragments()) {
        if let Fragment::Parameter(p) = frag {
            let name = names.get(k).cloned().unwrap_or_else(|| format!("arg{k}"));
            fields.push((name, field_value(&p.ty, &shown.to_string())));
            k += 1;
        }
    }
    let timestamp = frame.display_timestamp().map(|t| t.to_string());
    let timestamp_s = timestamp.as_deref().and_then(|t| t.trim().parse::<f64>().ok());
    Record {
        frame: number,
        offset,
        timestamp,
        timestamp_s,
        level: frame.level().map(level_name),
        kind,
        message: frame.display_message().to_string(),
        fields,
    }
}

/// Parses the defmt table of an ELF; the error is one line naming the file.
pub fn load_table(label: &str, elf: &[u8]) -> Result<Table> {
    match Table::parse(elf) {
        Ok(Some(t)) => Ok(t),
        Ok(None) => Err(HostError::Input(format!("{label}: no defmt data in this ELF (no .defmt section)"))),
        Err(e) => Err(HostError::Input(format!("{label}: not a usable firmware ELF: {e:#}"))),
    }
}

/// One rzCOBS frame (without its 0x00 separator) back to its bytes (the inverse of defmt's
/// rzCOBS encoder, as defmt-decoder 1.2's stream decoder reads it, whose decoder does not
/// return how much of a frame its format used): the frame is read from its end, each group
/// byte 0x01..=0x7F standing for 7 bytes (a set bit: a zero byte), 0x80..=0xFE for a zero
/// and (x & 0x7F) + 7 bytes, 0xFF for 134 bytes. `None` if the frame is malformed. The
/// result may end with up to 6 zero bytes of padding (a last, partial group).
pub fn rzcobs_decode(data: &[u8]) -> Option<Vec<u8>> {
    let mut res = Vec::with_capacity(data.len() + data.len() / 7 + 7);
    let mut it = data.iter().rev().copied();
    while let Some(x) = it.next() {
        match x {
            0 => return None,
            0x01..=0x7f => {
                for i in 0..7 {
                    if x & (1 << (6 - i)) == 0 {
                        res.push(it.next()?);
                    } else {
                        res.push(0);
                    }
                }
            }
            0x80..=0xfe => {
                res.push(0);
                for _ in 0..(x & 0x7f) + 7 {
                    res.push(it.next()?);
                }
            }
            0xff => {
                for _ in 0..134 {
                    res.push(it.next()?);
                }
            }
        }
    }
    res.reverse();
    Some(res)
}

/// The frame `raw` decoded with `table`, if its format uses all of it: what is left after the
/// format's arguments may only be the rzCOBS padding (fewer than 7 zero bytes). A frame of
/// another firmware's table (its index naming another format here) seldom fits its bytes
/// exactly: such a frame is dropped, not turned into a record of made-up values.
fn fitted<'t>(table: &'t Table, raw: &[u8]) -> Option<defmt_decoder::Frame<'t>> {
    let (frame, used) = table.decode(raw).ok()?;
    let rest = raw.get(used..)?;
    (rest.len() < 7 && rest.iter().all(|&b| b == 0)).then_some(frame)
}

/// Decodes a whole stream; each record goes to `sink` as it is decoded. Memory: one frame.
pub fn decode_stream<R: Read>(table: &Table, input: R, sink: impl FnMut(Record)) -> std::io::Result<StreamStats> {
    decode_frames(table, input, true, sink)
}

/// [`decode_stream`]'s counts alone: every frame decoded and fitted, no record built.
pub fn count_stream<R: Read>(table: &Table, input: R) -> std::io::Result<StreamStats> {
    decode_frames(table, input, false, |_| {})
}

/// [`decode_stream`], with the records built and sent to `sink` only where `build`.
fn decode_frames<R: Read>(table: &Table, mut input: R, build: bool, mut sink: impl FnMut(Record)) -> std::io::Result<StreamStats> {
    let mut st = StreamStats::default();
    let mut buf = vec![0u8; 1 << 16];
    let mut number = 0u64;
    match table.encoding() {
        Encoding::Rzcobs => {
            st.encoding = "rzcobs";
            let mut pending: Vec<u8> = Vec::new();
            let mut pending_offset = 0u64;
            let mut overlong = false;
            loop {
                let n = match input.read(&mut buf) {
                    Ok(0) => break,
                    Ok(n) => n,
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                    Err(e) => return Err(e),
                };
                for &b in &buf[..n] {
                    let at = st.bytes;
                    st.bytes += 1;
                    if b != 0 {
                        if pending.is_empty() && !overlong {
                            pending_offset = at;
                        }
                        if overlong {
                            st.bytes_skipped += 1;
                        } else if pending.len() >= MAX_FRAME_BYTES {
                            st.bytes_skipped += pending.len() as u64 + 1;
                            pending.clear();
                            overlong = true;
                        } else {
                            pending.push(b);
                        }
                        continue;
                    }
                    if overlong {
                        overlong = false;
                        st.frames_dropped += 1;
                        number += 1;
                        continue;
                    }
                    if pending.is_empty() {
                        continue; // a separator
                    }
                    match rzcobs_decode(&pending).and_then(|raw| fitted(table, &raw).map(|f| (f, raw.len()))) {
                        Some((frame, _)) => {
                            if build {
                                sink(record(&frame, number, pending_offset));
                            }
                            st.frames_decoded += 1;
                        }
                        None => {
                            st.frames_dropped += 1;
                            st.bytes_skipped += pending.len() as u64;
                        }
                    }
                    number += 1;
                    pending.clear();
                }
            }
            st.incomplete_bytes = pending.len() as u64;
        }
        _ => {
            st.encoding = "raw";
            let mut data = Vec::new();
            input.read_to_end(&mut data)?;
            st.bytes = data.len() as u64;
            let mut at = 0usize;
            while at < data.len() {
                match table.decode(&data[at..]) {
                    Ok((frame, used)) => {
                        if build {
                                sink(record(&frame, number, at as u64));
                            }
                        st.frames_decoded += 1;
                        number += 1;
                        at += used.max(1);
                    }
                    Err(DecodeError::UnexpectedEof) => {
                        st.incomplete_bytes = (data.len() - at) as u64;
                        break;
                    }
                    Err(DecodeError::Malformed) => {
                        // the raw encoding cannot resynchronise
                        st.frames_dropped += 1;
                        st.bytes_skipped = (data.len() - at) as u64;
                        break;
                    }
                }
            }
        }
    }
    Ok(st)
}

/// One CSV line (with its `\n`) of `cells`, quoted where needed: every CSV line `decode` and
/// `record` write.
pub fn csv_line(cells: &[String]) -> String {
    let mut w = csv::WriterBuilder::new().terminator(csv::Terminator::Any(b'\n')).from_writer(Vec::new());
    let _ = w.write_record(cells);
    String::from_utf8(w.into_inner().unwrap_or_default()).unwrap_or_default()
}

fn cell(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        Value::Null => String::new(),
        v => v.to_string(),
    }
}

/// What `stickslip decode` is asked for.
#[derive(Clone, Copy, Debug)]
pub struct DecodeRequest<'a> {
    /// The firmware ELF the stream came from (its .defmt section and symbols).
    pub elf: &'a std::path::Path,
    /// The raw defmt byte stream's file, `-` for standard input.
    pub input: &'a str,
    /// One JSON object instead of CSV.
    pub json: bool,
    /// CSV of one kind of record only.
    pub kind: Option<&'a str>,
}

/// `stickslip decode`. Memory: one frame and one record, whatever the length of an rzCOBS
/// stream (a raw-encoded one is read whole): the stream is read twice, first for its counts
/// (and `check_match`, and with `--kind` the kind's columns), then for the records, written to
/// standard output as they decode; standard input, a pipe or a FIFO is first copied to a
/// temporary file. Before, every record was held until the end: a 49 MB
/// stream took 1.9 GB (CSV) and 2.4 GB (JSON) (a campaign, 2026-11-28). Returns nothing to
/// print: the output has been written.
pub fn run_to_stdout(a: &DecodeRequest) -> Result<String> {
    let stdout = std::io::stdout();
    let mut lock = stdout.lock();
    run_into(a, &mut lock)?;
    Ok(String::new())
}

/// [`run_to_stdout`]'s output as a string (held whole: for a library caller, e.g. a test).
pub fn run(a: &DecodeRequest) -> Result<String> {
    let mut out: Vec<u8> = Vec::new();
    run_into(a, &mut out)?;
    String::from_utf8(out).map_err(|e| HostError::Output(format!("decode's output is not UTF-8: {e}")))
}

/// `stickslip decode` into `sink` (see [`run_to_stdout`]).
pub fn run_into(a: &DecodeRequest, sink: &mut dyn std::io::Write) -> Result<()> {
    let elf_label = a.elf.display().to_string();
    let elf = crate::limits::read_bytes(a.elf, "ELF", crate::limits::ELF_FILE_MAX_BYTES)?;
    let table = load_table(&elf_label, &elf)?;
    // a regular file is read twice; anything else (standard input, a pipe such as `<(...)` or
    // /dev/stdin, a FIFO) once, into a temporary file
    let label = if a.input == "-" { "<stdin>".to_string() } else { a.input.to_string() };
    let spool = if a.input == "-" {
        Some(Spool::of(std::io::stdin().lock(), &label)?)
    } else {
        let f = std::fs::File::open(a.input).map_err(|e| HostError::Input(format!("{label}: cannot open the stream: {e}")))?;
        if f.metadata().is_ok_and(|m| m.is_file()) {
            None
        } else {
            Some(Spool::of(f, &label)?)
        }
    };
    let open = || {
        match &spool {
            Some(sp) => sp.reader(),
            None => std::fs::File::open(a.input),
        }
        .map(std::io::BufReader::new)
        .map_err(|e| HostError::Input(format!("{label}: cannot open the stream: {e}")))
    };
    let read_err = |e: std::io::Error| HostError::Input(format!("{label}: cannot read the stream: {e}"));
    // pass 1: the counts, the kinds found, and --kind's columns (the union of the kind's fields)
    let mut kinds: Vec<String> = Vec::new();
    let mut cols: Vec<KindColumn> = Vec::new();
    let mut chosen = 0u64;
    let stats = match a.kind {
        None => count_stream(&table, open()?),
        Some(kind) => decode_stream(&table, open()?, |r| {
            if !kinds.contains(&r.kind) {
                kinds.push(r.kind.clone());
            }
            if r.kind == kind {
                chosen += 1;
                extend_kind_columns(&mut cols, &r);
            }
        }),
    }
    .map_err(read_err)?;
    check_match(&label, &elf_label, &stats)?;
    if let Some(kind) = a.kind {
        if chosen == 0 {
            kinds.sort_unstable();
            return Err(HostError::Input(format!(
                "--kind {kind}: no record of this kind in {label} (kinds found: {})",
                if kinds.is_empty() { "none".to_string() } else { kinds.join(", ") }
            )));
        }
    }
    // pass 2: the records as they decode, over the bytes pass 1 read (a file that grows
    // meanwhile, a capture still being written, is read to the same length)
    let mut w = std::io::BufWriter::new(sink);
    let mut failed: Option<std::io::Error> = None;
    let mut first = true;
    let mut windows = WindowGaps::default();
    let mut put = |w: &mut std::io::BufWriter<&mut dyn std::io::Write>, text: &str| {
        if failed.is_none() {
            if let Err(e) = std::io::Write::write_all(w, text.as_bytes()) {
                failed = Some(e);
            }
        }
    };
    let second = std::io::Read::take(open()?, stats.bytes);
    put(&mut w, &header(a, &cols));
    let again = decode_stream(&table, second, |r| {
        windows.see(&r);
        let text = match (a.json, a.kind) {
            (true, _) => {
                let one = serde_json::to_string_pretty(&r).unwrap_or_default();
                let lead = if first { "\n" } else { ",\n" };
                format!("{lead}{}", indent(&one, "    "))
            }
            (false, Some(kind)) if r.kind == kind => csv_line(&kind_row(&r, &cols)),
            (false, Some(_)) => String::new(),
            (false, None) => csv_line(&[
                r.frame.to_string(),
                r.offset.to_string(),
                r.timestamp_s.map_or(String::new(), |t| t.to_string()),
                r.level.unwrap_or("").to_string(),
                r.kind.to_string(),
                r.message.clone(),
            ]),
        };
        first = false;
        put(&mut w, &text);
    })
    .map_err(read_err)?;
    if a.json {
        let st = serde_json::to_string_pretty(&stats).unwrap_or_default();
        let close = if again.frames_decoded > 0 { "\n  ]" } else { "]" };
        put(&mut w, &format!("{close},\n  \"stream\": {}\n}}\n", indent(&st, "  ").trim_start()));
    }
    let flushed = std::io::Write::flush(&mut w);
    match failed.map_or(flushed, Err) {
        // a closed pipe (`| head`) is not an error worth a message
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => return Err(HostError::Output(format!("cannot write to stdout: {e}"))),
        _ => {}
    }
    let mut summary = stats.summary();
    let total = stats.frames_decoded + stats.frames_dropped;
    if total >= MATCH_MIN_FRAMES && stats.frames_dropped * 10 > total {
        summary.push_str(&format!(
            "; {} of {total} frames do not fit the defmt table of {elf_label}: a damaged stream, or the ELF of another build?",
            stats.frames_dropped
        ));
    }
    if windows.missing > 0 {
        summary.push_str(&format!(
            "; {} window record{} missing inside recordings ({} jump{} of the window index idx: lost in transport, where the framing cannot tell)",
            windows.missing,
            plural(windows.missing),
            windows.jumps,
            plural(windows.jumps)
        ));
    }
    eprintln!("stickslip: {label}: {summary}");
    Ok(())
}

/// "s" for a count other than 1 (a noun's plural ending in the summaries).
pub(crate) fn plural(n: u64) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// Window records missing inside a recording: the firmware numbers a recording's windows
/// (`rec`, `idx` from 0), so a jump of idx within one rec is windows lost, less those the
/// firmware itself did not log (the rise of `windows_dropped`, which every window record
/// carries): lost in transport, also where the framing cannot see it (frames lost whole at
/// their separators).
#[derive(Default)]
struct WindowGaps {
    /// The last window's rec, idx and windows_dropped.
    last: Option<(u64, u64, u64)>,
    missing: u64,
    jumps: u64,
}

impl WindowGaps {
    fn see(&mut self, r: &Record) {
        if r.kind != "window" {
            return;
        }
        let (Some(rec), Some(idx)) = (r.field("rec").and_then(Value::as_u64), r.field("idx").and_then(Value::as_u64)) else { return };
        let dropped = r.field("windows_dropped").and_then(Value::as_u64).unwrap_or(0);
        if let Some((lr, li, ld)) = self.last {
            if lr == rec && idx > li + 1 {
                let lost = (idx - li - 1).saturating_sub(dropped.saturating_sub(ld));
                if lost > 0 {
                    self.missing += lost;
                    self.jumps += 1;
                }
            }
        }
        self.last = Some((rec, idx, dropped));
    }
}

/// What `decode` writes before its records: the CSV's header, or the JSON's opening.
fn header(a: &DecodeRequest, cols: &[KindColumn]) -> String {
    match (a.json, a.kind) {
        (true, _) => "{\n  \"records\": [".to_string(),
        (false, Some(_)) => csv_line(&kind_header(cols)),
        (false, None) => "frame,offset,timestamp_s,level,kind,message\n".to_string(),
    }
}

/// Every line of `text` after `pad` (serde_json's pretty text nested one level deeper).
fn indent(text: &str, pad: &str) -> String {
    text.lines().map(|l| format!("{pad}{l}")).collect::<Vec<_>>().join("\n")
}

/// A stream that cannot be read twice (standard input, a pipe, a FIFO) copied to a temporary
/// file (readable by its owner alone) for `decode`'s two passes. On Unix its name is removed as
/// soon as it is created: the file lives while the spool holds it open, and the system frees
/// it when the process ends however it ends (Ctrl-C, a kill): nothing is left in the temporary
/// directory. Elsewhere it is removed when the spool is dropped.
struct Spool {
    file: std::fs::File,
    /// The name still to remove (not on Unix: removed at creation).
    path: Option<std::path::PathBuf>,
}

impl Spool {
    fn of(mut input: impl Read, label: &str) -> Result<Spool> {
        let nanos = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos());
        let path = std::env::temp_dir().join(format!("stickslip-decode-{}-{nanos}.defmt", std::process::id()));
        let mut options = std::fs::OpenOptions::new();
        options.read(true).write(true).create_new(true);
        #[cfg(unix)]
        std::os::unix::fs::OpenOptionsExt::mode(&mut options, 0o600);
        let file = options
            .open(&path)
            .map_err(|e| HostError::Output(format!("{}: cannot hold {label} in a temporary file: {e}", path.display())))?;
        let shown = path.display().to_string();
        let path = if cfg!(unix) {
            let _ = std::fs::remove_file(&path);
            None
        } else {
            Some(path)
        };
        let mut spool = Spool { file, path };
        std::io::copy(&mut input, &mut spool.file)
            .map_err(|e| HostError::Input(format!("{label}: cannot read the stream (into {shown}): {e}")))?;
        Ok(spool)
    }

    /// The spooled stream from its start (the passes are sequential: each rewinds the one
    /// file offset its handles share).
    fn reader(&self) -> std::io::Result<std::fs::File> {
        use std::io::Seek;
        let mut f = self.file.try_clone()?;
        f.seek(std::io::SeekFrom::Start(0))?;
        Ok(f)
    }
}

impl Drop for Spool {
    fn drop(&mut self) {
        if let Some(path) = &self.path {
            let _ = std::fs::remove_file(path);
        }
    }
}

/// Fewest frames for [`check_match`] to judge a stream by.
pub const MATCH_MIN_FRAMES: u64 = 8;

/// A stream of at least this many bytes must decode a frame ([`check_match`]).
pub const NOT_A_STREAM_BYTES: u64 = 1024;

/// Whether the stream is the ELF's: with [`MATCH_MIN_FRAMES`] frames or more, at least half
/// must decode and fit their format's length exactly ([`fitted`]). A stream of another build
/// (its format indices naming other formats here) fails that; so does a stream damaged beyond
/// use. A stream of [`NOT_A_STREAM_BYTES`] or more of which no frame decodes fails too. The
/// error names both files.
pub fn check_match(label: &str, elf_label: &str, st: &StreamStats) -> Result<()> {
    // a stream of some size from which nothing decodes (a CSV, a text file, another program's
    // binary) is not an empty log: the rig's frames are a few tens of bytes
    if st.frames_decoded == 0 && st.bytes >= NOT_A_STREAM_BYTES {
        return Err(HostError::Input(format!(
            "{label}: no frame of the defmt table of {elf_label} decodes from its {} bytes ({} frames dropped, {} bytes of an \
             incomplete frame): not this firmware's defmt stream (a raw RTT capture or defmt-semihosting output)",
            st.bytes, st.frames_dropped, st.incomplete_bytes
        )));
    }
    let total = st.frames_decoded + st.frames_dropped;
    if total >= MATCH_MIN_FRAMES && st.frames_dropped * 2 > total {
        return Err(HostError::Input(format!(
            "{label}: {} of {total} frames do not fit the defmt table of {elf_label}: the stream is not from this \
             firmware build (give the ELF of the firmware that sent it) or is damaged beyond use",
            st.frames_dropped
        )));
    }
    Ok(())
}

/// A column of `--kind`'s CSV after `frame,timestamp_s`: a field by name, or element `i` of an
/// array field (`key_i`).
pub type KindColumn = (String, Option<usize>);

/// Appends the columns of `r` that `cols` lacks, in the order of `r`'s fields: over a kind's
/// records in stream order, the union of their fields in order of appearance (the lines of kind
/// `log` have different fields); an array field expands to key_0, key_1, ... Returns whether a
/// column was added.
pub fn extend_kind_columns(cols: &mut Vec<KindColumn>, r: &Record) -> bool {
    let before = cols.len();
    for (k, v) in &r.fields {
        let parts: Vec<Option<usize>> = match v {
            Value::Array(a) => (0..a.len()).map(Some).collect(),
            _ => vec![None],
        };
        for p in parts {
            if !cols.iter().any(|(c, q)| c == k && *q == p) {
                cols.push((k.clone(), p));
            }
        }
    }
    cols.len() > before
}

/// The header of `--kind`'s CSV: frame, timestamp_s, then the columns.
pub fn kind_header(cols: &[KindColumn]) -> Vec<String> {
    let mut head = vec!["frame".to_string(), "timestamp_s".to_string()];
    head.extend(cols.iter().map(|(c, p)| p.map_or(c.clone(), |i| format!("{c}_{i}"))));
    head
}

/// A record's row of `--kind`'s CSV under `cols` (empty where it has no such field).
pub fn kind_row(r: &Record, cols: &[KindColumn]) -> Vec<String> {
    let mut row = vec![r.frame.to_string(), r.timestamp_s.map_or(String::new(), |t| t.to_string())];
    row.extend(cols.iter().map(|(c, p)| match (r.field(c), p) {
        (Some(Value::Array(a)), Some(i)) => a.get(*i).map_or(String::new(), cell),
        (Some(v), None) => cell(v),
        _ => String::new(),
    }));
    row
}
