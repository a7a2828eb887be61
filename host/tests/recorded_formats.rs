//! Recordings as rigs write them (issue 32, and issue 33's recording checks):
//! - the same samples as CSV, UFF 58 ASCII, 58b double, 58b single (files written by pyuff and
//!   from the published layout, read back by pyuff: `host/tests/data/recordings/make.py`) and
//!   WAV (Python's `wave`) give the same statistics, to the precision each stores;
//! - a logger's CSV (`Time [s]`, `Acc1 [g]` ... in another order) read with `--channel` gives
//!   the statistics of the same data under the rig's names;
//! - a pad_x-only recording gives the stick fraction and frequency; none without pad_x;
//! - a recording that starts inside the stick-slip cycle, at Table 3.1's levels, Coulomb and
//!   Stribeck, 0.005 and 0.02 m/s^2 of noise: `analyze FILE` with no flag gets the stick
//!   fraction within 0.02 and the frequency within 1 % of the model's own (the virtual rig's
//!   truth: its regime per sample and its exact transition times, never the estimator's);
//! - the time axis at full precision: a drop after a `0.0`, a gap of 1.5 intervals, `--gaps
//!   split`; a constant signal's groan-band RMS is 0; `compare` and `fit` apply the health
//!   verdict.
//!
//! The fixture's truth by construction (make.py): 100 Hz cycles with 40 % stick.

mod recorded_common;

use recorded_common::*;
use serde_json::Value;

fn data(name: &str) -> String {
    format!("{}/tests/data/recordings/{name}", env!("CARGO_MANIFEST_DIR"))
}

const WAV_MAP: [&str; 8] =
    ["--channel", "pad_x=#1*8", "--channel", "pad_trail=#2*8", "--channel", "disc_x=#3*8", "--channel", "pad_lead=#4*8"];

fn stats(v: &Value) -> Vec<(String, f64)> {
    let mut out = vec![];
    for ch in CHANNELS {
        for q in ["pp", "rms", "groan_rms", "mean"] {
            out.push((format!("{ch}.{q}"), num(v, &["channels", ch, q])));
        }
        out.push((format!("{ch}.peak_hz"), num(v, &["channels", ch, "peak_hz"])));
    }
    out.push(("stick_fraction".into(), num(v, &["stick_fraction"])));
    out.push(("stick_slip_hz".into(), num(v, &["stick_slip_hz"])));
    out.push(("sample_rate_hz".into(), num(v, &["sample_rate_hz"])));
    out.push(("samples".into(), num(v, &["samples"])));
    out
}

/// `got` against `want`, each statistic within `rel` relative (0: equal to the bit).
fn same(what: &str, got: &Value, want: &Value, rel: f64) {
    for ((name, g), (_, w)) in stats(got).iter().zip(stats(want)) {
        let ok = if rel == 0.0 { *g == w } else { (g - w).abs() <= rel * w.abs().max(1e-3) };
        assert!(ok, "{what}: {name} {g} against {w} (rel {rel})");
    }
}

#[test]
fn uff_58_58b_and_wav_give_the_statistics_of_the_csv() {
    let csv = json(&["analyze", &data("rec.csv"), "--json"]);
    assert_eq!(csv["format"], "CSV");
    // the fixture's truth: 40 % stick at 100 Hz
    assert!((num(&csv, &["stick_fraction"]) - 0.4).abs() <= 0.02, "{}", csv["stick_fraction"]);
    assert!((num(&csv, &["stick_slip_hz"]) / 100.0 - 1.0).abs() <= 0.01, "{}", csv["stick_slip_hz"]);
    assert_eq!(csv["estimator"]["thresholds_from"], "floor");
    // double and single 58b hold the values exactly (counts of 2^-12 m/s^2): equal to the bit
    for f in ["rec_58b_double.uff", "rec_58b_single.uff"] {
        let u = json(&["analyze", &data(f), "--json"]);
        assert_eq!(u["format"], "UFF dataset 58", "{f}");
        same(f, &u, &csv, 0.0);
    }
    let w = json(&[&["analyze", &data("rec.wav"), "--json"][..], &WAV_MAP[..]].concat());
    assert_eq!(w["format"], "WAV");
    same("rec.wav", &w, &csv, 0.0);
    let w = json(&[&["analyze", &data("rec24.wav"), "--json"][..], &WAV_MAP[..]].concat());
    same("rec24.wav", &w, &csv, 0.0);
    // float in m/s^2: mapped by number, no SCALE, and the report says what it assumed
    let w = json(&[
        "analyze", &data("rec_f32.wav"), "--json", "--channel", "pad_x=#1", "--channel", "pad_trail=#2", "--channel", "disc_x=#3",
        "--channel", "pad_lead=#4",
    ]);
    same("rec_f32.wav", &w, &csv, 0.0);
    assert!(w["notes"].as_array().unwrap().iter().any(|n| n.as_str().unwrap().contains("taken as m/s^2")), "{}", w["notes"]);
    // ASCII 58 at 6 significant digits (E13.5): 5e-6 per value
    let a = json(&["analyze", &data("rec_58.uff"), "--json"]);
    same("rec_58.uff", &a, &csv, 2e-5);
}

#[test]
fn the_format_is_told_by_content_not_by_name() {
    let dir = scratch("formats-by-content");
    let f = write(&dir, "recording.csv", std::fs::read(data("rec_58b_single.uff")).unwrap());
    let v = json(&["analyze", &f, "--json"]);
    assert_eq!(v["format"], "UFF dataset 58");
    let f = write(&dir, "recording.dat", std::fs::read(data("rec.wav")).unwrap());
    let v = json(&[&["analyze", &f, "--json"][..], &WAV_MAP[..]].concat());
    assert_eq!(v["format"], "WAV");
    // a UFF record mapped by name and by number, with a SCALE that replaces its units
    let v = json(&["analyze", &data("rec_58b_double.uff"), "--json", "--channel", "pad_x=#2", "--channel", "disc_x=DISC_X*2"]);
    let base = json(&["analyze", &data("rec_58b_double.uff"), "--json"]);
    assert_eq!(num(&v, &["channels", "pad_x", "pp"]), num(&base, &["channels", "pad_x", "pp"]));
    assert_eq!(num(&v, &["channels", "disc_x", "pp"]), 2.0 * num(&base, &["channels", "disc_x", "pp"]));
}

#[test]
fn reader_errors_are_one_line_naming_file_record_and_rule() {
    let dir = scratch("formats-errors");
    let wav = data("rec.wav");
    bad(&["analyze", &wav, "--channel", "pad_x=#1"], &[&wav, "16-bit integer PCM", "SCALE"]);
    bad(&["analyze", &wav, "--channel", "pad_x=Acc1*8"], &[&wav, "no names", "#N"]);
    bad(&["analyze", &wav, "--channel", "pad_x=#9*8"], &[&wav, "4 channels"]);
    bad(&["analyze", &wav], &[&wav, "pad_x is needed"]);
    bad(&["analyze", &data("rec.csv"), "--channel", "pad_x=nope"], &["line 1", "`nope`"]);
    bad(&["analyze", &data("rec.csv"), "--channel", "pad_x=#0"], &["--channel pad_x=#0", "from 1"]);
    bad(&["analyze", &data("rec.csv"), "--channel", "x=#1"], &["--channel x=#1", "not a channel"]);
    // a truncated binary record
    let bytes = std::fs::read(data("rec_58b_single.uff")).unwrap();
    let f = write(&dir, "cut.uff", &bytes[..bytes.len() / 3]);
    bad(&["analyze", &f], &[&f, "record 2"]);
    // an ASCII record with a bad value
    let text = std::fs::read_to_string(data("rec_58.uff")).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    lines[20] = lines[20].replacen('e', "x", 1);
    let f = write(&dir, "badvalue.uff", lines.join("\n") + "\n");
    bad(&["analyze", &f], &[&f, "line 21", "is not a number"]);
    // a record that is not a time response
    let f = write(&dir, "frf.uff", text.replacen("    1         0    0", "    4         0    0", 1));
    bad(&["analyze", &f], &[&f, "function type", "not a time response"]);
    // UFF on standard input
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_stickslip"))
        .args(["analyze", "-"])
        .stdin(std::fs::File::open(data("rec_58.uff")).unwrap())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("give it as a file"), "{}", String::from_utf8_lossy(&o.stderr));
}

/// The fixture's CSV rows: (t, [disc_x, pad_x, pad_trail, pad_lead]).
fn rows() -> Vec<(String, [f64; 4])> {
    let text = std::fs::read_to_string(data("rec.csv")).unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (c[0].to_string(), std::array::from_fn(|k| c[k + 1].parse().unwrap()))
        })
        .collect()
}

#[test]
fn a_loggers_csv_with_channel_gives_the_statistics_under_our_names() {
    let dir = scratch("formats-logger");
    let g = 9.806_65;
    // a logger's export: its own names, g, another order, a column to ignore, a preamble
    let mut s = String::from("Logger XYZ export\nTime [s],Acc3 [g],Acc1 [g],Temp [C],Acc4 [V],Acc2 [g]\n");
    for (t, a) in rows() {
        s.push_str(&format!("{t},{:?},{:?},21.5,{:?},{:?}\n", a[2] / g, a[1] / g, a[3] / 0.5, a[0] / g));
    }
    let f = write(&dir, "logger.csv", s);
    let v = json(&[
        "analyze", &f, "--json", "--channel", "pad_x=Acc1", "--channel", "disc_x=acc2 [g]", "--channel", "pad_trail=#1",
        "--channel", "pad_lead=Acc4*0.5",
    ]);
    let ours = json(&["analyze", &data("rec.csv"), "--json"]);
    // each value x/g*g is within an ulp of x: the statistics to 1e-12, the estimator's to the bit
    for ((name, a), (_, b)) in stats(&v).iter().zip(stats(&ours)) {
        assert!((a - b).abs() <= 1e-12 * b.abs().max(1e-3), "{name}: {a} against {b}");
    }
    // a V column without SCALE is refused, naming the column
    bad(&["analyze", &f, "--channel", "pad_x=Acc4"], &[&f, "line 2", "`Acc4 [V]`", "SCALE"]);
}

#[test]
fn pad_x_alone_gives_stick_fraction_and_frequency() {
    let dir = scratch("formats-pad-x-only");
    let mut s = String::from("t,pad_x\n");
    for (t, a) in rows() {
        s.push_str(&format!("{t},{:?}\n", a[1]));
    }
    let f = write(&dir, "pad_x.csv", s);
    let v = json(&["analyze", &f, "--json"]);
    assert!((num(&v, &["stick_fraction"]) - 0.4).abs() <= 0.02, "{}", v["stick_fraction"]);
    assert!((num(&v, &["stick_slip_hz"]) / 100.0 - 1.0).abs() <= 0.01, "{}", v["stick_slip_hz"]);
    for ch in ["disc_x", "pad_trail", "pad_lead"] {
        assert!(v["channels"][ch].is_null(), "{ch}: absent, not zero: {}", v["channels"][ch]);
        assert_eq!(v["present"][ch], false);
    }
    assert!(v["notes"].as_array().unwrap().iter().any(|n| n.as_str().unwrap().contains("no disc_x")), "{}", v["notes"]);
    let md = ok(&["analyze", &f]);
    assert!(md.contains("| disc_x | absent |") && md.contains("no disc_x"), "{md}");
    // without pad_x: one line, exit 2
    let mut s = String::from("t,disc_x,pad_trail\n");
    for (t, a) in rows().iter().take(50) {
        s.push_str(&format!("{t},{:?},{:?}\n", a[0], a[2]));
    }
    let f = write(&dir, "no_pad_x.csv", s);
    bad(&["analyze", &f], &[&f, "pad_x is needed"]);
    bad(&["compare", "push_center", &f], &[&f, "pad_x is needed"]);
}

/// A virtual recording of `scene` (ideal front end, `noise` m/s^2, no quiet lead-in), its rows
/// before `from` s cut off: it starts inside the cycle. Truth: the model's over t >= from.
fn inside_the_cycle(dir: &std::path::Path, scene: &str, noise: &str, from: f64) -> (String, Value) {
    let full = dir.join("full.csv");
    let truth = json(&[
        "sil", scene, "--front-end", "ideal", "--noise", noise, "--quiet-lead", "0", "--stats-from", &from.to_string(), "--csv",
        full.to_str().unwrap(), "--json",
    ]);
    let text = std::fs::read_to_string(&full).unwrap();
    let mut lines = text.lines();
    let mut out = format!("{}\n", lines.next().unwrap());
    for l in lines {
        let t: f64 = l.split(',').next().unwrap().parse().unwrap();
        if t >= from - 0.25 / 25_600.0 {
            out.push_str(l);
            out.push('\n');
        }
    }
    (write(dir, "cut.csv", out), truth)
}

#[test]
fn recordings_that_start_inside_the_cycle_need_no_flag() {
    let dir = scratch("formats-inside-the-cycle");
    let mut worst: (f64, f64) = (0.0, 0.0);
    for case in ["push_trail", "push_center", "push_lead", "pull_trail", "pull_center", "pull_lead"] {
        let toml = ok(&["scenes", "show", &format!("rig_quiet_{case}")]);
        for friction in ["stribeck", "coulomb"] {
            let scene = write(&dir, &format!("{case}_{friction}.toml"), toml.replace("friction = \"stribeck\"", &format!("friction = \"{friction}\"")));
            for (noise, from) in [("0.005", 0.3137), ("0.02", 0.4071)] {
                let (f, truth) = inside_the_cycle(&dir, &scene, noise, from);
                let pp = num(&truth, &["channels", "pad_x", "pp", "true"]);
                assert!((1.0..=4.5).contains(&pp), "{case} {friction}: pad_x pp {pp} not at Table 3.1's levels (about 1 to 4)");
                let tru = num(&truth, &["stick_fraction", "true"]);
                let ht = num(&truth, &["stick_slip_hz", "true"]);
                let a = json(&["analyze", &f, "--json"]);
                let label = format!("{case} {friction} noise {noise}");
                assert_eq!(a["estimator"]["thresholds_from"], "floor", "{label}: {}", a["estimator"]["floor_note"]);
                let est = num(&a, &["stick_fraction"]);
                let he = num(&a, &["stick_slip_hz"]);
                eprintln!("{label}: pad_x pp {pp:.3}, stick {est:.4} vs {tru:.4}, {he:.3} vs {ht:.3} Hz");
                worst = (worst.0.max((est - tru).abs()), worst.1.max((he / ht - 1.0).abs()));
                assert!((est - tru).abs() <= 0.02, "{label}: stick fraction {est} vs true {tru}");
                assert!((he / ht - 1.0).abs() <= 0.01, "{label}: frequency {he} vs true {ht}");
            }
        }
    }
    eprintln!("worst: stick fraction {:.4}, frequency {:.3} %", worst.0, 100.0 * worst.1);
}

/// The fixture's rows with the time printed as `t(i)`, rows `skip` left out.
fn with_times(t: impl Fn(usize) -> String, skip: &[usize]) -> String {
    let mut s = String::from("t,disc_x,pad_x,pad_trail,pad_lead\n");
    for (i, (_, a)) in rows().iter().enumerate() {
        if !skip.contains(&i) {
            s.push_str(&format!("{},{:?},{:?},{:?},{:?}\n", t(i), a[0], a[1], a[2], a[3]));
        }
    }
    s
}

#[test]
fn the_time_axis_is_checked_at_full_precision() {
    let dir = scratch("formats-time-axis");
    let t = |i: usize| if i == 0 { "0.0".to_string() } else { format!("{:.7}", i as f64 / 25_600.0) };
    // a `0.0` first (resolution 0.1 s) no longer switches the check off: 100 rows dropped
    let drop: Vec<usize> = (1000..1100).collect();
    let f = write(&dir, "drop.csv", with_times(t, &drop));
    bad(&["analyze", &f], &[&f, "line 1002", "a drop: 100 rows missing", "--gaps split"]);
    bad(&["compare", "push_center", &f], &[&f, "line 1002", "a drop"]);
    // a `0.25` in the middle, printed short but exact, is fine
    let t2 = |i: usize| if i == 6400 { "0.25".to_string() } else { format!("{:.7}", i as f64 / 25_600.0) };
    let f = write(&dir, "short.csv", with_times(t2, &[]));
    ok(&["analyze", &f]);
    // one interval of 1.5: a gap; --gaps split analyses the blocks and lists it
    let t3 = |i: usize| format!("{:.8}", (i as f64 + if i >= 2000 { 0.5 } else { 0.0 }) / 25_600.0);
    let f = write(&dir, "gap.csv", with_times(t3, &[]));
    bad(&["analyze", &f], &[&f, "line 2002", "a gap"]);
    let v = json(&["analyze", &f, "--gaps", "split", "--json"]);
    let gaps = v["gaps"].as_array().unwrap();
    assert_eq!(gaps.len(), 1, "{}", v["gaps"]);
    assert_eq!(gaps[0]["line"], 2002);
    assert!((num(&gaps[0], &["intervals"]) - 1.5).abs() < 1e-3);
    assert_eq!(num(&v, &["sample_rate_hz"]).round(), 25_600.0);
    assert!((num(&v, &["stick_slip_hz"]) / 100.0 - 1.0).abs() <= 0.01, "{}", v["stick_slip_hz"]);
    // a gap right after a gap is a gap too (the new block's first interval is checked)
    let t5 = |i: usize| format!("{:.8}", (i as f64 + if i == 2000 { 0.5 } else if i > 2000 { 2.0 } else { 0.0 }) / 25_600.0);
    let f = write(&dir, "two_gaps.csv", with_times(t5, &[]));
    let v = json(&["analyze", &f, "--gaps", "split", "--json"]);
    let lines: Vec<u64> = v["gaps"].as_array().unwrap().iter().map(|g| g["line"].as_u64().unwrap()).collect();
    assert_eq!(lines, [2002, 2003], "{}", v["gaps"]);
    // a repeated time is an error even with --gaps split
    let t4 = |i: usize| format!("{:.8}", (if i == 3000 { i - 1 } else { i }) as f64 / 25_600.0);
    let f = write(&dir, "repeat.csv", with_times(t4, &[]));
    bad(&["analyze", &f, "--gaps", "split"], &[&f, "line 3002", "repeats"]);
}

#[test]
fn a_constant_signal_has_no_groan_and_compare_and_fit_heed_the_verdict() {
    let dir = scratch("formats-constant");
    let mut s = String::from("t,disc_x,pad_x,pad_trail,pad_lead\n");
    // 1 s: past fit's default --from (the scene's stats_from, 0.5 s)
    for i in 0..25_600 {
        s.push_str(&format!("{},1.0,1.0,1.0,1.0\n", i as f64 / 25_600.0));
    }
    let f = write(&dir, "constant.csv", s);
    let v = json(&["analyze", &f, "--json"]);
    for ch in CHANNELS {
        assert_eq!(num(&v, &["channels", ch, "groan_rms"]), 0.0, "{ch}: the band-pass starts at the first value");
    }
    assert!(v["stick_fraction"].is_null());
    assert!(v["estimator"]["undecided"].as_str().unwrap().contains("pad_x flat"));
    // compare: the same words, no ratio of a flat channel, no measured stick fraction
    let c = json(&["compare", "push_center", &f, "--json"]);
    assert_eq!(c["health"]["pad_x"][0], "flat");
    assert!(c["channels"]["pad_x"]["pp"]["ratio"].is_null(), "{}", c["channels"]["pad_x"]);
    assert!(c["stick_fraction"]["measured"].is_null() && c["stick_fraction"]["ratio"].is_null());
    assert!(c["undecided"].as_str().unwrap().contains("pad_x flat"));
    let md = ok(&["compare", "push_center", &f]);
    assert!(md.contains("pad_x: flat: not compared") && md.contains("cannot decide"), "{md}");
    // fit: nothing of a flat recording is fitted; with nothing left it says so, exit 2
    let o = stickslip(&["fit", "--scene", "push_center", "--free", "mu_k", &format!("push_center={f}"), "--starts", "1"]);
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stdout));
    let err = stderr(&o);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("nothing left to fit"), "{err}");
}

/// A two-channel WAV at 25.6 kHz: `codes[i]` per frame, each `valid` bits, written
/// left-justified (the most significant bits) into `container`-byte little-endian samples
/// (8 bits: unsigned, offset 128); a plain PCM header with wBitsPerSample `valid`, or a
/// WAVE_FORMAT_EXTENSIBLE one with wBitsPerSample the container's and wValidBitsPerSample
/// `valid`; `extra` (whole chunks) between `fmt ` and `data`.
fn wav_of_codes(ext: bool, container: usize, valid: u32, extra: &[u8], codes: &[[i64; 2]]) -> Vec<u8> {
    let (ch, fs) = (2u16, 25_600u32);
    let block = container as u16 * ch;
    let mut fmt = Vec::new();
    fmt.extend((if ext { 0xFFFEu16 } else { 1 }).to_le_bytes());
    fmt.extend(ch.to_le_bytes());
    fmt.extend(fs.to_le_bytes());
    fmt.extend((fs * block as u32).to_le_bytes());
    fmt.extend(block.to_le_bytes());
    if ext {
        fmt.extend((8 * container as u16).to_le_bytes());
        fmt.extend(22u16.to_le_bytes());
        fmt.extend((valid as u16).to_le_bytes());
        fmt.extend(3u32.to_le_bytes());
        // KSDATAFORMAT_SUBTYPE_PCM
        fmt.extend([1, 0, 0, 0, 0, 0, 0x10, 0, 0x80, 0, 0, 0xaa, 0, 0x38, 0x9b, 0x71]);
    } else {
        fmt.extend((valid as u16).to_le_bytes());
    }
    let mut data = Vec::new();
    for f in codes {
        for &c in f {
            let raw = c << (8 * container as u32 - valid);
            let raw = if container == 1 { raw + 128 } else { raw };
            data.extend(&raw.to_le_bytes()[..container]);
        }
    }
    riff_wave(&fmt, extra, &data)
}

/// A RIFF WAVE file of a `fmt ` chunk's body, `extra` whole chunks, and a `data` chunk's body.
fn riff_wave(fmt: &[u8], extra: &[u8], data: &[u8]) -> Vec<u8> {
    let mut body = b"WAVEfmt ".to_vec();
    body.extend((fmt.len() as u32).to_le_bytes());
    body.extend(fmt);
    body.extend(extra);
    body.extend(b"data");
    body.extend((data.len() as u32).to_le_bytes());
    body.extend(data);
    let mut out = b"RIFF".to_vec();
    out.extend((body.len() as u32).to_le_bytes());
    out.extend(body);
    out
}

/// disc_x 0.05 sin(2 pi 50 t) and pad_x 0.5 sin(2 pi 200 t) of full scale, 4096 frames at
/// 25.6 kHz (whole periods; the 200 Hz sine's samples reach its crests), as `valid`-bit codes.
fn sine_codes(valid: u32) -> Vec<[i64; 2]> {
    let top = ((1i64 << (valid - 1)) - 1) as f64;
    (0..4096)
        .map(|i| {
            let t = i as f64 / 25_600.0;
            let s = |a: f64, f: f64| (a * top * (2.0 * std::f64::consts::PI * f * t).sin()).round() as i64;
            [s(0.05, 50.0), s(0.5, 200.0)]
        })
        .collect()
}

#[test]
fn wav_samples_are_decoded_by_their_container_with_the_valid_bits_left_justified() {
    let dir = scratch("formats-wav-containers");
    let map = ["--channel", "disc_x=#1*10", "--channel", "pad_x=#2*10"];
    // an odd-sized LIST chunk and its pad byte (RIFF chunks are word-aligned)
    let mut list = b"LIST".to_vec();
    list.extend(19u32.to_le_bytes());
    list.extend(b"INFOISFT\x07\0\0\0gen.py\0\0");
    for (name, ext, container, valid, extra) in [
        ("24in32_ext", true, 4, 24, &[][..]),
        ("20in24_ext", true, 3, 20, &[][..]),
        ("24in24_ext", true, 3, 24, &[][..]),
        ("12in16", false, 2, 12, &[][..]),
        ("16_oddlist", false, 2, 16, &list[..]),
        ("8", false, 1, 8, &[][..]),
    ] {
        let codes = sine_codes(valid);
        let f = write(&dir, &format!("{name}.wav"), wav_of_codes(ext, container, valid, extra, &codes));
        let v = json(&[&["analyze", &f, "--json"][..], &map[..]].concat());
        // closed form: a valid-bit code k is k / 2^(valid - 1) of full scale, 10 m/s^2
        let full = (1i64 << (valid - 1)) as f64;
        for (c, ch) in [(0, "disc_x"), (1, "pad_x")] {
            let hi = codes.iter().map(|f| f[c]).max().unwrap() as f64;
            let lo = codes.iter().map(|f| f[c]).min().unwrap() as f64;
            let ms = codes.iter().map(|f| (f[c] as f64 / full * 10.0).powi(2)).sum::<f64>() / codes.len() as f64;
            let pp = num(&v, &["channels", ch, "pp"]);
            assert!((pp - (hi - lo) / full * 10.0).abs() <= 1e-9, "{name} {ch}: pp {pp}");
            let rms = num(&v, &["channels", ch, "rms"]);
            assert!((rms - ms.sqrt()).abs() <= 1e-9, "{name} {ch}: rms {rms}");
        }
        // and the signal's own: pad_x 5 m/s^2 of amplitude at 200 Hz, to a count
        let pp = num(&v, &["channels", "pad_x", "pp"]);
        assert!((pp - 10.0).abs() <= 10.0 * 2.0 / full, "{name}: pad_x pp {pp} against 10");
        assert_eq!(num(&v, &["channels", "pad_x", "peak_hz"]), 200.0, "{name}");
    }
    // more valid bits than the container holds
    let f = write(&dir, "24in16_ext.wav", wav_of_codes(true, 2, 16, &[], &sine_codes(16)));
    let mut b = std::fs::read(&f).unwrap();
    b[38] = 24;
    std::fs::write(&f, b).unwrap();
    bad(&[&["analyze", &f][..], &map[..]].concat(), &[&f, "24 valid bits", "16-bit samples"]);
}

#[test]
fn a_name_that_matches_several_columns_or_records_is_an_error() {
    let dir = scratch("formats-ambiguous-names");
    // UFF: every record's ID lines 3 to 5 are NONE
    let uff = data("rec_58.uff");
    bad(
        &["analyze", &uff, "--channel", "pad_x=NONE"],
        &[&uff, "--channel pad_x=NONE matches records #1 `pad_lead`, #2 `pad_x`, #3 `disc_x`, #4 `pad_trail`", "#N"],
    );
    // UFF: two records named pad_x, found by name
    let text = std::fs::read_to_string(&uff).unwrap();
    assert!(text.contains("\npad_lead   "));
    let f = write(&dir, "two_pad_x.uff", text.replacen("\npad_lead   ", "\npad_x      ", 1));
    bad(&["analyze", &f], &[&f, "records #1 (`pad_x`) and #2 (`pad_x`) both name `pad_x`", "--channel pad_x=#N"]);
    // either, mapped by number, is read
    let v = json(&["analyze", &f, "--json", "--channel", "pad_x=#2", "--channel", "pad_lead=#1"]);
    let base = json(&["analyze", &uff, "--json"]);
    assert_eq!(num(&v, &["channels", "pad_x", "pp"]), num(&base, &["channels", "pad_x", "pp"]));
    // CSV: two columns whose names match once the unit is stripped
    let mut s = String::from("t,Acc [m/s^2],Acc [g],disc_x\n");
    for i in 0..2048 {
        let x = (2.0 * std::f64::consts::PI * 200.0 * i as f64 / 25_600.0).sin();
        s.push_str(&format!("{},{},{},0\n", i as f64 / 25_600.0, 5.0 * x, 0.25 * x));
    }
    let f = write(&dir, "acc_twice.csv", s);
    bad(&["analyze", &f, "--channel", "pad_x=Acc"], &[&f, "line 1", "--channel pad_x=Acc: columns 2 (`Acc [m/s^2]`) and 3 (`Acc [g]`) both match `Acc`", "#N"]);
    // the full name picks one: 0.25 g of amplitude, its crests sampled (128 samples a period)
    let v = json(&["analyze", &f, "--json", "--channel", "pad_x=Acc [g]"]);
    let pp = num(&v, &["channels", "pad_x", "pp"]);
    assert!((pp - 0.5 * 9.80665).abs() <= 1e-9, "{pp}");
}

#[test]
fn a_wav_clipped_at_its_own_full_scale_is_saturated() {
    let dir = scratch("formats-wav-full-scale");
    let map = ["--channel", "disc_x=#1*4", "--channel", "pad_x=#2*4"];
    for (ext, container, valid) in [(false, 2, 16), (true, 4, 24)] {
        let top = (1i64 << (valid - 1)) - 1;
        // pad_x 1.5 x full scale at 200 Hz, clipped at +-top (a symmetric writer's rails)
        let codes: Vec<[i64; 2]> = sine_codes(valid).iter().map(|f| [f[0], (3 * f[1]).clamp(-top, top)]).collect();
        let clipped = codes.iter().filter(|f| f[1].abs() >= top).count() as f64;
        assert!(clipped > 100.0);
        let f = write(&dir, &format!("clipped_{valid}.wav"), wav_of_codes(ext, container, valid, &[], &codes));
        let v = json(&[&["analyze", &f, "--json"][..], &map[..]].concat());
        assert_eq!(num(&v, &["samples_at_full_scale", "pad_x"]), clipped, "{valid} bits");
        assert_eq!(num(&v, &["samples_at_full_scale", "disc_x"]), 0.0);
        assert_eq!(v["estimator"]["health"]["pad_x"][0], "saturated", "{valid} bits: {}", v["estimator"]["health"]);
        assert!(v["estimator"]["health"]["disc_x"].as_array().unwrap().is_empty());
        assert!(v["stick_fraction"].is_null() && v["stick_slip_hz"].is_null());
        assert!(v["estimator"]["undecided"].as_str().unwrap().contains("pad_x saturated"), "{}", v["estimator"]["undecided"]);
        let md = ok(&[&["analyze", &f][..], &map[..]].concat());
        assert!(md.contains(&format!("Warning: pad_x: {clipped} samples at the file's full scale")) && md.contains("cannot decide"), "{md}");
    }
    // one sample at full scale (a recording normalised to its peak) is not clipping
    let mut codes = sine_codes(16);
    codes[1000][1] = 32767;
    let f = write(&dir, "one_peak.wav", wav_of_codes(false, 2, 16, &[], &codes));
    let v = json(&[&["analyze", &f, "--json"][..], &map[..]].concat());
    assert_eq!(num(&v, &["samples_at_full_scale", "pad_x"]), 1.0);
    assert!(v["estimator"]["health"]["pad_x"].as_array().unwrap().is_empty(), "{}", v["estimator"]["health"]);
    // (undecided it is, but not for clipping: a sine with no quiet rows is not told stuck)
    assert!(!v["estimator"]["undecided"].as_str().unwrap_or_default().contains("saturated"), "{}", v["estimator"]["undecided"]);
    // a CSV has no full scale
    let v = json(&["analyze", &data("rec.csv"), "--json"]);
    assert!(v["samples_at_full_scale"].is_null());
}

/// A 64-bit IEEE float WAV (format code 3, wBitsPerSample 64: what numpy/scipy and some
/// loggers write for doubles), two channels in m/s^2: read as written, exactly (it was refused
/// before).
#[test]
fn a_64_bit_float_wav_is_read_exactly() {
    let dir = scratch("formats-wav-f64");
    let (ch, fs) = (2u16, 25_600u32);
    let block = 8 * ch;
    let frames: Vec<[f64; 2]> = (0..4096)
        .map(|i| {
            let t = i as f64 / fs as f64;
            [0.3 * (2.0 * std::f64::consts::PI * 50.0 * t).sin(), 7.25 * (2.0 * std::f64::consts::PI * 200.0 * t).sin() + 0.125]
        })
        .collect();
    let mut fmt = Vec::new();
    fmt.extend(3u16.to_le_bytes());
    fmt.extend(ch.to_le_bytes());
    fmt.extend(fs.to_le_bytes());
    fmt.extend((fs * block as u32).to_le_bytes());
    fmt.extend(block.to_le_bytes());
    fmt.extend(64u16.to_le_bytes());
    let data: Vec<u8> = frames.iter().flat_map(|f| f.iter().flat_map(|v| v.to_le_bytes())).collect();
    let f = write(&dir, "f64.wav", riff_wave(&fmt, &[], &data));
    let v = json(&["analyze", &f, "--channel", "disc_x=#1", "--channel", "pad_x=#2", "--json"]);
    assert_eq!(v["format"].as_str().map(|s| s.contains("WAV")), Some(true), "{}", v["format"]);
    for (c, name) in [(0, "disc_x"), (1, "pad_x")] {
        let hi = frames.iter().map(|f| f[c]).fold(f64::NEG_INFINITY, f64::max);
        let lo = frames.iter().map(|f| f[c]).fold(f64::INFINITY, f64::min);
        let rms = (frames.iter().map(|f| f[c] * f[c]).sum::<f64>() / frames.len() as f64).sqrt();
        assert!((num(&v, &["channels", name, "pp"]) - (hi - lo)).abs() <= 1e-12, "{name} pp");
        assert!((num(&v, &["channels", name, "rms"]) - rms).abs() <= 1e-12, "{name} rms");
    }
}
