//! The least-squares problem of a fit and its solution: the weighted log-ratio residuals, the
//! search from several starts (argmin's Nelder-Mead, then the levenberg-marquardt crate), the
//! Jacobian at the optimum and what it
//! says about the parameters (standard errors, correlations, flat directions), and the
//! linearised bootstrap over a recording's windows.
//!
//! **Parameters.** Free key i is searched as u_i = ln(p_i / p_i,start): every parameter on
//! the same relative scale, positive by construction. Bounds [lo, hi] and the scene's own
//! rules (mu_k <= mu_s, ...) are enforced by a cost of [`OUTSIDE`] outside them.
//!
//! **Residuals.** r_j = sqrt(w_j) ln(model_j / measured_j) for every fitted statistic j with
//! weight w_j > 0; a statistic the model does not produce (no onset, a zero channel) counts
//! as a ratio of e^[`MISSING_LOG_RATIO`]. Cost = sum r_j^2 / 2.
//!
//! **Standard errors** (Gauss-Newton at the optimum): J_jk = d r_j / d u_k by central
//! differences (step [`JACOBIAN_STEP`] in u); the residual variance s^2 = sum r^2 / (m - n)
//! (m residuals, n parameters) sets the scale: cov(u) = s^2 (J^T J)^-1, std(p_k) = p_k
//! sqrt(cov_kk) (the delta method). A direction of u along which the cost rises by less than
//! s^2 / 2 within +-[`FLAT_LOG`] (a singular value sigma of J with s / sigma > FLAT_LOG) is
//! reported as flat: the data do not determine it.
//!
//! **Bootstrap** over a recording's windows: each resample draws the windows with
//! replacement (the same draw for every statistic of a recording), moves each measured
//! statistic by the ratio of the resampled windows' mean to all windows' mean, and takes the
//! Gauss-Newton step from the optimum that this moves the parameters by,
//! du = (J^T J)^-1 J^T dlog(measured): a linearised refit (exact to first order, and
//! one model run fewer than a refit per resample). The parameters' spread over the resamples
//! is the bootstrap standard error.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use argmin::core::{CostFunction, Error, Executor, State, TerminationReason, TerminationStatus};
use argmin::solver::neldermead::NelderMead;
use indicatif::ProgressBar;
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::storage::Owned;
use nalgebra::{DMatrix, DVector, Dyn};
use rayon::prelude::*;
use stickslip_model::harness::prng::XorShift32;
use stickslip_model::Scene;

use super::model::{self, FreeKey};
use super::stat::StatKey;
use crate::recorded::analysis::Analysis;

mod local_search;
mod problem;
mod profile;
mod screen;
mod uncertainty;
use local_search::*;
pub use problem::*;
pub use profile::*;
pub use screen::*;
pub use uncertainty::*;

/// The cost outside the bounds or the scene's rules.
pub const OUTSIDE: f64 = 1e12;
/// The log ratio a statistic the model does not produce counts as (e^7, about 1100 x).
pub const MISSING_LOG_RATIO: f64 = 7.0;
/// Central-difference step of the Jacobian in u = ln(p / p_start): 1 %.
pub const JACOBIAN_STEP: f64 = 0.01;
/// A direction whose standard error exceeds this in u (ln p: 0.3 is about +-35 %) is flat.
pub const FLAT_LOG: f64 = 0.3;
/// Nelder-Mead stops when the standard deviation of its vertices' costs is below this: it
/// only has to find the basin, Levenberg-Marquardt goes to the bottom.
pub const SD_TOLERANCE: f64 = 1e-6;
/// First simplex of a start: each vertex one parameter 10 % off.
const SIMPLEX_STEP: f64 = 0.1;

/// One start of the search.
#[derive(Clone, Debug)]
pub struct StartReport {
    /// Its starting values.
    pub from: Vec<f64>,
    pub values: Vec<f64>,
    pub cost: f64,
    pub converged: bool,
    /// The horizon stage (1, 2, ...) after which the start was left ([`LEAVE_RATIO`]); its
    /// `values` are that stage's end and `cost` the whole record's there: not searched further.
    pub left_after: Option<usize>,
}

/// A start whose cost after a horizon stage is this many times the best start's or more is
/// left there (statistics of recordings): on the rig set's truth the starts in other basins
/// of a stage cost 0.2 to 0.4 against the best's 1e-3 to 1e-4, and each of them took as many
/// whole-record runs as the best start (docs/fit.md).
pub const LEAVE_RATIO: f64 = 10.0;

/// The whole-record search of the best start after the horizon stages (statistics) also
/// starts from its stage end with its worst-determined key (the largest standard error of
/// ln p on that stage) this far either way in ln p; the start's end is the lowest of the three.
pub const VALLEY_SEED: f64 = 0.04;

/// The two seeds of [`VALLEY_SEED`] around `u` on the stage `st` (none where its Jacobian
/// cannot be taken).
fn valley_seeds(st: &Problem, u: &[f64]) -> Vec<Vec<f64>> {
    let Ok(r) = st.residuals(u) else { return Vec::new() };
    let j = jacobian(st, u, &r);
    let unc = uncertainty(&j, &r);
    let n = u.len();
    let Some(k) = (0..n).filter(|&k| unc.cov_u[(k, k)].is_finite()).max_by(|&a, &b| unc.cov_u[(a, a)].total_cmp(&unc.cov_u[(b, b)])) else {
        return Vec::new();
    };
    eprintln!("fit: the best start's seeds: {} x e^(+-{VALLEY_SEED})", st.free[k].key);
    [VALLEY_SEED, -VALLEY_SEED]
        .iter()
        .map(|d| {
            let mut x = u.to_vec();
            x[k] += d;
            x
        })
        .collect()
}

/// The search's result.
pub struct Solution {
    pub u: Vec<f64>,
    pub cost: f64,
    pub converged: bool,
    pub starts: Vec<StartReport>,
}

/// The search's result at one horizon stage (see [`search`]).
#[derive(Clone, Debug)]
pub struct StageResult {
    pub values: Vec<f64>,
    pub cost: f64,
    pub converged: bool,
}

/// Searches `p` from each start and keeps the lowest cost. With horizon stages (`stages`:
/// the same free keys fitted to the recordings' starts, shortest first), each start is
/// carried through them before `p`: a [`local_search`] of the first stage (short runs: cheap,
/// and smooth in the parameters, where the whole record's statistics jump wherever the kind
/// of stick-slip cycle changes), from its end a local search of the next stage, and so on to
/// `p` itself: a continuation in the record's length. The starts run in parallel, stage by
/// stage (each evaluation runs its cases in parallel too; stderr gives each stage's runs and
/// time); the lowest cost on `p` wins, and its stages are returned.
pub fn search(p: &Problem, stages: &[&Problem], starts: usize, max_iters: u64) -> Result<(Solution, Vec<StageResult>), String> {
    let t0 = std::time::Instant::now();
    let points = match stages.first() {
        Some(first) if first.features => screened_starts(first, starts, None, GLOBAL_POINTS_PER_KEY),
        Some(first) => screened_starts(first, starts, Some(SCREEN_FACTOR.ln()), SCREEN_POINTS_PER_KEY),
        None if p.time_domain() => screened_starts(p, starts, None, GLOBAL_POINTS_PER_KEY),
        None => screened_starts(p, starts, None, TABLE_POINTS_PER_KEY),
    };
    let total = points.len();
    let runs_of = |q: &Problem| q.runs.load(Ordering::Relaxed);
    if let Some(first) = stages.first() {
        eprintln!("fit: the screen: {} runs in {:.1} s", runs_of(first), t0.elapsed().as_secs_f64());
    }
    // each start: its index, its first point, where it is, its stages' results
    type Live = (usize, Vec<f64>, Vec<f64>, f64, Vec<StageResult>);
    let mut live: Vec<Live> = points.into_iter().enumerate().map(|(k, u0)| (k, u0.clone(), u0, f64::INFINITY, Vec::new())).collect();
    let mut reports: Vec<(usize, StartReport)> = Vec::new();
    for (i, st) in stages.iter().enumerate() {
        let (t, r0) = (std::time::Instant::now(), runs_of(st));
        let done: Vec<Result<Live, String>> = live
            .into_par_iter()
            .map(|(k, u0, u, _, mut chain)| {
                let (su, c, conv) = local_search(st, &u, SIMPLEX_STEP, max_iters)?;
                eprintln!("fit: start {} of {total}, horizon {}: cost {c:.6e}", k + 1, i + 1);
                chain.push(StageResult { values: st.values(&su), cost: c, converged: conv });
                Ok((k, u0, su, c, chain))
            })
            .collect();
        live = done.into_iter().collect::<Result<_, _>>()?;
        eprintln!("fit: horizon {}: {} runs in {:.1} s", i + 1, runs_of(st) - r0, t.elapsed().as_secs_f64());
        // a start whose cost on this stage is LEAVE_RATIO times the best start's or more is in
        // another basin of the stage: it is left here (statistics only; its report carries the
        // whole record's cost at the point where it was left, one run)
        if !p.time_domain() {
            let best = live.iter().map(|l| l.3).fold(f64::INFINITY, f64::min);
            let (keep, leave): (Vec<Live>, Vec<Live>) = live.into_iter().partition(|l| !(l.3 > LEAVE_RATIO * best));
            for (k, u0, u, c, _) in leave {
                let whole = p.residuals(&u).map_or(OUTSIDE, |r| cost_of(&r));
                eprintln!("fit: start {} of {total} left after horizon {}: cost {c:.4e} there, {:.0} x the best start's", k + 1, i + 1, c / best);
                reports.push((k, StartReport { from: p.values(&u0), values: p.values(&u), cost: whole, converged: false, left_after: Some(i + 1) }));
            }
            live = keep;
        }
    }
    let (t, r0) = (std::time::Instant::now(), runs_of(p));
    // each surviving start's whole-record search; the best start of the last horizon stage
    // (statistics) also from VALLEY_SEED either way along its worst-determined key
    let seeds = match stages.last() {
        Some(last) if !p.time_domain() && !live.is_empty() => {
            let b = (0..live.len()).min_by(|&a, &b| live[a].3.total_cmp(&live[b].3)).expect("a start");
            valley_seeds(last, &live[b].2).into_iter().map(|u| (live[b].0, u)).collect()
        }
        _ => Vec::new(),
    };
    let jobs: Vec<(usize, Vec<f64>)> = live.iter().map(|l| (l.0, l.2.clone())).chain(seeds).collect();
    let found: Vec<Result<(usize, Vec<f64>, f64, bool), String>> = jobs
        .into_par_iter()
        .map(|(k, u)| {
            let (u, cost, converged) = local_search(p, &u, SIMPLEX_STEP, max_iters)?;
            Ok((k, u, cost, converged))
        })
        .collect();
    let mut found = found.into_iter().collect::<Result<Vec<_>, _>>()?;
    type Run = (usize, Vec<f64>, f64, bool, StartReport, Vec<StageResult>);
    let runs: Vec<Result<Run, String>> = live
        .into_iter()
        .map(|(k, u0, _, _, chain)| {
            // this start's lowest end (its own search's, or a seed's)
            let i = (0..found.len()).filter(|&i| found[i].0 == k).min_by(|&a, &b| found[a].2.total_cmp(&found[b].2)).expect("searched");
            let (_, u, cost, converged) = found.swap_remove(i);
            found.retain(|f| f.0 != k);
            let values = p.values(&u);
            eprintln!(
                "fit: start {} of {total}: cost {cost:.6e} ({}): {}",
                k + 1,
                if converged { "converged" } else { "iteration limit" },
                p.free.iter().zip(&values).map(|(f, v)| format!("{} = {v:.6e}", f.key)).collect::<Vec<_>>().join(", ")
            );
            let report = StartReport { from: p.values(&u0), values, cost, converged, left_after: None };
            Ok((k, u, cost, converged, report, chain))
        })
        .collect();
    let mut ends = Vec::new();
    for r in runs {
        let (k, u, cost, converged, report, chain) = r?;
        reports.push((k, report));
        ends.push((u, cost, converged, chain));
    }
    eprintln!("fit: the whole record from the starts: {} runs in {:.1} s", runs_of(p) - r0, t.elapsed().as_secs_f64());
    reports.sort_by_key(|(k, _)| *k);
    let reports: Vec<StartReport> = reports.into_iter().map(|(_, r)| r).collect();
    let mut best: Option<(Vec<f64>, f64, bool, Vec<StageResult>)> = None;
    for (u, cost, converged, chain) in ends {
        if best.as_ref().is_none_or(|b| cost < b.1) {
            best = Some((u, cost, converged, chain));
        }
    }
    let (mut u, mut cost, mut converged, chain) = best.expect("at least one start");
    if cost >= OUTSIDE {
        return Err("no start reached a valid scene inside the bounds: every evaluation was rejected".into());
    }
    let (t, r0) = (std::time::Instant::now(), runs_of(p));
    // the polish: a simplex stalls early where the parameters are correlated and the cost is
    // not smooth at the sample scale (statistics such as the first slip's time move in steps
    // of a sample); restarted from its best point with a fresh, smaller simplex it goes on down
    // the valley. Restarts while a restart lowers the cost by more than POLISH_GAIN
    // (POLISH_GAIN_STATISTICS with statistics).
    for _ in 0..POLISH_RESTARTS {
        // from the lowest of a small Halton screen around the best point (a dip a simplex
        // cannot leave is left here) or from the best point itself
        let from = neighbourhood_best(p, &u, cost).unwrap_or_else(|| u.clone());
        let (pu, pc, pconv) = local_search(p, &from, POLISH_STEP, max_iters)?;
        if pc < cost {
            let gain = (cost - pc) / cost.max(f64::MIN_POSITIVE);
            u = pu;
            cost = pc;
            converged = pconv;
            eprintln!(
                "fit: polish of the best start: cost {cost:.6e}: {}",
                p.free.iter().zip(p.values(&u)).map(|(f, v)| format!("{} = {v:.6e}", f.key)).collect::<Vec<_>>().join(", ")
            );
            if gain > if p.time_domain() { POLISH_GAIN } else { POLISH_GAIN_STATISTICS } {
                continue;
            }
        }
        break;
    }
    eprintln!("fit: the polish: {} runs in {:.1} s", runs_of(p) - r0, t.elapsed().as_secs_f64());
    Ok((Solution { u, cost, converged, starts: reports }, chain))
}

