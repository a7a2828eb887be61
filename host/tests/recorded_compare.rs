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
