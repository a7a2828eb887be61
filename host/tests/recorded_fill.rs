//! Recordings as loggers write them around a trigger: the time before it (and after the stop)
//! filled with one value on every channel. Such fill has no sensor noise; taken as the noise
//! floor it put the slip threshold at its minimum, so that the stick phases' noise read as
//! slip (a stick fraction of 0.09 and 105 Hz for 0.6 and 100 Hz, exit 0). The fill is now
//! left out of the floor and of the statistics, and named in a note and in the JSON.
//!
//! Reference: the record's construction (a 10 ms cycle of 6 ms stick, sensor noise only, and
//! 4 ms of slip, one sine period of 20 m/s^2 on pad_x): stick fraction 0.6, 100 Hz. Also the
//! time column's messages: jitter is not called a gap, and a repeated time printed to 8
//! decimals is not blamed on too few decimals.

mod recorded_common;

use recorded_common::{bad, json, num, scratch, write, Noise};
use serde_json::Value;

const FS: f64 = 25_600.0;
const NOISE: f64 = 0.01;

/// `fill_lead` s of `fill` on every channel, `signal` s of stick-slip, `fill_trail` s of fill;
/// values printed to `decimals`.
fn record(fill_lead: f64, signal: f64, fill_trail: f64, fill: f64, decimals: usize) -> String {
    let mut noise = Noise(0x9e37_79b9_7f4a_7c15);
    let n = ((fill_lead + signal + fill_trail) * FS).round() as usize;
    let mut out = String::from("t,disc_x,pad_x,pad_trail,pad_lead\n");
    for i in 0..n {
        let t = i as f64 / FS;
        let row: [f64; 4] = if t < fill_lead - 0.25 / FS || t >= fill_lead + signal - 0.25 / FS {
            [fill; 4]
        } else {
            let ph = ((t - fill_lead) * 100.0).rem_euclid(1.0);
            let slip = if ph >= 0.6 { 20.0 * (2.0 * std::f64::consts::PI * (ph - 0.6) / 0.4).sin() } else { 0.0 };
            [noise.gauss(NOISE), slip + noise.gauss(NOISE), 5.0 * (2.0 * std::f64::consts::PI * 300.0 * t).sin(), 0.5 + noise.gauss(NOISE)]
        };
        out.push_str(&format!("{t:.8}"));
        for v in row {
            out.push_str(&format!(",{v:.decimals$}"));
        }
        out.push('\n');
    }
    out
}

/// `csv` written as `rec.csv` in a fresh scratch directory `name`: its path.
fn written(name: &str, csv: &str) -> String {
    write(&scratch(name), "rec.csv", csv)
}

fn analyze(name: &str, csv: &str) -> Value {
    json(&["analyze", &written(name, csv), "--json"])
}

fn assert_the_construction(v: &Value, what: &str) {
    let sf = num(v, &["stick_fraction"]);
    let hz = num(v, &["stick_slip_hz"]);
    assert!((sf - 0.6).abs() < 0.02, "{what}: stick fraction {sf}, built 0.6");
    assert!((hz - 100.0).abs() < 1.0, "{what}: {hz} Hz, built 100");
    // the floor is the stick phases' noise (a_rel = pad_x - disc_x: sqrt 2 sigma), not the fill
    let sigma = num(v, &["estimator", "floor", "a_rel_sigma_m_s2"]);
    assert!((sigma / (NOISE * 2f64.sqrt()) - 1.0).abs() < 0.1, "{what}: floor sigma {sigma}");
}

fn span(v: &Value, key: &str) -> Option<(f64, f64)> {
    let s = &v["estimator"]["floor"][key];
    s.as_array().map(|a| (a[0].as_f64().unwrap(), a[1].as_f64().unwrap()))
}

#[test]
fn a_fill_before_the_trigger_or_after_the_stop_is_not_the_noise_floor() {
    let plain = analyze("fill_none", &record(0.0, 1.0, 0.0, 0.0, 6));
    assert_the_construction(&plain, "no fill");
    assert!(span(&plain, "fill_lead_s").is_none() && span(&plain, "fill_trail_s").is_none());

    for (name, lead, trail, value) in [("fill_zeros_lead", 0.1, 0.0, 0.0), ("fill_level_lead", 0.1, 0.0, 0.25), ("fill_long_lead", 2.0, 0.0, 0.0), ("fill_trail", 0.0, 0.1, 0.0), ("fill_both", 0.1, 0.1, 0.0)] {
        let p = written(name, &record(lead, 1.0, trail, value, 6));
        let v = json(&["analyze", &p, "--json"]);
        assert_the_construction(&v, name);
        if lead > 0.0 {
            let (a, b) = span(&v, "fill_lead_s").unwrap_or_else(|| panic!("{name}: no leading fill reported"));
            assert!(a == 0.0 && (b - lead).abs() < 2.0 / FS, "{name}: leading fill {a} to {b} s, built 0 to {lead}");
            // the statistics start after it
            assert!(num(&v, &["t_first_s"]) >= lead - 0.5 / FS, "{name}: statistics from {}", v["t_first_s"]);
        } else {
            assert!(span(&v, "fill_lead_s").is_none(), "{name}");
        }
        if trail > 0.0 {
            let (a, _) = span(&v, "fill_trail_s").unwrap_or_else(|| panic!("{name}: no trailing fill reported"));
            assert!((a - (lead + 1.0)).abs() < 2.0 / FS, "{name}: trailing fill from {a} s, built {}", lead + 1.0);
            assert!(num(&v, &["t_last_s"]) < lead + 1.0, "{name}: statistics to {}", v["t_last_s"]);
        } else {
            assert!(span(&v, "fill_trail_s").is_none(), "{name}");
        }
        let notes = v["notes"].to_string();
        assert!(notes.contains("every channel holds one value"), "{name}: {notes}");
        // from standard input (one pass, the floor from the rows held back): the same
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_stickslip"))
            .args(["analyze", "-", "--json"])
            .stdin(std::fs::File::open(&p).unwrap())
            .output()
            .expect("runs");
        assert!(out.status.success(), "{name} from stdin: {}", String::from_utf8_lossy(&out.stderr));
        let w: Value = serde_json::from_slice(&out.stdout).expect("JSON");
        for key in ["stick_fraction", "stick_slip_hz", "t_first_s", "t_last_s"] {
            assert_eq!(w[key], v[key], "{name} from stdin: {key}");
        }
        assert_eq!(w["estimator"]["floor"]["fill_lead_s"], v["estimator"]["floor"]["fill_lead_s"], "{name} from stdin");
        assert_eq!(w["estimator"]["floor"]["fill_trail_s"], v["estimator"]["floor"]["fill_trail_s"], "{name} from stdin");
    }
}

#[test]
fn a_value_held_through_a_dropout_is_not_the_noise_floor() {
    // 1 s of stick-slip whose rows from 0.5 to 0.55 s are zeros on every channel (a dropout
    // as a logger writes it): taken for the floor, it gave 0.051 at 61 Hz for 0.6 at 100
    let csv = record(0.0, 1.0, 0.0, 0.0, 6);
    let mut lines: Vec<String> = csv.lines().map(str::to_string).collect();
    let (i0, i1) = ((0.5 * FS) as usize + 1, (0.55 * FS) as usize + 1);
    for line in &mut lines[i0..i1] {
        let t = line.split(',').next().unwrap().to_string();
        *line = format!("{t},0.000000,0.000000,0.000000,0.000000");
    }
    let v = analyze("fill_inside", &(lines.join("\n") + "\n"));
    let floor = &v["estimator"]["floor"];
    assert_eq!(floor["fill_inside_runs"], 1, "{floor}");
    let sigma = num(&v, &["estimator", "floor", "a_rel_sigma_m_s2"]);
    assert!((sigma / (NOISE * 2f64.sqrt()) - 1.0).abs() < 0.1, "floor sigma {sigma}");
    let hz = num(&v, &["stick_slip_hz"]);
    assert!((hz - 100.0).abs() < 6.0, "{hz} Hz, built 100 (5 of its cycles lost)");
    let sf = num(&v, &["stick_fraction"]);
    assert!((sf - 0.62).abs() < 0.03, "stick fraction {sf}: built 0.6, and 0.05 s of dropout counted as stick");
    assert!(v["notes"].to_string().contains("inside the record"), "{}", v["notes"]);
}

/// Several dropouts (eight of 10 ms, zeros on every channel) after a 0.1 s leading fill: they
/// are fill, however many, where they are fewer rows than the real stick phases' quiet rows
/// (a review: a first rule that counted runs took five dropouts for stick phases, and the floor
/// fell to sigma 0 again, 0.140 at 112 Hz).
#[test]
fn many_dropouts_are_still_fill() {
    let csv = record(0.1, 1.0, 0.0, 0.0, 6);
    let mut lines: Vec<String> = csv.lines().map(str::to_string).collect();
    for k in 0..8 {
        let t0 = 0.1 + 0.1 * (k as f64 + 1.0) + 0.003;
        let (i0, i1) = ((t0 * FS) as usize + 1, ((t0 + 0.01) * FS) as usize + 1);
        for line in &mut lines[i0..i1] {
            let t = line.split(',').next().unwrap().to_string();
            *line = format!("{t},0.000000,0.000000,0.000000,0.000000");
        }
    }
    let v = analyze("fill_many_dropouts", &(lines.join("\n") + "\n"));
    let floor = &v["estimator"]["floor"];
    assert_eq!(floor["fill_inside_runs"], 8, "{floor}");
    assert!(span(&v, "fill_lead_s").is_some(), "{floor}");
    let sigma = num(&v, &["estimator", "floor", "a_rel_sigma_m_s2"]);
    assert!((sigma / (NOISE * 2f64.sqrt()) - 1.0).abs() < 0.1, "floor sigma {sigma}");
    let hz = num(&v, &["stick_slip_hz"]);
    assert!((88.0..=101.0).contains(&hz), "{hz} Hz, built 100 (a cycle lost at each dropout)");
    let sf = num(&v, &["stick_fraction"]);
    assert!((0.58..=0.68).contains(&sf), "stick fraction {sf}: built 0.6, and 0.08 s of dropouts counted as stick");
}

#[test]
fn on_a_coarse_converter_runs_of_one_count_stay_stick() {
    // printed to 0.1 m/s^2, ten times the noise: the stick phases are runs of one value too,
    // so a run at the start is not told apart from stick and is not called fill
    let v = analyze("fill_coarse", &record(0.1, 1.0, 0.0, 0.0, 1));
    assert!(span(&v, "fill_lead_s").is_none(), "{}", v["estimator"]["floor"]);
    assert!(!v["notes"].to_string().contains("every channel holds one value"), "{}", v["notes"]);
}

#[test]
fn a_record_whose_only_quiet_rows_are_fill_has_no_floor_and_says_why() {
    // a steady 300 Hz groan (no stick) after 0.1 s of zeros: the zeros were the floor
    let mut csv = String::from("t,disc_x,pad_x,pad_trail,pad_lead\n");
    for i in 0..(1.1 * FS) as usize {
        let t = i as f64 / FS;
        let x = if t < 0.1 { 0.0 } else { 10.0 * (2.0 * std::f64::consts::PI * 300.0 * t).sin() };
        csv.push_str(&format!("{t:.8},0.000000,{x:.6},0.000000,0.000000\n"));
    }
    let v = analyze("fill_only_quiet", &csv);
    assert!(v["stick_fraction"].is_null(), "stick fraction {} from a record with no stick", v["stick_fraction"]);
    let why = v["estimator"]["floor_note"].as_str().unwrap_or_default();
    assert!(why.contains("runs of one value on every channel"), "{why}");
}

/// A record at 25.6 kHz with one interval of `k` intervals after row 100, times to 8 decimals.
fn with_interval(k: f64) -> String {
    let mut csv = String::from("t,disc_x,pad_x\n");
    let mut t = 0.0;
    for i in 0..2000 {
        csv.push_str(&format!("{t:.8},0.0,{:.4}\n", (i as f64 * 0.3).sin()));
        t += if i == 100 { k / FS } else { 1.0 / FS };
    }
    csv
}

#[test]
fn jitter_is_not_called_a_gap_and_a_repeat_is_not_blamed_on_decimals() {
    let dir = scratch("time_messages");
    let p = write(&dir, "jitter.csv", with_interval(1.2));
    let line = bad(&["analyze", &p], &["line 103", "jitter"]);
    assert!(!line.contains("of them): a gap") && !line.contains("--gaps split"), "{line}");
    let line = bad(&["analyze", &p, "--gaps", "split"], &["line 103", "jitter"]);
    assert!(!line.contains("--gaps split"), "{line}");
    let p = write(&dir, "gap.csv", with_interval(2.6));
    bad(&["analyze", &p], &["line 103", "of them): a gap", "--gaps split"]);
    // a time repeated, printed to 10 ns at a 39 us interval: not too few decimals
    let p = write(&dir, "repeat.csv", with_interval(0.0));
    let line = bad(&["analyze", &p], &["line 103", "repeats", "0.00390625"]);
    assert!(!line.contains("decimals"), "{line}");
}

/// pad_x alone (disc_x 0) on the rig's 12-bit converter (0.395 m/s^2 a count) with 0.005 m/s^2
/// of noise: every stick phase is a run of one count, as fill is, but it recurs every cycle.
/// Built at a stick fraction of 0.2 and 120 Hz (slips of one sine period of 50 m/s^2) after a
/// 0.1 s quiet lead; read as fill, its stick phases gave 0.147 at 105 Hz (a campaign). Runs
/// inside the record that hold more than half as many rows as the quiet rows found without
/// them are its stick, not fill.
#[test]
fn a_coarse_pad_x_alone_keeps_its_stick_phases() {
    let mut noise = Noise(0x2545_f491_4f6c_dd1d);
    let q = 0.395;
    let (lead, signal, hz, stick) = (0.1, 1.0, 120.0, 0.2);
    let mut csv = String::from("t,disc_x,pad_x\n");
    let n = ((lead + signal) * FS).round() as usize;
    for i in 0..n {
        let t = i as f64 / FS - lead;
        let ph = (t * hz).rem_euclid(1.0);
        let a = if t >= 0.0 && ph >= stick { 50.0 * (2.0 * std::f64::consts::PI * (ph - stick) / (1.0 - stick)).sin() } else { 0.0 };
        csv.push_str(&format!("{t:.8},0,{}\n", ((a + noise.gauss(0.005)) / q).round() * q));
    }
    let v = json(&["analyze", &written("fill_coarse_pad_x", &csv), "--json", "--from", "0"]);
    let (sf, f) = (num(&v, &["stick_fraction"]), num(&v, &["stick_slip_hz"]));
    assert!((sf - stick).abs() < 0.02, "stick fraction {sf}, built {stick}");
    assert!((f - hz).abs() < 1.0, "{f} Hz, built {hz}");
    assert!(span(&v, "fill_lead_s").is_none() && span(&v, "fill_trail_s").is_none(), "{}", v["estimator"]["floor"]);
    assert!(v["estimator"]["floor"]["fill_inside_runs"].as_u64().unwrap_or(0) == 0, "{}", v["estimator"]["floor"]);
}
