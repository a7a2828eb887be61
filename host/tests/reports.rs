//! `accuracy` and `stability`: the JSON contracts, every run classified, no NaN anywhere, and
//! the bounds of `--check` (the short versions, as CI runs them).

use std::process::Command;

use serde_json::Value;

fn run(args: &[&str]) -> (i32, Value) {
    let o = Command::new(env!("CARGO_BIN_EXE_stickslip")).args(args).output().expect("runs");
    let text = String::from_utf8(o.stdout).expect("UTF-8");
    assert!(!text.contains("NaN") && !text.contains("inf"), "{args:?} printed a non-finite value");
    let v = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{args:?}: not JSON ({e})"));
    (o.status.code().unwrap_or(-1), v)
}

#[test]
fn stability_rows_are_all_classified_and_exact_is_bounded_when_stiff() {
    let (code, v) = run(&["stability", "--quick", "--json", "--check"]);
    assert_eq!(code, 0);
    let rows = v["rows"].as_array().expect("rows");
    // 8 sweeps, 5 methods, 2 precisions; then 4 model-2 sweeps and part 2's 3 (the floating
    // pad: k_pivot, contact springs, model 3's contact exponent), the model-2 stepper, 2 precisions
    let values = 7 + 7 + 8 + 8 + 5 + 5 + 5 + 6;
    let model2_values = 7 + 5 + 5 + 5 + 5 + 7 + 5;
    // model 3's pneumatic drive: 5 cylinder sweeps, f64 only
    let model3_values = 5 + 3 + 3 + 4 + 3;
    // model 3's unilateral contact: 3 sweeps on the event runner, f64 only
    let unilateral_values = 5 + 4 + 5;
    assert_eq!(rows.len(), values * 5 * 2 + model2_values * 2 + model3_values + unilateral_values);
    let uni: Vec<&Value> = rows.iter().filter(|r| r["method"] == "event").collect();
    assert_eq!(uni.len(), unilateral_values);
    for r in &uni {
        assert_eq!(r["precision"], "f64", "{r}");
        // the load at the trailing edge of a floating push pad tips it over: the model's own
        // contact loss; every other extreme (edges from 1e4 to 1e10 N/m, the pivot from
        // floating to 1e10 N/m, the load anywhere else on the pad) runs bounded
        let expect = if r["sweep"] == "unilateral_beta" && r["beta"] == 0.0 { "contact_loss" } else { "bounded" };
        assert_eq!(r["outcome"], expect, "{r}");
    }
    let m3: Vec<&Value> = rows.iter().filter(|r| r["method"] == "pneumatic").collect();
    assert_eq!(m3.len(), model3_values);
    for r in &m3 {
        assert_eq!(r["precision"], "f64", "{r}");
        assert_eq!(r["outcome"], "bounded", "the pneumatic drive's extremes stay bounded: {r}");
        assert!(r["cylinder_value"].as_f64().is_some_and(f64::is_finite), "{r}");
    }
    assert!(m3.iter().any(|r| r["sweep"] == "column_length" && r["cylinder_value"] == 0.005));
    // model 2's extremes (v_s down to 1e-6 m/s, k_b to 1e10 N/m, m_b 1e-3 to 1e3 kg, damping to
    // critical) stay bounded on its stepper in both precisions
    let m2: Vec<&Value> = rows.iter().filter(|r| r["method"] == "model2").collect();
    assert_eq!(m2.len(), model2_values * 2);
    for r in &m2 {
        // the fitted floating set (mu_k 0.447) flutters on contact springs of 1e7 N/m and
        // stiffer (their coupling threshold falls to mu_k 0.35 to 0.34), so those runs end with a
        // spring lifting off (N < 0): a physical halt, named, not a blow-up
        if r["sweep"] == "float_contact_stiffness" && r["outcome"] == "contact_loss" {
            assert!(r["contact_stiffness"].as_f64().is_some_and(|k| k >= 1e7), "{r}");
            assert!(r["detail"].as_str().is_some_and(|d| d.starts_with("N = -")), "{r}");
        } else {
            assert_eq!(r["outcome"], "bounded", "{r}");
        }
        for key in ["v_s", "k_b", "m_b"] {
            assert!(r[key].as_f64().is_some_and(f64::is_finite), "{r}");
        }
    }
    assert!(m2.iter().any(|r| r["sweep"] == "v_s" && r["v_s"] == 1e-6));
    // the floating pad's rows carry k_pivot (0 to 1e10 N/m), the others null
    let float: Vec<&&Value> = m2.iter().filter(|r| !r["k_pivot"].is_null()).collect();
    assert_eq!(float.len(), (5 + 7 + 5) * 2);
    // the contact law's rows carry their exponent, 1 (linear) to 5, and stay bounded
    let law: Vec<&&&Value> = float.iter().filter(|r| r["sweep"] == "contact_exponent").collect();
    assert_eq!(law.len(), 5 * 2);
    assert!(law.iter().any(|r| r["contact_exponent"] == 5.0 && r["outcome"] == "bounded"));
    assert!(float.iter().any(|r| r["sweep"] == "k_pivot" && r["k_pivot"] == 1e10));
    assert!(float.iter().any(|r| r["sweep"] == "float_contact_stiffness" && r["contact_stiffness"] == 1e10));
    for r in rows {
        for key in ["method", "precision", "dt", "contact_stiffness", "k_g", "mu_s", "v", "beta", "f_n", "damping_ratio", "outcome"] {
            assert!(!r[key].is_null(), "row without {key}: {r}");
        }
        let o = r["outcome"].as_str().unwrap();
        assert!(["bounded", "sprag", "contact_loss", "method_unstable"].contains(&o), "{o}");
        if r["method"] == "exact" {
            assert_ne!(o, "method_unstable", "the exact method failed: {r}");
        }
    }
    let stiff = rows.iter().filter(|r| r["sweep"] == "contact_stiffness" && r["contact_stiffness"] == 1e10 && r["method"] == "exact");
    assert_eq!(stiff.filter(|r| r["outcome"] == "bounded").count(), 2);
    // explicit Euler on the undamped rotation at the rig's rate is an artefact, and is named so
    let ee = rows.iter().find(|r| r["sweep"] == "contact_stiffness" && r["contact_stiffness"] == 1e6 && r["method"] == "explicit_euler").unwrap();
    assert_eq!(ee["outcome"], "method_unstable");
    // past mu = K / (w c_N) the pad self-locks: the model's finding, not the method's
    let sprag = rows.iter().find(|r| r["sweep"] == "mu_s" && r["mu_s"] == 8.0 && r["method"] == "exact").unwrap();
    assert_eq!(sprag["outcome"], "sprag");
    assert!(sprag["stiffness_margin"].as_f64().unwrap() < 0.0);
}

#[test]
fn accuracy_report_meets_its_bounds() {
    let (code, v) = run(&["accuracy", "--quick", "--json", "--check"]);
    assert_eq!(code, 0, "a bound failed: {}", v["checks"]);
    let rows = v["rows"].as_array().expect("rows");
    // thesis scenes: 3 steps x 5 methods x 2 precisions + 3 tolerances; model 2: 4 scenes (the
    // last the floating pad's) x (3 steps x 4 precisions (f64, f32, f32 with libm's and with
    // micromath's exp) + 3 tolerances); model 3's unilateral scene: the event runner at 2
    // tolerances, the reference at 3; model 3's pneumatic scene: the pneumatic runner at 2
    // tolerances, its reference at 3
    assert_eq!(rows.len(), 3 * (3 * 5 * 2 + 3) + 4 * (3 * 4 + 3) + (2 + 3) + (2 + 3));
    for r in rows {
        for key in ["scene", "method", "precision", "run_s"] {
            assert!(!r[key].is_null(), "row without {key}: {r}");
        }
        let adaptive = r["method"] == "dop853_adaptive" || r["method"] == "event" || r["method"] == "pneumatic";
        assert_eq!(r["dt"].is_null(), adaptive, "{r}");
    }
    let exact = |scene: &str, prec: &str| {
        rows.iter()
            .find(|r| r["scene"] == scene && r["method"] == "exact" && r["precision"] == prec && r["dt"] == 1.0 / 25600.0)
            .and_then(|r| r["error"].as_f64())
            .expect("row")
    };
    assert!(exact("oracle_1dof", "f64") <= 1e-9);
    assert!(exact("oracle_1dof", "f32") <= 1e-5);
    let model2 = |scene: &str, prec: &str| {
        rows.iter()
            .find(|r| r["scene"] == scene && r["method"] == "model2" && r["precision"] == prec && r["dt"] == 1.0 / 25600.0)
            .and_then(|r| r["error"].as_f64())
            .expect("row")
    };
    assert!(model2("oracle_stribeck", "f64") <= 1e-6);
    assert!(model2("oracle_stribeck", "f32") <= 1e-4);
    // the alternative exps' rows are there and ran; their own errors are listed
    assert!(model2("oracle_stribeck", "f32 libm exp") <= 1e-4);
    assert!(model2("oracle_stribeck", "f32 micromath exp").is_finite());
    let exps = v["exp_f32"].as_array().expect("exp_f32");
    assert_eq!(exps.len(), 3);
    for e in exps {
        assert!(e["max_rel_error"].as_f64().is_some_and(|x| x > 0.0 && x < 1e-2), "{e}");
    }
    // unilateral contact: the event runner at the host's tolerance against the independent
    // reference (its openings equal, its period, amplitude and open time within 1e-6)
    let event = rows
        .iter()
        .find(|r| r["scene"] == "rig_float_pull_edge" && r["method"] == "event" && r["rtol"] == 1e-12)
        .and_then(|r| r["error"].as_f64())
        .expect("the unilateral event runner's row");
    assert!(event <= 1e-6, "unilateral event runner's error {event:e}");
    // the pneumatic drive: its runner at the host's tolerance against its independent reference
    let pneumatic = rows
        .iter()
        .find(|r| r["scene"] == "rig_push_center_pneumatic" && r["method"] == "pneumatic" && r["rtol"] == 1e-10)
        .and_then(|r| r["error"].as_f64())
        .expect("the pneumatic runner's row");
    assert!(pneumatic <= 1e-6, "pneumatic runner's error {pneumatic:e}");
    assert!(v["speedup_at_equal_error"].as_f64().unwrap() >= 10.0);
    let rc = &v["reference_check"];
    assert!(rc["worst_time_difference_s"].as_f64().unwrap() < 1e-9);
}
