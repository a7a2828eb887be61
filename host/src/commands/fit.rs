//! `fit`.

use super::recordings::read_options;
use super::{stderr_is_terminal, to_json};
use crate::error::{HostError, Result};
use crate::scenes::scene_source::{self, Overrides};

/// `fit`.
pub fn fit(a: &crate::cli::FitArgs) -> Result<String> {
    use crate::fit::{self, output, FitRequest};
    if a.horizons.len() > 16 {
        return Err(HostError::Input(format!("--horizons: {} stages, at most 16", a.horizons.len())));
    }
    let ns = scene_source::prepare(scene_source::resolve(&a.scene)?, &Overrides::default())?;
    let req = FitRequest {
        free: a.free.clone(),
        bounds: a.bounds.clone(),
        recordings: a.recordings.clone(),
        tables: a.table.clone(),
        holdout: a.holdout.clone(),
        weights: a.weights.clone(),
        from_s: a.from,
        segment: a.record.segment,
        breakaway_jump_m_s2: a.record.breakaway_jump,
        starts: a.starts,
        max_iters: a.max_iters,
        bootstrap: a.bootstrap,
        seed: a.seed,
        progress: stderr_is_terminal(),
        horizons: a.horizons.iter().copied().filter(|n| *n != 0.0).collect(),
        read: read_options(&a.input)?,
        cost: fit::CostKind::parse(&a.cost).ok_or_else(|| {
            HostError::Input(format!("--cost {}: give auto, waveform or statistics", a.cost))
        })?,
    };
    if let Some(spec) = &a.profile {
        if a.out.is_some() || a.plot.is_some() || !a.holdout.is_empty() {
            return Err(HostError::Input("--profile evaluates the cost only: it takes no --out, --plot or --holdout".into()));
        }
        let p = fit::run_profile(ns, &req, spec);
        // a cancelled profile's evaluations were refused: its result, or its error, is not one
        crate::cancel::check()?;
        let p = p?;
        return Ok(if a.json { to_json(&output::ProfileJson::new(&p)) } else { output::profile_markdown(&p) });
    }
    let r = fit::run_fit(ns, &req);
    crate::cancel::check()?;
    let r = r?;
    if let Some(path) = &a.out {
        std::fs::write(path, output::fitted_toml(&r))
            .map_err(|e| HostError::Output(format!("{}: cannot write the fitted scene: {e}", path.display())))?;
    }
    if let Some(path) = &a.plot {
        output::write_plot(&r, path)?;
    }
    Ok(if a.json { to_json(&output::FitJson::new(&r)) } else { output::markdown(&r) })
}
