//! `cases`: the six cases, their damping sensitivity and their figures.

use std::path::Path;

use super::{overrides, to_json};
use crate::cli::CasesArgs;
use crate::error::{HostError, Result};
use crate::output::format::short;
use crate::output::plots::{self, FigureContext, Line};
use crate::output::report::{self, CaseJson, CasesJson};
use crate::scenes::builtin;
use crate::scenes::run::{self, RunReport};
use crate::scenes::scene_source::{self, NamedScene};
use crate::scenes::series::{NoSink, Recorder};

/// The plotted window [s]: checked against the run length.
fn plot_window(a: &CasesArgs, ns: &NamedScene) -> Result<(f64, f64)> {
    let run_s = run::planned_steps(&ns.scene) as f64 * ns.scene.dt;
    let from = a.plot_from.unwrap_or(ns.scene.stats_from);
    let bad = |opt: &str, v: f64, rule: String| Err(HostError::Input(format!("{opt} {}: {rule}", short(v))));
    if !(from.is_finite() && from >= 0.0 && from < run_s) {
        return bad(
            "--plot-from",
            from,
            format!("plot start must satisfy 0 <= start < run length {run_s} s"),
        );
    }
    let to = a.plot_to.unwrap_or((from + 0.1).min(run_s));
    if !(to.is_finite() && to > from && to <= run_s * (1.0 + 1e-12)) {
        return bad(
            "--plot-to",
            to,
            format!("plot end must satisfy plot start {from} s < end <= run length {run_s} s"),
        );
    }
    Ok((from, to))
}

pub fn cases(a: &CasesArgs) -> Result<String> {
    let ov = overrides(&a.run);
    let set = match a.set {
        crate::cli::CaseSet::Thesis => builtin::cases(),
        crate::cli::CaseSet::Rig => builtin::rig_cases(),
        crate::cli::CaseSet::RigFloat => builtin::rig_float_cases(),
        crate::cli::CaseSet::RigBuilt => {
            if a.run.precision != run::Precision::F64 {
                return Err(HostError::Input(format!(
                    "--set rig-built has unilateral contact (contact = \"unilateral\"), which runs in f64 only: \
                     drop --precision {} (f64 is the default)",
                    a.run.precision.name()
                )));
            }
            builtin::rig_built_cases()
        }
    };
    let scenes = set
        .into_iter()
        .map(|b| scene_source::prepare(NamedScene::from_builtin(b), &ov))
        .collect::<Result<Vec<_>>>()?;
    let window = match &a.plots {
        Some(_) => Some(plot_window(a, &scenes[0])?),
        None => None,
    };
    let mut runs: Vec<(NamedScene, RunReport)> = Vec::with_capacity(scenes.len());
    let mut recorded: Vec<Recorder> = Vec::new();
    for ns in scenes {
        let r = match window {
            Some((from, to)) => {
                let mut rec = Recorder::new(from, to);
                let r = run::run(&ns.scene, a.run.precision, &mut rec)?;
                recorded.push(rec);
                r
            }
            None => run::run(&ns.scene, a.run.precision, &mut NoSink)?,
        };
        runs.push((ns, r));
    }
    if let (Some(dir), Some((from, to))) = (&a.plots, window) {
        let n = write_figures(dir, &runs, &recorded, from, to)?;
        eprintln!("stickslip: wrote {n} SVG figures to {}", dir.display());
    }
    if a.json {
        let (ns0, r0) = &runs[0];
        let j = CasesJson {
            precision: a.run.precision.name(),
            dt: ns0.scene.dt,
            duration: ns0.scene.duration,
            stats_from: r0.window_start,
            cases: runs.iter().map(|(ns, r)| CaseJson::new(ns, r)).collect(),
        };
        Ok(to_json(&j))
    } else {
        let mut out = report::cases_table(&runs);
        if a.set == crate::cli::CaseSet::Thesis {
            out.push_str(&damping_sensitivity(&runs, a.run.precision)?);
        }
        Ok(out)
    }
}

/// The thesis set has no damping, and its push cases hinge on that: each case again with 1 %
/// and 5 % of critical damping on phi (c_phi = 2 zeta sqrt(K I)), each statistic as the
/// relative change from the undamped run.
fn damping_sensitivity(runs: &[(NamedScene, RunReport)], precision: run::Precision) -> Result<String> {
    let mut out = String::from(
        "\nSensitivity to damping on phi (the thesis sets none): each case with zeta_phi = 1 % and 5 %, \
         c_phi = 2 zeta sqrt(K I); relative change from the undamped run above.\n\n\
         | case | zeta_phi | x pp | x' pp | phi pp | phi' pp | stick fraction | stick-slip frequency |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for (ns, r0) in runs {
        for zeta in [0.01, 0.05] {
            let mut s = ns.scene;
            s.c_phi = 2.0 * zeta * (stickslip_model::Coefficients::of(&s).k_rot * s.inertia).sqrt();
            let r = run::run(&s, precision, &mut NoSink)?;
            let change = |a: Option<f64>, b: Option<f64>| match (a, b) {
                (Some(a), Some(b)) if b != 0.0 => format!("{:+.1} %", (a / b - 1.0) * 100.0),
                _ => "n/a".into(),
            };
            let sf = |r: &RunReport| r.has_window().then_some(r.stats.stick_fraction);
            let hz = |r: &RunReport| r.has_window().then_some(r.stats.stick_slip_hz);
            out.push_str(&format!(
                "| {} | {} % | {} | {} | {} | {} | {} | {} |\n",
                ns.name,
                zeta * 100.0,
                change(r.pp(0), r0.pp(0)),
                change(r.pp(1), r0.pp(1)),
                change(r.pp(2), r0.pp(2)),
                change(r.pp(3), r0.pp(3)),
                change(sf(&r), sf(r0)),
                change(hz(&r), hz(r0)),
            ));
        }
    }
    Ok(out)
}

fn write_figures(
    dir: &Path,
    runs: &[(NamedScene, RunReport)],
    rec: &[Recorder],
    from: f64,
    to: f64,
) -> Result<usize> {
    std::fs::create_dir_all(dir).map_err(|e| {
        HostError::Output(format!(
            "{}: cannot create the figure directory: {e}",
            dir.display()
        ))
    })?;
    let mut n = 0;
    for caliper in ["push", "pull"] {
        let idx: Vec<usize> = (0..runs.len())
            .filter(|&i| runs[i].0.scene.caliper.name() == caliper)
            .collect();
        let Some(&first) = idx.first() else { continue };
        let lines: Vec<Line> = idx
            .iter()
            .map(|&i| {
                let ns = &runs[i].0;
                let place = ns.name.rsplit('_').next().unwrap_or("");
                let place = match place {
                    "trail" => "trailing",
                    "center" => "centre",
                    "lead" => "leading",
                    p => p,
                };
                Line {
                    label: format!("β = {:.3} m ({place})", ns.scene.beta),
                    samples: &rec[i].samples,
                }
            })
            .collect();
        let s = &runs[first].0.scene;
        let ctx = FigureContext {
            caliper,
            from,
            to,
            run_s: run::planned_steps(s) as f64 * s.dt,
            v: s.v,
        };
        n += plots::caliper_figures(dir, &ctx, &lines)?.len();
    }
    Ok(n)
}
