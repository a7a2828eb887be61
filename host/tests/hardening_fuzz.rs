//! Fuzz targets (proptest, stable Rust) for the readers of small files: the scene TOML reader and
//! the map shard JSON reader (with `map merge`'s checks, its Markdown and its figure). The defmt
//! stream decoder's are in recorded_decode.rs (`random_bytes_never_panic`,
//! `mutated_streams_never_panic`). Each input must give a value or an error, never a panic;
//! inputs are bounded in size (a few KiB), so each case is bounded in time. Cases:
//! STICKSLIP_FUZZ_CASES (default 256).

use proptest::prelude::*;
use serde_json::Value;

use stickslip::map::cell::CellOptions;
use stickslip::map::sweep::{Grid, Sweep};
use stickslip::map::{self, MapJson, MapSpec};
use stickslip::scenes::run::{self, Precision};
use stickslip::scenes::{builtin, scene_file};

fn cases() -> u32 {
    std::env::var("STICKSLIP_FUZZ_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(256)
}

/// The complete scene file of a built-in scene, as `scenes show` prints it.
fn scene_text(name: &str) -> String {
    let b = builtin::find(name).unwrap();
    scene_file::to_toml(&b.name, &b.description, &b.scene)
}

/// A scene text through the reader, and, if it reads, validation and the work-budget check
/// (not a run: that is bounded by the budget, tested in hardening.rs).
fn read_scene(text: &str) {
    if let Ok(p) = scene_file::parse(text) {
        if p.scene.validate().is_ok() {
            let _ = run::over_budget(&p.scene);
        }
    }
}

/// A small map's JSON (2 x 2 cells, 0.02 s runs), made by the tool.
fn shard_json() -> Value {
    let sweeps = ["beta=0.01:0.07:2", "mu_s=0.4:0.8:2"].iter().map(|s| Sweep::parse(s).unwrap()).collect();
    let mut base = builtin::find("push_center").unwrap().scene;
    base.duration = 0.02;
    base.stats_from = 0.01;
    let spec = MapSpec {
        scene_name: "fuzz".into(),
        base,
        grid: Grid::new(sweeps).unwrap(),
        options: CellOptions { precision: Precision::F64, kick: 0.01, stick_jump: true },
        shard: None,
        jobs: Some(1),
        progress: false,
        share_sliding: true,
    };
    serde_json::to_value(map::run_map(&spec).unwrap().0).unwrap()
}

thread_local! {
    static SHARD: Value = shard_json();
}

/// A shard text through `map merge`: read, checked, merged; if accepted, its Markdown, CSV and
/// figure are made (none may panic).
fn merge_shard(text: &str) {
    let Ok(m) = serde_json::from_str::<MapJson>(text) else { return };
    if let Ok(merged) = map::merge(vec![("fuzz.json".into(), m)]) {
        let _ = map::output::markdown(&merged);
        let dir = std::env::temp_dir().join(format!("stickslip-fuzz-{}", std::process::id()));
        let _ = std::fs::create_dir_all(&dir);
        let _ = map::output::write_csv(&merged, &dir.join("m.csv"));
        let _ = map::plot::write(&merged, &dir.join("m.svg"));
    }
}

/// Every number, string and container of `v`, as JSON pointers.
fn paths(v: &Value, at: String, out: &mut Vec<String>) {
    out.push(at.clone());
    match v {
        Value::Object(o) => o.iter().for_each(|(k, x)| paths(x, format!("{at}/{k}"), out)),
        Value::Array(a) => a.iter().enumerate().for_each(|(i, x)| paths(x, format!("{at}/{i}"), out)),
        _ => {}
    }
}

fn any_json() -> impl Strategy<Value = Value> {
    prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::from),
        any::<i64>().prop_map(Value::from),
        prop::num::f64::ANY.prop_map(|x| serde_json::Number::from_f64(x).map_or(Value::Null, Value::Number)),
        Just(Value::from(0)),
        Just(Value::from(-1)),
        Just(Value::from(1e300)),
        "[a-z_]{0,12}".prop_map(Value::from),
        Just(Value::Array(vec![])),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    #[test]
    fn scene_reader_random_text(text in ".{0,400}") {
        read_scene(&text);
    }

    #[test]
    fn scene_reader_mutated_files(name in prop::sample::select(vec!["push_center", "rig_push_center", "rig_float_pull_lead", "oracle_stribeck"]),
                                  edits in prop::collection::vec((any::<prop::sample::Index>(), "[-+0-9.e=\\[\\]\"a-z_ \n#]{0,8}", 0u8..3), 1..6)) {
        let mut text = scene_text(name);
        for (at, piece, op) in edits {
            let mut i = at.index(text.len() + 1);
            while !text.is_char_boundary(i) {
                i -= 1;
            }
            match op {
                0 => text.insert_str(i, &piece),
                1 => {
                    let mut j = (i + piece.len()).min(text.len());
                    while !text.is_char_boundary(j) {
                        j -= 1;
                    }
                    text.replace_range(i..j, &piece)
                }
                _ => text.truncate(i),
            }
        }
        read_scene(&text);
    }

    #[test]
    fn shard_reader_random_bytes(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        merge_shard(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn shard_reader_mutated_values(edits in prop::collection::vec((any::<prop::sample::Index>(), any_json()), 1..4)) {
        let mut v = SHARD.with(|s| s.clone());
        for (at, x) in edits {
            let mut all = Vec::new();
            paths(&v, String::new(), &mut all);
            let p = all[at.index(all.len())].clone();
            if let Some(slot) = v.pointer_mut(&p) {
                *slot = x;
            }
        }
        merge_shard(&v.to_string());
    }

    #[test]
    fn shard_reader_mutated_text(edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>(), 0u8..3), 1..8)) {
        let mut bytes = SHARD.with(|s| s.to_string()).into_bytes();
        for (at, b, op) in edits {
            let i = at.index(bytes.len() + 1);
            match op {
                0 if i < bytes.len() => bytes[i] = b,
                1 => bytes.insert(i, b),
                _ => bytes.truncate(i.max(1)),
            }
        }
        merge_shard(&String::from_utf8_lossy(&bytes));
    }
}

/// The generated shard itself passes `map merge`'s checks (so the mutations start from a good one).
#[test]
fn the_unmutated_shard_merges() {
    let m: MapJson = serde_json::from_value(SHARD.with(|s| s.clone())).unwrap();
    map::merge(vec![("fuzz.json".into(), m)]).unwrap();
}
