//! The built rig set `rig-built` (issue 34, "Back to Table 3.1"; docs/fit.md, "Back to Table
//! 3.1 (rig-built)"): the floating rig set with model 3's soft band and unilateral edges.
//! Checked here:
//! - the six scenes `rig_built_*` exist, validate, and are `rig_float_*` with the model-3
//!   keys, mu_k, the run's length and window changed and nothing else;
//! - they run to completion (library and `cases --set rig-built --json`), their statistics and
//!   accelerations finite, no edge lost; `--precision f32` is refused with a line that says why;
//! - their pad_x and disc_x peak-to-peak against Table 3.1 stay at the RMS log ratio measured
//!   when the set was made (a change of the set or of the model that moves them fails);
//! - the rig set and the floating rig set are as they were: their keys at the values of their
//!   own fits, written out here (their digests: shared/tests/model2_anchor.rs).

use std::process::Command;

use serde_json::Value;
use stickslip::scenes::builtin;
use stickslip::scenes::run::{self, Precision, RunReport};
use stickslip::scenes::series::NoSink;
use stickslip_model::catalogue::CASE_BETAS;
use stickslip_model::rig_set::{self, rig_built_scene, rig_float_scene};
use stickslip_model::{Caliper, ContactLaw};

fn names(prefix: &str) -> Vec<(String, Caliper, f64)> {
    let mut v = Vec::new();
    for caliper in [Caliper::Push, Caliper::Pull] {
        for (tag, beta) in CASE_BETAS {
            v.push((format!("{prefix}{}_{tag}", caliper.name()), caliper, beta));
        }
    }
    v
}

fn report(name: &str) -> RunReport {
    let b = builtin::find(name).unwrap_or_else(|| panic!("{name}: no such built-in scene"));
    run::run(&b.scene, Precision::F64, &mut NoSink).unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn the_six_scenes_are_the_floating_set_with_model_3() {
    for (name, caliper, beta) in names("rig_built_") {
        let b = builtin::find(&name).unwrap_or_else(|| panic!("{name} is not a built-in scene"));
        let s = b.scene;
        s.validate().unwrap_or_else(|e| panic!("{name}: {e:?}"));
        assert_eq!((s.caliper, s.beta), (caliper, beta), "{name}");
        assert_eq!(s, rig_built_scene(caliper, beta), "{name}");
        // the values the set was made with (docs/fit.md), written out
        assert_eq!(s.contact, ContactLaw::Unilateral, "{name}");
        assert_eq!(
            (s.mu_k, s.k_b, s.m_b, s.contact_exponent, s.duration, s.stats_from),
            (0.4482, 1.89e4, 0.514, 1.5, 3.0, 1.5),
            "{name}"
        );
        let zeta_b = s.c_b / (2.0 * (s.k_b * s.m_b).sqrt());
        assert!((zeta_b - 0.05).abs() < 1e-15, "{name}: zeta_b {zeta_b}");
        // and otherwise the floating set's scene, key for key
        let mut want = rig_float_scene(caliper, beta);
        want.mu_k = s.mu_k;
        want.k_b = s.k_b;
        want.m_b = s.m_b;
        want.c_b = s.c_b;
        want.contact = ContactLaw::Unilateral;
        want.contact_exponent = s.contact_exponent;
        want.duration = s.duration;
        want.stats_from = s.stats_from;
        assert_eq!(s, want, "{name}");
    }
}

/// Table 3.1's pad_x and disc_x peak-to-peak [m/s^2] (host/data/thesis_table_3_1.csv), in the
/// order of [`names`].
const TABLE_3_1_PAD_DISC: [(f64, f64); 6] =
    [(3.975, 3.975), (2.744, 1.846), (1.23, 0.461), (3.411, 1.949), (3.4109, 1.6158), (3.488, 1.846)];

#[test]
fn the_set_runs_and_keeps_its_fit() {
    let mut ln2 = Vec::new();
    for ((name, _, _), (pad_t31, disc_t31)) in names("rig_built_").into_iter().zip(TABLE_3_1_PAD_DISC) {
        let r = report(&name);
        assert_eq!(r.outcome.keyword(), "completed", "{name}");
        assert!(r.has_window(), "{name}");
        for i in 0..4 {
            let pp = r.pp(i).unwrap_or_else(|| panic!("{name}: no pp {i}"));
            assert!(pp.is_finite() && pp > 0.0, "{name}: pp {i} = {pp}");
        }
        assert!(r.stats.stick_slip_hz.is_finite() && r.stats.stick_slip_hz > 0.0, "{name}");
        assert!(r.stats.stick_fraction > 0.0 && r.stats.stick_fraction < 1.0, "{name}");
        let edges = r.edges.unwrap_or_else(|| panic!("{name}: a unilateral run reports its edges"));
        for i in 0..2 {
            let f = edges.open_fraction(i);
            assert!(f.is_finite() && (0.0..1.0).contains(&f), "{name}: edge {i} open {f}");
        }
        let m2 = r.model2.unwrap_or_else(|| panic!("{name}: model 2's accelerations"));
        assert!(m2.pad_acc_pp.is_finite() && m2.pad_acc_pp > 0.0, "{name}");
        assert!(m2.band_acc_pp.is_finite() && m2.band_acc_pp > 0.0, "{name}");
        ln2.push((m2.pad_acc_pp / pad_t31).ln().powi(2));
        ln2.push((m2.band_acc_pp / disc_t31).ln().powi(2));
    }
    // measured when the set was made (docs/fit.md): RMS_12
    let rms = (ln2.iter().sum::<f64>() / ln2.len() as f64).sqrt();
    assert!((rms - RMS_12).abs() < 0.01, "pad_x and disc_x against Table 3.1: RMS ln ratio {rms}, made at {RMS_12}");
}

/// The RMS log ratio of the set's 12 pad_x and disc_x peak-to-peak values against Table 3.1
/// when it was made (docs/fit.md).
const RMS_12: f64 = 0.6015;

fn stickslip(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_stickslip")).args(args).output().expect("the stickslip binary runs")
}

#[test]
fn cases_set_rig_built_json_and_f32_refused() {
    let o = stickslip(&["cases", "--set", "rig-built", "--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let j: Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(j["precision"], "f64");
    assert_eq!(j["duration"].as_f64(), Some(3.0));
    let cases = j["cases"].as_array().expect("cases");
    let want = names("rig_built_");
    assert_eq!(cases.len(), want.len());
    for (c, (name, caliper, beta)) in cases.iter().zip(&want) {
        assert_eq!(c["name"].as_str(), Some(name.as_str()));
        assert_eq!(c["caliper"].as_str(), Some(caliper.name()));
        assert_eq!(c["beta"].as_f64(), Some(*beta));
        for k in ["x_pp", "xdot_pp", "phi_pp", "phidot_pp", "stick_fraction", "stick_slip_hz"] {
            let v = c[k].as_f64().unwrap_or_else(|| panic!("{name}: {k} missing: {c}"));
            assert!(v.is_finite() && v > 0.0, "{name}: {k} = {v}");
        }
    }
    let o = stickslip(&["cases", "--set", "rig-built", "--precision", "f32"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("rig-built") && err.contains("f64 only"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
}

#[test]
fn the_rig_sets_are_as_they_were() {
    for (name, caliper, beta) in names("rig_float_") {
        let s = builtin::find(&name).unwrap_or_else(|| panic!("{name}")).scene;
        assert_eq!(s, rig_float_scene(caliper, beta), "{name}");
        assert_eq!((s.mu_k, s.v_s, s.k_b, s.m_b), (0.4473, 1.2e-3, 1.3e6, 2.0), "{name}");
        assert_eq!((s.contact, s.contact_exponent, s.duration, s.stats_from), (ContactLaw::Bilateral, 1.0, 1.0, 0.5), "{name}");
        assert!(s.face && s.k_pivot == 0.0, "{name}");
    }
    for (name, caliper, beta) in names("rig_") {
        let s = builtin::find(&name).unwrap_or_else(|| panic!("{name}")).scene;
        assert_eq!(s, rig_set::rig_scene(caliper, beta), "{name}");
        assert_eq!((s.mu_k, s.v_s, s.k_b, s.m_b), (0.4398, 4.4e-4, 7.8e5, 2.0), "{name}");
        assert_eq!((s.contact, s.contact_exponent, s.duration, s.stats_from), (ContactLaw::Bilateral, 1.0, 1.0, 0.5), "{name}");
        assert!(!s.face && s.k_pivot == f64::INFINITY, "{name}");
    }
}
