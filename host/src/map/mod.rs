//! Regime maps (`stickslip map`): where stick-slip starts.
//!
//! A map sweeps one or two scene keys over a grid ([`sweep`]); each cell ([`cell`]) holds the
//! linear stability of steady sliding (the theory's boundary) and two runs, one from perturbed
//! steady sliding and one from the default stuck start, each classified into a regime. Where
//! the two runs disagree (sliding stays steady, the run from rest keeps stick-slipping) the
//! scene is bistable: the subcritical Hopf band. The cells run in parallel (rayon); a map can
//! be split into shards (`--shard K/N`: the cells i with i mod N = K) and the shards joined
//! ([`merge`]) into the map the unsplit run gives, byte for byte.

pub mod cell;
pub mod output;
pub mod plot;
pub mod ring_down;
pub mod sweep;

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use stickslip_model::Scene;

use crate::error::{HostError, Result};
use crate::scenes::table_cache::PropagatorCache;
use cell::{CellJson, CellOptions};
use sweep::{Grid, Sweep};

/// Every N-th cell, starting at K (0 <= K < N).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

impl Shard {
    /// Reads `K/N`.
    pub fn parse(arg: &str) -> std::result::Result<Shard, String> {
        let bad = || format!("--shard {arg}: expected K/N with whole numbers 0 <= K < N <= {}", crate::limits::MAP_MAX_CELLS);
        let (k, n) = arg.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if n == 0 || k >= n || n > crate::limits::MAP_MAX_CELLS {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

/// A map (or a shard of one) as `--json` prints it and `map merge` reads it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapJson {
    /// The base scene's name.
    pub scene: String,
    /// The base scene as a scene file (every key): the map can be remade from it.
    pub scene_toml: String,
    pub sweeps: Vec<Sweep>,
    /// Run length [s], statistics window start [s], step [s] of the base scene (a sweep of
    /// duration, stats_from or dt changes them per cell).
    pub duration_s: f64,
    pub stats_from_s: f64,
    pub dt_s: f64,
    pub precision: String,
    /// The start from sliding: velocity kick relative to V.
    pub kick: f64,
    /// A completed run that never sticks is steady sliding while its sliding velocity's
    /// peak-to-peak is at most this times kick V.
    pub steady_pp_over_kick_v: f64,
    /// Cells of the whole map.
    pub cells_total: usize,
    /// The shard this file holds (null: the whole map).
    pub shard: Option<Shard>,
    pub cells: Vec<CellJson>,
}

/// What to map.
pub struct MapSpec {
    pub scene_name: String,
    pub base: Scene,
    pub grid: Grid,
    pub options: CellOptions,
    pub shard: Option<Shard>,
    /// Worker threads (None: every core).
    pub jobs: Option<usize>,
    /// Draw the progress bar on stderr (it hides itself when stderr is not a terminal).
    pub progress: bool,
    /// Share the run from sliding between cells that differ only in a swept mu_s where that
    /// run read no mu_s ([`SlidingShare`]); `false` runs every cell's own (the same map, byte
    /// for byte: the test of the sharing).
    pub share_sliding: bool,
}

/// Cells that differ only in a swept mu_s (the groups: the cells with the same values of
/// the other sweep) have the same run from sliding when that run never reached the velocity
/// match or stick, the only places mu_s enters a Coulomb scene's run. One cell of each group,
/// its representative, runs it first ([`cell::sliding_run_free_of_mu_s`], which tests that);
/// the others take it where their scene is the representative's with its mu_s. A beta x mu_s
/// map of the thesis model runs one run from sliding per beta instead of one per cell.
struct SlidingShare {
    /// Which sweep is mu_s.
    mu_s_sweep: usize,
    /// Per group: the representative's scene and its shared run (None: not shared).
    runs: Vec<Option<(Scene, cell::RunCell)>>,
}

impl SlidingShare {
    /// The group of cell `i`: its coordinates in the sweeps other than mu_s.
    fn group(grid: &Grid, mu_s_sweep: usize, i: usize) -> usize {
        let coords = grid.coords(i);
        let mut g = 0;
        for (j, sw) in grid.sweeps.iter().enumerate().rev() {
            if j != mu_s_sweep {
                g = g * sw.n + coords[j];
            }
        }
        g
    }

    /// The shared runs of the groups of `indices` (None: the map sweeps no mu_s, or its base
    /// scene's runs read mu_s in slip). Returns the steps run.
    fn build(spec: &MapSpec, indices: &[usize], cache: &PropagatorCache) -> Result<(Option<SlidingShare>, cell::Steps)> {
        let grid = &spec.grid;
        let Some(mu_s_sweep) = grid.sweeps.iter().position(|sw| sw.key == "mu_s") else { return Ok((None, cell::Steps::default())) };
        if !spec.share_sliding || !cell::mu_s_free(&spec.base) {
            return Ok((None, cell::Steps::default()));
        }
        let groups = grid.cells() / grid.sweeps[mu_s_sweep].n;
        // the representative: the group's first cell (in this shard) with a valid scene
        let mut rep: Vec<Option<(usize, Scene)>> = vec![None; groups];
        for &i in indices {
            let g = Self::group(grid, mu_s_sweep, i);
            if rep[g].is_none() {
                if let Ok(sc) = grid.scene(&spec.base, i) {
                    rep[g] = Some((i, sc));
                }
            }
        }
        let token = crate::cancel::current();
        let runs: Vec<(Option<(Scene, cell::RunCell)>, cell::Steps)> = rep
            .par_iter()
            .map(|r| match r {
                Some((_, sc)) => crate::cancel::carried(&token, || {
                    let (run, steps) = cell::sliding_run_free_of_mu_s(sc, spec.options, cache)?;
                    Ok((run.map(|rc| (*sc, rc)), steps))
                }),
                None => Ok((None, cell::Steps::default())),
            })
            .collect::<Result<_>>()?;
        let steps = runs.iter().fold(cell::Steps::default(), |a, r| a + r.1);
        Ok((Some(SlidingShare { mu_s_sweep, runs: runs.into_iter().map(|r| r.0).collect() }), steps))
    }

    /// The shared run for cell `i` of scene `scene`: where its group has one and the scene is
    /// the representative's but for mu_s.
    fn for_cell(&self, grid: &Grid, i: usize, scene: &std::result::Result<Scene, String>) -> Option<&cell::RunCell> {
        let (rep, run) = self.runs[Self::group(grid, self.mu_s_sweep, i)].as_ref()?;
        let scene = scene.as_ref().ok()?;
        (Scene { mu_s: rep.mu_s, ..*scene } == *rep).then_some(run)
    }
}

/// How long the map took (stderr only: the JSON stays reproducible).
#[derive(Clone, Copy, Debug)]
pub struct Timing {
    pub cells: usize,
    /// Every step of the runs, those jumped over in stick included.
    pub steps: u64,
    /// Of `steps`, those jumped over in stick in closed form (not stepped).
    pub jumped: u64,
    pub seconds: f64,
    pub threads: usize,
}

impl Timing {
    /// The steps stepped, not jumped over.
    pub fn stepped(&self) -> u64 {
        self.steps - self.jumped.min(self.steps)
    }
}

/// Runs the cells of `spec` (of its shard) in parallel.
pub fn run_map(spec: &MapSpec) -> Result<(MapJson, Timing)> {
    spec.grid.check(&spec.base).map_err(HostError::Input)?;
    let total = spec.grid.cells();
    let indices: Vec<usize> = match spec.shard {
        Some(sh) => (sh.k..total).step_by(sh.n).collect(),
        None => (0..total).collect(),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(spec.jobs.unwrap_or(0))
        .build()
        .map_err(|e| HostError::Input(format!("--jobs: cannot start the worker threads: {e}")))?;
    let bar = if spec.progress { ProgressBar::new(indices.len() as u64) } else { ProgressBar::hidden() };
    bar.set_style(
        ProgressStyle::with_template("map {bar:40} {pos}/{len} cells, {elapsed} elapsed, {eta} left")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let steps = AtomicU64::new(0);
    let jumped = AtomicU64::new(0);
    let t0 = Instant::now();
    // the thesis stepper's tables, one build per distinct key (a beta x mu_s map: one per beta)
    let cache = PropagatorCache::new();
    let (share, shared_steps) = pool.install(|| SlidingShare::build(spec, &indices, &cache))?;
    steps.fetch_add(shared_steps.done, Ordering::Relaxed);
    jumped.fetch_add(shared_steps.jumped, Ordering::Relaxed);
    let token = crate::cancel::current();
    let cells: Result<Vec<CellJson>> = pool.install(|| {
        indices
            .par_iter()
            .map(|&i| {
                crate::cancel::carried(&token, || {
                    let scene = spec.grid.scene(&spec.base, i);
                    let from_sliding = share.as_ref().and_then(|sh| sh.for_cell(&spec.grid, i, &scene));
                    let (c, n) = cell::cell(i, &spec.grid.params(i), scene, spec.options, from_sliding, &cache)?;
                    steps.fetch_add(n.done, Ordering::Relaxed);
                    jumped.fetch_add(n.jumped, Ordering::Relaxed);
                    bar.inc(1);
                    Ok(c)
                })
            })
            .collect()
    });
    bar.finish_and_clear();
    let cells = cells?;
    let timing = Timing { cells: cells.len(), steps: steps.load(Ordering::Relaxed), jumped: jumped.load(Ordering::Relaxed), seconds: t0.elapsed().as_secs_f64(), threads: pool.current_num_threads() };
    let b = &spec.base;
    Ok((
        MapJson {
            scene: spec.scene_name.clone(),
            scene_toml: crate::scenes::scene_file::to_toml(&spec.scene_name, "", b),
            sweeps: spec.grid.sweeps.clone(),
            duration_s: b.duration,
            stats_from_s: b.stats_from,
            dt_s: b.dt,
            precision: spec.options.precision.name().to_string(),
            kick: spec.options.kick,
            steady_pp_over_kick_v: cell::STEADY_PP,
            cells_total: total,
            shard: spec.shard,
            cells,
        },
        timing,
    ))
}

/// Checks a map's JSON (a shard or a whole map) against its own header before anything
/// trusts it: the sweeps as `--sweep` would accept them, the cell count their product, the
/// shard's K/N, the run settings (dt > 0, duration > 0, 0 <= stats_from < duration, precision
/// f32/f64, 0 < kick <= 0.5, the steady-sliding factor of this build), the base scene a valid
/// scene file, and every cell: its index in the shard (ascending, i mod N = K), its parameters
/// the grid's keys and values at that index, its regimes known words. The error names the
/// file (`name`), the cell and the field.
pub fn validate(name: &str, m: &MapJson) -> std::result::Result<(), String> {
    use crate::output::format::short as sig4;
    let bad = |what: String| Err(format!("map merge: {name}: {what}"));
    let sweeps: Vec<Sweep> = match m.sweeps.iter().map(|sw| Sweep::parse(&sw.spec())).collect::<std::result::Result<Vec<_>, _>>() {
        Ok(v) => v,
        Err(e) => return bad(format!("sweeps: {e}")),
    };
    if sweeps != m.sweeps {
        return bad("sweeps: a sweep does not read back as given (not written by `map`)".into());
    }
    let grid = match Grid::new(sweeps) {
        Ok(g) => g,
        Err(e) => return bad(format!("sweeps: {e}")),
    };
    if grid.cells() != m.cells_total {
        return bad(format!("cells_total = {} but the sweeps give {} cells", m.cells_total, grid.cells()));
    }
    let fin = |v: f64| v.is_finite();
    if !(fin(m.dt_s) && m.dt_s > 0.0) {
        return bad(format!("dt_s = {}: the step must be a finite time > 0 s", sig4(m.dt_s)));
    }
    if !(fin(m.duration_s) && m.duration_s > 0.0) {
        return bad(format!("duration_s = {}: the run length must be a finite time > 0 s", sig4(m.duration_s)));
    }
    if !(fin(m.stats_from_s) && m.stats_from_s >= 0.0 && m.stats_from_s < m.duration_s) {
        return bad(format!("stats_from_s = {}: must satisfy 0 <= stats_from < duration_s", sig4(m.stats_from_s)));
    }
    if !matches!(m.precision.as_str(), "f32" | "f64") {
        return bad(format!("precision `{}`: must be f32 or f64", m.precision));
    }
    if !(fin(m.kick) && m.kick > 0.0 && m.kick <= 0.5) {
        return bad(format!("kick = {}: must satisfy 0 < kick <= 0.5", sig4(m.kick)));
    }
    if m.steady_pp_over_kick_v != cell::STEADY_PP {
        return bad(format!(
            "steady_pp_over_kick_v = {}: this build classifies with {} (a map of another version)",
            sig4(m.steady_pp_over_kick_v),
            cell::STEADY_PP
        ));
    }
    if let Err(e) = crate::scenes::scene_file::parse(&m.scene_toml) {
        return bad(format!("scene_toml: not a scene file: {}", e.message));
    }
    let (k, n) = match m.shard {
        Some(sh) if sh.n == 0 || sh.k >= sh.n => return bad(format!("shard {}/{}: needs 0 <= K < N", sh.k, sh.n)),
        Some(sh) => (sh.k, sh.n),
        None => (0, 1),
    };
    let expected = if k < m.cells_total { (m.cells_total - k).div_ceil(n) } else { 0 };
    if m.cells.len() != expected {
        return bad(format!(
            "{} cells, but shard {k}/{n} of {} cells holds {expected}",
            m.cells.len(),
            m.cells_total
        ));
    }
    let words: Vec<&str> = output::REGIMES.iter().map(|(r, _)| *r).collect();
    for (j, c) in m.cells.iter().enumerate() {
        let want = k + j * n;
        if c.index != want {
            return bad(format!("cell {} at position {j}: shard {k}/{n} has cell {want} there", c.index));
        }
        let params = grid.params(c.index);
        // a JSON object: its keys in any order (serde_json writes them sorted)
        let keys_ok = c.params.len() == params.len() && params.iter().all(|(b, _)| c.params.contains_key(b));
        if !keys_ok {
            return bad(format!("cell {}: params {:?}: must be the swept keys {:?}", c.index, c.params.keys().collect::<Vec<_>>(), params.iter().map(|(k, _)| k).collect::<Vec<_>>()));
        }
        for (key, v) in &params {
            match c.params.get(key).and_then(|x| x.as_f64()) {
                Some(x) if x == *v => {}
                Some(x) => return bad(format!("cell {}: {key} = {}: the grid's value there is {}", c.index, sig4(x), sig4(*v))),
                None => return bad(format!("cell {}: {key} is not a number", c.index)),
            }
        }
        let runs = [("from_sliding", &c.from_sliding), ("from_rest", &c.from_rest)];
        match &c.invalid {
            Some(_) if c.linear.is_some() || runs.iter().any(|(_, r)| r.is_some()) => {
                return bad(format!("cell {}: an invalid cell with results", c.index));
            }
            Some(_) => {}
            None => {
                for (what, r) in runs {
                    let Some(r) = r else { return bad(format!("cell {}: {what} missing", c.index)) };
                    if !words.contains(&r.regime.as_str()) || r.regime == "invalid" {
                        return bad(format!("cell {}: {what}.regime `{}`: not a regime ({})", c.index, r.regime, words.join(", ")));
                    }
                    let vals = [r.stick_fraction, r.stick_slip_hz, r.pad_x_pp, r.groan_rms, r.slide_v_pp, r.halt_s];
                    if vals.iter().flatten().any(|v| !v.is_finite() || *v < 0.0) {
                        return bad(format!("cell {}: {what}: a value is negative or not finite", c.index));
                    }
                    // maps written before the fraction was clamped at 1 carry a rounding's excess
                    if r.stick_fraction.is_some_and(|f| f > 1.0 + 1e-9) {
                        return bad(format!("cell {}: {what}.stick_fraction > 1", c.index));
                    }
                }
            }
        }
    }
    Ok(())
}

/// Joins shards of one map: every shard must come from the same job (scene, sweeps, options),
/// no cell twice, none missing. `names` label the inputs in errors. Each shard is
/// [`validate`]d first.
pub fn merge(parts: Vec<(String, MapJson)>) -> std::result::Result<MapJson, String> {
    for (name, m) in &parts {
        validate(name, m)?;
    }
    let mut it = parts.into_iter();
    let Some((first_name, first)) = it.next() else {
        return Err("map merge: give the shards' JSON files".into());
    };
    let header = |m: &MapJson| {
        let mut h = m.clone();
        h.cells.clear();
        h.shard = None;
        h
    };
    let want = header(&first);
    // which file holds each cell, to name both where one is given twice
    let mut held_by: std::collections::HashMap<usize, String> = first.cells.iter().map(|c| (c.index, first_name.clone())).collect();
    let mut cells = first.cells;
    for (name, m) in it {
        if header(&m) != want {
            return Err(format!(
                "map merge: {name} is not a shard of the same map as {first_name} (scene, sweeps or options differ)"
            ));
        }
        for c in &m.cells {
            if let Some(other) = held_by.insert(c.index, name.clone()) {
                return Err(format!("map merge: cell {} is in both {other} and {name} (the same shard given twice?)", c.index));
            }
        }
        cells.extend(m.cells);
    }
    cells.sort_by_key(|c| c.index);
    for w in cells.windows(2) {
        if w[0].index == w[1].index {
            return Err(format!("map merge: cell {} appears twice (the same shard given twice?)", w[0].index));
        }
    }
    if let Some(c) = cells.iter().find(|c| c.index >= want.cells_total) {
        return Err(format!("map merge: cell {} is beyond the map's {} cells", c.index, want.cells_total));
    }
    if cells.len() != want.cells_total {
        let have: std::collections::HashSet<usize> = cells.iter().map(|c| c.index).collect();
        let first_missing = (0..want.cells_total).find(|i| !have.contains(i)).unwrap_or(0);
        return Err(format!(
            "map merge: {} of {} cells missing (first: cell {first_missing}): give every shard",
            want.cells_total - cells.len(),
            want.cells_total
        ));
    }
    Ok(MapJson { cells, ..want })
}

/// Reads a map's JSON file (`map merge`).
pub fn read_json(path: &std::path::Path) -> Result<MapJson> {
    let text = crate::limits::read_text(path, "map shard", crate::limits::SHARD_FILE_MAX_BYTES)?;
    serde_json::from_str(&text).map_err(|e| HostError::Input(format!("{}: not a map's JSON: {e}", path.display())))
}
