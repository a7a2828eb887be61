//! `stickslip fit` on a table of peak-to-peak values with mu_s held: mu_k is searched as its
//! drop mu_s - mu_k on a log scale (`fit::model::drop_coordinate`). The coordinate's algebra,
//! and a small drop found from a start 40 times as large.

mod recorded_common;

use recorded_common::*;
use stickslip::fit::goodness::Verdict;
use stickslip::fit::model::{self, FreeKey, DROP_FLOOR};
use stickslip::fit::stat::Stat;
use stickslip::fit::{self, FitRequest};
use stickslip::scenes::scene_source::{NamedScene, Origin};
use stickslip_model::rig::ACCEL_NAMES;

fn named(name: &str, scene: stickslip_model::Scene) -> NamedScene {
    NamedScene { name: name.into(), description: String::new(), origin: Origin::Builtin, scene }
}

/// The coordinate u = ln((value - origin) / (start - origin)) and back, its range, its scale
/// (d value / d u), and when it is taken.
#[test]
fn the_drop_coordinate_maps_mu_k_to_its_drop_below_mu_s() {
    let mu_s = 0.45;
    let mut keys = vec![FreeKey::new("mu_k", 0.35, 0.05, 1.5), FreeKey::new("k_b", 1e6, 1e3, 1e9)];
    let note = model::drop_coordinate(&mut keys, mu_s).expect("mu_k with mu_s held takes the drop");
    assert!(note.contains("upper bound lowered"), "{note}");
    let f = &keys[0];
    assert_eq!(f.origin, mu_s);
    assert_eq!(f.hi, mu_s * (1.0 - DROP_FLOOR), "no mu_k at or above mu_s is searched");
    // the drop 0.1 at the start; u = ln(drop / 0.1), independently of the code's form
    for drop in [1e-4, 2.7e-3, 0.1, 0.4] {
        let v = mu_s - drop;
        let u = f.coord(v);
        assert!((u - (drop / 0.1f64).ln()).abs() < 1e-12, "u of drop {drop}: {u}");
        assert!((f.value(u) - v).abs() < 1e-15, "round trip of {v}");
        assert!((f.scale(v) - drop).abs() < 1e-15, "d mu_k / d u = -drop at {v}");
    }
    // u rises as mu_k falls: the range's low end is the upper bound's drop
    let (a, b) = f.u_range();
    assert!((a - (mu_s * DROP_FLOOR / 0.1).ln()).abs() < 1e-9 && (b - ((mu_s - 0.05) / 0.1f64).ln()).abs() < 1e-12, "{a} {b}");
    // k_b keeps the plain log scale
    assert_eq!(keys[1].origin, 0.0);
    assert!((keys[1].value(1.0f64.ln() + 2.0) - 1e6 * 2f64.exp()).abs() < 1e-6);
    // mu_s free: both keep the plain log scale
    let mut both = vec![FreeKey::new("mu_s", 0.45, 0.05, 1.5), FreeKey::new("mu_k", 0.35, 0.05, 1.5)];
    assert!(model::drop_coordinate(&mut both, 0.45).is_none());
    assert!(both.iter().all(|f| f.origin == 0.0));
    // a start within the floor of mu_s: no drop to take the log of
    let mut near = vec![FreeKey::new("mu_k", 0.45 * (1.0 - 0.5 * DROP_FLOOR), 0.05, 0.45)];
    assert!(model::drop_coordinate(&mut near, 0.45).is_none());
    assert_eq!(near[0].origin, 0.0);
}

/// The floating rig set's drop is 0.0027 (mu_k 0.4473 under mu_s 0.45). A table of its
/// peak-to-peak values (two cases, four channels, the fit's own model runs at the truth) is
/// fitted from mu_k = 0.34 (a drop of 0.11, 40 times the truth's) and k_b x 0.5, with the
/// default physical bounds: mu_k within 2 % of its drop, k_b within 2 %, verdict `fits`.
/// On a plain ln(mu_k) scale the truth's basin is a sliver of the bounds (mu_k's cliff where
/// the cycle changes lies 1e-3 above it: docs/fit.md, "Coordinates").
#[test]
fn a_small_friction_drop_is_found_from_a_start_far_off() {
    let truth = stickslip::scenes::builtin::find("rig_float_push_center").expect("built-in").scene;
    let dir = scratch("fit-table-drop");
    let table = rig_float_table(&dir, "truth.csv", |_| 1.0, None);
    let mut start = truth;
    start.mu_k = 0.34;
    start.k_b = truth.k_b * 0.5;
    let req = FitRequest {
        free: vec!["mu_k,k_b".into()],
        tables: vec![table],
        starts: 3,
        max_iters: fit::DEFAULT_MAX_ITERS,
        bootstrap: 0,
        seed: 1,
        breakaway_jump_m_s2: Some(8.0),
        ..FitRequest::default()
    };
    let r = fit::run_fit(named("rig_float_push_center", start), &req).expect("the fit runs");
    let drop_truth = truth.mu_s - truth.mu_k;
    let drop_fit = truth.mu_s - r.values[0];
    println!(
        "mu_k {} (drop {drop_fit:.6e} against {drop_truth:.6e}, {:+.3} %), k_b {} ({:+.3} %), cost {:.3e}, {} evaluations, {:.1} s",
        r.values[0],
        100.0 * (drop_fit - drop_truth) / drop_truth,
        r.values[1],
        100.0 * (r.values[1] - truth.k_b) / truth.k_b,
        r.cost,
        r.evaluations,
        r.seconds
    );
    assert!((drop_fit - drop_truth).abs() <= 0.02 * drop_truth, "drop {drop_fit} against {drop_truth}");
    assert!((r.values[1] - truth.k_b).abs() <= 0.02 * truth.k_b, "k_b {} against {}", r.values[1], truth.k_b);
    assert_eq!(r.goodness.verdict, Verdict::Fits);
    assert!(r.converged);
    assert!(r.notes.iter().any(|n| n.contains("drop mu_s - mu_k")), "the report says how mu_k was searched: {:?}", r.notes);
}

/// The floating rig set's pp table (two cases, four channels) at the set's own values, each
/// value times `factor(row)`, with a `sigma` column of `sigma(row)` (None: the 4-column table).
fn rig_float_table(dir: &std::path::Path, name: &str, factor: impl Fn(usize) -> f64, sigma: Option<&dyn Fn(usize, f64) -> String>) -> String {
    let truth = stickslip::scenes::builtin::find("rig_float_push_center").expect("built-in").scene;
    let base = named("rig_float_push_center", truth);
    let mut csv = String::from(if sigma.is_some() { "case,channel,statistic,value,sigma\n" } else { "case,channel,statistic,value\n" });
    let mut row = 0;
    for case in ["push_center", "pull_lead"] {
        let scene = model::case_scene(&base, case).expect("a case");
        let a = model::statistics(case, &scene, 8.0, None, false).expect("the truth runs");
        for (c, ch) in ACCEL_NAMES.iter().enumerate() {
            let v = Stat::Pp.of(&a, Some(c)).expect("a pp") * factor(row);
            match sigma {
                Some(sg) => csv.push_str(&format!("{case},{ch},pp,{v:e},{}\n", sg(row, v))),
                None => csv.push_str(&format!("{case},{ch},pp,{v:e}\n")),
            }
            row += 1;
        }
    }
    write(dir, name, csv)
}

/// A table's `sigma` column is the value's standard error in its unit: chi^2 takes sigma /
/// value as the error of ln(value) instead of the assumed 0.25. The same values (pp of the
/// floating set, alternately 3 % high and low: no parameter matches them) fitted with mu_k
/// free: without sigma the 3 % are well inside the assumed scatter (`fits`); with a stated 1 %
/// the same optimum's chi^2 is (0.25 / 0.01)^2 = 625 times larger and the verdict is not `fits`.
/// A column with some errors empty mixes the two, and says so. Bad sigmas name their line.
#[test]
fn a_tables_sigma_column_is_its_stated_error() {
    let dir = scratch("fit-table-sigma");
    let wobble = |row: usize| if row % 2 == 0 { 1.03 } else { 1.0 / 1.03 };
    let plain = rig_float_table(&dir, "plain.csv", wobble, None);
    let one_percent = |_: usize, v: f64| format!("{:e}", 0.01 * v);
    let stated = rig_float_table(&dir, "stated.csv", wobble, Some(&one_percent));
    let some_empty = |row: usize, v: f64| if row < 4 { format!("{:e}", 0.01 * v) } else { String::new() };
    let mixed = rig_float_table(&dir, "mixed.csv", wobble, Some(&some_empty));
    let fit = |table: &str| {
        json(&["fit", "--scene", "rig_float_push_center", "--free", "mu_k", "--table", table, "--starts", "1", "--breakaway-jump", "8", "--json"])
    };
    let (a, b, c) = (fit(&plain), fit(&stated), fit(&mixed));
    let chi = |j: &serde_json::Value| num(j, &["goodness", "chi2_per_dof"]);
    println!("chi2/dof: assumed {}, stated 1 % {}, mixed {}; noise {} / {} / {}", chi(&a), chi(&b), chi(&c), a["goodness"]["noise"], b["goodness"]["noise"], c["goodness"]["noise"]);
    // the same search (the cost does not see sigma), so the same optimum
    assert_eq!(a["parameters"]["mu_k"]["value"], b["parameters"]["mu_k"]["value"]);
    let ratio = chi(&b) / chi(&a);
    assert!((ratio - 625.0).abs() <= 1e-6 * 625.0, "chi^2 ratio {ratio}");
    assert_eq!(a["goodness"]["verdict"], "fits");
    assert_ne!(b["goodness"]["verdict"], "fits");
    assert!((num(&b, &["goodness", "noise"]) - 0.01).abs() < 1e-12);
    assert!(b["goodness"]["noise_source"].as_str().unwrap().contains("sigma column"), "{}", b["goodness"]["noise_source"]);
    let src = c["goodness"]["noise_source"].as_str().unwrap();
    assert!(src.contains("sigma for 4") && src.contains("for 4"), "{src}");
    // rows 0..4 at 1 %, rows 4..8 at 0.25: chi^2 is the sum of both kinds
    assert!(chi(&c) > chi(&a) && chi(&c) < chi(&b));

    let head = "case,channel,statistic,value,sigma\n";
    for (body, needles) in [
        ("push_center,pad_x,pp,3.0,x\n", &["line 2", "sigma `x` is not a number"][..]),
        ("push_center,pad_x,pp,3.0,0\n", &["line 2", "sigma 0", "> 0"][..]),
        ("push_center,pad_x,pp,3.0,-1\n", &["line 2", "sigma -1"][..]),
        ("push_center,pad_x,pp,3.0,inf\n", &["line 2", "sigma inf"][..]),
        ("push_center,pad_x,pp,3.0\n", &["line 2", "4 fields where the header has 5"][..]),
    ] {
        let f = write(&dir, "bad.csv", format!("{head}{body}"));
        bad(&["fit", "--scene", "rig_float_push_center", "--free", "mu_k", "--table", &f], needles);
    }
    let f = write(&dir, "badhead.csv", "case,channel,statistic,value,error\npush_center,pad_x,pp,3.0,0.1\n");
    bad(&["fit", "--scene", "rig_float_push_center", "--free", "mu_k", "--table", &f], &["line 1", "case,channel,statistic,value,sigma"]);
}

/// Issue 31's Table 3.1 command, exactly: S.toml is `scenes show rig_float_push_center` with
/// `duration = 3.0`, `stats_from = 1.5` and its `c_b` line replaced by `zeta_b = 0.05`;
/// `fit --scene S.toml --free mu_k,v_s,k_b,m_b --table thesis_table_3_1 --json`, no bounds.
/// It reaches an RMS log ratio <= 0.62, and its verdict is not `fits` (Table 3.1 is not
/// fitted within the assumed 0.25 in ln(value)). Ignored by default for its time (about 270 s
/// on 2 cores): `cargo test --release -p stickslip --test fit_table -- --ignored --nocapture`.
#[test]
#[ignore]
fn table_3_1_with_a_soft_band_reaches_0_62() {
    let shown = ok(&["scenes", "show", "rig_float_push_center"]);
    let mut lines: Vec<String> = Vec::new();
    for l in shown.lines() {
        let key = l.split('=').next().unwrap_or("").trim();
        lines.push(match key {
            "duration" => "duration = 3.0".into(),
            "stats_from" => "stats_from = 1.5".into(),
            "c_b" => "zeta_b = 0.05".into(),
            _ => l.to_string(),
        });
    }
    assert_eq!(lines.iter().filter(|l| l.starts_with("zeta_b")).count(), 1, "the scene has a c_b line");
    let dir = scratch("fit-table-3-1");
    let s = write(&dir, "S.toml", lines.join("\n") + "\n");
    let j = json(&["fit", "--scene", &s, "--free", "mu_k,v_s,k_b,m_b", "--table", "thesis_table_3_1", "--json"]);
    let rms = num(&j, &["rms_log_ratio_fitted"]);
    println!("RMS log ratio {rms}, goodness {}, parameters {}", j["goodness"], j["parameters"]);
    assert!(rms <= 0.62, "RMS log ratio {rms}");
    assert_ne!(j["goodness"]["verdict"], "fits");
    assert_eq!(j["converged"], false);
}

/// A table of rig_push_center's own statistics at mu_s 0.6, mu_k 0.5, v_s 1 mm/s (its virtual
/// rig on the ideal path, no noise; sigma 1 %), fitted from the rig set's values: a campaign
/// found the fit ending in another optimum (0.513, 0.408, 0.38 mm/s) with chi^2 / dof 1.18, a
/// `fits` with standard errors of 1 %, while the truth's cost is 100 times lower. Only one of
/// the three starts ends there; the report now says that the cost has other optima and that
/// the standard errors are local to the one found.
#[test]
fn a_fit_whose_starts_end_apart_says_the_errors_are_local() {
    let dir = scratch("fit-table-basins");
    let rows = [
        ("", "stick_fraction", 0.871572533),
        ("", "stick_slip_hz", 30.416702),
        ("disc_x", "rms", 1.94897645),
        ("disc_x", "groan_rms", 1.31896083),
        ("pad_x", "rms", 10.1969976),
        ("pad_x", "groan_rms", 9.12808335),
        ("pad_lead", "rms", 6.13039069),
        ("pad_lead", "groan_rms", 5.00579375),
        ("pad_trail", "rms", 0.408692713),
        ("pad_trail", "groan_rms", 0.333719566),
    ];
    let mut csv = String::from("case,channel,statistic,value,sigma\n");
    for (ch, st, v) in rows {
        csv.push_str(&format!("push_center,{ch},{st},{v},{}\n", 0.01 * v));
    }
    let table = write(&dir, "truth.csv", csv);
    let v = json(&["fit", "--scene", "rig_push_center", "--free", "mu_s,mu_k,v_s", "--table", &table, "--json"]);
    let g = &v["goodness"];
    let (agree, starts) = (g["starts_agreeing"].as_u64().unwrap(), v["starts"].as_array().unwrap().len() as u64);
    assert_eq!(g["verdict"], "fits", "{g}");
    assert!(agree < starts, "the starts agree ({agree} of {starts}): not the case this test is about");
    let notes = v["notes"].to_string();
    assert!(notes.contains(&format!("{agree} of {starts} starts ended at the best cost")) && notes.contains("local"), "{notes}");
}
