//! No silent wrong answer (issue 33): one test per class of bad or careless input, each through
//! the binary as a user runs it, asserting exit code 2 and one line naming the file or option
//! and the rule (or, for a run that would take hours, the classified outcome `budget`).
//! Expected figures are worked out here from the inputs (closed forms), not read from the tool.

mod recorded_common;

use recorded_common::*;
use serde_json::Value;

/// A scene file of the given keys (every other key: the default pad's).
fn scene(dir: &std::path::Path, name: &str, keys: &str) -> String {
    write(dir, name, keys)
}

#[test]
fn files_read_whole_are_bounded() {
    let dir = scratch("hardening-files");
    // /dev/zero never ends: each reader stops at its limit, with one line naming the file
    if std::path::Path::new("/dev/zero").exists() {
        bad(&["simulate", "/dev/zero"], &["/dev/zero", "scene file", "larger than 1 MiB"]);
        bad(&["fit", "--scene", "push_center", "--free", "mu_k", "--table", "/dev/zero"], &["/dev/zero", "table", "larger than 1 MiB"]);
        bad(&["map", "merge", "/dev/zero"], &["/dev/zero", "map shard", "larger than 64 MiB"]);
        bad(&["decode", "--elf", "/dev/zero", "/dev/null"], &["/dev/zero", "ELF", "larger than 64 MiB"]);
    }
    // a regular file one byte over the scene limit (1 MiB = 1048576 bytes): a comment line
    let big = "#".repeat(1 << 20) + "\n";
    let f = write(&dir, "big.toml", big);
    bad(&["simulate", &f], &["big.toml", "larger than 1 MiB"]);
    // a directory is not a scene file
    bad(&["simulate", dir.to_str().unwrap()], &["directory"]);
}

#[test]
fn runs_that_would_take_hours_halt_as_budget() {
    let dir = scratch("hardening-budget");
    // m = 1e-30 kg: the x mode's rate sqrt(k_g / m) is about 1e18 1/s; at dt = 1/25600 s the
    // quarter-radian rule asks for 1e18 * 3.9e-5 / 0.25 = 1.6e14 substeps per step, far past
    // the cap of 4096
    let tiny_m = scene(&dir, "tiny_m.toml", "m = 1e-30\n");
    let band_stiff = scene(&dir, "band_stiff.toml", "friction = \"stribeck\"\nband = true\nk_b = 1e30\n");
    let zeta = scene(&dir, "zeta.toml", "zeta_x = 1e6\n");
    for f in [&tiny_m, &band_stiff, &zeta] {
        let j = json(&["simulate", f, "--json"]);
        assert_eq!(j["outcome"], "budget", "{f}: {j}");
        assert_eq!((j["halt_t_s"].as_f64(), j["transitions"].as_u64()), (Some(0.0), Some(0)), "{f}: not stepped");
        let text = ok(&["simulate", f]);
        assert!(text.contains("halted, budget:") && text.contains("substeps per step"), "{f}: {text}");
        let s = json(&["sil", f, "--json"]);
        assert_eq!(s["outcome"], "budget", "{f}: {s}");
    }
    // a run whose substeps are few but whose steps are many: 2^27 = 134217728 is the budget;
    // 2e4 s at 1/25600 s is 5.12e8 steps of one substep each
    let long = json(&["simulate", "push_center", "--duration", "20000", "--json"]);
    assert_eq!(long["outcome"], "budget");
    // the event-driven runs (unilateral contact, the pneumatic drive) have the budget too: at
    // dt = 1e-9 s, 5e8 grid times; they ran for hours (a campaign's hang)
    let pneumatic = dir.join("pneumatic.toml");
    std::fs::write(&pneumatic, ok(&["scenes", "show", "rig_push_center"]) + "drive = \"pneumatic\"\n").unwrap();
    for f in ["rig_built_push_center", pneumatic.to_str().unwrap()] {
        let j = json(&["simulate", f, "--dt", "1e-9", "--duration", "0.5", "--stats-from", "0.2", "--json"]);
        assert_eq!((j["outcome"].as_str(), j["transitions"].as_u64()), (Some("budget"), Some(0)), "{f}: {j}");
    }
    // a pneumatic drive too stiff for the event runner's steps (a throttle 1e8 times wider than
    // the solved one; a band of 1 ug): the steps shrink to 1e-11 s. Such a run used its whole
    // budget (22 s for 1 s, 40 minutes for 100 s) and then halted as a `transition_storm`; it
    // stops at its pace now, and is called what it is
    let rig_pn = ok(&["scenes", "show", "rig_push_center"]) + "drive = \"pneumatic\"\n";
    for (name, extra) in [("wide_throttle.toml", "throttle_conductance = 1e-3\n"), ("light_band.toml", "")] {
        let body = if extra.is_empty() { rig_pn.replace("\nm_b = 2.0", "\nm_b = 1e-9") } else { rig_pn.clone() + extra };
        assert!(body.contains("m_b = 1e-9") || !extra.is_empty(), "the light band's key");
        let f = scene(&dir, name, &body);
        let j = json(&["simulate", &f, "--duration", "100", "--json"]);
        assert_eq!(j["outcome"], "stalled", "{name}: {j}");
        assert!(j["halt_t_s"].as_f64().unwrap() < 0.01, "{name}: {j}");
        let text = ok(&["simulate", &f, "--duration", "100"]);
        assert!(text.contains("halted, stalled:") && text.contains("too stiff"), "{name}: {text}");
    }
    // the virtual rig over the budget builds no quiet lead either (at dt = 1e-9 s its 0.1 s
    // would be 1e8 frames): nothing is sampled
    let rig = json(&["sil", "push_center", "--dt", "1e-9", "--json"]);
    assert_eq!((rig["outcome"].as_str(), rig["samples"].as_u64()), (Some("budget"), Some(0)), "{rig}");
    // the advice: the work is about max(steps, duration x the fastest rate / a quarter radian),
    // so a smaller dt never helps (it said "a smaller dt" before); one substep a step: a larger
    // dt; many (m = 1e-7 kg: 221 a step): the fastest mode, whatever dt
    let steps_bound = ok(&["simulate", "push_center", "--dt", "1e-9"]);
    assert!(steps_bound.contains("a larger dt") && !steps_bound.contains("smaller dt"), "{steps_bound}");
    let fast = scene(&dir, "fast_m.toml", "m = 1e-7\nduration = 500.0\n");
    let substeps_bound = ok(&["simulate", &fast]);
    assert!(substeps_bound.contains("halted, budget:") && substeps_bound.contains("slower fastest mode"), "{substeps_bound}");
    assert!(!substeps_bound.contains("smaller dt") && !substeps_bound.contains("larger dt"), "{substeps_bound}");
    // through a map: k_b = 1e6 runs; 1e18 (rate sqrt(k_b / m_b) about 1e9 1/s: 1.6e5 substeps
    // per step) and 1e30 are over the budget
    let m = json(&["map", "rig_push_center", "--sweep", "k_b=1e6:1e30:3:log", "--duration", "0.05", "--stats-from", "0.02", "--json"]);
    let regimes: Vec<&str> = m["cells"].as_array().unwrap().iter().map(|c| c["from_rest"]["regime"].as_str().unwrap()).collect();
    assert_ne!(regimes[0], "budget");
    assert_eq!(&regimes[1..], ["budget", "budget"]);
}

#[test]
fn scenes_at_the_ends_of_the_number_range_end_in_an_outcome_not_a_hang() {
    // each of these once hung in the set-up: a row of the system matrix summing to inf (k_g =
    // 1e308 over m = 0.3 kg overflows), and the balancing before the matrix exponential and
    // before the eigenvalues halved inf for ever. Each scene is valid (every value a finite
    // number > 0); what the run makes of it must be a classified outcome.
    let dir = scratch("hardening-range-ends");
    for (i, keys) in ["k_g = 1e308\n", "f_n = 1e307\n", "m = 1e-310\n", "inertia = 1e-320\n", "k_l = 1e308\n"].iter().enumerate() {
        let f = scene(&dir, &format!("ends_{i}.toml"), keys);
        let j = json(&["simulate", &f, "--duration", "0.01", "--stats-from", "0.005", "--json"]);
        let outcome = j["outcome"].as_str().unwrap_or_default().to_string();
        assert!(!outcome.is_empty(), "{keys}: {j}");
        let s = json(&["sil", &f, "--duration", "0.01", "--stats-from", "0.005", "--json"]);
        assert!(s["outcome"].is_string(), "{keys}: {s}");
    }
    // the map's linear analysis: its eigenvalues of the same overflowing matrix
    let m = json(&["map", "push_center", "--sweep", "k_g=1e307:1.7e308:2:log", "--duration", "0.01", "--stats-from", "0.005", "--json"]);
    assert_eq!(m["cells"].as_array().map(Vec::len), Some(2), "{m}");
}

#[test]
fn counts_are_capped_and_name_their_option() {
    bad(&["map", "push_center", "--sweep", "beta=0.01:0.07:1000000000"], &["--sweep", "1000000000", "100000"]);
    bad(&["map", "push_center", "--sweep", "beta=0.01:0.07:10000", "--sweep", "mu_s=0.4:0.8:10000"], &["cells", "10000000"]);
    bad(&["map", "push_center", "--sweep", "beta=0.01:0.07:3", "--shard", "0/1000000000"], &["--shard 0/1000000000"]);
    bad(&["map", "push_center", "--sweep", "beta=0.01:0.07:3", "--shard", "-1/3"], &["--shard -1/3"]);
    bad(&["map", "push_center", "--sweep", "beta=0.01:0.07:3", "--jobs", "0"], &["--jobs"]);
    bad(&["fit", "--scene", "push_center", "--free", "mu_k", "--table", "thesis_table_3_1", "--profile", "mu_k=0.1:0.4:1000000000"], &["--profile", "1000"]);
    bad(&["fit", "--scene", "push_center", "--free", "mu_k", "--table", "thesis_table_3_1", "--starts", "100000"], &["--starts 100000"]);
    bad(&["sil", "push_center", "--quiet-lead", "1e6"], &["--quiet-lead", "60"]);
    bad(&["sil", "push_center", "--oversample", "17"], &["--oversample"]);
    bad(&["accuracy", "--repeats", "1000"], &["--repeats"]);
}

#[test]
fn the_virtual_rig_noise_and_gain_are_checked_and_its_health_applied() {
    // out of range: one line, the number short
    let l = bad(&["sil", "push_center", "--noise", "1e300"], &["--noise 1.000e300", "m/s^2"]);
    assert!(l.len() < 200, "{l}");
    bad(&["sil", "push_center", "--gain", "1e6"], &["--gain 1000000", "V/V"]);
    bad(&["sil", "push_center", "--gain", "1e-300"], &["--gain 1.000e-300"]);
    bad(&["compare", "push_center", "/dev/null", "--gain", "0"], &["--gain 0"]);
    // in range but every frame saturated: gain 1000 spans +-0.16 m/s^2 (100 mV/g x 1000 over
    // the ADC's +-1.65 V), and push_center's pad_x swings by hundreds of m/s^2
    let j = json(&["sil", "push_center", "--gain", "1000", "--json"]);
    assert!(j["saturated_frames"].as_u64().unwrap() > 0);
    assert!(j["undecided"].as_str().unwrap().contains("pad_x"), "{j}");
    assert!(j["health"]["pad_x"].as_array().unwrap().iter().any(|w| w == "saturated"), "{j}");
    assert_eq!(j["stick_fraction"]["estimated"], Value::Null);
    assert_eq!(j["channels"]["pad_x"]["pp"]["estimated"], Value::Null);
    let text = ok(&["sil", "push_center", "--gain", "1000"]);
    assert!(text.contains("cannot decide") && text.contains("Channel pad_x: saturated"), "{text}");
    assert!(!text.contains("inf") && !text.contains("NaN"), "{text}");
    // the default virtual rig is healthy: none of the new keys
    let d = json(&["sil", "push_center", "--json"]);
    assert!(d.get("undecided").is_none() && d.get("health").is_none(), "{d}");
}

#[test]
fn fit_inputs_are_checked() {
    let dir = scratch("hardening-fit");
    let head = "case,channel,statistic,value\n";
    let sf = write(&dir, "sf.csv", format!("{head}push_center,,stick_fraction,1.5\npush_center,pad_x,pp,100\n"));
    bad(&["fit", "--scene", "push_center", "--free", "mu_k", "--table", &sf], &["sf.csv", "line 2", "stick_fraction", "1.5"]);
    let huge = write(&dir, "huge.csv", format!("{head}push_center,pad_x,pp,1e308\n"));
    bad(&["fit", "--scene", "push_center", "--free", "mu_k", "--table", &huge], &["huge.csv", "line 2", "pp", "1.000e308"]);
    let tiny = write(&dir, "tiny.csv", format!("{head}push_center,pad_x,pp,1e-308\n"));
    bad(&["fit", "--scene", "push_center", "--free", "mu_k", "--table", &tiny], &["tiny.csv", "line 2", "1.000e-308"]);
    // keys that do nothing
    bad(&["fit", "--scene", "push_center", "--free", "k_b", "--table", "thesis_table_3_1"], &["--free k_b", "no band"]);
    bad(&["fit", "--scene", "push_center", "--free", "v_s", "--table", "thesis_table_3_1"], &["--free v_s", "Coulomb"]);
    bad(&["map", "push_center", "--sweep", "v_s=0.01:0.1:3"], &["--sweep v_s=0.01:0.1:3", "Coulomb"]);
    // the profile's grid: its ends are LO and HI exactly, every point finite and inside, log-spaced
    let v = stickslip::fit::profile_values(0.1, 4.0, 5);
    assert_eq!((v[0], v[4]), (0.1, 4.0));
    // middle: 0.1 x 40^(i/4), by hand: 0.1 x 40^0.5 = 0.632456
    assert!((v[2] - 0.1 * 40f64.sqrt()).abs() < 1e-12);
    let w = stickslip::fit::profile_values(1e-300, 1e300, 3);
    assert_eq!((w[0], w[2]), (1e-300, 1e300));
    // the geometric middle of 1e-300 and 1e300 is 1
    assert!((w[1] - 1.0).abs() < 1e-9, "{w:?}");
    assert!(w.iter().all(|x| x.is_finite()));
}

/// A small real map's JSON, made by the tool: beta over 2 values, short runs.
fn small_map(dir: &std::path::Path) -> Value {
    let out = ok(&["map", "push_center", "--sweep", "beta=0.01:0.07:2", "--duration", "0.05", "--stats-from", "0.02", "--json"]);
    let _ = dir;
    serde_json::from_str(&out).unwrap()
}

#[test]
fn map_merge_checks_each_shard_against_its_header() {
    let dir = scratch("hardening-merge");
    let good = small_map(&dir);
    let f = write(&dir, "good.json", good.to_string());
    ok(&["map", "merge", &f]);
    let tamper = |name: &str, edit: &dyn Fn(&mut Value), needles: &[&str]| {
        let mut m = good.clone();
        edit(&mut m);
        let p = write(&dir, name, m.to_string());
        let mut n = vec![name];
        n.extend_from_slice(needles);
        bad(&["map", "merge", &p], &n);
        // with --plot and --csv too: the input is blamed, nothing panics
        let svg = dir.join("out.svg");
        let csv = dir.join("out.csv");
        bad(&["map", "merge", &p, "--plot", svg.to_str().unwrap(), "--csv", csv.to_str().unwrap()], &n);
    };
    tamper("dt0.json", &|m| m["dt_s"] = 0.0.into(), &["dt_s = 0"]);
    tamper("dur.json", &|m| m["duration_s"] = (-1.0).into(), &["duration_s = -1"]);
    tamper("prec.json", &|m| m["precision"] = "f128".into(), &["precision `f128`"]);
    tamper("regime.json", &|m| m["cells"][0]["from_rest"]["regime"] = "bogus".into(), &["cell 0", "regime `bogus`"]);
    tamper("offgrid.json", &|m| m["cells"][1]["params"]["beta"] = 0.05.into(), &["cell 1", "beta = 0.05", "0.07"]);
    tamper("n0.json", &|m| m["sweeps"][0]["n"] = 0.into(), &["sweeps", "N `0`"]);
    tamper("n3.json", &|m| m["sweeps"][0]["n"] = 3.into(), &["cells_total = 2", "3 cells"]);
    tamper("total.json", &|m| m["cells_total"] = 5.into(), &["cells_total = 5"]);
    tamper("order.json", &|m| m["cells"].as_array_mut().unwrap().swap(0, 1), &["cell 1 at position 0"]);
    tamper("kick.json", &|m| m["kick"] = 7.0.into(), &["kick = 7"]);
    tamper("key.json", &|m| m["sweeps"][0]["key"] = "warp".into(), &["sweeps", "warp"]);
}

#[test]
fn decode_refuses_a_stream_of_another_build() {
    let elf = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/defmt-fixture.elf");
    let stream = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/defmt-fixture.defmt")).unwrap();
    // another build's stream: the same frames, each naming another format (its index's low
    // byte changed). In rzCOBS the first byte of a frame is the first byte of the message when
    // that is not zero (the group's non-zero bytes come first, its group byte after them), and
    // the message starts with the format's index, u16 little-endian.
    let mut other = stream.clone();
    let mut start = true;
    let mut changed = 0;
    for b in other.iter_mut() {
        if start && *b != 0 {
            *b = if *b == 0xFE { 0x01 } else { *b + 1 };
            changed += 1;
        }
        start = *b == 0;
    }
    assert!(changed >= 8);
    let dir = scratch("hardening-decode");
    let f = write(&dir, "other.defmt", &other);
    bad(&["decode", "--elf", elf, &f], &["other.defmt", "do not fit the defmt table", "defmt-fixture.elf"]);
    // the fixture itself still decodes whole (every frame fits its format)
    let j = json(&["decode", "--elf", elf, concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/defmt-fixture.defmt"), "--json"]);
    assert_eq!(j["stream"]["frames_dropped"], 0);
}

#[test]
fn errors_are_short_and_blame_what_the_user_gave() {
    let dir = scratch("hardening-unclear");
    let rec = write(&dir, "rec.csv", "t,disc_x,pad_x,pad_trail,pad_lead\n0,0,0,0,0\n0.001,0,1,0,0\n");
    bad(&["analyze", &rec, "--breakaway-jump", "1e308"], &["--breakaway-jump 1.000e308"]);
    // CR-only line endings (old Mac): named as such
    let mut cr = String::from("t,disc_x,pad_x,pad_trail,pad_lead\r");
    for i in 0..20000 {
        cr.push_str(&format!("{},0,0,0,0\r", i as f64 / 25600.0));
    }
    let crf = write(&dir, "cr.csv", cr);
    bad(&["analyze", &crf], &["cr.csv", "CR alone"]);
    // a duplicate key in a scene file is named, with its line
    let dup = scene(&dir, "dup.toml", "m = 1.0\nbeta = 0.02\nm = 2.0\n");
    bad(&["simulate", &dup], &["dup.toml", "line 3", "m"]);
    // a value printed short, not as 300 digits
    let huge = scene(&dir, "huge.toml", "f_n = -1e300\n");
    let l = bad(&["simulate", &huge], &["huge.toml", "f_n", "-1.000e300"]);
    assert!(l.len() < 300, "{l}");
    // ... and in a recording's cell (it printed all 301 digits of -1e300)
    let huge_csv = write(&dir, "huge.csv", "t_s,disc_x_m_s2,pad_x_m_s2,pad_trail_m_s2,pad_lead_m_s2\n0,0,0,0,0\n0.001,0,-1e300,0,0\n");
    let l = bad(&["analyze", &huge_csv], &["huge.csv", "line 3", "-1.000e300 m/s^2 is beyond the plausible range"]);
    assert!(l.len() < 300, "{l}");
    // a rule on a word key names its word, not a number (it printed `contact` = inf, `drive` = 0)
    let hinged = scene(&dir, "hinged.toml", "contact = \"unilateral\"\n");
    bad(&["simulate", &hinged], &["hinged.toml", "field `contact` = \"unilateral\": unilateral contact needs a pad that is not hinged"]);
    // unilateral contact with no load: refused, naming f_n (it halted as a transition storm at
    // t = 0: the edges carried nothing and opened and closed at once)
    let unloaded = scene(&dir, "unloaded.toml", "contact = \"unilateral\"\nk_pivot = 0.0\nface = true\nfriction = \"stribeck\"\nf_n = 0.0\n");
    bad(&["simulate", &unloaded], &["unloaded.toml", "field `f_n` = 0", "unilateral contact needs a normal load"]);
    let no_band = scene(&dir, "no_band.toml", "drive = \"pneumatic\"\n");
    bad(&["simulate", &no_band], &["no_band.toml", "field `drive` = \"pneumatic\": a pneumatic drive pushes the band"]);
    // a recording that ends before the scene's stats_from: the start is the scene's, not a
    // --from the user never gave
    let short = dir.join("short.csv");
    ok(&["sil", "push_center", "--duration", "0.3", "--stats-from", "0.1", "--csv", short.to_str().unwrap()]);
    let arg = format!("push_center={}", short.display());
    let l = bad(&["fit", "--scene", "push_center", "--free", "mu_k", &arg], &["short.csv", "stats_from", "no --from given"]);
    assert!(!l.contains("--from 0.5"), "{l}");
    bad(&["fit", "--scene", "push_center", "--free", "mu_k", &arg, "--from", "0.4"], &["--from 0.4 s"]);
    // a shard given twice: both files named
    let m = ok(&["map", "push_center", "--sweep", "beta=0.01:0.07:2", "--duration", "0.05", "--stats-from", "0.02", "--json"]);
    let a = write(&dir, "a.json", &m);
    let b = write(&dir, "b.json", &m);
    bad(&["map", "merge", &a, &b], &["cell 0", "a.json", "b.json"]);
    // a step as long as the statistics window: every statistic would be n/a
    bad(&["cases", "--dt", "1"], &["--dt", "holds no step"]);
    // dt = 0.8 s: round(1 / 0.8) = 1 step, the window starting at step round(0.5 / 0.8) = 1
    bad(&["simulate", "push_center", "--dt", "0.8"], &["--dt", "holds no step"]);
}

#[test]
fn a_scene_key_that_does_nothing_in_its_scene_gets_a_note() {
    let dir = scratch("hardening-inert-keys");
    // v_s under Coulomb friction, k_b without the band: the run is the base scene's, and
    // stderr says which value was not used and why
    for (keys, needle) in [("v_s = 0.001\n", "`v_s` = 0.001"), ("k_b = 1e5\n", "`k_b` = ")] {
        let f = scene(&dir, &format!("inert_{}.toml", &keys[..3]), keys);
        let o = stickslip(&["simulate", &f, "--duration", "0.02", "--stats-from", "0.01", "--json"]);
        assert_eq!(o.status.code(), Some(0), "{keys}");
        let err = stderr(&o);
        assert!(err.contains(needle) && err.contains("does nothing") && err.contains(&f), "{keys}: {err}");
    }
    // a file that sets every key at its default (as `scenes show` writes it) gets no note
    let shown = ok(&["scenes", "show", "push_center"]);
    let f = write(&dir, "shown.toml", &shown);
    let o = stickslip(&["simulate", &f, "--duration", "0.02", "--stats-from", "0.01", "--json"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(!stderr(&o).contains("does nothing"), "{}", stderr(&o));
}
