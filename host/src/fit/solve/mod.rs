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
    }
    let (t, r0) = (std::time::Instant::now(), runs_of(p));
    type Run = (usize, Vec<f64>, f64, bool, StartReport, Vec<StageResult>);
    let runs: Vec<Result<Run, String>> = live
        .into_par_iter()
        .map(|(k, u0, u, _, chain)| {
            let (u, cost, converged) = local_search(p, &u, SIMPLEX_STEP, max_iters)?;
            let values = p.values(&u);
            eprintln!(
                "fit: start {} of {total}: cost {cost:.6e} ({}): {}",
                k + 1,
                if converged { "converged" } else { "iteration limit" },
                p.free.iter().zip(&values).map(|(f, v)| format!("{} = {v:.6e}", f.key)).collect::<Vec<_>>().join(", ")
            );
            let report = StartReport { from: p.values(&u0), values, cost, converged };
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
    // the valley. Restarts while a restart lowers the cost by more than POLISH_GAIN.
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
            if gain > POLISH_GAIN {
                continue;
            }
        }
        break;
    }
    eprintln!("fit: the polish: {} runs in {:.1} s", runs_of(p) - r0, t.elapsed().as_secs_f64());
    Ok((Solution { u, cost, converged, starts: reports }, chain))
}

