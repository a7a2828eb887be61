//! `map` and `map merge`.

use super::{overrides, to_json};
use crate::error::{HostError, Result};
use crate::scenes::scene_source;

/// `map` and `map merge`.
pub fn map(a: &crate::cli::MapArgs) -> Result<String> {
    use crate::map::{self, cell::CellOptions, sweep::Grid, sweep::Sweep, MapSpec, Shard};
    let (m, out) = match &a.action {
        Some(crate::cli::MapAction::Merge(mg)) => {
            let mut parts = Vec::new();
            for f in &mg.files {
                parts.push((f.display().to_string(), map::read_json(f)?));
            }
            (map::merge(parts).map_err(HostError::Input)?, &mg.out)
        }
        None => {
            // clap requires SCENE when no subcommand is given
            let scene = a.scene.as_deref().ok_or_else(|| HostError::Input("map: give SCENE".into()))?;
            let ns = scene_source::prepare(scene_source::resolve(scene)?, &overrides(&a.run))?;
            let sweeps = a.sweeps.iter().map(|s| Sweep::parse(s)).collect::<std::result::Result<Vec<_>, _>>().map_err(HostError::Input)?;
            let grid = Grid::new(sweeps).map_err(HostError::Input)?;
            // a file's damping ratios hold in every cell (its coefficients from the cell's
            // stiffness), not the coefficients they give at the file's own stiffness
            let held = scene_source::file_ratios(&ns, &grid.keys());
            let grid = grid.holding_ratios(held);
            // a run setting given twice, as an option and as a sweep: the sweep would win silently
            for (option, given, key) in [("--dt", a.run.dt.is_some(), "dt"), ("--duration", a.run.duration.is_some(), "duration"), ("--stats-from", a.run.stats_from.is_some(), "stats_from")] {
                if let Some(sw) = grid.sweeps.iter().find(|sw| sw.key == key).filter(|_| given) {
                    return Err(HostError::Input(format!("{option} and --sweep {}: both set `{key}`; give one", sw.spec())));
                }
            }
            let shard = a.shard.as_deref().map(Shard::parse).transpose().map_err(HostError::Input)?;

            let spec = MapSpec {
                scene_name: ns.name.clone(),
                base: ns.scene,
                grid,
                options: CellOptions { precision: a.run.precision, kick: a.kick, stick_jump: !a.step_stick },
                shard,
                jobs: a.jobs.map(usize::from),
                progress: true,
                share_sliding: true,
            };
            // an output file that cannot be written fails now, not after the map has run
            if let Some(path) = &a.out.csv {
                crate::output::check_writable(path, "CSV")?;
            }
            if let Some(path) = &a.out.plot {
                crate::output::check_writable(path, "figure")?;
            }
            let (m, t) = map::run_map(&spec)?;
            eprintln!(
                "map: {} cells, {} steps ({} stepped, {} jumped over stick) in {:.2} s on {} threads: {:.3e} steps/s, {:.3e} stepped/s",
                t.cells,
                t.steps,
                t.stepped(),
                t.jumped,
                t.seconds,
                t.threads,
                t.steps as f64 / t.seconds.max(1e-9),
                t.stepped() as f64 / t.seconds.max(1e-9)
            );
            (m, &a.out)
        }
    };
    if let Some(path) = &out.csv {
        map::output::write_csv(&m, path)?;
    }
    if let Some(path) = &out.plot {
        map::plot::write(&m, path)?;
    }
    Ok(if out.json { to_json(&m) } else { map::output::markdown(&m) })
}
