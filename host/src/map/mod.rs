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
pub mod sweep;

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use stickslip_model::Scene;

use crate::error::{HostError, Result};
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
        let bad = || format!("--shard {arg}: expected K/N with whole numbers 0 <= K < N");
        let (k, n) = arg.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if n == 0 || k >= n {
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
}

/// How long the map took (stderr only: the JSON stays reproducible).
#[derive(Clone, Copy, Debug)]
pub struct Timing {
    pub cells: usize,
    pub steps: u64,
    pub seconds: f64,
    pub threads: usize,
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
    let t0 = Instant::now();
    let cells: Result<Vec<CellJson>> = pool.install(|| {
        indices
            .par_iter()
            .map(|&i| {
                let (c, n) = cell::cell(i, &spec.grid.params(i), spec.grid.scene(&spec.base, i), spec.options)?;
                steps.fetch_add(n, Ordering::Relaxed);
                bar.inc(1);
                Ok(c)
            })
            .collect()
    });
    bar.finish_and_clear();
    let cells = cells?;
    let timing = Timing { cells: cells.len(), steps: steps.load(Ordering::Relaxed), seconds: t0.elapsed().as_secs_f64(), threads: pool.current_num_threads() };
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

/// Joins shards of one map: every shard must come from the same job (scene, sweeps, options),
/// no cell twice, none missing. `names` label the inputs in errors.
pub fn merge(parts: Vec<(String, MapJson)>) -> std::result::Result<MapJson, String> {
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
    let mut cells = first.cells;
    for (name, m) in it {
        if header(&m) != want {
            return Err(format!(
                "map merge: {name} is not a shard of the same map as {first_name} (scene, sweeps or options differ)"
            ));
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
    let text = std::fs::read_to_string(path).map_err(|e| HostError::Input(format!("{}: cannot read: {e}", path.display())))?;
    serde_json::from_str(&text).map_err(|e| HostError::Input(format!("{}: not a map's JSON: {e}", path.display())))
}
