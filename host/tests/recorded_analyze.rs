//! `stickslip analyze` on recordings generated here with known content: a sine per channel of
//! known amplitude A and frequency f, printed to a known number of decimals. The expected
//! values are worked out by hand, never taken from the tool:
//!
//! - the sines are sampled at fs = 4 k f (k integer), so samples fall on the crests, sin = +-1
//!   exactly, and the printed extremes are +-A: peak-to-peak = 2 A to the printed precision;
//! - the record holds whole periods of every sine, so the mean of sin^2 over the samples is
//!   exactly 1/2: RMS = A / sqrt(2), off by at most the printing's half unit in the last place
//!   (the RMS is a Euclidean norm / sqrt(n): a perturbation of at most q per sample moves it
//!   by at most q);
//! - the spectral peak lies within one bin (fs / segment) of f;
//! - the groan-band RMS is A / sqrt(2) times the band-pass gain at f, from the closed form of
//!   a 4th-order Butterworth band-pass through the bilinear transform:
//!   |H|^2 = 1 / (1 + ((W^2 - W0^2) / (W B))^4), W = 2 fs tan(pi f / fs), W0^2 = W_lo W_hi,
//!   B = W_hi - W_lo, edges 100 and 500 Hz;
//! - all amplitudes stay below a quarter of the default breakaway jump (33.2 m/s^2 / 4): the
//!   estimator never leaves stick, stick fraction 1, no stick-slip frequency.

mod recorded_common;

use std::f64::consts::PI;

use recorded_common::*;
use serde_json::Value;

/// Closed-form gain of the groan band-pass at f [Hz] and rate fs [Hz].
fn groan_gain(f: f64, fs: f64) -> f64 {
    let w = |f: f64| 2.0 * fs * (PI * f / fs).tan();
    let (wl, wh) = (w(100.0), w(500.0));
    let (w0sq, b) = (wl * wh, wh - wl);
    let x = (w(f).powi(2) - w0sq) / (w(f) * b);
    (1.0 / (1.0 + x.powi(4))).sqrt()
}

struct Sine {
    amp: f64,
    hz: f64,
}

/// The samples of channel `c` at sample `i`.
fn value(s: &Sine, i: usize, fs: f64) -> f64 {
    s.amp * (2.0 * PI * s.hz * i as f64 / fs).sin()
}

fn check_channels(v: &Value, sines: &[Sine; 4], fs: f64, decimals: i32, segment: f64) {
    let q = 0.5 * 10f64.powi(-decimals);
    for (c, s) in sines.iter().enumerate() {
        let name = CHANNELS[c];
        let pp = num(v, &["channels", name, "pp"]);
        assert!((pp - 2.0 * s.amp).abs() <= 1e-9, "{name}: pp {pp}, want {}", 2.0 * s.amp);
        let rms = num(v, &["channels", name, "rms"]);
        let want = s.amp / 2f64.sqrt();
        assert!((rms - want).abs() <= q + 1e-12, "{name}: rms {rms}, want {want} +- {q}");
        let peak = num(v, &["channels", name, "peak_hz"]);
        assert!((peak - s.hz).abs() <= fs / segment * (1.0 + 1e-6), "{name}: peak {peak} Hz, want {} Hz", s.hz);
    }
    // the rate comes from the printed time column: within 1e-6 of fs here
    let res = num(v, &["spectrum", "resolution_hz"]);
    assert!((res - fs / segment).abs() <= 1e-6 * fs / segment, "resolution {res} Hz");
    // sines with no quiet rows: the thresholds are the scene's guess, and a pad_x that moves
    // (here at least 1.7 m/s^2 of standard deviation, above a tenth of the stick level 8.3)
    // without one slip onset is not told stuck (it was 1.0 before: a plausible wrong number)
    assert!(v["stick_fraction"].is_null(), "{}", v["stick_fraction"]);
    assert!(v["stick_slip_hz"].is_null());
    let why = v["estimator"]["undecided"].as_str().unwrap_or_default();
    assert!(why.contains("cannot be told from stick"), "{why}");
}

/// A spreadsheet export: semicolons, decimal commas, quoted header with units in two styles
/// and a unit-less name with a trailing underscore (as in the thesis's Table 3.1), CRLF line
/// ends, a row of separators and blank lines at the end.
fn spreadsheet(sines: &[Sine; 4], fs: f64, n: usize) -> String {
    let mut s = String::from("\"Time [s]\";\"pad_x [m/s^2]\";\"disc_x (m/s²)\";\"pad_lead\";\"pad_trail_\"\r\n");
    for i in 0..n {
        let v: Vec<f64> = (0..4).map(|c| value(&sines[c], i, fs)).collect();
        let cells = [
            format!("{:.7}", i as f64 / fs),
            format!("{:.4}", v[1]),
            format!("{:.4}", v[0]),
            format!("{:.4}", v[3]),
            format!("{:.4}", v[2]),
        ];
        s.push_str(&cells.iter().map(|c| c.replace('.', ",")).collect::<Vec<_>>().join(";"));
        s.push_str("\r\n");
    }
    s.push_str(";;;;\r\n\r\n\r\n");
    s
}

#[test]
fn spreadsheet_export_with_semicolons_and_decimal_commas() {
    let dir = scratch("spreadsheet");
    // fs = 5120 Hz, 1 s; fs / f = 128, 32, 16, 64: multiples of 4, whole periods
    let fs = 5120.0;
    let sines = [
        Sine { amp: 0.5, hz: 40.0 },
        Sine { amp: 2.25, hz: 160.0 },
        Sine { amp: 1.2345, hz: 320.0 },
        Sine { amp: 3.0, hz: 80.0 },
    ];
    let file = write(&dir, "export.csv", spreadsheet(&sines, fs, 5120));
    let v = json(&["analyze", &file, "--json"]);
    // default segment at 5120 Hz: the smallest power of two with a resolution <= 2 Hz is 4096
    check_channels(&v, &sines, fs, 4, 4096.0);
    assert_eq!(num(&v, &["samples"]), 5120.0);
    assert_eq!(num(&v, &["rows"]), 5120.0);
    // time printed to 1e-7 s: the rate from the first and last rows is within 1e-7 / 1 s
    assert!((num(&v, &["sample_rate_hz"]) - fs).abs() / fs < 1e-6);
    assert_eq!(num(&v, &["time_resolution_s"]), 1e-7);

    // groan band: after 0.25 s (the filter's transient gone), still whole periods
    let v = json(&["analyze", &file, "--json", "--from", "0.25"]);
    assert_eq!(num(&v, &["samples"]), 3840.0);
    for (c, s) in sines.iter().enumerate() {
        let g = num(&v, &["channels", CHANNELS[c], "groan_rms"]);
        let want = s.amp / 2f64.sqrt() * groan_gain(s.hz, fs);
        assert!((g - want).abs() <= 0.01 * want + 1e-4, "{}: groan rms {g}, want {want}", CHANNELS[c]);
    }
}

#[test]
fn plain_csv_with_columns_reordered_and_other_units() {
    let dir = scratch("plain");
    // 25.6 kHz, 1 s; time in ms, pad_x in g, an extra column; fs / f = 64, 128, 256, 32
    let fs = 25_600.0;
    let sines = [
        Sine { amp: 1.5, hz: 400.0 },
        Sine { amp: 0.25, hz: 200.0 }, // in g: 0.25 g
        Sine { amp: 7.125, hz: 100.0 },
        Sine { amp: 0.875, hz: 800.0 },
    ];
    let mut s = String::from("pad_lead,pad_x [g],Time (ms),comment,disc_x,pad_trail [m/s^2]\n");
    for i in 0..25_600 {
        let v: Vec<f64> = (0..4).map(|c| value(&sines[c], i, fs)).collect();
        s.push_str(&format!(
            "{:.3},{:.5},{:.6},\"a, quoted note\",{:.3},{:.3}\n",
            v[3],
            v[1],
            i as f64 * 1e3 / fs,
            v[0],
            v[2]
        ));
    }
    let file = write(&dir, "plain.csv", s);
    let v = json(&["analyze", &file, "--json"]);
    // pad_x was written in g: expect 9.80665 times the g values
    let g = 9.806_65;
    let in_si = [
        Sine { amp: 1.5, hz: 400.0 },
        Sine { amp: 0.25 * g, hz: 200.0 },
        Sine { amp: 7.125, hz: 100.0 },
        Sine { amp: 0.875, hz: 800.0 },
    ];
    // printing: 3 decimals (m/s^2) except pad_x, 5 decimals of g; check_channels takes the
    // coarsest, 0.5e-3, which bounds both (0.5e-5 g = 4.9e-5 m/s^2)
    check_channels(&v, &in_si, fs, 3, 16_384.0);
    assert!((num(&v, &["sample_rate_hz"]) - fs).abs() / fs < 1e-6);
    assert_eq!(num(&v, &["spectrum", "segments"]), 2.0, "25600 samples hold 2 half-overlapped 16384-sample segments");
}

#[test]
fn markdown_summary_and_figures() {
    let dir = scratch("markdown");
    let fs = 5120.0;
    let sines = [
        Sine { amp: 0.5, hz: 40.0 },
        Sine { amp: 2.25, hz: 160.0 },
        Sine { amp: 1.2345, hz: 320.0 },
        Sine { amp: 3.0, hz: 80.0 },
    ];
    let file = write(&dir, "export.csv", spreadsheet(&sines, fs, 5120));
    let figs = dir.join("figs");
    let out = ok(&["analyze", &file, "--plots", figs.to_str().unwrap()]);
    assert!(out.contains("| channel | peak-to-peak [m/s^2] | RMS [m/s^2] | spectral peak [Hz] | groan-band RMS [m/s^2] |"), "{out}");
    assert!(out.contains("| pad_trail | 2.46900 |"), "{out}");
    assert!(out.contains("Welch"), "{out}");
    for name in ["disc_x", "pad_x", "pad_trail", "pad_lead", "spectra"] {
        let svg = std::fs::read_to_string(figs.join(format!("{name}.svg"))).unwrap();
        assert!(svg.starts_with("<svg"), "{name}.svg");
        assert!(svg.contains("<polyline") || svg.contains("<path"), "{name}.svg has no line");
    }
    let t = std::fs::read_to_string(figs.join("pad_x.svg")).unwrap();
    assert!(t.contains("time t [s]") && t.contains("pad_x [m/s^2]"));
}

#[test]
fn standard_input_and_a_logger_preamble() {
    let dir = scratch("stdin");
    let fs = 2048.0;
    let mut s = String::from("Logger XYZ export\nsample rate;2048 Hz\n\n");
    s.push_str("t;disc_x;pad_x;pad_trail;pad_lead\n");
    for i in 0..2048 {
        // a square wave on pad_x: +1 for 512 samples, -1 for 512
        let sq = if (i / 512) % 2 == 0 { 1 } else { -1 };
        s.push_str(&format!("{};0;{sq},000;0;0\n", format!("{:.6}", i as f64 / fs).replace('.', ",")));
    }
    let file = write(&dir, "preamble.csv", &s);
    let v = json(&["analyze", &file, "--json"]);
    assert_eq!(num(&v, &["channels", "pad_x", "pp"]), 2.0);
    assert_eq!(num(&v, &["channels", "pad_x", "rms"]), 1.0);
    assert_eq!(num(&v, &["channels", "disc_x", "pp"]), 0.0);
    // the same through standard input
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_stickslip"))
        .args(["analyze", "-", "--json"])
        .stdin(std::fs::File::open(&file).unwrap())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let w: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(w["channels"], v["channels"]);
}

/// `--windows FILE`: the estimator's own 100 ms windows, one CSV row each with the keys of the
/// firmware's `window` record. Sines on the crests with whole periods in every window of 2 560
/// samples at 25.6 kHz (fs / f = 512, 256, 128, 64): each window's peak-to-peak is 2 A and its
/// RMS A / sqrt(2) (by hand, as above), its groan RMS A / sqrt(2) times the closed-form gain
/// once the filter's transient is gone (from the second window on), its first sample and the
/// time column at its last sample those of the rows written here. 0.35 s: three whole windows,
/// the fourth never closes.
#[test]
fn windows_are_the_estimators_own_one_row_per_window() {
    let dir = scratch("windows");
    let fs = 25_600.0;
    let sines = [
        Sine { amp: 1.0, hz: 50.0 },
        Sine { amp: 2.0, hz: 100.0 },
        Sine { amp: 3.0, hz: 200.0 },
        Sine { amp: 4.0, hz: 400.0 },
    ];
    let n = 8_960;
    let mut s = String::from("t,disc_x,pad_x,pad_trail,pad_lead\n");
    let mut times = vec![];
    for i in 0..n {
        let t = format!("{:.9}", i as f64 / fs);
        let v: Vec<String> = (0..4).map(|c| format!("{:.6}", value(&sines[c], i, fs))).collect();
        s.push_str(&format!("{t},{}\n", v.join(",")));
        times.push(t);
    }
    let file = write(&dir, "sines.csv", s);
    let out = dir.join("windows.csv");
    let o = stickslip(&["analyze", &file, "--breakaway-jump", "40", "--windows", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).contains("wrote 3 estimator windows"), "{}", stderr(&o));

    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    // the names `decode --kind window` gives the firmware's record (channel c of CHANNELS)
    let mut want_header = vec!["idx", "first", "samples", "valid"];
    let names: Vec<String> = ["pp", "rms", "groan_rms"].iter().flat_map(|stat| (0..4).map(move |c| format!("{stat}_{c}"))).collect();
    want_header.extend(names.iter().map(String::as_str));
    want_header.extend(["stick", "ss_hz", "onsets", "saturated", "faulted", "nonfinite", "t_end_s"]);
    assert_eq!(header, want_header);
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 3, "{text}");
    let col = |r: &Vec<&str>, key: &str| -> f64 {
        let k = header.iter().position(|h| *h == key).unwrap();
        r[k].parse().unwrap_or_else(|_| panic!("{key} = {}", r[k]))
    };
    for (k, r) in rows.iter().enumerate() {
        let first = 2_560 * k;
        assert_eq!((col(r, "idx"), col(r, "first")), (k as f64, first as f64));
        assert_eq!((col(r, "samples"), col(r, "valid")), (2_560.0, 2_560.0));
        assert_eq!(col(r, "t_end_s"), times[first + 2_559].parse::<f64>().unwrap(), "window {k}");
        for (c, s) in sines.iter().enumerate() {
            let name = CHANNELS[c];
            let pp = col(r, &format!("pp_{c}"));
            assert!((pp - 2.0 * s.amp).abs() <= 1e-6 * s.amp, "window {k} {name}: pp {pp}");
            let rms = col(r, &format!("rms_{c}"));
            let want = s.amp / 2f64.sqrt();
            assert!((rms - want).abs() <= 5e-7 + 1e-5 * want, "window {k} {name}: rms {rms}, want {want}");
            if k >= 1 {
                let g = col(r, &format!("groan_rms_{c}"));
                let want = want * groan_gain(s.hz, fs);
                assert!((g - want).abs() <= 0.01 * want + 1e-4, "window {k} {name}: groan rms {g}, want {want}");
            }
        }
        assert_eq!((col(r, "stick"), col(r, "ss_hz"), col(r, "onsets")), (1.0, 0.0, 0.0), "window {k}: stick throughout");
        assert_eq!((col(r, "saturated"), col(r, "faulted")), (0.0, 0.0));
        assert_eq!(r[header.len() - 2], "false");
    }
}

#[test]
fn windows_to_an_unwritable_path_is_a_clear_error() {
    let dir = scratch("windows_bad");
    let mut s = String::from("t,disc_x,pad_x,pad_trail,pad_lead\n");
    for i in 0..3000 {
        s.push_str(&format!("{},0,0,0,0\n", i as f64 / 25_600.0));
    }
    let file = write(&dir, "quiet.csv", s);
    let target = dir.join("no_such_dir").join("w.csv");
    // an output error: exit 1 (the tool's convention, host/src/error.rs), one line naming the file
    let o = stickslip(&["analyze", &file, "--windows", target.to_str().unwrap()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.starts_with("error: ") && err.contains("w.csv: cannot write the windows"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// A pad at rest (pad_x about 0.001 m/s^2, far below the default stick level of 8.3 m/s^2):
/// from 16 rows on the estimator starts (16 quiet rows in a row) and calls every row stick;
/// below 16 it never starts, and a stick fraction would be a guess (it was 0: every row
/// counted as slip), so it is null with the reason, while the per-channel figures stand.
#[test]
fn a_record_too_short_to_start_the_estimator_has_no_stick_fraction() {
    let dir = scratch("short-records");
    for rows in [2usize, 10, 15, 16, 17] {
        let mut s = String::from("t,pad_x\n");
        for i in 0..rows {
            s.push_str(&format!("{:.8},{:.4}\n", i as f64 / 25_600.0, 0.001 * (i % 3) as f64));
        }
        let f = write(&dir, &format!("rest_{rows}.csv"), s);
        let v = json(&["analyze", &f, "--json"]);
        let pp = num(&v, &["channels", "pad_x", "pp"]);
        let want = 0.001 * (rows - 1).min(2) as f64;
        assert!((pp - want).abs() <= 1e-12, "{rows} rows: pp {pp} against {want}");
        if rows < 16 {
            assert!(v["stick_fraction"].is_null() && v["stick_slip_hz"].is_null(), "{rows} rows: {}", v["stick_fraction"]);
            let why = v["estimator"]["undecided"].as_str().unwrap_or_default().to_string();
            assert!(why.starts_with(&format!("{rows} rows: ")) && why.contains("16 rows in a row"), "{rows} rows: {why}");
            let md = ok(&["analyze", &f]);
            assert!(md.contains("cannot decide") && !md.contains("Stick fraction: 0"), "{md}");
        } else {
            assert_eq!(num(&v, &["stick_fraction"]), 1.0, "{rows} rows");
            assert!(v["estimator"]["undecided"].is_null());
        }
    }
}

#[test]
fn a_pad_that_moves_below_the_scenes_threshold_with_no_quiet_rows_is_not_called_stuck() {
    // a pure 200 Hz sine on pad_x, no quiet rows: the thresholds come from push_center's
    // breakaway jump (onset 16.6 m/s^2, stick 8.3 m/s^2); at an amplitude of 10 m/s^2 (standard
    // deviation 7.07) no slip onset is seen, which does not make the pad stuck
    let dir = scratch("moving-below-threshold");
    for (amplitude, decided) in [(10.0, false), (0.05, true)] {
        let mut s = String::from("t,pad_x\n");
        for i in 0..25_600 {
            let t = i as f64 / 25_600.0;
            s.push_str(&format!("{t:.8},{:.6}\n", amplitude * (2.0 * std::f64::consts::PI * 200.0 * t).sin()));
        }
        let f = write(&dir, &format!("sine_{amplitude}.csv"), s);
        let v = json(&["analyze", &f, "--json"]);
        let why = v["estimator"]["undecided"].as_str().unwrap_or_default().to_string();
        if decided {
            // a quiet pad (standard deviation 0.035 m/s^2, below a tenth of the stick level)
            assert_eq!(num(&v, &["stick_fraction"]), 1.0, "{amplitude}: {why}");
        } else {
            assert!(v["stick_fraction"].is_null() && v["stick_slip_hz"].is_null(), "{amplitude}: {}", v["stick_fraction"]);
            assert!(why.contains("cannot be told from stick") && why.contains("7.07"), "{why}");
        }
    }
}
