//! A fit's Markdown, JSON, figure (model against measured, per statistic, every case) and
//! fitted scene file.

use std::collections::BTreeMap;
use std::path::Path;

use plotters::prelude::*;
use serde::Serialize;

use crate::output::style;

use super::stat::Stat;
use super::{rms_log_ratio, Compared, FitReport};
use crate::error::{HostError, Result};
use crate::output::format::{num, opt};
use crate::scenes::scene_file;

mod plot;
mod profile;
pub use plot::*;
pub use profile::*;

fn pct(v: f64) -> String {
    if v.is_finite() {
        format!("{:.3} %", 100.0 * v)
    } else {
        "n/a".into()
    }
}

#[derive(Serialize)]
pub struct ParameterJson {
    pub value: f64,
    /// From the Jacobian (delta method); null where not determined.
    pub std: Option<f64>,
    pub std_bootstrap: Option<f64>,
    pub start: f64,
    pub lo: f64,
    pub hi: f64,
    /// The 95 % profile-likelihood interval [lo, hi]; null on a side where the profile does not
    /// close inside the bounds (not identifiable there); absent where not computed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interval: Option<[Option<f64>; 2]>,
    /// The profile's points behind `interval`, by value: the optimum at delta_chi2 0, the
    /// interval's ends where delta_chi2 crosses 3.841; absent where not computed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub profile: Option<Vec<ProfilePointDchi2Json>>,
}

/// A point of a key's profile: the key's value and the rise of chi^2 over the optimum (the
/// other free keys refitted), scaled so that the 95 % threshold is 3.841.
#[derive(Serialize)]
pub struct ProfilePointDchi2Json {
    pub value: f64,
    pub delta_chi2: f64,
}

#[derive(Serialize)]
pub struct GoodnessJson {
    pub chi2_per_dof: f64,
    pub dof: usize,
    pub noise: f64,
    pub noise_source: String,
    pub chi2_limit: f64,
    pub starts_agreeing: usize,
    pub verdict: &'static str,
}

#[derive(Serialize)]
pub struct ComparedJson {
    pub case: String,
    pub channel: Option<&'static str>,
    pub statistic: &'static str,
    pub measured: f64,
    pub model: Option<f64>,
    pub log_ratio: Option<f64>,
    pub weight: f64,
    pub source: String,
}

impl From<&Compared> for ComparedJson {
    fn from(c: &Compared) -> Self {
        ComparedJson {
            case: c.key.case.clone(),
            channel: c.key.channel.map(|_| c.key.channel_name()),
            statistic: c.key.stat.name(),
            measured: c.measured,
            model: c.model,
            log_ratio: c.log_ratio(),
            weight: c.weight,
            source: c.source.clone(),
        }
    }
}

#[derive(Serialize)]
pub struct FlatJson {
    pub direction: BTreeMap<String, f64>,
    pub std_log: Option<f64>,
}

#[derive(Serialize)]
pub struct StartJson {
    pub from: BTreeMap<String, f64>,
    pub values: BTreeMap<String, f64>,
    pub cost: f64,
    pub converged: bool,
    /// The horizon stage after which this start was left (its cost there far above the best
    /// start's); null: searched to the end.
    pub left_after_horizon: Option<usize>,
}

#[derive(Serialize)]
pub struct FitJson {
    pub scene: String,
    pub parameters: BTreeMap<String, ParameterJson>,
    pub residuals: Vec<ComparedJson>,
    pub holdout: Vec<ComparedJson>,
    pub converged: bool,
    pub goodness: GoodnessJson,
    /// "waveform" (the time-domain cost) or "statistics".
    pub cost_kind: &'static str,
    pub identifiable: bool,
    pub flat_directions: Vec<FlatJson>,
    pub correlation: BTreeMap<String, BTreeMap<String, Option<f64>>>,
    pub cost: f64,
    pub residual_variance: Option<f64>,
    pub rms_log_ratio_fitted: Option<f64>,
    pub rms_log_ratio_holdout: Option<f64>,
    pub weights: BTreeMap<&'static str, f64>,
    pub breakaway_jump_m_s2: f64,
    pub bootstrap_resamples: usize,
    pub evaluations: usize,
    pub seconds: f64,
    pub starts: Vec<StartJson>,
    /// The horizon stages searched before the whole record, shortest first.
    pub stages: Vec<StageJson>,
    pub skipped: Vec<String>,
    pub notes: Vec<String>,
}

/// One horizon stage: `cycles` stick-slip periods after each recording's first slip onset,
/// the horizon of each case [s], the statistics fitted, and the stage's best point and cost.
#[derive(Serialize)]
pub struct StageJson {
    pub cycles: f64,
    pub horizons_s: BTreeMap<String, f64>,
    pub statistics: usize,
    pub values: BTreeMap<String, f64>,
    pub cost: Option<f64>,
    pub converged: bool,
}

fn finite(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}

impl FitJson {
    pub fn new(r: &FitReport) -> Self {
        let keyed = |v: &[f64]| -> BTreeMap<String, f64> { r.free.iter().zip(v).map(|(f, x)| (f.key.clone(), *x)).collect() };
        let parameters = r
            .free
            .iter()
            .enumerate()
            .map(|(k, f)| {
                (
                    f.key.clone(),
                    ParameterJson {
                        value: r.values[k],
                        std: finite(r.std[k]),
                        std_bootstrap: r.std_bootstrap.as_ref().and_then(|s| finite(s[k])),
                        start: f.start,
                        lo: f.lo,
                        hi: f.hi,
                        interval: r.intervals.get(k).map(|(a, b)| [*a, *b]),
                        profile: r.profiles.get(k).map(|p| {
                            p.iter().map(|(value, d)| ProfilePointDchi2Json { value: *value, delta_chi2: *d }).collect()
                        }),
                    },
                )
            })
            .collect();
        let correlation = r
            .free
            .iter()
            .enumerate()
            .map(|(a, fa)| {
                (fa.key.clone(), r.free.iter().enumerate().map(|(b, fb)| (fb.key.clone(), finite(r.correlation[(a, b)]))).collect())
            })
            .collect();
        FitJson {
            scene: r.scene.name.clone(),
            parameters,
            residuals: r.fitted.iter().map(Into::into).collect(),
            holdout: r.holdout.iter().map(Into::into).collect(),
            converged: r.converged,
            goodness: GoodnessJson {
                chi2_per_dof: r.goodness.chi2_per_dof,
                dof: r.goodness.dof,
                noise: r.goodness.noise,
                noise_source: r.goodness.noise_source.clone(),
                chi2_limit: super::goodness::chi2_limit(r.goodness.dof),
                starts_agreeing: r.goodness.starts_agreeing,
                verdict: r.goodness.verdict.name(),
            },
            cost_kind: if r.time_domain { "waveform" } else { "statistics" },
            identifiable: r.identifiable(),
            flat_directions: r
                .uncertainty
                .flat
                .iter()
                .map(|f| FlatJson { direction: keyed(&f.direction), std_log: finite(f.std_log) })
                .collect(),
            correlation,
            cost: r.cost,
            residual_variance: finite(r.uncertainty.residual_variance),
            rms_log_ratio_fitted: rms_log_ratio(&r.fitted),
            rms_log_ratio_holdout: rms_log_ratio(&r.holdout),
            weights: r.weights.iter().map(|(s, w)| (s.name(), *w)).collect(),
            breakaway_jump_m_s2: r.jump_m_s2,
            bootstrap_resamples: if r.std_bootstrap.is_some() { r.bootstrap_resamples } else { 0 },
            evaluations: r.evaluations,
            seconds: r.seconds,
            starts: r
                .starts
                .iter()
                .map(|s| StartJson { from: keyed(&s.from), values: keyed(&s.values), cost: s.cost, converged: s.converged, left_after_horizon: s.left_after })
                .collect(),
            stages: r
                .stages
                .iter()
                .map(|st| StageJson {
                    cycles: st.cycles,
                    horizons_s: st.horizons.iter().cloned().collect(),
                    statistics: st.statistics,
                    values: keyed(&st.result.values),
                    cost: finite(st.result.cost),
                    converged: st.result.converged,
                })
                .collect(),
            skipped: r.skipped.iter().map(|s| format!("{} ({}): {}", s.key.label(), s.source, s.why)).collect(),
            notes: r.notes.clone(),
        }
    }
}

fn compared_table(rows: &[Compared]) -> String {
    let mut s = String::from("| case | channel | statistic | measured | model | model / measured | weight |\n|---|---|---|---:|---:|---:|---:|\n");
    for r in rows {
        s.push_str(&format!(
            "| {} | {} | {} [{}] | {} | {} | {} | {} |\n",
            r.key.case,
            if r.key.channel.is_some() { r.key.channel_name() } else { "-" },
            r.key.stat.name(),
            r.key.stat.unit(),
            num(r.measured),
            opt(r.model),
            r.log_ratio().map_or("n/a".into(), |l| format!("{:.4}", l.exp())),
            num(r.weight)
        ));
    }
    s
}

/// A direction as "0.71 mu_s + 0.70 mu_k".
fn direction_text(r: &FitReport, d: &[f64]) -> String {
    let mut parts: Vec<(f64, &str)> = d.iter().zip(&r.free).map(|(x, f)| (*x, f.key.as_str())).collect();
    parts.sort_by(|a, b| b.0.abs().total_cmp(&a.0.abs()));
    parts
        .iter()
        .filter(|(x, _)| x.abs() >= 0.05)
        .map(|(x, k)| format!("{x:+.2} ln {k}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The Markdown report.
pub fn markdown(r: &FitReport) -> String {
    let mut s = format!("# Fit of scene `{}` ({})\n\n", r.scene.name, r.scene.origin_short());
    let cases: Vec<&str> = {
        let mut c: Vec<&str> = r.fitted.iter().map(|x| x.key.case.as_str()).collect();
        c.dedup();
        c
    };
    // the time-domain cost fits the samples, not the statistics (which it only lists)
    let what = if r.time_domain {
        format!("The recorded pad_x, sample by sample ({} degrees of freedom),", r.goodness.dof)
    } else {
        format!("{} statistics of {} case{} ({})", r.fitted.len(), cases.len(), if cases.len() == 1 { "" } else { "s" }, cases.join(", "))
    };
    s.push_str(&format!(
        "{what} fitted with {} free key{}; {} evaluations of the virtual rig in {:.1} s; {}.\n\n",
        r.free.len(),
        if r.free.len() == 1 { "" } else { "s" },
        r.evaluations,
        r.seconds,
        match r.goodness.verdict {
            super::goodness::Verdict::Fits => "verdict **fits**: the best cost is what the noise explains",
            super::goodness::Verdict::Misfit => "verdict **misfit**: the starts agree on a cost the noise does not explain (the model family does not fit)",
            super::goodness::Verdict::NotConverged => "verdict **not converged**: the starts end at different costs",
        }
    ));
    s.push_str(&format!(
        "Goodness: chi^2 / dof = {:.4} over {} degrees of freedom (fits up to {:.4}); noise {} ({}); {} of {} starts at the best cost. Cost: {}.\n\n",
        r.goodness.chi2_per_dof,
        r.goodness.dof,
        super::goodness::chi2_limit(r.goodness.dof),
        num(r.goodness.noise),
        r.goodness.noise_source,
        r.goodness.starts_agreeing,
        r.starts.len(),
        if r.time_domain { "the recorded pad_x sample by sample (time domain, multiple shooting over the cycles)" } else { "the statistics' log ratios" }
    ));
    s.push_str("| key | start | fitted | std (Jacobian) | std (bootstrap) | 95 % interval (profile) | bounds |\n|---|---:|---:|---:|---:|---|---|\n");
    for (k, f) in r.free.iter().enumerate() {
        let rel = r.std[k] / r.values[k];
        let boot = r.std_bootstrap.as_ref().map_or("-".into(), |b| format!("{} ({})", num(b[k]), pct(b[k] / r.values[k])));
        let side = |x: Option<f64>, open: &str| x.map_or(open.to_string(), num);
        let interval = r.intervals.get(k).map_or("-".into(), |(a, b)| format!("[{}, {}]", side(*a, "not closed"), side(*b, "not closed")));
        s.push_str(&format!(
            "| {} | {} | {} | {} ({}) | {} | {} | [{}, {}] |\n",
            f.key,
            num(f.start),
            num(r.values[k]),
            num(r.std[k]),
            pct(rel),
            boot,
            interval,
            num(f.lo),
            num(f.hi)
        ));
    }
    s.push('\n');
    if r.goodness.verdict == super::goodness::Verdict::NotConverged {
        // the curvature of a point that may not be the optimum says nothing of the optimum's
        s.push_str("At the best point found, which the starts do not confirm as the optimum (not converged): the standard errors and directions below are its local curvature's, not error bars of an estimate.\n\n");
    }
    if r.no_stick_slip {
        s.push_str("**Not identifiable**: no recording holds stick-slip (read with its own noise floor, as `analyze` reads it: see the notes); nothing in the data determines the friction, whatever the standard errors below say.\n\n");
    }
    let undetermined = !r.uncertainty.flat.is_empty() || !r.open_profiles().is_empty();
    if r.identifiable() {
        s.push_str("Identifiable: every direction of the parameters is determined to better than +-35 % (the standard error of ln p along each singular vector of the Jacobian is below 0.3).\n\n");
    } else if undetermined {
        s.push_str("**Not identifiable**: the data leave these directions of the parameters undetermined (standard error of ln p along them above 0.3, about +-35 %, or a profile interval that does not close):\n\n");
        for f in &r.uncertainty.flat {
            s.push_str(&format!("- {} (std {})\n", direction_text(r, &f.direction), num(f.std_log)));
        }
        for (k, below, above) in r.open_profiles() {
            let side = match (below, above) {
                (true, true) => "on either side",
                (true, false) => "below: an upper bound only",
                _ => "above: a lower bound only",
            };
            s.push_str(&format!("- {}: its 95 % profile interval does not close {side}\n", r.free[k].key));
        }
        s.push_str("\nFix one of the keys along a flat direction, or add a target that moves it.\n\n");
    }
    if r.free.len() > 1 {
        s.push_str(&format!("Correlation of the fitted parameters (of {}):\n\n|  |", coordinates(r)));
        for f in &r.free {
            s.push_str(&format!(" {} |", f.key));
        }
        s.push_str("\n|---|");
        s.push_str(&"---:|".repeat(r.free.len()));
        s.push('\n');
        for (a, fa) in r.free.iter().enumerate() {
            s.push_str(&format!("| {} |", fa.key));
            for b in 0..r.free.len() {
                let c = r.correlation[(a, b)];
                s.push_str(&if c.is_finite() { format!(" {c:+.3} |") } else { " n/a |".into() });
            }
            s.push('\n');
        }
        s.push('\n');
    }
    s.push_str(&format!(
        "## Residuals (fitted cases)\n\nRMS of ln(model / measured): {} over {} statistics; residual variance s^2 = {} ({} degrees of freedom).\n\n",
        opt(rms_log_ratio(&r.fitted)),
        r.fitted.len(),
        num(r.uncertainty.residual_variance),
        r.uncertainty.dof
    ));
    s.push_str(&compared_table(&r.fitted));
    if !r.holdout.is_empty() {
        s.push_str(&format!(
            "\n## Held out: {}\n\nThe fitted model's prediction of cases it was not fitted to. RMS of ln(model / measured): {}.\n\n",
            r.holdout_cases.join(", "),
            opt(rms_log_ratio(&r.holdout))
        ));
        s.push_str(&compared_table(&r.holdout));
    }
    let kv = |v: &[f64]| r.free.iter().zip(v).map(|(f, x)| format!("{} = {}", f.key, num(*x))).collect::<Vec<_>>().join(", ");
    s.push_str("\n## Starts\n\n| start | from | fitted | cost | converged |\n|---:|---|---|---:|---|\n");
    for (i, st) in r.starts.iter().enumerate() {
        let conv = match st.left_after {
            Some(h) => format!("left after horizon {h}"),
            None => st.converged.to_string(),
        };
        s.push_str(&format!("| {} | {} | {} | {:.4e} | {conv} |\n", i + 1, kv(&st.from), kv(&st.values), st.cost));
    }
    if !r.stages.is_empty() {
        s.push_str(
            "\n## Horizon stages\n\nEach start is fitted to each recording's start (t = 0 to its first slip onset + the cycles given, in the recording's own stick-slip periods), from there to the next horizon, then to the whole record. The winning start's stages:\n\n| cycles | horizons [s] | statistics | fitted | cost | converged |\n|---:|---|---:|---|---:|---|\n",
        );
        for st in &r.stages {
            let hz = st.horizons.iter().map(|(c, h)| format!("{c} {}", num(*h))).collect::<Vec<_>>().join(", ");
            s.push_str(&format!(
                "| {} | {hz} | {} | {} | {:.4e} | {} |\n",
                num(st.cycles),
                st.statistics,
                kv(&st.result.values),
                st.result.cost,
                st.result.converged
            ));
        }
        s.push_str(&format!("| whole | - | {} | {} | {:.4e} | {} |\n", r.fitted.len(), kv(&r.values), r.cost, r.converged));
    }
    if r.time_domain {
        s.push_str(
            "\nMethod: residual = (recorded - model) / noise per sample of pad_x, by multiple shooting over the recording's stick-slip cycles (each cycle from the known breakaway state, its start shifted to fit), and the first re-stick's timing (docs/fit.md). ",
        );
        s.push_str(&format!(
            "Nelder-Mead (argmin) on {} from each start, then Levenberg-Marquardt from its best point; standard errors from the central-difference Jacobian at the optimum scaled by the residual variance.\n",
            coordinates(r)
        ));
    } else {
    s.push_str(&format!(
        "\nMethod: residual = sqrt(weight) ln(model / measured) per statistic; weights {}. The model side is the scene's virtual rig on the ideal sensor path (its accelerations at the samples, no noise or ADC) through the analysis `analyze` runs, the estimator's breakaway jump fixed at {} m/s^2 on both sides. Nelder-Mead (argmin) on {} from each start, then Levenberg-Marquardt from its best point; standard errors from the central-difference Jacobian at the optimum scaled by the residual variance{}.\n",
        r.weights.iter().map(|(st, w)| format!("{}={}", st.name(), num(*w))).collect::<Vec<_>>().join(", "),
        num(r.jump_m_s2),
        coordinates(r),
        if r.std_bootstrap.is_some() {
            format!("; bootstrap: {} resamples of the recordings' {} windows, each a linearised refit", r.bootstrap_resamples, super::target::WINDOWS)
        } else {
            String::new()
        }
    ));
    }
    if !r.skipped.is_empty() {
        s.push_str("\nNot fitted (recordings' statistics that are 0 or missing):\n\n");
        for k in &r.skipped {
            s.push_str(&format!("- {} ({}): {}\n", k.key.label(), k.source, k.why));
        }
    }
    for n in &r.notes {
        s.push_str(&format!("\nNote: {n}\n"));
    }
    s
}

/// The fitted scene as a scene file: the base scene with the fitted values.
pub fn fitted_toml(r: &FitReport) -> String {
    let desc = format!(
        "{} fitted ({}): {}",
        r.scene.name,
        if r.converged { "converged" } else { "not converged" },
        r.free
            .iter()
            .enumerate()
            .map(|(k, f)| format!("{} = {} +- {}", f.key, num(r.values[k]), num(r.std[k])))
            .collect::<Vec<_>>()
            .join(", ")
    );
    scene_file::to_toml(&format!("{}_fit", r.scene.name), &desc, &r.fitted_scene)
}

/// The search's coordinates in words: `ln p`, or with a drop coordinate `ln p (mu_k:
/// ln(0.45 - mu_k))` ([`crate::fit::model::FreeKey::coordinate_name`]).
fn coordinates(r: &FitReport) -> String {
    let special: Vec<String> = r.free.iter().filter(|f| f.origin != 0.0).map(|f| format!("{}: {}", f.key, f.coordinate_name())).collect();
    if special.is_empty() {
        "ln p".to_string()
    } else {
        format!("ln p ({})", special.join(", "))
    }
}
