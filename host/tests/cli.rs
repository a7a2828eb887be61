//! End-to-end tests of the `stickslip` binary: exit codes, output shapes, scene files, CSV,
//! figures, and the closed-form check. Reference values come from docs (model.md's closed
//! form and the thesis's case definitions), never from the code under test.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn stickslip(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_stickslip"))
        .args(args)
        .output()
        .expect("the stickslip binary runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).expect("stdout is UTF-8")
}

fn stderr(o: &Output) -> String {
    String::from_utf8(o.stderr.clone()).expect("stderr is UTF-8")
}

/// Runs and expects exit code 0; returns stdout.
fn ok(args: &[&str]) -> String {
    let o = stickslip(args);
    assert_eq!(o.status.code(), Some(0), "{args:?} failed: {}", stderr(&o));
    stdout(&o)
}

fn json(args: &[&str]) -> Value {
    let out = ok(args);
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{args:?}: not JSON ({e}):\n{out}"))
}

/// A fresh directory for one test.
fn scratch(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("stickslip-cli")
        .join(name);
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

/// Expects exit code 2 and one line on stderr starting with "error: " and containing every
/// needle; returns the line.
fn bad(args: &[&str], needles: &[&str]) -> String {
    let o = stickslip(args);
    let err = stderr(&o);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{args:?}: want exit 2, stderr: {err}"
    );
    assert!(o.stdout.is_empty(), "{args:?}: nothing on stdout on error");
    let line = err.trim_end();
    assert_eq!(
        line.lines().count(),
        1,
        "{args:?}: one line on stderr, got:\n{err}"
    );
    assert!(line.starts_with("error: "), "{args:?}: {line}");
    assert!(!line.contains("panicked"), "{args:?}: {line}");
    for n in needles {
        assert!(line.contains(n), "{args:?}: `{n}` missing from: {line}");
    }
    line.to_string()
}

fn num(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("`{key}` is not a number in {v}"))
}

fn close(got: f64, want: f64, rel: f64, what: &str) {
    assert!(
        (got - want).abs() <= rel * want.abs(),
        "{what}: got {got}, want {want} (relative tolerance {rel})"
    );
}

const CASE_NAMES: [&str; 6] = [
    "push_trail",
    "push_center",
    "push_lead",
    "pull_trail",
    "pull_center",
    "pull_lead",
];
const BUILTINS: [&str; 8] = [
    "push_trail",
    "push_center",
    "push_lead",
    "pull_trail",
    "pull_center",
    "pull_lead",
    "thesis-mu",
    "oracle_1dof",
];
const CASE_KEYS: [&str; 9] = [
    "name",
    "caliper",
    "beta",
    "x_pp",
    "xdot_pp",
    "phi_pp",
    "phidot_pp",
    "stick_fraction",
    "stick_slip_hz",
];

#[test]
fn no_arguments_runs_simulate_on_push_center() {
    let out = ok(&[]);
    for needle in [
        "push_center",
        "outcome",
        "completed",
        "x pp",
        " m/s",
        " rad/s",
        "stick fraction",
        "Hz",
        "first slip",
    ] {
        assert!(out.contains(needle), "`{needle}` missing from:\n{out}");
    }
    assert_eq!(out, ok(&["simulate"]), "no subcommand = simulate");
    assert_eq!(
        out,
        ok(&["simulate", "push_center"]),
        "default scene = push_center"
    );
    for bad_word in ["NaN", "nan ", "inf"] {
        assert!(!out.contains(bad_word), "`{bad_word}` printed:\n{out}");
    }
}

#[test]
fn help_and_version_exit_zero() {
    let h = ok(&["--help"]);
    assert!(
        h.contains("Exit codes")
            && h.contains("simulate")
            && h.contains("cases")
            && h.contains("scenes"),
        "{h}"
    );
    assert!(ok(&["simulate", "--help"]).contains("--csv"));
    assert!(ok(&["cases", "--help"]).contains("--plots"));
    assert!(ok(&["--version"]).starts_with("stickslip "));
}

/// A model-2 scene's `simulate --json` carries the rig's pad_x and disc_x peak-to-peaks, the
/// same as the summary's lines (to the summary's 5 digits); the thesis model's has neither.
#[test]
fn simulate_json_gives_pad_x_and_disc_x_of_a_model2_scene() {
    let v = json(&["simulate", "rig_push_center", "--json"]);
    let text = ok(&["simulate", "rig_push_center"]);
    let line = |label: &str| -> f64 {
        let l = text.lines().find(|l| l.starts_with(label)).unwrap_or_else(|| panic!("no `{label}` line: {text}"));
        l[label.len()..].split_whitespace().next().expect("a value").parse().expect("a number")
    };
    for (key, label) in [("pad_x_pp", "pad x'' pp"), ("disc_x_pp", "band x_b'' pp")] {
        let (j, t) = (num(&v, key), line(label));
        assert!(j > 0.0 && ((j - t) / t).abs() < 1e-4, "{key} {j} against the summary's {t}");
    }
    let thesis = json(&["simulate", "push_center", "--json"]);
    assert!(thesis.get("pad_x_pp").is_none() && thesis.get("disc_x_pp").is_none(), "{thesis}");
}

#[test]
fn simulate_json_has_the_contract_keys() {
    let v = json(&["simulate", "push_center", "--json"]);
    let obj = v.as_object().expect("one object");
    for k in CASE_KEYS
        .iter()
        .chain(["dt", "duration", "outcome", "first_slip_s", "transitions"].iter())
    {
        assert!(obj.contains_key(*k), "key `{k}` missing: {v}");
    }
    assert_eq!(v["name"], "push_center");
    assert_eq!(v["caliper"], "push");
    assert_eq!(num(&v, "beta"), 0.040);
    assert_eq!(v["outcome"], "completed");
    assert_eq!(num(&v, "dt"), 1.0 / 25600.0);
    assert_eq!(num(&v, "duration"), 1.0);
    for k in ["x_pp", "xdot_pp", "phi_pp", "phidot_pp", "stick_slip_hz"] {
        let x = num(&v, k);
        assert!(x.is_finite() && x > 0.0, "{k} = {x}");
    }
    let sf = num(&v, "stick_fraction");
    assert!(sf > 0.0 && sf < 1.0, "stick_fraction = {sf}");
    let first = num(&v, "first_slip_s");
    assert!(first > 0.0 && first < 1.0);
    assert!(v["transitions"].as_u64().unwrap() > 0);
}

/// model.md's closed form of the mass on a moving belt, for the oracle_1dof scene
/// (m = 1, k = 100, N = 10, V = 0.05, mu_s = 0.6, mu_k = 0.4; statistics on [1.3, 6] s).
#[test]
fn oracle_1dof_matches_the_closed_form() {
    let (m, k, n, v, mu_s, mu_k) = (1.0f64, 100.0f64, 10.0, 0.05, 0.6, 0.4);
    let omega = (k / m).sqrt();
    let delta = (mu_s - mu_k) * n / k;
    let x_k = mu_k * n / k;
    let t_stick = 2.0 * delta / v;
    let t_slip = (2.0 * std::f64::consts::PI - 2.0 * (omega * delta / v).atan()) / omega;
    let r = (delta * delta + (v / omega).powi(2)).sqrt();
    // model.md's check values, so that the formulas above are the documented ones
    close(t_stick, 0.8, 1e-12, "T_stick");
    close(t_slip, 0.363155, 1e-5, "T_slip");
    close(x_k + r, 0.0606155, 1e-6, "x_max");
    close(x_k - r, 0.0193845, 1e-5, "x_min");
    // From rest the pad sticks until x_s = mu_s N / k; then slips of T_slip alternate with
    // sticks of T_stick. Stick fraction over [1.3, 6] s from that timeline:
    let (w0, w1) = (1.3, 6.0);
    let mut slip_start = mu_s * n / k / v;
    let mut slip_in_window = 0.0;
    let mut onsets_in_window = 0;
    while slip_start < w1 {
        let (a, b) = (slip_start.max(w0), (slip_start + t_slip).min(w1));
        if b > a {
            slip_in_window += b - a;
        }
        if slip_start >= w0 {
            onsets_in_window += 1;
        }
        slip_start += t_slip + t_stick;
    }
    assert_eq!(onsets_in_window, 4, "test timeline");
    let stick_fraction = 1.0 - slip_in_window / (w1 - w0);

    let j = json(&["simulate", "oracle_1dof", "--json"]);
    assert_eq!(j["outcome"], "completed");
    close(num(&j, "x_pp"), 2.0 * r, 1e-9, "x_pp");
    close(
        num(&j, "xdot_pp"),
        v + ((omega * delta).powi(2) + v * v).sqrt(),
        1e-9,
        "xdot_pp",
    );
    assert_eq!(num(&j, "phi_pp"), 0.0, "rotation off: phi held");
    assert_eq!(num(&j, "phidot_pp"), 0.0, "rotation off: phi held");
    close(
        num(&j, "stick_slip_hz"),
        1.0 / (t_stick + t_slip),
        1e-9,
        "stick_slip_hz",
    );
    close(
        num(&j, "stick_fraction"),
        stick_fraction,
        1e-9,
        "stick_fraction",
    );
    close(
        num(&j, "first_slip_s"),
        mu_s * n / k / v,
        1e-9,
        "first slip",
    );
    assert_eq!(j["slip_onsets"].as_u64(), Some(onsets_in_window));
    close(num(&j, "period_mean_s"), t_stick + t_slip, 1e-9, "period");
    assert!(
        num(&j, "period_sd_s") < 1e-9,
        "a periodic motion has no period spread"
    );

    // the f32 stepper agrees to f32's resolution
    let j32 = json(&["simulate", "oracle_1dof", "--json", "--precision", "f32"]);
    assert_eq!(j32["precision"], "f32");
    close(num(&j32, "x_pp"), 2.0 * r, 1e-4, "f32 x_pp");
    close(
        num(&j32, "stick_slip_hz"),
        1.0 / (t_stick + t_slip),
        1e-4,
        "f32 stick_slip_hz",
    );
}

#[test]
fn thesis_mu_has_no_sustained_stick_slip() {
    // model.md: with mu_k = mu_s the pad slides after a few early events; its velocity only
    // touches the band's once per 0.49 s, a stick of 3 us (at 0.956 s in the window)
    let j = json(&["simulate", "thesis-mu", "--json"]);
    assert_eq!(j["outcome"], "completed");
    assert_eq!(num(&j, "stick_slip_hz"), 0.0);
    assert!(num(&j, "stick_fraction") < 1e-4, "stick fraction {}", num(&j, "stick_fraction"));
    assert!(num(&j, "first_slip_s") < 0.1, "it does slip early");
}

#[test]
fn cases_json_shape() {
    let v = json(&["cases", "--json"]);
    let cases = v["cases"].as_array().expect("\"cases\" is an array");
    assert_eq!(cases.len(), 6);
    let betas = [0.025, 0.040, 0.055];
    for (i, c) in cases.iter().enumerate() {
        let obj = c.as_object().unwrap();
        let mut keys: Vec<&str> = obj.keys().map(String::as_str).collect();
        keys.sort_unstable();
        let mut want = CASE_KEYS.to_vec();
        want.sort_unstable();
        assert_eq!(keys, want, "case {i} keys");
        assert_eq!(c["name"], CASE_NAMES[i]);
        assert_eq!(c["caliper"], if i < 3 { "push" } else { "pull" });
        assert_eq!(num(c, "beta"), betas[i % 3]);
        for k in ["x_pp", "xdot_pp", "phi_pp", "phidot_pp", "stick_slip_hz"] {
            let x = num(c, k);
            assert!(x.is_finite() && x > 0.0, "{} {k} = {x}", CASE_NAMES[i]);
        }
        let sf = num(c, "stick_fraction");
        assert!(
            sf > 0.0 && sf < 1.0,
            "{} stick_fraction = {sf}",
            CASE_NAMES[i]
        );
    }
    // the cases are the built-in scenes: same numbers as `simulate NAME`
    let s = json(&["simulate", "pull_lead", "--json"]);
    for k in CASE_KEYS {
        assert_eq!(cases[5][k], s[k], "{k}");
    }
}

#[test]
fn cases_markdown_table() {
    let out = ok(&["cases"]);
    let header = out
        .lines()
        .find(|l| l.starts_with("| case"))
        .expect("a table header");
    for unit in [
        "beta [m]",
        "x pp [m]",
        "x' pp [m/s]",
        "phi pp [rad]",
        "phi' pp [rad/s]",
        "stick fraction",
        "[Hz]",
    ] {
        assert!(header.contains(unit), "`{unit}` missing from {header}");
    }
    let cols = header.matches('|').count();
    for name in CASE_NAMES {
        let row = out
            .lines()
            .find(|l| l.starts_with(&format!("| {name} |")))
            .unwrap_or_else(|| panic!("row {name}"));
        assert_eq!(row.matches('|').count(), cols, "{row}");
    }
    assert!(!out.contains("NaN") && !out.contains("inf"));
}

#[test]
fn cases_overrides_apply_to_every_case() {
    let v = json(&[
        "cases",
        "--json",
        "--duration",
        "0.3",
        "--stats-from",
        "0.2",
        "--dt",
        "1e-4",
    ]);
    assert_eq!(num(&v, "duration"), 0.3);
    assert_eq!(num(&v, "dt"), 1e-4);
    assert_eq!(v["cases"].as_array().unwrap().len(), 6);
    bad(&["cases", "--dt", "0"], &["--dt", "field `dt`", "> 0 s"]);
}

#[test]
fn precision_f32_agrees_on_the_periodic_pull_cases() {
    // model.md: the pull cases settle into a periodic cycle, the push cases are irregular.
    let a = json(&["cases", "--json"]);
    let b = json(&["cases", "--json", "--precision", "f32"]);
    for i in 3..6 {
        for k in ["x_pp", "xdot_pp", "stick_fraction", "stick_slip_hz"] {
            close(num(&b["cases"][i], k), num(&a["cases"][i], k), 1e-3, k);
        }
    }
}

#[test]
fn scenes_lists_every_builtin() {
    let out = ok(&["scenes"]);
    for name in BUILTINS {
        let row = out
            .lines()
            .find(|l| l.split_whitespace().next() == Some(name));
        let row = row.unwrap_or_else(|| panic!("{name} not listed:\n{out}"));
        assert!(row.contains("push") || row.contains("pull"), "{row}");
    }
}

#[test]
fn scenes_show_round_trips_through_simulate() {
    let dir = scratch("roundtrip");
    let keys = [
        "name",
        "description",
        "caliper",
        "m",
        "inertia",
        "l",
        "w",
        "l_cl",
        "l_ct",
        "k_l",
        "k_t",
        "k_g",
        "f_n",
        "beta",
        "v",
        "mu_s",
        "mu_k",
        "c_x",
        "c_phi",
        "rotation",
        "dt",
        "duration",
        "stats_from",
    ];
    for name in BUILTINS {
        let text = ok(&["scenes", "show", name]);
        for k in keys {
            let line = text
                .lines()
                .find(|l| l.starts_with(&format!("{k} =")))
                .unwrap_or_else(|| panic!("{name}: key {k} missing"));
            assert!(line.contains('#'), "{name}: `{k}` has no comment: {line}");
        }
        let file = write(&dir, &format!("{name}.toml"), &text);
        let from_file = ok(&["simulate", &file, "--json"]);
        let builtin = ok(&["simulate", name, "--json"]);
        assert_eq!(
            from_file, builtin,
            "{name}: the shown file runs the same scene"
        );
    }
}

#[test]
fn scene_file_keys_left_out_take_the_default_pad() {
    let dir = scratch("partial");
    let file = write(
        &dir,
        "pull.toml",
        "name = \"pull_center\"\ncaliper = \"pull\"\n",
    );
    assert_eq!(
        ok(&["simulate", &file, "--json"]),
        ok(&["simulate", "pull_center", "--json"])
    );
}

#[test]
fn csv_has_a_header_and_one_row_per_step() {
    let dir = scratch("csv");
    let f = dir.join("run.csv");
    let f_s = f.to_str().unwrap();
    for (dt, duration, rows) in [("3.90625e-5", "0.01", 256usize), ("1e-4", "0.02", 200)] {
        ok(&[
            "simulate",
            "--csv",
            f_s,
            "--dt",
            dt,
            "--duration",
            duration,
            "--stats-from",
            "0",
        ]);
        let text = fs::read_to_string(&f).unwrap();
        let mut lines = text.lines();
        assert_eq!(
            lines.next(),
            Some("t_s,x_m,xdot_m_per_s,phi_rad,phidot_rad_per_s,n_N,f_f_N,regime")
        );
        let body: Vec<&str> = lines.collect();
        assert_eq!(body.len(), rows, "dt {dt}, duration {duration}");
        let dt: f64 = dt.parse().unwrap();
        for (i, row) in body.iter().enumerate() {
            let f: Vec<&str> = row.split(',').collect();
            assert_eq!(f.len(), 8, "{row}");
            let t: f64 = f[0].parse().unwrap();
            close(t, (i + 1) as f64 * dt, 1e-9, "t");
            for v in &f[1..7] {
                assert!(v.parse::<f64>().unwrap().is_finite(), "{row}");
            }
            assert!(
                ["stick", "slip_slower", "slip_faster"].contains(&f[7]),
                "{row}"
            );
        }
        // the run starts in stick at the band speed V = 0.005 m/s
        assert!(
            body[0].ends_with(",stick") && body[0].split(',').nth(2) == Some("0.005"),
            "{}",
            body[0]
        );
    }
}

#[test]
fn plots_writes_eight_svg_figures_with_legends() {
    let dir = scratch("plots");
    let out = stickslip(&[
        "cases",
        "--plots",
        dir.to_str().unwrap(),
        "--duration",
        "0.2",
        "--stats-from",
        "0.1",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let mut n = 0;
    for caliper in ["push", "pull"] {
        for q in [
            "displacement",
            "velocity",
            "angular_displacement",
            "angular_velocity",
        ] {
            let p = dir.join(format!("{caliper}_{q}.svg"));
            let svg = fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            assert!(svg.contains("<svg"), "{}", p.display());
            for label in [
                "β = 0.025 m (trailing)",
                "β = 0.040 m (centre)",
                "β = 0.055 m (leading)",
                "time t [s]",
            ] {
                assert!(svg.contains(label), "{}: `{label}` missing", p.display());
            }
            // the data are drawn: 0.1 s at 25600 steps/s is 2560 points per line
            let points: usize = svg
                .lines()
                .filter(|l| l.starts_with("<polyline"))
                .map(|l| l.matches(',').count())
                .sum();
            assert!(points > 3000, "{}: only {points} points drawn", p.display());
            assert!(svg.contains(if caliper == "push" {
                "Push caliper"
            } else {
                "Pull caliper"
            }));
            n += 1;
        }
    }
    assert_eq!(n, 8);
    assert_eq!(
        fs::read_dir(&dir).unwrap().count(),
        8,
        "exactly the 8 figures"
    );
}

#[test]
fn bad_scene_files_exit_2_with_one_line() {
    let dir = scratch("bad");
    let missing = dir.join("nope.toml");
    bad(
        &["simulate", missing.to_str().unwrap()],
        &["nope.toml", "cannot read"],
    );
    let f = write(&dir, "syntax.toml", "name = \"x\"\nm = [1\n");
    bad(&["simulate", &f], &["syntax.toml", "line 2"]);
    let f = write(&dir, "unknown.toml", "name = \"x\"\nbogus = 1\n");
    bad(&["simulate", &f], &["unknown.toml", "line 2", "bogus"]);
    let f = write(&dir, "type.toml", "m = \"heavy\"\n");
    bad(&["simulate", &f], &["type.toml", "line 1", "invalid type"]);
    let f = write(&dir, "caliper.toml", "caliper = \"sideways\"\n");
    bad(&["simulate", &f], &["caliper.toml", "sideways"]);
    let f = write(&dir, "nan.toml", "name = \"x\"\nk_g = nan\n");
    bad(
        &["simulate", &f],
        &["nan.toml", "line 2", "field `k_g`", "finite"],
    );
    let f = write(&dir, "inf.toml", "f_n = inf\n");
    bad(&["simulate", &f], &["inf.toml", "field `f_n`", "finite"]);
    let f = write(&dir, "neg.toml", "name = \"x\"\n\nm = -1\n");
    let line = bad(&["simulate", &f], &["neg.toml", "line 3"]);
    assert!(
        line.ends_with("field `m` = -1: mass must be > 0 kg"),
        "{line}"
    );
    let f = write(&dir, "mu.toml", "mu_s = 0.3\nmu_k = 0.4\n");
    bad(
        &["simulate", &f],
        &["mu.toml", "field `mu_k`", "mu_k <= mu_s"],
    );
    let f = write(&dir, "beta.toml", "beta = 0.1\n");
    bad(
        &["simulate", &f],
        &["beta.toml", "field `beta`", "0 <= beta <= 2 l"],
    );
    // `scenes show FILE` checks the same way
    bad(&["scenes", "show", &f], &["beta.toml", "field `beta`"]);
}

#[test]
fn unknown_builtin_lists_the_valid_names() {
    let line = bad(&["simulate", "push_middle"], &["push_middle"]);
    for name in BUILTINS {
        assert!(line.contains(name), "{name} not offered: {line}");
    }
    bad(
        &["scenes", "show", "push_middle"],
        &["push_middle", "oracle_1dof"],
    );
}

#[test]
fn bad_dt_and_duration_exit_2() {
    bad(&["simulate", "--dt", "abc"], &["--dt"]);
    bad(
        &["simulate", "--dt", "-1"],
        &["--dt", "field `dt`", "> 0 s"],
    );
    bad(&["simulate", "--dt", "0"], &["--dt", "field `dt`"]);
    bad(&["simulate", "--dt", "nan"], &["--dt", "finite"]);
    bad(&["simulate", "--dt", "2"], &["--dt", "run length"]);
    bad(&["simulate", "--duration", "xyz"], &["--duration"]);
    bad(
        &["simulate", "--duration", "-0.5"],
        &["--duration", "field `duration`"],
    );
    bad(
        &["simulate", "--duration", "inf"],
        &["--duration", "finite"],
    );
    bad(
        &["simulate", "--duration", "0.3"],
        &["--duration 0.3", "field `stats_from`"],
    );
    bad(&["cases", "--duration", "0"], &["--duration"]);
    bad(&["simulate", "--precision", "f16"], &["f16"]);
    bad(&["frobnicate"], &["frobnicate"]);
}

#[test]
fn a_halted_run_is_a_finding_not_a_crash() {
    let dir = scratch("halt");
    // Strong friction on a fast band: the pad's rotation overshoots and N goes negative.
    let f = write(
        &dir,
        "lift.toml",
        "name = \"lift\"\nmu_s = 4.0\nmu_k = 3.6\nv = 0.5\n",
    );
    let j = json(&["simulate", &f, "--json"]);
    assert_eq!(j["outcome"], "contact_loss");
    assert!(num(&j, "halt_t_s") > 0.0 && num(&j, "halt_t_s") < 0.5);
    assert!(
        j["x_pp"].is_null(),
        "no statistics from a window the run never reached"
    );
    let text = ok(&["simulate", &f]);
    assert!(
        text.contains("contact_loss") && !text.contains("NaN"),
        "{text}"
    );
    // Thick pad, strong friction: mu_s w c_N > K, the push pad self-locks and never slips.
    let f = write(
        &dir,
        "lock.toml",
        "name = \"lock\"\nmu_s = 4.0\nmu_k = 3.6\nv = 0.5\nw = 0.03\n",
    );
    let j = json(&["simulate", &f, "--json"]);
    assert_eq!(j["outcome"], "sprag");
    assert!(j["first_slip_s"].is_null());
    let out = stdout(&stickslip(&["simulate", &f, "--json"]));
    assert!(!out.contains("NaN") && !out.contains("inf"));
}
