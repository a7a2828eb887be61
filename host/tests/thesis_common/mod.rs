//! What the tests of the thesis model's runs at event speed share (`stick_jump`,
//! `map_located`): the built-in scenes, a relative difference, the six cases with the 1-DOF
//! scene, and a map of a scene at event speed or stepped.
#![allow(dead_code)]

use stickslip::map::cell::CellOptions;
use stickslip::map::sweep::{Grid, Sweep};
use stickslip::map::{self, MapJson, MapSpec};
use stickslip::scenes::run::Precision;
use stickslip_model::Scene;

pub fn builtin(name: &str) -> Scene {
    stickslip::scenes::builtin::find(name).expect("a built-in scene").scene
}

pub fn rel(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else {
        (a - b).abs() / a.abs().max(b.abs())
    }
}

/// The six cases and the 1-DOF thesis scene (rotation held: the stick jump's bound is exact
/// there).
pub fn scenes() -> Vec<(String, Scene)> {
    let mut v: Vec<(String, Scene)> = ["push_trail", "push_center", "push_lead", "pull_trail", "pull_center", "pull_lead"]
        .iter()
        .map(|n| (n.to_string(), builtin(n)))
        .collect();
    v.push(("push_center, rotation held".into(), Scene { rotation: false, ..builtin("push_center") }));
    v
}

/// The map of `scene` (named `name`) over `sweeps` in f64 with a kick of 0.01, at event speed
/// (`fast`: the default) or stepped at every step (`--step-stick`).
pub fn map_of(name: &str, scene: Scene, fast: bool, sweeps: &[&str]) -> MapJson {
    let spec = MapSpec {
        scene_name: name.into(),
        base: scene,
        grid: Grid::new(sweeps.iter().map(|s| Sweep::parse(s).unwrap()).collect()).unwrap(),
        options: CellOptions { precision: Precision::F64, kick: 0.01, stick_jump: fast },
        shard: None,
        jobs: None,
        progress: false,
        share_sliding: true,
    };
    map::run_map(&spec).unwrap().0
}
