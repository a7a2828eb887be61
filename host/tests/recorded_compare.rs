//! `stickslip compare`: the JSON shape, and ratios known by construction: the model against
//! its own virtual-rig recording gives 1 for every ratio; a recording with every channel
//! doubled gives 2 for peak-to-peak and RMS, 1 for the spectral peak, and (with the breakaway
//! jump doubled as well, so that the estimator's thresholds scale with the signal) 1 for the
//! stick fraction and the stick-slip frequency.

mod recorded_common;

use recorded_common::*;
use serde_json::Value;

const QUANTITIES: [&str; 4] = ["pp", "peak_hz", "rms", "groan_rms"];

fn pairs(v: &Value) -> Vec<(String, &Value)> {
    let mut out = Vec::new();
    for ch in CHANNELS {
        for q in QUANTITIES {
            out.push((format!("{ch}.{q}"), &v["channels"][ch][q]));
        }
    }
    out.push(("stick_fraction".into(), &v["stick_fraction"]));
    out.push(("stick_slip_hz".into(), &v["stick_slip_hz"]));
    out
}

#[test]
fn the_model_against_its_own_recording_gives_ratio_one() {
    let dir = scratch("compare-self");
    let csv = dir.join("pull_center.csv");
    let csv = csv.to_str().unwrap();
    // noise above one ADC count, so that even the band channel (true 0) has a peak-to-peak
    ok(&["sil", "pull_center", "--csv", csv, "--noise", "0.5"]);
    let v = json(&["compare", "pull_center", csv, "--from", "0.5", "--noise", "0.5", "--json"]);
    // shape
    for key in ["scene", "file", "channels", "stick_fraction", "stick_slip_hz", "measured", "model", "model_outcome"] {
        assert!(v.get(key).is_some(), "key {key} missing: {v}");
    }
    assert_eq!(v["scene"], "pull_center");
    assert_eq!(v["channels"].as_object().unwrap().len(), 4);
    for ch in CHANNELS {
        assert_eq!(v["channels"][ch].as_object().unwrap().len(), QUANTITIES.len(), "{ch}");
    }
    for (name, p) in pairs(&v) {
        let keys: Vec<&String> = p.as_object().unwrap().keys().collect();
        assert_eq!(keys.len(), 3, "{name}: {p}");
        let (m, s, r) = (p["measured"].as_f64(), p["model"].as_f64(), p["ratio"].as_f64());
        let (m, s, r) = (m.unwrap_or_else(|| panic!("{name}: {p}")), s.unwrap(), r.unwrap());
        assert_eq!(m, s, "{name}: the same samples give the same value");
        assert_eq!(r, 1.0, "{name}");
    }
    assert_eq!(num(&v, &["measured", "samples"]), num(&v, &["model", "samples"]));
    // the Markdown table
    let md = ok(&["compare", "pull_center", csv, "--from", "0.5", "--noise", "0.5"]);
    assert!(md.contains("| channel | quantity | measured | model | measured / model |"), "{md}");
    assert!(md.contains("| pad | stick fraction [-] |") && md.contains("| 1.000 |"), "{md}");
}

#[test]
fn a_recording_twice_as_strong_gives_ratio_two() {
    let dir = scratch("compare-double");
    let csv = dir.join("run.csv");
    ok(&["sil", "push_lead", "--csv", csv.to_str().unwrap(), "--noise", "0.5"]);
    // double every acceleration (exact in binary), keep the time column
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let mut out = format!("{}\n", lines.next().unwrap());
    for l in lines {
        let mut cells = l.split(',');
        out.push_str(cells.next().unwrap());
        for c in cells {
            out.push_str(&format!(",{}", 2.0 * c.parse::<f64>().unwrap()));
        }
        out.push('\n');
    }
    let doubled = write(&dir, "doubled.csv", out);
    // push_lead's breakaway jump is 45.61 m/s^2 (ratio of the scene's numbers:
    // (0.45 - 0.35) N0 / 0.3 kg); doubled for the doubled signal
    let jump = json(&["analyze", &doubled, "--scene", "push_lead", "--json"])["estimator"]["breakaway_jump_m_s2"]
        .as_f64()
        .unwrap();
    let j2 = format!("{}", 2.0 * jump);
    let v = json(&["compare", "push_lead", &doubled, "--from", "0.5", "--breakaway-jump", &j2, "--noise", "0.5", "--json"]);
    for ch in CHANNELS {
        for q in ["pp", "rms"] {
            let r = num(&v, &["channels", ch, q, "ratio"]);
            assert!((r - 2.0).abs() <= 1e-12, "{ch}.{q}: ratio {r}");
        }
        assert_eq!(num(&v, &["channels", ch, "peak_hz", "ratio"]), 1.0, "{ch}");
        // the band-pass is linear too (f32: to its rounding)
        let r = num(&v, &["channels", ch, "groan_rms", "ratio"]);
        assert!((r - 2.0).abs() <= 1e-5, "{ch}.groan_rms: ratio {r}");
    }
    for q in ["stick_fraction", "stick_slip_hz"] {
        let r = num(&v, &[q, "ratio"]);
        assert!((r - 1.0).abs() <= 0.01, "{q}: ratio {r}");
    }
}

/// The model side is `sil SCENE` with the same options, and says what `sil` says: where `sil`
/// cannot decide the model's stick fraction and frequency (a gain that leaves pad_x one ADC
/// count), or a model channel is saturated, `compare` shows no model value and no ratio, and
/// says why. Before, it printed the estimator's raw 1.0 against a measured 0.805 (ratio 0.805).
/// The measured side's notes (`analyze`'s) come along: a recording without disc_x says that
/// a_rel is pad_x alone.
#[test]
fn the_model_side_says_what_sil_says() {
    let dir = scratch("compare-model-undecided");
    let csv = dir.join("push_center.csv");
    let csv = csv.to_str().unwrap();
    ok(&["sil", "push_center", "--csv", csv]);
    let sil = json(&["sil", "push_center", "--gain", "0.001", "--json"]);
    assert!(sil["stick_fraction"]["estimated"].is_null(), "not the case this test is about: {}", sil["stick_fraction"]);
    let v = json(&["compare", "push_center", csv, "--from", "0.5", "--gain", "0.001", "--json"]);
    for q in ["stick_fraction", "stick_slip_hz"] {
        assert!(v[q]["model"].is_null() && v[q]["ratio"].is_null(), "{q}: {}", v[q]);
        assert!(v[q]["measured"].is_number(), "{q}: {}", v[q]);
    }
    assert_eq!(v["model_undecided"], sil["undecided"]);
    let text = ok(&["compare", "push_center", csv, "--from", "0.5", "--gain", "0.001"]);
    assert!(text.contains("Model stick fraction and stick-slip frequency: the virtual rig cannot decide"), "{text}");

    // a saturated model channel: no model peak-to-peak, as in sil (its RMS still compared)
    let sil5 = json(&["sil", "push_center", "--gain", "5", "--json"]);
    let v5 = json(&["compare", "push_center", csv, "--from", "0.5", "--gain", "5", "--json"]);
    let mut saturated = 0;
    for ch in CHANNELS {
        let sat = sil5["health"][ch].as_array().is_some_and(|h| h.iter().any(|w| w == "saturated"));
        assert_eq!(v5["model_health"][ch], sil5["health"][ch], "{ch}");
        if sat {
            saturated += 1;
            assert!(v5["channels"][ch]["pp"]["model"].is_null() && v5["channels"][ch]["pp"]["ratio"].is_null(), "{ch}: {}", v5["channels"][ch]["pp"]);
            assert_eq!(v5["channels"][ch]["pp"]["model"], sil5["channels"][ch]["pp"]["estimated"], "{ch}: sil's pp");
            assert!(v5["channels"][ch]["rms"]["model"].is_number(), "{ch}: {}", v5["channels"][ch]["rms"]);
        }
    }
    assert!(saturated >= 1, "no model channel saturated at gain 5: {}", sil5["health"]);

    // without disc_x: analyze's note
    let text = std::fs::read_to_string(csv).unwrap();
    let mut rows = text.lines().map(|l| l.split(',').collect::<Vec<_>>());
    let head = rows.next().unwrap();
    let keep: Vec<usize> = (0..head.len()).filter(|&i| !head[i].starts_with("disc_x")).collect();
    assert_eq!(keep.len() + 1, head.len(), "one disc_x column: {head:?}");
    let no_disc: String = text.lines().map(|l| {
        let c: Vec<&str> = l.split(',').collect();
        keep.iter().map(|&i| c[i]).collect::<Vec<_>>().join(",") + "\n"
    }).collect();
    let path = write(&dir, "no_disc.csv", no_disc);
    let v = json(&["compare", "push_center", &path, "--from", "0.5", "--json"]);
    let notes: Vec<&str> = v["notes"].as_array().expect("notes").iter().filter_map(|n| n.as_str()).collect();
    assert!(notes.iter().any(|n| n.starts_with("no disc_x")), "{notes:?}");
}
