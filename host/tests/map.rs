//! `stickslip map`: the linear boundary against closed forms (the 1-DOF Stribeck oracle's V_cr,
//! its growth rate, the floating pad's two-mode flutter analysis), the runs against the linear
//! analysis and against the measured growth of their own envelopes, shards against the unsplit
//! map, and the command line's errors. Reference values come from closed forms written out
//! here, never from the code under test.

use std::process::{Command, Output};

use stickslip::map::cell::{self, CellJson, CellOptions};
use stickslip::map::sweep::{Grid, Sweep};
use stickslip::map::{self, output, MapJson, MapSpec, Shard};
use stickslip::scenes::run::{self, Detail, Precision, Start};
use stickslip::scenes::series::{Sample, Sink};
use stickslip_model::rig_set::rig_float_scene;
use stickslip_model::{Caliper, Coefficients, FrictionLaw, Scene};

fn builtin(name: &str) -> Scene {
    stickslip::scenes::builtin::find(name).expect("a built-in scene").scene
}

fn spec(base: Scene, sweeps: &[&str], shard: Option<Shard>, jobs: Option<usize>) -> MapSpec {
    let sweeps = sweeps.iter().map(|s| Sweep::parse(s).expect("a good sweep")).collect();
    MapSpec {
        scene_name: "test".into(),
        base,
        grid: Grid::new(sweeps).expect("a good grid"),
        options: CellOptions { precision: Precision::F64, kick: 0.01, stick_jump: true },
        shard,
        jobs,
        progress: false,
        share_sliding: true,
    }
}

fn run_map(s: &MapSpec) -> MapJson {
    map::run_map(s).unwrap_or_else(|e| panic!("map failed: {e}")).0
}

fn param(c: &CellJson, key: &str) -> f64 {
    c.params[key].as_f64().expect("a number")
}

/// The oracle's normal force: N0 = 10 N by its definition (model.md, `Scene::oracle_1dof`).
const ORACLE_N: f64 = 10.0;

/// V_cr = v_s ln(N (mu_s - mu_k) / (c v_s)) of the 1-DOF oracle (model.md).
fn oracle_v_cr(s: &Scene) -> f64 {
    s.v_s * (ORACLE_N * (s.mu_s - s.mu_k) / (s.c_x * s.v_s)).ln()
}

/// Growth rate of steady sliding of the 1-DOF Stribeck oracle (delta = 1) at its V, closed
/// form: m x'' + (c + N mu'(V)) x' + k x = 0, mu'(V) = -(mu_s - mu_k) e^(-V/v_s) / v_s; the
/// larger real part of the two roots.
fn oracle_growth_rate(s: &Scene) -> f64 {
    let n = ORACLE_N;
    let slope = -(s.mu_s - s.mu_k) * (-s.v / s.v_s).exp() / s.v_s;
    let c = s.c_x + n * slope;
    let disc = c * c - 4.0 * s.m * s.k_g;
    if disc < 0.0 {
        -c / (2.0 * s.m)
    } else {
        (-c + disc.sqrt()) / (2.0 * s.m)
    }
}

#[test]
fn the_oracle_boundary_brackets_v_cr_and_the_runs_from_sliding_agree_off_the_boundary() {
    let base = builtin("oracle_stribeck");
    let v_cr = oracle_v_cr(&base);
    assert!((v_cr - 0.03).abs() < 1e-12, "the built-in oracle puts V_cr at 0.03 m/s: {v_cr}");
    let m = run_map(&spec(base, &["v=0.002:0.2:60:log"], None, None));
    assert_eq!(m.cells.len(), 60);
    let pairs = output::boundary_pairs(&m);
    assert_eq!(pairs.len(), 1, "one boundary along v: {pairs:?}");
    let (i, j) = pairs[0];
    let (vi, vj) = (param(&m.cells[i], "v"), param(&m.cells[j], "v"));
    assert!(vi < v_cr && v_cr < vj, "the boundary cells {vi} and {vj} bracket V_cr = {v_cr}");
    for c in &m.cells {
        let v = param(c, "v");
        let lin = c.linear.as_ref().expect("valid");
        assert_eq!(lin.stable, v > v_cr, "linear stability at v = {v}");
        if c.index == i || c.index == j {
            continue;
        }
        let r = &c.from_sliding.as_ref().expect("a run").regime;
        if lin.stable {
            assert_eq!(r, "steady_sliding", "v = {v} > V_cr: sliding stays steady");
        } else {
            assert!(r == "stick_slip" || r == "sliding_oscillation", "v = {v} < V_cr: sliding does not stay steady ({r})");
        }
    }
}

/// Records the deviation of the sliding velocity from steady sliding, v_slide + V.
struct Deviation {
    v: f64,
    samples: Vec<(f64, f64)>,
}

impl Sink for Deviation {
    fn wants_kinematics(&self) -> bool {
        true
    }

    fn sample(&mut self, s: &Sample) -> stickslip::error::Result<()> {
        self.samples.push((s.t, s.v_slide + self.v));
        Ok(())
    }
}

/// The growth rate of an oscillation from its extremes: least squares of ln|extreme| against
/// time over the extremes below `limit` (the linear range).
fn envelope_growth_rate(samples: &[(f64, f64)], limit: f64) -> (f64, usize) {
    let mut pts = Vec::new();
    for w in samples.windows(3) {
        let (a, b, c) = (w[0].1, w[1].1, w[2].1);
        let extreme = (b > a && b >= c) || (b < a && b <= c);
        if extreme && b.abs() < limit {
            pts.push((w[1].0, b.abs().ln()));
        }
        if b.abs() >= limit {
            break;
        }
    }
    let n = pts.len() as f64;
    let (mt, my) = (pts.iter().map(|p| p.0).sum::<f64>() / n, pts.iter().map(|p| p.1).sum::<f64>() / n);
    let sxy: f64 = pts.iter().map(|p| (p.0 - mt) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mt) * (p.0 - mt)).sum();
    (sxy / sxx, pts.len())
}

#[test]
fn the_linear_growth_rate_matches_the_runs_early_envelope_on_three_unstable_cells() {
    for v in [0.024, 0.026, 0.028] {
        let mut s = builtin("oracle_stribeck");
        s.v = v;
        s.duration = 8.0;
        s.stats_from = 1.0;
        // the map's linear analysis of this cell
        let (c, _) = cell::cell(0, &[("v".into(), v)], Ok(s), CellOptions { precision: Precision::F64, kick: 0.01, stick_jump: true }, None, &Default::default()).expect("a cell");
        let lin = c.linear.expect("valid");
        assert!(!lin.stable, "v = {v} < V_cr is unstable");
        let rate = lin.max_growth_rate.expect("finite");
        let closed = oracle_growth_rate(&s);
        assert!((rate - closed).abs() <= 1e-9 * closed.abs(), "v = {v}: linear {rate} against the closed form {closed}");
        // a run from steady sliding with a small kick, its extremes while they stay inside
        // the friction curve's linear range (|dv| < v_s / 10: the cubic term changes the
        // growth by (dv / v_s)^2, under 1 %)
        let mut dev = Deviation { v, samples: Vec::new() };
        run::run_from(&s, Precision::F64, Start::Sliding { kick: 1e-8 }, Detail::Full, &mut dev).expect("runs");
        let (measured, n) = envelope_growth_rate(&dev.samples, s.v_s / 10.0);
        assert!(n >= 8, "v = {v}: {n} extremes in the linear range");
        let err = (measured - rate).abs() / rate;
        println!("v = {v}: linear {rate:.5} 1/s, envelope {measured:.5} 1/s over {n} extremes: {:.3} %", 100.0 * err);
        assert!(err < 0.02, "v = {v}: envelope {measured} against linear {rate} ({:.2} %)", 100.0 * err);
    }
}

/// The floating pad with Coulomb friction and no damping: its (y, phi) block decouples from x
/// in slip, and its modes are the roots lambda = omega^2 of the two-mode quadratic
/// det(K_f - lambda M) = 0 (model.md; written out here from the mass and stiffness matrices).
fn floating_coulomb(caliper: Caliper, beta: f64) -> Scene {
    let mut s = rig_float_scene(caliper, beta);
    s.friction = FrictionLaw::Coulomb;
    s.mu_s = 0.9;
    s.c_x = 0.0;
    s.c_phi = 0.0;
    s.c_y = 0.0;
    s.duration = 0.004;
    s.stats_from = 0.002;
    s
}

/// The two-mode quadratic's (a, b, c) at friction mu, from M = [[I, m l], [m l, m]] and
/// K_f = [[K - s w mu c_N, c_N - s w mu (k_L + k_T)], [c_N, k_L + k_T]] (k_pivot = 0).
fn two_mode(s: &Scene, mu: f64) -> (f64, f64, f64) {
    let co = Coefficients::of(s);
    let sw = co.s * s.w;
    let ks = s.k_l + s.k_t;
    let (m11, m12, m22) = (s.inertia, s.m * s.l, s.m);
    let (k11, k12, k21, k22) = (co.k_rot - sw * mu * co.c_n, co.c_n - sw * mu * ks, co.c_n, ks);
    (m11 * m22 - m12 * m12, -(k11 * m22 + k22 * m11 - k12 * m12 - k21 * m12), k11 * k22 - k12 * k21)
}

#[test]
fn the_floating_pads_flutter_threshold_is_on_the_map_where_the_two_mode_analysis_puts_it() {
    for caliper in [Caliper::Push, Caliper::Pull] {
        // the two-mode threshold: the discriminant of the quadratic in omega^2 turns negative
        let disc = |mu: f64| {
            let (a, b, c) = two_mode(&floating_coulomb(caliper, 0.04), mu);
            b * b - 4.0 * a * c
        };
        let (mut lo, mut hi) = (0.0, 0.9);
        assert!(disc(lo) > 0.0 && disc(hi) < 0.0);
        for _ in 0..80 {
            let mid = 0.5 * (lo + hi);
            if disc(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let threshold = 0.5 * (lo + hi);
        let mut boundaries = Vec::new();
        for beta in [0.025, 0.04, 0.055] {
            let m = run_map(&spec(floating_coulomb(caliper, beta), &["mu_k=0.3:0.6:31"], None, None));
            let pairs = output::boundary_pairs(&m);
            assert_eq!(pairs.len(), 1, "{caliper:?} beta {beta}: one boundary along mu_k: {pairs:?}");
            let (i, j) = pairs[0];
            let (mi, mj) = (param(&m.cells[i], "mu_k"), param(&m.cells[j], "mu_k"));
            assert!(mi < threshold && threshold < mj, "{caliper:?} beta {beta}: the boundary {mi}..{mj} brackets the two-mode threshold {threshold}");
            boundaries.push((mi, mj));
            // below the threshold the map's modes hold the two-mode analysis's frequencies
            for c in m.cells.iter().filter(|c| param(c, "mu_k") < threshold) {
                let (a, b, cc) = two_mode(&floating_coulomb(caliper, beta), param(c, "mu_k"));
                let r = (b * b - 4.0 * a * cc).sqrt();
                for lambda in [(-b - r) / (2.0 * a), (-b + r) / (2.0 * a)] {
                    let hz = lambda.sqrt() / (2.0 * std::f64::consts::PI);
                    let lin = c.linear.as_ref().expect("valid");
                    let near = lin.modes.iter().filter_map(|md| md.hz).map(|f| (f - hz).abs() / hz).fold(f64::INFINITY, f64::min);
                    assert!(near < 1e-6, "{caliper:?} beta {beta} mu {}: a mode at {hz} Hz (closest {near:e})", param(c, "mu_k"));
                }
            }
            // above it, the growing pair is the merged one: oscillating, in the groan band
            let above = m.cells.iter().find(|c| param(c, "mu_k") > mj + 0.02).expect("a cell above");
            let hz = above.linear.as_ref().and_then(|l| l.unstable_hz).expect("an unstable mode");
            assert!((100.0..=500.0).contains(&hz), "{caliper:?}: the flutter mode at {hz} Hz lies in the groan band");
        }
        // the load is a dead force and the contact springs linear: beta moves the rest state,
        // not the linearisation, so the threshold is the same at every load position
        assert!(boundaries.windows(2).all(|w| w[0] == w[1]), "{caliper:?}: {boundaries:?}");
    }
}

#[test]
fn four_shards_merge_into_the_unsplit_map_and_threads_do_not_change_it() {
    let mut base = builtin("push_center");
    base.duration = 0.06;
    base.stats_from = 0.03;
    let sweeps = ["beta=0.01:0.07:7", "mu_s=0.36:0.6:5"];
    let whole = run_map(&spec(base, &sweeps, None, Some(2)));
    let one_thread = run_map(&spec(base, &sweeps, None, Some(1)));
    assert_eq!(whole, one_thread);
    let shards: Vec<(String, MapJson)> = (0..4)
        .map(|k| {
            let m = run_map(&spec(base, &sweeps, Some(Shard { k, n: 4 }), None));
            // through JSON, as a cluster's job array hands them over
            let text = serde_json::to_string(&m).expect("serialises");
            (format!("shard {k}"), serde_json::from_str(&text).expect("reads back"))
        })
        .collect();
    assert_eq!(shards.iter().map(|s| s.1.cells.len()).sum::<usize>(), 35);
    let merged = map::merge(shards.clone()).expect("merges");
    let (a, b) = (serde_json::to_string(&merged).unwrap(), serde_json::to_string(&whole).unwrap());
    let first = a.bytes().zip(b.bytes()).position(|(x, y)| x != y);
    assert!(a == b, "the merged map differs from the unsplit one at byte {first:?}: {}", first.map_or(String::new(), |i| a[i.saturating_sub(80)..(i + 40).min(a.len())].to_string()));
    // a missing shard, a shard twice, a shard of another map
    let missing = map::merge(shards[..3].to_vec()).unwrap_err();
    assert!(missing.contains("missing"), "{missing}");
    let mut twice = shards.clone();
    twice.push(shards[0].clone());
    assert!(map::merge(twice).unwrap_err().contains("twice"));
    let mut other = shards.clone();
    other[1].1.kick = 0.02;
    assert!(map::merge(other).unwrap_err().contains("not a shard of the same map"));
}

fn stickslip(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_stickslip")).args(args).output().expect("the binary runs")
}

#[test]
fn bad_sweeps_get_one_line_naming_the_sweep_and_exit_2() {
    let cases: [(&[&str], &str); 9] = [
        (&["--sweep", "mass=1:2:3"], "--sweep mass=1:2:3: unknown numeric scene key `mass`"),
        (&["--sweep", "v=0.01:0.001:5:log"], "--sweep v=0.01:0.001:5:log: a log sweep needs FROM <= TO"),
        (&["--sweep", "v=0:0.01:5:log"], "a log sweep needs FROM > 0"),
        (&["--sweep", "beta=0.01:0.07:0"], "--sweep beta=0.01:0.07:0: N `0` must be a whole number >= 1"),
        (&["--sweep", "beta=0.01:x:3"], "--sweep beta=0.01:x:3: TO `x` is not a finite number"),
        (&["--sweep", "m=-1:1:3"], "--sweep m=-1:1:3: m = -1: the scene rejects it: field `m`"),
        (&["--sweep", "beta=0.01:0.07:3", "--sweep", "beta=0.02:0.03:2"], "both set `beta`"),
        (&["--sweep", "beta=0.01:0.07:3", "--sweep", "v=0.01:0.02:2", "--sweep", "m=1:2:2"], "3 sweeps given"),
        (&["--sweep", "beta=0.01:0.07:3", "--shard", "4/4"], "--shard 4/4: expected K/N"),
    ];
    for (args, want) in cases {
        let mut all = vec!["map", "push_center"];
        all.extend_from_slice(args);
        let o = stickslip(&all);
        let err = String::from_utf8_lossy(&o.stderr).to_string();
        assert_eq!(o.status.code(), Some(2), "{all:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{all:?}: one line: {err}");
        assert!(err.contains(want), "{all:?}: `{err}` names `{want}`");
    }
    // a file that is not a map's JSON
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let bad = dir.join("not_a_map.json");
    std::fs::write(&bad, "{\"cells\": 3}").unwrap();
    let o = stickslip(&["map", "merge", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("not a map's JSON"));
}

#[test]
fn a_cell_whose_scene_is_invalid_is_reported_as_such_and_the_json_has_the_issues_shape() {
    let o = stickslip(&[
        "map", "push_center", "--sweep", "mu_s=0.3:0.45:2", "--sweep", "mu_k=0.3:0.4:2", "--duration", "0.02", "--stats-from", "0.01", "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let cells = v["cells"].as_array().expect("cells");
    assert_eq!(cells.len(), 4);
    // mu_s = 0.3 with mu_k = 0.4: invalid; the other three are maps' cells
    let bad: Vec<&serde_json::Value> = cells.iter().filter(|c| !c["invalid"].is_null()).collect();
    assert_eq!(bad.len(), 1);
    assert!(bad[0]["invalid"].as_str().unwrap().contains("mu_k"));
    assert!(bad[0]["linear"].is_null() && bad[0]["from_rest"].is_null());
    for c in cells.iter().filter(|c| c["invalid"].is_null()) {
        assert!(c["params"]["mu_s"].is_number() && c["params"]["mu_k"].is_number());
        assert!(c["linear"]["stable"].is_boolean() && c["linear"]["max_growth_rate"].is_number());
        assert!(c["linear"].get("unstable_hz").is_some());
        for run in ["from_sliding", "from_rest"] {
            assert!(c[run]["regime"].is_string() && c[run].get("stick_fraction").is_some() && c[run].get("stick_slip_hz").is_some());
        }
    }
}

#[test]
fn a_swept_damping_ratio_uses_the_cells_stiffness_and_log_sweeps_end_on_their_bounds() {
    // zeta_x with k_g swept beside it: c_x = 2 zeta_x sqrt(k_g m) with the cell's k_g
    let base = builtin("push_center");
    let grid = Grid::new(vec![Sweep::parse("zeta_x=0.01:0.05:3").unwrap(), Sweep::parse("k_g=1e5:4e5:2").unwrap()]).unwrap();
    for i in 0..grid.cells() {
        let s = grid.scene(&base, i).expect("valid");
        let p = grid.params(i);
        let (zeta, k_g) = (p[0].1, p[1].1);
        assert_eq!(s.k_g, k_g);
        let want = 2.0 * zeta * (k_g * base.m).sqrt();
        assert!((s.c_x - want).abs() <= 1e-12 * want, "cell {i}: c_x {} against {want}", s.c_x);
    }
    let w = Sweep::parse("v=0.001:0.1:7:log").unwrap();
    assert_eq!((w.value(0), w.value(6)), (0.001, 0.1));
    // geometric: each value 10^(1/3) times the one before
    for i in 0..6 {
        assert!((w.value(i + 1) / w.value(i) - 10f64.powf(1.0 / 3.0)).abs() < 1e-12);
    }
}

/// A map with and without the sharing of runs from sliding across a swept mu_s
/// (`MapSpec::share_sliding`): (map, steps run).
fn shared_and_own(base: Scene, sweeps: &[&str], kick: f64) -> ((MapJson, u64), (MapJson, u64)) {
    let mut on = spec(base, sweeps, None, Some(2));
    on.options.kick = kick;
    let mut off = spec(base, sweeps, None, Some(2));
    off.options.kick = kick;
    off.share_sliding = false;
    let run = |s: &MapSpec| {
        let (m, t) = map::run_map(s).unwrap_or_else(|e| panic!("map failed: {e}"));
        (m, t.steps)
    };
    (run(&on), run(&off))
}

#[test]
fn runs_from_sliding_shared_across_mu_s_give_the_map_of_every_cells_own_run() {
    // the thesis model: steady sliding never reaches the velocity match, so every group of
    // a beta x mu_s map runs one run from sliding (its representative's) instead of five
    let mut thesis = builtin("push_center");
    thesis.duration = 0.06;
    thesis.stats_from = 0.03;
    let sweeps = ["beta=0.01:0.07:4", "mu_s=0.36:0.6:5"];
    for kick in [0.01, 0.5] {
        let ((shared, steps_shared), (own, steps_own)) = shared_and_own(thesis, &sweeps, kick);
        assert_eq!(shared, own, "thesis, kick {kick}: the shared runs give another map");
        // own: 20 cells x 2 runs; shared: 20 runs from rest + 4 representatives, and the
        // groups whose representative came near the velocity match (kick 0.5: its sliding
        // velocity's clearance is not 4 times its change in a step) run their own as well
        let n = (thesis.duration / thesis.dt).round() as u64;
        assert_eq!(steps_own, 40 * n);
        if kick == 0.01 {
            assert_eq!(steps_shared, 24 * n, "thesis, kick {kick}: steps run");
        } else {
            assert!((24 * n..=44 * n).contains(&steps_shared), "thesis, kick {kick}: {steps_shared} steps run");
        }
    }
    // a floating pad past its flutter threshold (Coulomb friction): steady sliding grows into
    // stick-slip, whose runs read mu_s; each cell must run its own
    let mut float = floating_coulomb(Caliper::Push, 0.04);
    float.mu_k = 0.6;
    float.duration = 0.05;
    float.stats_from = 0.025;
    let ((shared, steps_shared), (own, steps_own)) = shared_and_own(float, &["mu_s=0.6:0.9:4"], 0.01);
    assert_eq!(shared, own, "floating pad: the shared runs give another map");
    let sticks = own.cells.iter().filter_map(|c| c.from_sliding.as_ref()).filter(|r| r.stick_fraction.is_some_and(|f| f > 0.0)).count();
    assert!(sticks > 0, "the floating pad's runs from sliding stick (the case where mu_s is read)");
    let n = (float.duration / float.dt).round() as u64;
    assert_eq!(steps_shared, steps_own + n, "floating pad: the representative's run is not shared");
    // Stribeck friction reads mu_s in slip: nothing is shared
    let mut rig = builtin("rig_float_push_center");
    rig.duration = 0.02;
    rig.stats_from = 0.01;
    let ((shared, steps_shared), (own, steps_own)) = shared_and_own(rig, &["mu_s=0.5:0.7:3"], 0.01);
    assert_eq!((shared, steps_shared), (own, steps_own), "Stribeck: no sharing");
}

#[test]
fn a_cell_over_the_work_budget_is_not_counted_as_disagreeing_with_the_linear_analysis() {
    // k_g = 1e18 N/m: linearly stable, its runs over the work budget (not run)
    let m = run_map(&spec(builtin("push_center"), &["k_g=1e18:1e18:1", "beta=0.03:0.05:2"], None, Some(1)));
    assert!(m.cells.iter().all(|c| c.linear.as_ref().is_some_and(|l| l.stable)));
    assert!(m.cells.iter().all(|c| c.from_sliding.as_ref().is_some_and(|r| r.regime == "budget")));
    let md = output::markdown(&m);
    assert!(md.contains("disagrees with the linear analysis (linearly stable but not steady, or unstable but steady): 0 "), "{md}");
}
