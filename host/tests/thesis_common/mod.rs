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

/// The regimes of two maps of the same cells equal, their statistics within 1e-6 (the groan
/// RMS 1e-5: f32's filter against the ring-down's closed form in stick); returns the runs from
/// rest or from sliding that stick-slip. `what`: the maps, for the messages.
pub fn assert_maps_agree(what: &str, a: &MapJson, b: &MapJson) -> usize {
    assert_maps_within(what, a, b, [1e-6, 1e-6, 1e-6, 1e-6, 1e-5], false).0
}

/// [`assert_maps_agree`] to the tolerances `tol` of stick fraction, stick-slip frequency,
/// pad_x's and the sliding velocity's peak-to-peak and the groan RMS (relative; the stick
/// fraction's absolute where `abs_fraction`); also returns the largest difference of each.
pub fn assert_maps_within(what: &str, a: &MapJson, b: &MapJson, tol: [f64; 5], abs_fraction: bool) -> (usize, [f64; 5]) {
    assert_eq!(a.cells.len(), b.cells.len(), "{what}");
    let mut stick_slip = 0;
    let mut worst = [0.0f64; 5];
    for (ca, cb) in a.cells.iter().zip(&b.cells) {
        assert_eq!(ca.invalid, cb.invalid, "{what} cell {}", ca.index);
        for (ra, rb) in [(&ca.from_rest, &cb.from_rest), (&ca.from_sliding, &cb.from_sliding)] {
            let (Some(ra), Some(rb)) = (ra, rb) else {
                assert_eq!(ra.is_none(), rb.is_none(), "{what} cell {}", ca.index);
                continue;
            };
            assert_eq!(ra.regime, rb.regime, "{what} cell {}", ca.index);
            stick_slip += usize::from(ra.regime == "stick_slip");
            let pairs = [
                ("stick_fraction", ra.stick_fraction, rb.stick_fraction),
                ("stick_slip_hz", ra.stick_slip_hz, rb.stick_slip_hz),
                ("pad_x_pp", ra.pad_x_pp, rb.pad_x_pp),
                ("slide_v_pp", ra.slide_v_pp, rb.slide_v_pp),
                ("groan_rms", ra.groan_rms, rb.groan_rms),
            ];
            for (i, (key, x, y)) in pairs.into_iter().enumerate() {
                match (x, y) {
                    (Some(x), Some(y)) => {
                        let d = if i == 0 && abs_fraction { (x - y).abs() } else { rel(x, y) };
                        worst[i] = worst[i].max(d);
                        assert!(d <= tol[i], "{what} cell {} {key}: {x} against {y}", ca.index);
                    }
                    (x, y) => assert_eq!(x, y, "{what} cell {} {key}", ca.index),
                }
            }
        }
    }
    (stick_slip, worst)
}
