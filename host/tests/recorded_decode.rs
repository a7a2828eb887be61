//! `stickslip decode` on a defmt stream with known content: `tests/data/defmt-fixture.defmt`
//! was captured from `tests/data/defmt-fixture.elf` running under QEMU (defmt-semihosting);
//! the program (tests/data/defmt-fixture/src/main.rs) logs one record of every kind of the rig
//! firmware's log, through the firmware's own formatting, with fixed values, then one line that
//! is no record. The expected values below are written out here, not read from that program:
//! change both together. Framing facts used below are the rzCOBS rules (every frame ends with
//! 0x00; no frame holds a 0x00), checked on the bytes here, not taken from the decoder.

mod recorded_common;

use proptest::prelude::*;
use recorded_common::*;
use recorded_common::defmt_fixture::{fixture, frames, ELF, FRAMES, FRAME_KINDS, STREAM};
use serde_json::Value;
use stickslip::recorded::decode::{decode_stream, load_table, Record, StreamStats};

fn decode(elf: &[u8], bytes: &[u8]) -> (Vec<Record>, StreamStats) {
    let table = load_table("fixture.elf", elf).unwrap();
    let mut recs = Vec::new();
    let st = decode_stream(&table, bytes, |r| recs.push(r)).unwrap();
    (recs, st)
}

/// An expected field value.
#[derive(Clone, Copy, Debug)]
enum V {
    /// An integer.
    U(u64),
    /// An f32 parameter: a JSON number that reads back to this f32 exactly.
    F(f32),
    /// An f64 parameter: a JSON number equal to this.
    D(f64),
    S(&'static str),
    B(bool),
    /// An f32 array: a JSON array of numbers, each reading back to its f32 exactly.
    A(&'static [f32]),
}

fn check(what: &str, got: &Value, want: V) {
    match want {
        V::U(x) => assert_eq!(got.as_u64(), Some(x), "{what}: want the integer {x}, got {got}"),
        V::F(x) => {
            let g = got.as_f64().unwrap_or_else(|| panic!("{what}: want a number, got {got}"));
            assert_eq!(g as f32, x, "{what}: got {got}");
        }
        V::D(x) => assert_eq!(got.as_f64(), Some(x), "{what}: got {got}"),
        V::S(x) => assert_eq!(got.as_str(), Some(x), "{what}: got {got}"),
        V::B(x) => assert_eq!(got.as_bool(), Some(x), "{what}: got {got}"),
        V::A(xs) => {
            let a = got.as_array().unwrap_or_else(|| panic!("{what}: want a JSON array, got {got}"));
            assert_eq!(a.len(), xs.len(), "{what}: got {got}");
            for (j, (g, &x)) in a.iter().zip(xs).enumerate() {
                check(&format!("{what}[{j}]"), g, V::F(x));
            }
        }
    }
}

struct Expected {
    kind: &'static str,
    level: &'static str,
    fields: &'static [(&'static str, V)],
    message: &'static str,
}

/// What the fixture program logged, frame by frame.
const EXPECTED: [Expected; FRAMES] = [
    Expected {
        kind: "boot",
        level: "info",
        fields: &[
            ("fw", V::S("0.1.0-fixture")),
            ("schema", V::U(1)),
            ("reset", V::S("power_on")),
            ("sysclk_hz", V::U(168_000_000)),
            ("fs_hz", V::F(25_599.5)),
            ("timer_clocks", V::U(3281)),
            ("adc_channels", V::U(8)),
            ("window_samples", V::U(2560)),
            ("batch_frames", V::U(128)),
            ("pressure", V::B(true)),
            ("end_of_stroke", V::B(false)),
        ],
        message: "boot fw=0.1.0-fixture schema=1 reset=power_on sysclk_hz=168000000 fs_hz=25599.5 timer_clocks=3281 adc_channels=8 window_samples=2560 batch_frames=128 pressure=true end_of_stroke=false",
    },
    Expected {
        kind: "config_error",
        level: "error",
        fields: &[("field", V::S("beta_m")), ("rule", V::S("inside the pad")), ("value", V::D(-0.015625))],
        message: "config_error field=beta_m rule=inside the pad value=-0.015625",
    },
    Expected {
        kind: "armed",
        level: "info",
        fields: &[
            ("build_us", V::U(1234)),
            ("caliper", V::S("push")),
            ("beta", V::F(0.03125)),
            ("f_n", V::F(1500.5)),
            ("v", V::F(0.375)),
            ("n0", V::F(1498.25)),
        ],
        message: "armed build_us=1234 caliper=push beta=0.03125 f_n=1500.5 v=0.375 n0=1498.25",
    },
    Expected {
        kind: "start",
        level: "info",
        fields: &[("watchdog_us", V::U(250_000)), ("stack_used", V::U(3412)), ("stack_size", V::U(16_384))],
        message: "start watchdog_us=250000 stack_used=3412 stack_size=16384",
    },
    Expected {
        kind: "state",
        level: "info",
        fields: &[
            ("n", V::U(51_199)),
            ("rec", V::U(1)),
            ("from", V::S("record")),
            ("to", V::S("fault")),
            ("cause", V::S("accel_saturation")),
            ("valves", V::U(2)),
        ],
        message: "state n=51199 rec=1 from=record to=fault cause=accel_saturation valves=2",
    },
    Expected {
        kind: "command",
        level: "info",
        fields: &[
            ("n", V::U(12_800)),
            ("in", V::S("idle")),
            ("cmd", V::S("start")),
            ("result", V::S("accepted")),
            ("refused_by", V::S("none")),
        ],
        message: "command n=12800 in=idle cmd=start result=accepted refused_by=none",
    },
    Expected {
        kind: "command",
        level: "info",
        fields: &[
            ("n", V::U(51_300)),
            ("in", V::S("fault")),
            ("cmd", V::S("reset")),
            ("result", V::S("refused")),
            ("refused_by", V::S("estop")),
        ],
        message: "command n=51300 in=fault cmd=reset result=refused refused_by=estop",
    },
    Expected {
        kind: "event",
        level: "info",
        fields: &[
            ("n", V::U(51_200)),
            ("rec", V::U(1)),
            ("sample", V::U(25_600)),
            ("kind", V::S("stick_to_slip")),
            ("v_r", V::F(-0.0078125)),
            ("a_rel", V::F(-24.5)),
        ],
        message: "event n=51200 rec=1 sample=25600 kind=stick_to_slip v_r=-0.0078125 a_rel=-24.5",
    },
    Expected {
        kind: "window",
        level: "info",
        fields: &[
            ("n", V::U(53_760)),
            ("rec", V::U(1)),
            ("idx", V::U(20)),
            ("first", V::U(51_200)),
            ("samples", V::U(2560)),
            ("valid", V::U(2558)),
            ("pp", V::A(&[3.25, 80.5, 12.0, 150.75])),
            ("rms", V::A(&[0.5, 10.25, 2.5, 30.0])),
            ("groan_rms", V::A(&[0.125, 8.5, 2.0, 25.5])),
            ("stick", V::F(0.8125)),
            ("ss_hz", V::F(48.5)),
            ("onsets", V::U(5)),
            ("saturated", V::U(3)),
            ("faulted", V::U(2)),
            ("nonfinite", V::B(false)),
            ("model", V::B(true)),
            ("model_samples", V::U(2304)),
            ("model_stick", V::F(0.8046875)),
            ("model_ss_hz", V::F(48.75)),
            ("model_onsets", V::U(4)),
            ("residual_rms", V::F(1.5)),
            ("model_halt", V::S("contact_loss")),
            ("p_mean", V::A(&[5.0, 0.625])),
            ("p_min", V::A(&[4.875, 0.5625])),
            ("p_max", V::A(&[5.125, 0.6875])),
            ("state", V::S("record")),
            ("overruns", V::U(1)),
            ("events_dropped", V::U(7)),
            ("windows_dropped", V::U(2)),
            ("batch_cyc_max", V::U(41_000)),
            ("batch_cyc_budget", V::U(65_625)),
        ],
        message: "window n=53760 rec=1 idx=20 first=51200 samples=2560 valid=2558 pp=[3.25, 80.5, 12.0, 150.75] rms=[0.5, 10.25, 2.5, 30.0] groan_rms=[0.125, 8.5, 2.0, 25.5] stick=0.8125 ss_hz=48.5 onsets=5 saturated=3 faulted=2 nonfinite=false model=true model_samples=2304 model_stick=0.8046875 model_ss_hz=48.75 model_onsets=4 residual_rms=1.5 model_halt=contact_loss p_mean=[5.0, 0.625] p_min=[4.875, 0.5625] p_max=[5.125, 0.6875] state=record overruns=1 events_dropped=7 windows_dropped=2 batch_cyc_max=41000 batch_cyc_budget=65625",
    },
    Expected {
        kind: "overrun",
        level: "warn",
        fields: &[("n", V::U(60_000)), ("count", V::U(2))],
        message: "overrun n=60000 count=2",
    },
    Expected {
        kind: "stall",
        level: "error",
        fields: &[("n", V::U(60_128)), ("ms", V::U(12)), ("adc_ovr", V::B(true))],
        message: "stall n=60128 ms=12 adc_ovr=true",
    },
    Expected {
        kind: "input",
        level: "warn",
        fields: &[("name", V::S("estop")), ("active", V::B(true))],
        message: "input name=estop active=true",
    },
    Expected {
        kind: "panic",
        level: "error",
        fields: &[("file", V::S("src/main.rs")), ("line", V::U(42)), ("msg", V::S("explicit panic"))],
        message: "panic file=src/main.rs line=42 msg=explicit panic",
    },
    // no record: positional fields; a hex-formatted number stays as shown
    Expected {
        kind: "log",
        level: "warn",
        fields: &[("arg0", V::U(3)), ("arg1", V::S("0x28"))],
        message: "DMA: error on channel 3 (flags 0x28)",
    },
];

#[test]
fn the_fixture_decodes_to_the_values_it_logged() {
    let (elf, bytes) = fixture();
    let (recs, st) = decode(&elf, &bytes);
    let fr = frames(&bytes);
    assert_eq!(fr.len(), FRAMES, "the fixture holds {FRAMES} frames");
    assert_eq!((st.frames_decoded, st.frames_dropped, st.bytes_skipped, st.incomplete_bytes), (FRAMES as u64, 0, 0, 0));
    assert_eq!(st.bytes, bytes.len() as u64);
    assert_eq!(st.encoding, "rzcobs");
    let kinds: Vec<&str> = recs.iter().map(|r| r.kind.as_str()).collect();
    assert_eq!(kinds, FRAME_KINDS);
    for (i, (r, want)) in recs.iter().zip(&EXPECTED).enumerate() {
        assert_eq!(r.frame, i as u64);
        assert_eq!(r.offset as usize, fr[i].0, "frame {i}");
        // the fixture's timestamp counts 1000 us per frame, printed in seconds
        assert_eq!(r.timestamp.as_deref(), Some(format!("0.{:03}000", i).as_str()), "frame {i}");
        assert_eq!(r.timestamp_s, Some(i as f64 / 1000.0), "frame {i}");
        assert_eq!(r.kind, want.kind, "frame {i}");
        assert_eq!(r.level, Some(want.level), "frame {i} ({})", want.kind);
        assert_eq!(r.message, want.message, "frame {i}");
        // every field, by name and in the order logged
        let keys: Vec<&str> = r.fields.iter().map(|(k, _)| k.as_str()).collect();
        let want_keys: Vec<&str> = want.fields.iter().map(|(k, _)| *k).collect();
        assert_eq!(keys, want_keys, "frame {i} ({})", want.kind);
        for ((k, got), (_, v)) in r.fields.iter().zip(want.fields) {
            check(&format!("frame {i} ({}) {k}", want.kind), got, *v);
            assert_eq!(r.field(k), Some(got), "frame {i}: field() finds {k}");
        }
    }
    assert_eq!(recs[8].field("nope"), None);
}

#[test]
fn every_truncation_keeps_the_complete_frames() {
    let (elf, bytes) = fixture();
    for len in 0..=bytes.len() {
        let cut = &bytes[..len];
        let (recs, st) = decode(&elf, cut);
        let complete = frames(cut);
        assert_eq!(st.frames_decoded as usize, complete.len(), "cut at {len}");
        assert_eq!(st.frames_dropped, 0);
        // the non-zero bytes after the last zero
        let tail = cut.iter().rev().take_while(|&&b| b != 0).count();
        assert_eq!(st.incomplete_bytes as usize, tail, "cut at {len}");
        // the complete frames are the first ones of the whole stream, as they were
        let kinds: Vec<&str> = recs.iter().map(|r| r.kind.as_str()).collect();
        let want: Vec<&str> = EXPECTED[..complete.len()].iter().map(|e| e.kind).collect();
        assert_eq!(kinds, want, "cut at {len}");
        if let Some(last) = recs.last() {
            assert_eq!(last.frame as usize, complete.len() - 1);
            assert_eq!(last.message, EXPECTED[complete.len() - 1].message, "cut at {len}");
        }
    }
}

#[test]
fn a_corrupted_frame_is_dropped_and_counted() {
    let (elf, bytes) = fixture();
    let fr = frames(&bytes);
    // overwrite frame 4 (state) with 0xFF: an rzCOBS group byte 0xFF needs 134 bytes after
    // it, so the frame cannot decode
    let (o, n) = fr[4];
    assert!(n < 134, "frame 4 is {n} bytes");
    let mut bad = bytes.clone();
    bad[o..o + n].fill(0xFF);
    // and insert a short garbage frame between frames 7 (event) and 8 (window)
    let at = fr[8].0;
    bad.splice(at..at, [0xFF, 0xFF, 0xFF, 0x00]);
    let (recs, st) = decode(&elf, &bad);
    assert_eq!((st.frames_decoded, st.frames_dropped), (FRAMES as u64 - 1, 2));
    assert_eq!(st.bytes_skipped as usize, n + 3);
    assert_eq!(st.incomplete_bytes, 0);
    let numbers: Vec<u64> = recs.iter().map(|r| r.frame).collect();
    assert_eq!(numbers, [0, 1, 2, 3, 5, 6, 7, 9, 10, 11, 12, 13, 14]);
    let kinds: Vec<&str> = recs.iter().map(|r| r.kind.as_str()).collect();
    assert_eq!(
        kinds,
        [
            "boot",
            "config_error",
            "armed",
            "start",
            "command",
            "command",
            "event",
            "window",
            "overrun",
            "stall",
            "input",
            "panic",
            "log"
        ]
    );
    // the frames after the damage decode to what was logged
    assert_eq!(recs[4].field("result").unwrap(), "accepted");
    assert_eq!(recs[7].field("pp").unwrap(), &serde_json::json!([3.25, 80.5, 12.0, 150.75]));
    assert_eq!(recs[7].offset as usize, at + 4);
    assert_eq!(recs[11].field("msg").unwrap(), "explicit panic");
}

/// A window whose rms holds a NaN (the firmware's `nonfinite` flag is for that): the array keeps
/// its shape and its finite values, the NaN its text. Before, the whole array became one
/// string: the CSV's rms_0 .. rms_3 cells were empty for that window, a column `rms` was added at
/// the end, and `record`'s window.csv differed from `decode --kind window`.
/// `tests/data/defmt-window-nan.defmt` (366 bytes, 3 window records of the fixture's ELF, the
/// second with rms = [0.5, NaN, 2.5, 30.0], the others [0.5, 10.25, 2.5, 30.0]) was written by an
/// rzCOBS encoder written apart from this tool (Python, a campaign of 2026-11-28), from those
/// values.
#[test]
fn a_nan_in_an_array_keeps_the_array() {
    let stream = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/defmt-window-nan.defmt");
    let bytes = std::fs::read(stream).unwrap();
    assert_eq!(bytes.split(|&b| b == 0).filter(|f| !f.is_empty()).count(), 3, "three frames between 0x00 separators");
    let json: Value = serde_json::from_str(&ok(&["decode", "--elf", ELF, stream, "--json"])).unwrap();
    let records = json["records"].as_array().unwrap();
    assert_eq!(records.len(), 3);
    for (i, r) in records.iter().enumerate() {
        let rms = r["fields"]["rms"].as_array().unwrap_or_else(|| panic!("record {i}: rms is {}", r["fields"]["rms"]));
        assert_eq!(rms.len(), 4, "record {i}");
        assert_eq!((rms[0].as_f64(), rms[2].as_f64(), rms[3].as_f64()), (Some(0.5), Some(2.5), Some(30.0)), "record {i}");
        if i == 1 {
            assert_eq!(rms[1], "NaN");
        } else {
            assert_eq!(rms[1].as_f64(), Some(10.25), "record {i}");
        }
    }
    let csv = ok(&["decode", "--elf", ELF, stream, "--kind", "window"]);
    let lines: Vec<&str> = csv.lines().collect();
    let head: Vec<&str> = lines[0].split(',').collect();
    assert!(!head.contains(&"rms"), "a column `rms` beside rms_0 .. rms_3: {}", lines[0]);
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}"));
    let cells: Vec<Vec<&str>> = lines[1..].iter().map(|l| l.split(',').collect()).collect();
    assert_eq!(cells.len(), 3);
    assert_eq!((cells[1][col("rms_0")], cells[1][col("rms_1")], cells[1][col("rms_3")]), ("0.5", "NaN", "30.0"));
    // `record` writes the same window.csv
    let dir = scratch("decode-window-nan");
    let out = dir.join("rec");
    let o = stickslip(&["record", "--elf", ELF, "--input", stream, "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(out.join("window.csv")).unwrap(), csv);
}

/// Frames lost whole at their separators (an RTT overflow that drops complete frames) leave no
/// trace in the framing, but the window records' index does: a window removed from the middle
/// of tests/data/defmt-window-nan.defmt (windows idx 0, 1, 2 of one recording) is reported
/// missing; the stream as it is reports none.
#[test]
fn windows_lost_whole_are_reported() {
    let stream = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/defmt-window-nan.defmt");
    let bytes = std::fs::read(stream).unwrap();
    let whole = stderr(&stickslip(&["decode", "--elf", ELF, stream]));
    assert!(!whole.contains("missing"), "{whole}");
    // the frames with their separators; the second one left out
    let mut frames: Vec<Vec<u8>> = Vec::new();
    let mut cur = Vec::new();
    for &b in &bytes {
        cur.push(b);
        if b == 0 {
            frames.push(std::mem::take(&mut cur));
        }
    }
    let nonempty: Vec<usize> = (0..frames.len()).filter(|&i| frames[i].len() > 1).collect();
    assert_eq!(nonempty.len(), 3);
    let cut: Vec<u8> = frames.iter().enumerate().filter(|(i, _)| *i != nonempty[1]).flat_map(|(_, f)| f.clone()).collect();
    let dir = scratch("decode-window-gap");
    let path = write(&dir, "gap.defmt", &cut);
    let o = stickslip(&["decode", "--elf", ELF, &path]);
    assert!(o.status.success());
    let e = stderr(&o);
    assert!(e.contains("dropped 0 frames") && e.contains("1 window record missing"), "{e}");
}

/// Standard input, and a pipe named as a file, are decoded as the file is (spooled to a
/// temporary file for the two passes that keep memory bounded: counts, then the records
/// written as they decode), in every output form, and the temporary file is gone afterwards.
#[test]
fn standard_input_decodes_as_the_file() {
    use std::io::Write as _;
    // `-`, and a pipe named as a file (/dev/stdin on a pipe; `<(...)` is the same): read once,
    // not twice (the second read found the pipe empty: the CSV's header alone, exit 0)
    let inputs: &[&str] = if cfg!(target_os = "linux") { &["-", "/dev/stdin"] } else { &["-"] };
    for (mode, input) in [&[][..], &["--json"][..], &["--kind", "window"][..]].into_iter().flat_map(|m| inputs.iter().map(move |i| (m, *i))) {
        let mut args = vec!["decode", "--elf", ELF, STREAM];
        args.extend_from_slice(mode);
        let from_file = ok(&args);
        args[3] = input;
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_stickslip"))
            .args(&args)
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let id = child.id();
        child.stdin.take().unwrap().write_all(&std::fs::read(STREAM).unwrap()).unwrap();
        let o = child.wait_with_output().unwrap();
        assert!(o.status.success(), "{mode:?} {input}: {}", String::from_utf8_lossy(&o.stderr));
        assert_eq!(String::from_utf8(o.stdout).unwrap(), from_file, "{mode:?} {input}");
        let left = spooled_by(id);
        assert!(left.is_empty(), "temporary files left: {left:?}");
    }
}

/// A decode killed while it spools standard input (Ctrl-C, a kill) leaves nothing in the
/// temporary directory: the spool's name is removed as it is created, the open file still
/// holds the stream (seen in /proc as "(deleted)"), and the system frees it with the process.
#[cfg(target_os = "linux")]
#[test]
fn a_killed_decode_leaves_no_temporary_file() {
    use std::io::Write as _;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_stickslip"))
        .args(["decode", "--elf", ELF, "-"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let id = child.id();
    let mut stdin = child.stdin.take().unwrap();
    stdin.write_all(&std::fs::read(STREAM).unwrap()).unwrap();
    stdin.flush().unwrap();
    // the stream is spooling (standard input still open): wait for the spool's handle
    let spool_open = || {
        std::fs::read_dir(format!("/proc/{id}/fd")).into_iter().flatten().filter_map(|e| e.ok()).any(|e| {
            std::fs::read_link(e.path()).is_ok_and(|t| t.to_string_lossy().contains(&format!("stickslip-decode-{id}-")))
        })
    };
    let t0 = std::time::Instant::now();
    while !spool_open() && t0.elapsed() < std::time::Duration::from_secs(20) {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert!(spool_open(), "decode holds no spool of its standard input");
    let named = spooled_by(id);
    child.kill().unwrap();
    child.wait().unwrap();
    drop(stdin);
    assert!(named.is_empty(), "the spool has a name while decode runs: {named:?}");
    let left = spooled_by(id);
    assert!(left.is_empty(), "temporary files left by a killed decode: {left:?}");
}

/// The temporary files the `decode` of process `pid` spooled standard input to (none must
/// outlive it).
fn spooled_by(pid: u32) -> Vec<String> {
    let prefix = format!("stickslip-decode-{pid}-");
    std::fs::read_dir(std::env::temp_dir())
        .map(|d| d.filter_map(|e| e.ok()).map(|e| e.file_name().to_string_lossy().into_owned()).filter(|n| n.starts_with(&prefix)).collect())
        .unwrap_or_default()
}

#[test]
fn the_command_line() {
    let text = ok(&["decode", "--elf", ELF, STREAM, "--json"]);
    let json: Value = serde_json::from_str(&text).unwrap();
    let records = json["records"].as_array().unwrap();
    assert_eq!(records.len(), FRAMES);
    for k in ["encoding", "bytes", "frames_decoded", "frames_dropped", "bytes_skipped", "incomplete_bytes"] {
        assert!(json["stream"].get(k).is_some(), "stream.{k}");
    }
    assert_eq!(json["stream"]["encoding"], "rzcobs");
    assert_eq!(json["stream"]["frames_decoded"], FRAMES as u64);
    let stream_len = std::fs::metadata(STREAM).unwrap().len();
    assert_eq!(json["stream"]["bytes"], stream_len);
    // the window record: every key, in order, arrays as JSON arrays
    let w = &records[8];
    assert_eq!((w["frame"].as_u64(), w["kind"].as_str(), w["level"].as_str()), (Some(8), Some("window"), Some("info")));
    assert_eq!(w["timestamp"], "0.008000");
    assert_eq!(w["timestamp_s"].as_f64(), Some(0.008));
    let keys: Vec<&str> = w["fields"].as_object().unwrap().keys().map(|k| k.as_str()).collect();
    assert_eq!(keys.len(), EXPECTED[8].fields.len());
    // in the text, the keys come in the logged order (serde_json's map here sorts them)
    let start = text.find("\"kind\": \"window\"").expect("the window record");
    let end = text.find("\"kind\": \"overrun\"").expect("the overrun record");
    let window_text = &text[start..end];
    let mut at = 0;
    for (k, _) in EXPECTED[8].fields {
        let next =
            window_text[at..].find(&format!("\"{k}\": ")).unwrap_or_else(|| panic!("{k} after the previous key"));
        at += next + 1;
    }
    assert_eq!(w["fields"]["pp"], serde_json::json!([3.25, 80.5, 12.0, 150.75]));
    assert_eq!(w["fields"]["p_min"], serde_json::json!([4.875, 0.5625]));
    assert_eq!(w["fields"]["model_halt"], "contact_loss");
    assert_eq!(records[6]["fields"]["refused_by"], "estop");

    let csv = ok(&["decode", "--elf", ELF, STREAM]);
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "frame,offset,timestamp_s,level,kind,message");
    assert_eq!(lines.len(), FRAMES + 1);
    let fr = frames(&std::fs::read(STREAM).unwrap());
    assert_eq!(
        lines[5],
        format!(
            "4,{},0.004,info,state,state n=51199 rec=1 from=record to=fault cause=accel_saturation valves=2",
            fr[4].0
        )
    );
    assert_eq!(
        lines[13],
        format!("12,{},0.012,error,panic,panic file=src/main.rs line=42 msg=explicit panic", fr[12].0)
    );
    // a message with commas is quoted
    assert!(lines[9].starts_with(&format!("8,{},0.008,info,window,\"window n=53760 ", fr[8].0)), "{}", lines[9]);

    let cmd = ok(&["decode", "--elf", ELF, STREAM, "--kind", "command"]);
    let cl: Vec<&str> = cmd.lines().collect();
    assert_eq!(
        cl,
        [
            "frame,timestamp_s,n,in,cmd,result,refused_by",
            "5,0.005,12800,idle,start,accepted,none",
            "6,0.006,51300,fault,reset,refused,estop"
        ]
    );
    let win = ok(&["decode", "--elf", ELF, STREAM, "--kind", "window"]);
    let wl: Vec<&str> = win.lines().collect();
    assert_eq!(wl.len(), 2);
    assert_eq!(
        wl[0],
        "frame,timestamp_s,n,rec,idx,first,samples,valid,pp_0,pp_1,pp_2,pp_3,rms_0,rms_1,rms_2,rms_3,\
         groan_rms_0,groan_rms_1,groan_rms_2,groan_rms_3,stick,ss_hz,onsets,saturated,faulted,nonfinite,model,\
         model_samples,model_stick,model_ss_hz,model_onsets,residual_rms,model_halt,p_mean_0,p_mean_1,\
         p_min_0,p_min_1,p_max_0,p_max_1,state,overruns,events_dropped,windows_dropped,batch_cyc_max,batch_cyc_budget"
    );
    assert_eq!(
        wl[1],
        "8,0.008,53760,1,20,51200,2560,2558,3.25,80.5,12.0,150.75,0.5,10.25,2.5,30.0,0.125,8.5,2.0,25.5,\
         0.8125,48.5,5,3,2,false,true,2304,0.8046875,48.75,4,1.5,contact_loss,5.0,0.625,4.875,0.5625,5.125,0.6875,\
         record,1,7,2,41000,65625"
    );
    let log = ok(&["decode", "--elf", ELF, STREAM, "--kind", "log"]);
    assert_eq!(log, "frame,timestamp_s,arg0,arg1\n13,0.013,3,0x28\n");
    // the counts go to stderr, one line
    let o = stickslip(&["decode", "--elf", ELF, STREAM]);
    assert_eq!(
        stderr(&o).trim_end(),
        format!(
            "stickslip: {STREAM}: decoded {FRAMES} frames from {stream_len} bytes; dropped 0 frames (0 bytes skipped); \
             0 bytes of an incomplete frame at the end"
        )
    );
    // bad input
    bad(&["decode", "--elf", STREAM, STREAM], &["not a usable firmware ELF"]);
    bad(&["decode", "--elf", "/nonexistent.elf", STREAM], &["/nonexistent.elf", "cannot read"]);
    bad(&["decode", "--elf", ELF, "/nonexistent.defmt"], &["/nonexistent.defmt", "cannot open"]);
    // a CSV given as the stream: no zero byte, so no frame; not an empty log
    let dir = scratch("decode-not-a-stream");
    let csv_text: String = std::iter::once("t,pad_x\n".to_string()).chain((0..200).map(|i| format!("{},{}\n", i as f64 / 25600.0, i % 7))).collect();
    assert!(csv_text.len() >= 1024);
    let f = write(&dir, "recording.csv", &csv_text);
    bad(&["decode", "--elf", ELF, &f], &["recording.csv", "no frame", "not this firmware's defmt stream"]);
    // a short one (a capture cut before its first frame ended) still decodes to nothing
    let short = write(&dir, "short.defmt", "abc");
    ok(&["decode", "--elf", ELF, &short]);
    bad(
        &["decode", "--elf", ELF, STREAM, "--kind", "transition"],
        &[
            "--kind transition",
            "no record",
            "armed, boot, command, config_error, event, input, log, overrun, panic, stall, start, state, window",
        ],
    );
}

fn cases() -> u32 {
    std::env::var("STICKSLIP_FUZZ_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(256)
}

/// Decoding never panics, and the counts add up: every zero-terminated run is a frame, decoded
/// or dropped; skipped and incomplete bytes are at most the stream.
fn consistent(elf: &[u8], bytes: &[u8]) {
    let (recs, st) = decode(elf, bytes);
    assert_eq!(st.bytes as usize, bytes.len());
    assert_eq!((st.frames_decoded + st.frames_dropped) as usize, frames(bytes).len());
    assert_eq!(recs.len() as u64, st.frames_decoded);
    assert!(st.bytes_skipped + st.incomplete_bytes <= st.bytes);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let (elf, _) = fixture();
        consistent(&elf, &bytes);
    }

    #[test]
    fn mutated_streams_never_panic(edits in prop::collection::vec((any::<usize>(), any::<u8>(), 0u8..3), 1..8)) {
        let (elf, mut bytes) = fixture();
        for (i, b, op) in edits {
            let i = i % (bytes.len() + 1);
            match op {
                0 if i < bytes.len() => bytes[i] = b,
                1 => bytes.insert(i, b),
                _ => bytes.truncate(i.max(1)),
            }
        }
        consistent(&elf, &bytes);
    }
}
