//! `stickslip record --input`: the pipeline the probe feeds, on the shipped defmt fixture
//! (`tests/data/defmt-fixture.{elf,defmt}`, one record of every kind: see recorded_decode.rs)
//! and on streams made from it (repeated, corrupted, cut mid-frame, fed slowly through a pipe
//! and stopped by SIGINT). What it must write is what `stickslip decode` prints for the same
//! bytes: the raw file byte for byte equal to the input, each KIND.csv equal to `decode --kind
//! KIND`, the summary's stream line equal to decode's counts. The frame layout used to build
//! the damaged streams is the rzCOBS rule (each frame ends with 0x00), read off the bytes here;
//! the counts they must give are worked out here from that construction, not read from the
//! decoder. The on-target session's stream, produced under QEMU and fed as it is produced, is
//! `tests/tests/records_on_target.rs` (stage 5 of scripts/test-all.sh).

mod recorded_common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use recorded_common::*;
use recorded_common::defmt_fixture::{frames, kinds as fixture_kinds, ELF, FRAMES, STREAM};

/// The fixture's frame 4 (a state record) and 8 (the window record).
const STATE_FRAME: usize = 4;
const WINDOW_FRAME: usize = 8;

/// Hang guard of the waits below (a run takes well under a second): not a timing assertion,
/// a recorder that never catches up fails instead of blocking the test run.
const HANG_GUARD: Duration = Duration::from_secs(120);

fn csv_files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".csv"))
        .collect();
    v.sort();
    v
}

/// decode's counts line for `stream` (its stderr, after the file's label).
fn decode_counts(stream: &str) -> String {
    let o = stickslip(&["decode", "--elf", ELF, stream]);
    assert_eq!(o.status.code(), Some(0), "decode {stream}: {}", stderr(&o));
    let err = stderr(&o);
    let line = err.trim_end();
    line.strip_prefix(&format!("stickslip: {stream}: ")).unwrap_or_else(|| panic!("decode's stderr: {line}")).to_string()
}

/// The kinds decode finds in `stream` (its CSV's kind column), first appearance order.
fn decode_kinds(stream: &str) -> Vec<String> {
    let csv = ok(&["decode", "--elf", ELF, stream]);
    let mut rd = csv::Reader::from_reader(csv.as_bytes());
    let mut kinds: Vec<String> = Vec::new();
    for r in rd.records() {
        let k = r.unwrap()[4].to_string();
        if !kinds.contains(&k) {
            kinds.push(k);
        }
    }
    kinds
}

/// What `record` wrote in `dir` is what decode makes of `input`: the raw file is `input`'s
/// bytes, one CSV per kind decode finds and nothing else, each equal to `decode --kind`'s; the
/// summary on `stdout` carries decode's counts. Returns the kinds.
fn assert_as_decode(dir: &Path, input: &[u8], stdout: &str) -> Vec<String> {
    let raw_path = dir.join("raw.defmt");
    let raw = std::fs::read(&raw_path).unwrap();
    assert!(raw == input, "raw.defmt ({} bytes) is not the input ({} bytes)", raw.len(), input.len());
    let raw_s = raw_path.to_str().unwrap();
    let kinds = decode_kinds(raw_s);
    let mut want: Vec<String> = kinds.iter().map(|k| format!("{k}.csv")).collect();
    want.sort();
    assert_eq!(csv_files(dir), want, "the CSV files in {}", dir.display());
    for k in &kinds {
        let ours = std::fs::read_to_string(dir.join(format!("{k}.csv"))).unwrap();
        let theirs = ok(&["decode", "--elf", ELF, raw_s, "--kind", k]);
        assert_eq!(ours, theirs, "{k}.csv against decode --kind {k}");
    }
    let counts = decode_counts(raw_s);
    assert!(stdout.contains(&format!("stream: {counts}\n")), "decode's counts `{counts}` not in the summary:\n{stdout}");
    kinds
}

fn run_record(dir: &Path, input: &str) -> (String, String) {
    let o = stickslip(&["record", "--elf", ELF, "--input", input, "--out", dir.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "record --input {input}: {}", stderr(&o));
    (String::from_utf8(o.stdout.clone()).unwrap(), stderr(&o))
}

#[test]
fn the_fixture_is_recorded_as_decode_reads_it() {
    let dir = scratch("record-fixture");
    let out = dir.join("rec");
    let (stdout, err) = run_record(&out, STREAM);
    let input = std::fs::read(STREAM).unwrap();
    let kinds = assert_as_decode(&out, &input, &stdout);
    assert_eq!(kinds, fixture_kinds(), "every kind of the fixture, in order");
    assert!(stdout.starts_with("record: the input ended\n"), "{stdout}");
    // decode's counts, worked out from the fixture: 14 frames, nothing lost
    assert!(
        stdout.contains(&format!(
            "stream: decoded {FRAMES} frames from {} bytes; dropped 0 frames (0 bytes skipped); 0 bytes of an incomplete frame at the end\n",
            input.len()
        )),
        "{stdout}"
    );
    // the window record's values as the fixture logged them (recorded_decode.rs): stick 0.8125,
    // ss_hz 48.5, pad_x p-p 80.5; the valves of the state record before it: 2, the band's
    let w = std::fs::read_to_string(out.join("window.csv")).unwrap();
    let mut rd = csv::Reader::from_reader(w.as_bytes());
    let head = rd.headers().unwrap().clone();
    let row = rd.records().next().unwrap().unwrap();
    let cell = |k: &str| row[head.iter().position(|h| h == k).unwrap_or_else(|| panic!("column {k}"))].to_string();
    assert_eq!((cell("frame"), cell("stick"), cell("ss_hz"), cell("pp_1")), ("8".into(), "0.8125".into(), "48.5".into(), "80.5".into()));
    // stderr: the start line, the state line, the window's status line, the warn/error lines
    let window_lines: Vec<&str> = err.lines().filter(|l| l.contains(" window ")).collect();
    assert_eq!(window_lines.len(), 1, "{err}");
    assert_eq!(
        window_lines[0],
        "t 0.008 s  rec 1 window 20: stick 0.8125, stick-slip 48.50 Hz, pad_x 80.50 m/s^2 p-p, valves band open (record), 0 frames dropped"
    );
    assert!(err.contains("t 0.004 s  state n=51199 rec=1 from=record to=fault cause=accel_saturation valves=2\n"), "{err}");
    assert!(err.contains("t 0.012 s  panic file=src/main.rs line=42 msg=explicit panic\n"), "{err}");
    // the firmware's own counts of what it did not log: the window record's events_dropped 7,
    // windows_dropped 2, overruns 1
    assert!(stdout.contains("firmware: 1 window record: 7 event records and 2 windows not logged"), "{stdout}");
    assert!(stdout.contains("1 overrun since boot"), "{stdout}");
    // the CSVs are listed with their rows
    let window_csv = out.join("window.csv");
    assert!(stdout.lines().any(|l| l.split_whitespace().collect::<Vec<_>>() == ["window", "1", window_csv.to_str().unwrap()]), "{stdout}");
}

/// Three copies of the fixture: frame 4 of the second overwritten with 0xFF (an rzCOBS group
/// byte that needs 134 bytes after it: it cannot decode), a garbage frame `FF FF FF 00`
/// before the second copy's window frame, and the stream cut `cut_back` bytes before the end
/// of the third copy's window frame. Returns the stream, the length of the state frame and the
/// incomplete tail's length.
fn damaged(cut_back: usize) -> (Vec<u8>, usize, usize) {
    let one = std::fs::read(STREAM).unwrap();
    let fr = frames(&one);
    let (so, sn) = fr[STATE_FRAME];
    assert!(sn < 134);
    let mut second = one.clone();
    second[so..so + sn].fill(0xFF);
    second.splice(fr[WINDOW_FRAME].0..fr[WINDOW_FRAME].0, [0xFF, 0xFF, 0xFF, 0x00]);
    let (wo, wn) = fr[WINDOW_FRAME];
    assert!(cut_back >= 1 && cut_back < wn);
    let third = &one[..wo + wn - cut_back];
    let s = [one.as_slice(), &second, third].concat();
    (s, sn, wn - cut_back)
}

#[test]
fn a_corrupted_and_cut_stream_is_recorded_with_decode_s_loss_counts() {
    let dir = scratch("record-damaged");
    for cut_back in [1, 40] {
        let (stream, state_len, tail) = damaged(cut_back);
        let input = write(&dir, &format!("damaged-{cut_back}.defmt"), &stream);
        let out = dir.join(format!("rec-{cut_back}"));
        let (stdout, err) = run_record(&out, &input);
        assert_as_decode(&out, &stream, &stdout);
        // worked out from the construction: copy 1 whole (14), copy 2 without its state frame
        // (13) and the garbage frame dropped (2 dropped, the state frame's bytes and 3 skipped),
        // copy 3's frames before its window (8), the window's first bytes incomplete
        let decoded = FRAMES + (FRAMES - 1) + WINDOW_FRAME;
        assert!(
            stdout.contains(&format!(
                "stream: decoded {decoded} frames from {} bytes; dropped 2 frames ({} bytes skipped); {tail} bytes of an incomplete frame at the end\n",
                stream.len(),
                state_len + 3
            )),
            "{stdout}"
        );
        // a status line per decoded window, with the frames dropped before it
        let dropped: Vec<&str> =
            err.lines().filter(|l| l.contains(" window ")).map(|l| l.rsplit(", ").next().unwrap()).collect();
        assert_eq!(dropped, ["0 frames dropped", "2 frames dropped"], "{err}");
        assert_eq!(std::fs::read_to_string(out.join("window.csv")).unwrap().lines().count(), 3);
    }
}

#[test]
fn sigint_during_a_slow_pipe_leaves_complete_files_and_a_summary() {
    let dir = scratch("record-sigint");
    let one = std::fs::read(STREAM).unwrap();
    let fr = frames(&one);
    // the writer: a child process writing the fixture twice in pieces (every frame in two
    // parts, the second copy's first frame only half), with pauses between, then holding
    // the pipe open
    let mut pieces: Vec<Vec<u8>> = Vec::new();
    let mut at = 0;
    for &(o, n) in &fr {
        pieces.push(one[at..o + n / 2].to_vec());
        pieces.push(one[o + n / 2..o + n + 1].to_vec());
        at = o + n + 1;
    }
    pieces.push(one[at..].to_vec());
    let (o0, n0) = fr[0];
    pieces.push(one[..o0 + n0 / 2].to_vec());
    let sent: Vec<u8> = pieces.concat();
    let mut files = Vec::new();
    for (i, p) in pieces.iter().enumerate() {
        files.push(write(&dir, &format!("piece-{i:03}"), p));
    }
    let mut writer = Command::new("sh")
        .arg("-c")
        .arg("for f in \"$@\"; do cat \"$f\"; sleep 0.02; done; exec sleep 600")
        .arg("sh")
        .args(&files)
        .stdout(Stdio::piped())
        .spawn()
        .expect("sh runs");
    let out = dir.join("rec");
    let mut rec = Command::new(env!("CARGO_BIN_EXE_stickslip"))
        .args(["record", "--elf", ELF, "--input", "-", "--out", out.to_str().unwrap()])
        .stdin(Stdio::from(writer.stdout.take().unwrap()))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("stickslip runs");
    // wait until everything sent is in the raw file (then it has been decoded too)
    let raw = out.join("raw.defmt");
    let started = Instant::now();
    while std::fs::metadata(&raw).map_or(0, |m| m.len()) < sent.len() as u64 {
        assert!(started.elapsed() < HANG_GUARD, "record did not take the {} bytes sent", sent.len());
        assert!(rec.try_wait().unwrap().is_none(), "record ended before the SIGINT");
        std::thread::sleep(Duration::from_millis(20));
    }
    let status = Command::new("kill").args(["-INT", &rec.id().to_string()]).status().expect("kill runs");
    assert!(status.success());
    let started = Instant::now();
    let code = loop {
        if let Some(s) = rec.try_wait().unwrap() {
            break s.code();
        }
        if started.elapsed() > HANG_GUARD {
            let _ = rec.kill();
            let _ = writer.kill();
            panic!("record did not stop on SIGINT");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    // the writer still holds the pipe open: the end was the SIGINT's
    assert!(writer.try_wait().unwrap().is_none(), "the writer ended first");
    let _ = writer.kill();
    let _ = writer.wait();
    let o = rec.wait_with_output().unwrap();
    let stdout = String::from_utf8(o.stdout).unwrap();
    assert_eq!(code, Some(0), "stderr: {}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout.starts_with("record: stopped by Ctrl-C\n"), "{stdout}");
    assert_as_decode(&out, &sent, &stdout);
    assert!(
        stdout.contains(&format!(
            "stream: decoded {FRAMES} frames from {} bytes; dropped 0 frames (0 bytes skipped); {} bytes of an incomplete frame at the end\n",
            sent.len(),
            n0 / 2
        )),
        "{stdout}"
    );
}

/// The probe path's end without a probe: a source that sends part of the stream and then
/// reports its connection lost (what the probe's poll thread sends on a USB error). The files
/// hold everything received, the recording says why it stopped, and decode's counts of the
/// received bytes (the frame in flight incomplete).
#[test]
fn a_lost_connection_keeps_what_was_received() {
    use stickslip::recorded::decode::load_table;
    use stickslip::recorded::live::source::{Chunk, End, Stop};
    use stickslip::recorded::live::{create_output, record_chunks};

    let dir = scratch("record-lost");
    let one = std::fs::read(STREAM).unwrap();
    let fr = frames(&one);
    // up to the middle of the window frame, in chunks of 7 bytes
    let (wo, wn) = fr[WINDOW_FRAME];
    let sent = one[..wo + wn / 2].to_vec();
    let (tx, rx) = std::sync::mpsc::sync_channel(4);
    let stop = Stop::new(tx.clone());
    let chunks: Vec<Vec<u8>> = sent.chunks(7).map(<[u8]>::to_vec).collect();
    let source = std::thread::spawn(move || {
        for c in chunks {
            tx.send(Chunk::Data(c)).unwrap();
        }
        tx.send(Chunk::End(End::Lost("USB device gone".into()))).unwrap();
    });
    let table = load_table("fixture", &std::fs::read(ELF).unwrap()).unwrap();
    let out = dir.join("rec");
    let mut status = Vec::new();
    let rec = record_chunks(&table, rx, &stop, create_output(Some(&out), None).unwrap(), false, &mut status);
    source.join().unwrap();
    assert_eq!(rec.end, End::Lost("USB device gone".into()));
    let summary = rec.summary();
    assert!(summary.starts_with("record: the probe connection was lost: USB device gone\n"), "{summary}");
    assert_as_decode(&out, &sent, &summary);
    // the frames before the window, the window's first half incomplete
    assert_eq!((rec.stats.frames_decoded, rec.stats.frames_dropped, rec.stats.incomplete_bytes), (WINDOW_FRAME as u64, 0, (wn / 2) as u64));
    assert_eq!(rec.kinds.iter().map(|k| k.rows).sum::<u64>(), WINDOW_FRAME as u64);
}

#[test]
fn bad_input_is_one_line_and_exit_2() {
    let dir = scratch("record-bad");
    let d = |n: &str| dir.join(n).to_str().unwrap().to_string();
    // a folder that is not empty, a raw file that exists
    std::fs::create_dir_all(dir.join("full")).unwrap();
    write(&dir.join("full"), "notes.txt", "x");
    bad(&["record", "--elf", ELF, "--input", STREAM, "--out", &d("full")], &["--out", "not empty", "notes.txt"]);
    write(&dir, "old.defmt", "x");
    bad(
        &["record", "--elf", ELF, "--input", STREAM, "--out", &d("new1"), "--raw", &d("old.defmt")],
        &["--raw", "old.defmt", "exists"],
    );
    assert!(!dir.join("new1").exists(), "no folder for a refused --raw");
    // an input that does not open, an ELF without defmt data
    bad(&["record", "--elf", ELF, "--input", &d("nope.defmt"), "--out", &d("new2")], &["nope.defmt", "cannot open"]);
    assert!(!dir.join("new2").exists(), "no folder for an input that does not open");
    // a folder as the input opens on Unix; it is refused before the output folder is made
    bad(&["record", "--elf", ELF, "--input", dir.to_str().unwrap(), "--out", &d("new4")], &["a folder, not a stream"]);
    assert!(!dir.join("new4").exists(), "no folder for a folder as the input");
    bad(&["record", "--elf", STREAM, "--input", STREAM, "--out", &d("new3")], &["not a usable firmware ELF"]);
    bad(&["record", "--elf", ELF, "--input", STREAM, "--probe", "0483:374b"], &["--probe", "--input"]);
}

/// The probe path here, where no probe is attached (this machine): one line, exit 2, no folder.
/// Without the feature `probe` the same command says the tool was built without it.
#[test]
fn no_probe_is_one_line_and_exit_2() {
    let dir = scratch("record-no-probe");
    let o = Command::new(env!("CARGO_BIN_EXE_stickslip"))
        .args(["record", "--elf", ELF])
        .current_dir(&dir)
        .output()
        .unwrap();
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    let want = if cfg!(feature = "probe") { "no debug probe found" } else { "cargo feature `probe`" };
    assert!(err.starts_with("error: ") && err.contains(want), "{err}");
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "no folder is made");
    if cfg!(feature = "probe") {
        // --flash must be the --elf file (checked before the probe is looked for)
        bad(&["record", "--elf", ELF, "--flash", STREAM], &["--flash", "not the same file as --elf"]);
        bad(&["record", "--elf", ELF, "--probe", "zz:1"], &["--probe zz:1", "VID:PID"]);
    }
}

#[test]
fn the_default_folder_is_named_by_the_start_time() {
    let dir = scratch("record-default-dir");
    let o = Command::new(env!("CARGO_BIN_EXE_stickslip"))
        .args(["record", "--elf", ELF, "--input", STREAM])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let made: Vec<PathBuf> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(made.len(), 1, "{made:?}");
    let name = made[0].file_name().unwrap().to_str().unwrap().to_string();
    // rig-YYYYMMDDTHHMMSSZ
    let stamp = name.strip_prefix("rig-").unwrap_or_else(|| panic!("{name}"));
    assert_eq!(stamp.len(), 16, "{name}");
    assert!(stamp[..8].bytes().all(|b| b.is_ascii_digit()) && &stamp[8..9] == "T" && stamp.ends_with('Z'), "{name}");
    assert!(made[0].join("raw.defmt").is_file() && made[0].join("window.csv").is_file());
    let stdout = String::from_utf8(o.stdout).unwrap();
    assert!(stdout.contains(&format!("folder: {name}\n")), "{stdout}");
}
