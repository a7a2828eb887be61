//! What `stickslip map` writes, as a user reads it (the binary, as a shell runs it): the
//! table's and the CSV's columns are the sweeps' in the order given, `map merge` takes the
//! command's own output, a cell's pad_x peak-to-peak keeps the peak of x'' at a re-stick
//! (between step ends), and the damping ratios a scene file gives hold in every cell. The
//! references are the map's own JSON read by key, and `simulate` of each cell's scene (whose
//! pad_x peak-to-peak is the continuous motion's, from its segments).

use std::path::PathBuf;
use std::process::Command;

use serde_json::Value;

fn stickslip(args: &[&str]) -> (String, String, Option<i32>) {
    let o = Command::new(env!("CARGO_BIN_EXE_stickslip")).args(args).output().expect("the binary runs");
    (String::from_utf8_lossy(&o.stdout).into_owned(), String::from_utf8_lossy(&o.stderr).into_owned(), o.status.code())
}

fn ok(args: &[&str]) -> String {
    let (out, err, code) = stickslip(args);
    assert_eq!(code, Some(0), "{args:?}: {err}");
    out
}

fn json(args: &[&str]) -> Value {
    serde_json::from_str(&ok(args)).unwrap_or_else(|e| panic!("{args:?}: not JSON: {e}"))
}

fn scratch(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("map-written-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// A built-in scene's file with `keys` set (each replacing its line).
fn scene_file(dir: &std::path::Path, name: &str, builtin: &str, drop: &[&str], keys: &[(&str, f64)]) -> PathBuf {
    let text = ok(&["scenes", "show", builtin]);
    let mut lines: Vec<String> = text
        .lines()
        .filter(|l| {
            let key = l.split('=').next().unwrap_or("").trim();
            !keys.iter().any(|(k, _)| *k == key) && !drop.contains(&key)
        })
        .map(String::from)
        .collect();
    lines.extend(keys.iter().map(|(k, v)| format!("{k} = {v:?}")));
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    path
}

/// Sweeps given out of alphabetical order (mu_s before beta): the cells' params are a JSON
/// object (its keys sorted), and the table and the CSV wrote its values in that order under
/// the sweeps' headers, mu_s's column holding beta; `map merge` refused the command's own
/// file ("params [beta, mu_s]: must be the swept keys [mu_s, beta]").
#[test]
fn sweeps_out_of_alphabetical_order_keep_their_columns_and_merge() {
    let dir = scratch("order");
    let csv = dir.join("cells.csv");
    let common = ["map", "push_center", "--sweep", "mu_s=0.4:0.6:2", "--sweep", "beta=0.02:0.06:3", "--duration", "0.06", "--stats-from", "0.03"];
    let mut args = common.to_vec();
    args.extend(["--json", "--csv", csv.to_str().unwrap()]);
    let whole = json(&args);
    let cells = whole["cells"].as_array().unwrap();
    assert_eq!(cells.len(), 6);
    // the CSV: each row's mu_s and beta are its cell's
    let mut r = csv::Reader::from_path(&csv).unwrap();
    let head: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(&head[..3], ["cell", "mu_s", "beta"]);
    for (row, c) in r.records().map(|r| r.unwrap()).zip(cells) {
        for (col, key) in [(1, "mu_s"), (2, "beta")] {
            let got: f64 = row[col].parse().unwrap();
            assert_eq!(got, num(&c["params"][key]), "cell {}: CSV column {key}", c["index"]);
        }
    }
    // the Markdown cells table: the first two columns, mu_s then beta
    let md = ok(&common);
    let rows: Vec<&str> = md.lines().skip_while(|l| !l.starts_with("| mu_s | beta |")).skip(2).take_while(|l| l.starts_with('|')).collect();
    assert_eq!(rows.len(), 6, "{md}");
    for (row, c) in rows.iter().zip(cells) {
        let cols: Vec<f64> = row.split('|').skip(1).take(2).map(|s| s.trim().parse().unwrap()).collect();
        for (got, key) in cols.iter().zip(["mu_s", "beta"]) {
            let want = num(&c["params"][key]);
            assert!((got - want).abs() <= 1e-3 * want.abs(), "cell {}: table column {key}: {got} for {want}", c["index"]);
        }
    }
    // map merge: the unsplit file alone, and its three shards
    let whole_path = dir.join("whole.json");
    std::fs::write(&whole_path, serde_json::to_string(&whole).unwrap()).unwrap();
    let merged: Value = serde_json::from_str(&ok(&["map", "merge", whole_path.to_str().unwrap(), "--json"])).unwrap();
    assert_eq!(merged["cells"], whole["cells"]);
    let mut shards = vec!["map", "merge"];
    let paths: Vec<String> = (0..3)
        .map(|k| {
            let mut a = common.to_vec();
            let shard = format!("{k}/3");
            a.extend(["--json", "--shard", shard.as_str()]);
            let p = dir.join(format!("shard{k}.json"));
            std::fs::write(&p, ok(&a)).unwrap();
            p.to_str().unwrap().to_string()
        })
        .collect();
    shards.extend(paths.iter().map(String::as_str));
    shards.push("--json");
    let merged: Value = serde_json::from_str(&ok(&shards)).unwrap();
    assert_eq!(merged["cells"], whole["cells"]);
}

/// Stribeck friction's x'' peaks at a re-stick, between step ends: the map sampled step ends
/// only, and gave 96.8 m/s^2 for the 146.8 of the continuous motion (and 102.9 and 134.5 at
/// dt / 2 and dt / 4) on this campaign cell. A cell stuck throughout has a stick fraction of
/// 1, not its sum of segments' 1.0000000000000375, which `map merge` refused as above 1.
#[test]
fn a_cells_pad_x_keeps_the_peak_at_re_stick_and_a_stuck_cell_sticks_one() {
    let dir = scratch("peak");
    let v = 0.0021867241478865564;
    let m = json(&["map", "rig_pull_center", "--sweep", "mu_s=0.6:0.6:1", "--sweep", &format!("v=0.0005:{v}:2"), "--duration", "0.3", "--stats-from", "0.15", "--json"]);
    let cells = m["cells"].as_array().unwrap();
    let (stuck, slips) = (&cells[0]["from_rest"], &cells[1]["from_rest"]);
    assert_eq!(stuck["regime"], "stuck");
    assert_eq!(num(&stuck["stick_fraction"]), 1.0);
    assert_eq!(slips["regime"], "stick_slip");
    let file = scene_file(&dir, "cell", "rig_pull_center", &[], &[("mu_s", 0.6), ("v", v)]);
    let sim = json(&["simulate", file.to_str().unwrap(), "--duration", "0.3", "--stats-from", "0.15", "--json"]);
    let (map_pp, sim_pp) = (num(&slips["pad_x_pp"]), num(&sim["pad_x_pp"]));
    assert!((map_pp / sim_pp - 1.0).abs() < 1e-3, "pad_x peak-to-peak: map {map_pp}, simulate {sim_pp}");
    // the map's model-2 runs at event speed: the sampled run's statistics to 1e-5 (docs/maps.md,
    // "Model 2 at event speed"; here 1.5e-12)
    let (map_sf, sim_sf) = (num(&slips["stick_fraction"]), num(&sim["stick_fraction"]));
    assert!((map_sf - sim_sf).abs() <= 1e-9, "stick fraction: map {map_sf}, simulate {sim_sf}");
    let path = dir.join("map.json");
    std::fs::write(&path, serde_json::to_string(&m).unwrap()).unwrap();
    ok(&["map", "merge", path.to_str().unwrap(), "--json"]);
}

/// A scene file that gives its damping as ratios (zeta_x, zeta_phi): each cell of a map that
/// sweeps a stiffness has those ratios (its coefficients from the cell's k_g and contact
/// springs), as `simulate` of the cell's scene file has them. The map used the coefficients at
/// the file's own stiffness: growth -31.22 1/s for -20.35 at k_g = 5e4.
#[test]
fn a_files_damping_ratios_hold_in_every_cell() {
    let dir = scratch("zeta");
    let zeta = [("zeta_x", 0.05), ("zeta_phi", 0.02)];
    let base = scene_file(&dir, "base", "rig_push_center", &["c_x", "c_phi"], &zeta);
    let run = ["--duration", "0.2", "--stats-from", "0.1"];
    let mut args = vec!["map", base.to_str().unwrap(), "--sweep", "k_g=5e4:4e5:2", "--sweep", "k_l=5e5:2e6:2", "--json"];
    args.extend(run);
    let m = json(&args);
    let mut far = 0;
    for c in m["cells"].as_array().unwrap() {
        let (k_g, k_l) = (num(&c["params"]["k_g"]), num(&c["params"]["k_l"]));
        let mut keys = zeta.to_vec();
        keys.extend([("k_g", k_g), ("k_l", k_l)]);
        let file = scene_file(&dir, &format!("cell{}", c["index"]), "rig_push_center", &["c_x", "c_phi"], &keys);
        let mut a = vec!["simulate", file.to_str().unwrap(), "--json"];
        a.extend(run);
        let sim = json(&a);
        let (got, want) = (num(&c["linear"]["max_growth_rate"]), num(&sim["linear"]["max_growth_rate"]));
        assert!((got - want).abs() <= 1e-9 * want.abs(), "cell {}: growth {got} 1/s, simulate {want}", c["index"]);
        // (at event speed: the sampled run's to 1e-5 (docs/maps.md, "Model 2 at event speed"),
        // here within 6e-9)
        let (map_sf, sim_sf) = (num(&c["from_rest"]["stick_fraction"]), num(&sim["stick_fraction"]));
        assert!((map_sf - sim_sf).abs() <= 1e-6, "cell {}: stick fraction {map_sf}, simulate {sim_sf}", c["index"]);
        far += usize::from(k_g != 2e5);
    }
    assert!(far >= 2, "no cell away from the file's own k_g: not the case this test is about");
}

/// An output file that cannot be written (`--csv` or `--plot` into a missing directory) fails
/// at once, before the map runs: a map of hours lost only at its end before.
#[test]
fn an_unwritable_output_fails_before_the_map_runs() {
    let dir = scratch("unwritable");
    let missing = dir.join("no-such-dir").join("out");
    for (option, what) in [("--csv", "CSV"), ("--plot", "figure")] {
        let path = format!("{}.{}", missing.display(), if option == "--csv" { "csv" } else { "svg" });
        let (_, err, code) = stickslip(&["map", "push_center", "--sweep", "beta=0.02:0.06:3", option, &path]);
        assert_eq!(code, Some(1), "{option}: {err}");
        assert!(err.contains(&format!("cannot write the {what}")) && err.contains(&path), "{option}: {err}");
        assert!(!err.contains("map: 3 cells"), "{option}: the map ran first: {err}");
    }
}

/// Unilateral contact: the CSV carries each run's edges' open fractions (the JSON's), which it
/// left out.
#[test]
fn a_unilateral_maps_csv_has_the_open_fractions() {
    let dir = scratch("edges");
    let csv = dir.join("cells.csv");
    let m = json(&["map", "rig_built_push_trail", "--sweep", "beta=0.02:0.06:2", "--duration", "0.2", "--stats-from", "0.1", "--json", "--csv", csv.to_str().unwrap()]);
    let mut r = csv::Reader::from_path(&csv).unwrap();
    let head: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    let col = |name: &str| head.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name}: {head:?}"));
    let rows: Vec<csv::StringRecord> = r.records().map(|r| r.unwrap()).collect();
    for (row, c) in rows.iter().zip(m["cells"].as_array().unwrap()) {
        for run in ["from_sliding", "from_rest"] {
            for q in ["open_fraction_trail", "open_fraction_lead"] {
                let want = &c[run][q];
                let got = &row[col(&format!("{run}_{q}"))];
                assert!(want.is_number(), "cell {}: {run}.{q} in the JSON: {want}", c["index"]);
                assert_eq!(got.parse::<f64>().unwrap(), num(want), "cell {} {run}_{q}", c["index"]);
            }
        }
    }
}
