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

/// One fitted statistic.
#[derive(Clone, Debug)]
pub struct Row {
    pub key: StatKey,
    /// Index of its case in [`Problem::cases`].
    pub case: usize,
    pub measured: f64,
    pub weight: f64,
    pub windows: Vec<f64>,
    pub source: String,
}

/// The least-squares problem.
pub struct Problem {
    pub free: Vec<FreeKey>,
    /// The fitted cases and their scenes before the free keys are applied.
    pub cases: Vec<(String, Scene)>,
    pub rows: Vec<Row>,
    pub jump_m_s2: f64,
    pub segment: Option<usize>,
    /// Whether a statistic needs the spectra (peak_hz weighted).
    pub spectra: bool,
    pub evals: AtomicUsize,
    best: Mutex<f64>,
    progress: Option<ProgressBar>,
    /// The recordings' pad_x series when the cost is the time-domain one
    /// ([`super::waveform`]); empty: the statistics' log ratios of `rows`.
    pub traces: Vec<super::waveform::Trace>,
    /// With `traces`: the global stage's cost, the recordings' cycle features
    /// ([`super::waveform::feature_residuals`]), instead of their samples.
    pub features: bool,
    /// Damping ratios held while the free keys move ([`model::held_ratios`]).
    pub ratios: Vec<(String, f64)>,
}

impl Problem {
    pub fn new(
        free: Vec<FreeKey>,
        cases: Vec<(String, Scene)>,
        rows: Vec<Row>,
        jump_m_s2: f64,
        segment: Option<usize>,
        progress: Option<ProgressBar>,
    ) -> Self {
        let spectra = rows.iter().any(|r| r.key.stat == super::stat::Stat::PeakHz);
        Problem {
            free,
            cases,
            rows,
            jump_m_s2,
            segment,
            spectra,
            evals: AtomicUsize::new(0),
            best: Mutex::new(f64::INFINITY),
            progress,
            traces: Vec::new(),
            features: false,
            ratios: Vec::new(),
        }
    }

    /// The number of residuals: one per statistic, or per sample (and timing) of the traces.
    pub fn residual_count(&self) -> usize {
        if self.traces.is_empty() {
            self.rows.len()
        } else {
            self.traces.iter().map(|t| t.residual_count(self.features)).sum()
        }
    }

    /// Whether the cost is the time-domain one.
    pub fn time_domain(&self) -> bool {
        !self.traces.is_empty()
    }

    /// The time-domain residuals of every trace at parameters `values`.
    fn trace_residuals(&self, values: &[f64]) -> Result<Vec<f64>, String> {
        let parts: Vec<Result<Vec<f64>, String>> = self
            .traces
            .par_iter()
            .map(|tr| {
                let scene = model::with_values_held(&self.cases[tr.case_index].1, &self.free, values, &self.ratios)?;
                if self.features {
                    super::waveform::feature_residuals(tr, &scene)
                } else {
                    super::waveform::residuals(tr, &scene, None)
                }
            })
            .collect();
        let mut out = Vec::with_capacity(self.residual_count());
        for p in parts {
            out.extend(p?);
        }
        Ok(out)
    }

    /// The parameters at u.
    pub fn values(&self, u: &[f64]) -> Vec<f64> {
        self.free.iter().zip(u).map(|(f, x)| f.start * x.exp()).collect()
    }

    /// The statistics of every case at parameters `values` (the cases run in parallel).
    pub fn run_cases(&self, cases: &[(String, Scene)], values: &[f64]) -> Vec<Result<Analysis, String>> {
        cases
            .par_iter()
            .map(|(name, s)| {
                let scene = model::with_values_held(s, &self.free, values, &self.ratios)?;
                model::statistics(name, &scene, self.jump_m_s2, self.segment, self.spectra)
            })
            .collect()
    }

    /// The model's value of each row from the cases' statistics.
    pub fn model_values(rows: &[Row], stats: &[Result<Analysis, String>]) -> Vec<Option<f64>> {
        rows.iter()
            .map(|r| stats[r.case].as_ref().ok().and_then(|a| r.key.stat.of(a, r.key.channel)))
            .collect()
    }

    /// The residual of a row with model value `model`.
    pub fn residual(row: &Row, model: Option<f64>) -> f64 {
        let lr = match model {
            Some(m) if m.is_finite() && m > 0.0 => (m / row.measured).ln(),
            _ => MISSING_LOG_RATIO,
        };
        row.weight.sqrt() * lr
    }

    /// The residuals at u; an error (the first case's) where u is outside the bounds or a
    /// case's scene is invalid or its run halts.
    pub fn residuals(&self, u: &[f64]) -> Result<Vec<f64>, String> {
        let values = self.values(u);
        for (f, v) in self.free.iter().zip(&values) {
            if !(*v >= f.lo && *v <= f.hi) {
                return Err(format!("{} = {v} outside [{}, {}]", f.key, f.lo, f.hi));
            }
        }
        if self.time_domain() {
            return self.trace_residuals(&values);
        }
        let stats = self.run_cases(&self.cases, &values);
        if let Some(Err(e)) = stats.iter().find(|s| s.is_err()) {
            return Err(e.clone());
        }
        let model = Self::model_values(&self.rows, &stats);
        Ok(self.rows.iter().zip(model).map(|(r, m)| Self::residual(r, m)).collect())
    }

    fn note(&self, cost: f64) {
        let n = self.evals.fetch_add(1, Ordering::Relaxed) + 1;
        let mut best = self.best.lock().expect("not poisoned");
        if cost < *best {
            *best = cost;
        }
        if let Some(p) = &self.progress {
            p.set_message(format!("evaluation {n}: cost {cost:.4e}, best {:.4e}", *best));
            p.tick();
        }
    }
}

pub fn cost_of(r: &[f64]) -> f64 {
    0.5 * r.iter().map(|x| x * x).sum::<f64>()
}

impl CostFunction for &Problem {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, u: &Vec<f64>) -> Result<f64, Error> {
        let c = match self.residuals(u) {
            Ok(r) => cost_of(&r),
            Err(_) => OUTSIDE,
        };
        self.note(c);
        Ok(c)
    }
}

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

/// Bases of the Halton sequence, one per free key.
const HALTON_BASES: [u32; 12] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37];

/// Element `k` of the Halton sequence in base `b`, in [0, 1).
fn halton(mut k: u32, b: u32) -> f64 {
    let (mut f, mut x) = (1.0, 0.0);
    while k > 0 {
        f /= b as f64;
        x += f * (k % b) as f64;
        k /= b;
    }
    x
}

/// Screen of the first horizon stage: this many points per free key, spread over
/// start / [`SCREEN_FACTOR`] .. start x [`SCREEN_FACTOR`] by a Halton sequence.
pub const SCREEN_POINTS_PER_KEY: usize = 64;
/// Half-width of the screen, as a factor on each start value.
pub const SCREEN_FACTOR: f64 = 2.0;

/// Global stage over the whole box of the bounds: this many Halton points per free key on
/// the time-domain cost (cheap: one slip per evaluation).
pub const GLOBAL_POINTS_PER_KEY: usize = 256;
/// Global stage on a table's statistics (each point runs every case).
pub const TABLE_POINTS_PER_KEY: usize = 24;
/// Two starts taken from a screen differ by at least this in some ln p.
pub const START_SEPARATION: f64 = 0.05;

/// The starts of a search: the scene's values (u = 0) and the `starts - 1` lowest-cost points
/// of a Halton screen of `first` (`per_key` points per free key), at least
/// [`START_SEPARATION`] apart. The screen spans the whole box of the bounds (`span` `None`: the
/// global stage) or a factor e^span either way of each start, inside the bounds (the horizon
/// stages' screen). No screen for a single start.
pub fn screened_starts(first: &Problem, starts: usize, span: Option<f64>, per_key: usize) -> Vec<Vec<f64>> {
    let n = first.free.len();
    if starts <= 1 {
        return vec![vec![0.0; n]];
    }
    let t0 = std::time::Instant::now();
    let point = |k: usize| -> Vec<f64> {
        first
            .free
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let (mut a, mut b) = ((f.lo / f.start).ln(), (f.hi / f.start).ln());
                if let Some(sp) = span {
                    a = a.max(-sp);
                    b = b.min(sp);
                }
                a + (b - a) * halton(k as u32, HALTON_BASES[i % HALTON_BASES.len()])
            })
            .collect()
    };
    let screen: Vec<Vec<f64>> = (1..=per_key * n).map(point).collect();
    let costs: Vec<f64> = screen.par_iter().map(|u| first.residuals(u).map_or(OUTSIDE, |r| cost_of(&r))).collect();
    let mut order: Vec<usize> = (0..screen.len()).filter(|&i| costs[i] < OUTSIDE).collect();
    order.sort_by(|&a, &b| costs[a].total_cmp(&costs[b]));
    eprintln!(
        "fit: {} of {} points in {:.1} s ({} valid), lowest cost {:.4e}",
        if span.is_none() { "global screen over the bounds" } else { "screen of the first horizon" },
        screen.len(),
        t0.elapsed().as_secs_f64(),
        order.len(),
        order.first().map_or(f64::NAN, |&i| costs[i])
    );
    let mut out = vec![vec![0.0; n]];
    for i in order {
        if out.len() >= starts {
            break;
        }
        let far = out[1..].iter().all(|o| o.iter().zip(&screen[i]).any(|(a, b)| (a - b).abs() >= START_SEPARATION));
        if far {
            out.push(screen[i].clone());
        }
    }
    out
}

/// Nelder-Mead from `u0`: a simplex of `step`, at most `max_iters` iterations, until the
/// costs of the simplex's vertices agree to [`SD_TOLERANCE`] (their standard deviation).
fn nelder_mead(p: &Problem, u0: &[f64], step: f64, max_iters: u64) -> Result<(Vec<f64>, f64, bool), String> {
    let n = u0.len();
    let mut simplex = vec![u0.to_vec()];
    for i in 0..n {
        let mut v = u0.to_vec();
        v[i] += step;
        simplex.push(v);
    }
    let solver = NelderMead::new(simplex).with_sd_tolerance(SD_TOLERANCE).map_err(|e| e.to_string())?;
    let res = Executor::new(p, solver).configure(|s| s.max_iters(max_iters)).run().map_err(|e| e.to_string())?;
    let st = res.state();
    let converged = matches!(st.get_termination_status(), TerminationStatus::Terminated(TerminationReason::SolverConverged));
    let best = st.get_best_param().cloned().unwrap_or_else(|| u0.to_vec());
    Ok((best, st.get_best_cost(), converged))
}

/// The problem as `levenberg_marquardt` sees it: parameters u, the residuals (a rejected
/// point gives residuals of [`REJECTED_RESIDUAL`], so that the step is refused), the
/// central-difference Jacobian.
struct LmProblem<'a> {
    p: &'a Problem,
    u: DVector<f64>,
    /// The residuals at `u`, computed once for both calls at a point.
    r: std::cell::RefCell<Option<Vec<f64>>>,
}

/// Each residual at a rejected point (outside the bounds, an invalid scene, a run that halts).
const REJECTED_RESIDUAL: f64 = 1e6;

impl LmProblem<'_> {
    fn r(&self) -> Vec<f64> {
        if let Some(r) = self.r.borrow().as_ref() {
            return r.clone();
        }
        let u: Vec<f64> = self.u.iter().copied().collect();
        let r = match self.p.residuals(&u) {
            Ok(r) => r,
            Err(_) => vec![REJECTED_RESIDUAL; self.p.residual_count()],
        };
        self.p.note(cost_of(&r));
        *self.r.borrow_mut() = Some(r.clone());
        r
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for LmProblem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, u: &DVector<f64>) {
        self.u.copy_from(u);
        *self.r.borrow_mut() = None;
    }

    fn params(&self) -> DVector<f64> {
        self.u.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        Some(DVector::from_vec(self.r()))
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let r0 = self.r();
        let u: Vec<f64> = self.u.iter().copied().collect();
        Some(jacobian(self.p, &u, &r0))
    }
}

/// Levenberg-Marquardt from `u0` (the `levenberg-marquardt` crate, MINPACK's algorithm):
/// the cost's relative reduction or the parameters' relative step below 1e-8, at most
/// `max_iters` residual evaluations beyond the Jacobians'.
fn levenberg_marquardt(p: &Problem, u0: &[f64], max_iters: u64) -> (Vec<f64>, f64, bool) {
    let n = u0.len();
    let lm = LevenbergMarquardt::new()
        .with_ftol(1e-8)
        .with_xtol(1e-8)
        .with_patience((max_iters as usize).div_ceil(n + 1).max(1));
    let start = LmProblem { p, u: DVector::from_column_slice(u0), r: std::cell::RefCell::new(None) };
    let (done, report) = lm.minimize(start);
    let u: Vec<f64> = done.u.iter().copied().collect();
    let cost = cost_of(&done.r());
    (u, cost, report.termination.was_successful())
}

/// One start's local search: Nelder-Mead from a simplex `step` wide in ln(value) (10 % for a start), then Levenberg-Marquardt
/// from its best point (the simplex finds the basin, the Gauss-Newton steps follow its valley
/// to the bottom, where a simplex stalls when the parameters are correlated). Returns u, the
/// cost and whether Levenberg-Marquardt converged.
fn local_search(p: &Problem, u0: &[f64], step: f64, max_iters: u64) -> Result<(Vec<f64>, f64, bool), String> {
    let (mut u, mut cost, _) = nelder_mead(p, u0, step, max_iters)?;
    let mut converged = false;
    if cost < OUTSIDE {
        let (lu, lc, conv) = levenberg_marquardt(p, &u, max_iters);
        if lc <= cost {
            u = lu;
            cost = lc;
        }
        converged = conv;
    }
    Ok((u, cost, converged))
}

/// Restarts of the local search from the best start's end ([`search`]): at most this many.
const POLISH_RESTARTS: usize = 3;
/// A restart that lowers the cost by more than this fraction is followed by another.
const POLISH_GAIN: f64 = 0.01;
/// The polish's simplex: 5 % in each ln(value) (the basin is found; the simplex only has to
/// follow the valley).
const POLISH_STEP: f64 = 0.05;

/// The polish's screen around the best point: this many Halton points per free key.
const NEIGHBOURHOOD_POINTS_PER_KEY: usize = 8;
/// Its box in ln(value) is at most this wide either way along any direction.
const NEIGHBOURHOOD_SPAN: f64 = 0.05;

/// The lowest point of a Halton screen around `u` (cost `cost`), if lower: the screen's box
/// lies along the singular vectors of the Jacobian at `u`, each side as far as the local
/// quadratic model of the cost rises by `cost` (sqrt(2 cost) / s_i along singular value s_i,
/// at most [`NEIGHBOURHOOD_SPAN`]): a lower valley beside the best point's dip, across a ridge
/// no higher than the cost itself, is found where a box in the keys' own axes would miss a
/// valley narrower than its points' spacing (correlated keys).
fn neighbourhood_best(p: &Problem, u: &[f64], cost: f64) -> Option<Vec<f64>> {
    let n = u.len();
    let r0 = p.residuals(u).ok()?;
    let svd = jacobian(p, u, &r0).svd(false, true);
    let v_t = svd.v_t?;
    let half: Vec<f64> = svd
        .singular_values
        .iter()
        .map(|&s| if s > 0.0 { ((2.0 * cost).sqrt() / s).min(NEIGHBOURHOOD_SPAN) } else { NEIGHBOURHOOD_SPAN })
        .collect();
    let screen: Vec<Vec<f64>> = (1..=NEIGHBOURHOOD_POINTS_PER_KEY * n)
        .map(|k| {
            let z: Vec<f64> = (0..half.len()).map(|i| half[i] * (2.0 * halton(k as u32, HALTON_BASES[i % HALTON_BASES.len()]) - 1.0)).collect();
            (0..n).map(|j| u[j] + (0..z.len()).map(|i| v_t[(i, j)] * z[i]).sum::<f64>()).collect()
        })
        .collect();
    let costs: Vec<f64> = screen
        .par_iter()
        .map(|x| {
            let c = p.residuals(x).map_or(OUTSIDE, |r| cost_of(&r));
            p.note(c);
            c
        })
        .collect();
    let best = (0..screen.len()).min_by(|&a, &b| costs[a].total_cmp(&costs[b]))?;
    (costs[best] < cost).then(|| screen[best].clone())
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
/// `p` itself: a continuation in the record's length. The starts run in parallel (each
/// evaluation runs its cases in parallel too); the lowest cost on `p` wins, and its stages are
/// returned.
pub fn search(p: &Problem, stages: &[&Problem], starts: usize, max_iters: u64) -> Result<(Solution, Vec<StageResult>), String> {
    let points = match stages.first() {
        Some(first) if first.features => screened_starts(first, starts, None, GLOBAL_POINTS_PER_KEY),
        Some(first) => screened_starts(first, starts, Some(SCREEN_FACTOR.ln()), SCREEN_POINTS_PER_KEY),
        None if p.time_domain() => screened_starts(p, starts, None, GLOBAL_POINTS_PER_KEY),
        None => screened_starts(p, starts, None, TABLE_POINTS_PER_KEY),
    };
    let total = points.len();
    type Run = (Vec<f64>, f64, bool, StartReport, Vec<StageResult>);
    let runs: Vec<Result<Run, String>> = points
        .into_par_iter()
        .enumerate()
        .map(|(k, u0)| {
            let mut u = u0.clone();
            let mut chain = Vec::new();
            for (i, st) in stages.iter().enumerate() {
                let (su, c, conv) = local_search(st, &u, SIMPLEX_STEP, max_iters)?;
                eprintln!("fit: start {} of {total}, horizon {}: cost {c:.6e}", k + 1, i + 1);
                chain.push(StageResult { values: st.values(&su), cost: c, converged: conv });
                u = su;
            }
            let (u, cost, converged) = local_search(p, &u, SIMPLEX_STEP, max_iters)?;
            let values = p.values(&u);
            eprintln!(
                "fit: start {} of {total}: cost {cost:.6e} ({}): {}",
                k + 1,
                if converged { "converged" } else { "iteration limit" },
                p.free.iter().zip(&values).map(|(f, v)| format!("{} = {v:.6e}", f.key)).collect::<Vec<_>>().join(", ")
            );
            let report = StartReport { from: p.values(&u0), values, cost, converged };
            Ok((u, cost, converged, report, chain))
        })
        .collect();
    let mut reports = Vec::new();
    let mut best: Option<(Vec<f64>, f64, bool, Vec<StageResult>)> = None;
    for r in runs {
        let (u, cost, converged, report, chain) = r?;
        reports.push(report);
        if best.as_ref().is_none_or(|b| cost < b.1) {
            best = Some((u, cost, converged, chain));
        }
    }
    let (mut u, mut cost, mut converged, chain) = best.expect("at least one start");
    if cost >= OUTSIDE {
        return Err("no start reached a valid scene inside the bounds: every evaluation was rejected".into());
    }
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
    Ok((Solution { u, cost, converged, starts: reports }, chain))
}

/// d r / d u at `u` by central differences (one-sided where one side is rejected; a zero
/// column where both are).
pub fn jacobian(p: &Problem, u: &[f64], r0: &[f64]) -> DMatrix<f64> {
    let (m, n) = (r0.len(), u.len());
    let mut j = DMatrix::zeros(m, n);
    for k in 0..n {
        let at = |d: f64| {
            let mut v = u.to_vec();
            v[k] += d;
            p.residuals(&v).ok()
        };
        let h = JACOBIAN_STEP;
        let col: Option<Vec<f64>> = match (at(h), at(-h)) {
            (Some(a), Some(b)) => Some(a.iter().zip(&b).map(|(x, y)| (x - y) / (2.0 * h)).collect()),
            (Some(a), None) => Some(a.iter().zip(r0).map(|(x, y)| (x - y) / h).collect()),
            (None, Some(b)) => Some(r0.iter().zip(&b).map(|(x, y)| (x - y) / h).collect()),
            (None, None) => None,
        };
        if let Some(c) = col {
            for i in 0..m {
                j[(i, k)] = c[i];
            }
        }
    }
    j
}

/// A direction in u the data do not determine.
#[derive(Clone, Debug)]
pub struct Flat {
    /// The unit vector's components, per free key.
    pub direction: Vec<f64>,
    /// Its standard error in u (ln p).
    pub std_log: f64,
    pub singular_value: f64,
}

/// What the Jacobian says about the parameters.
pub struct Uncertainty {
    /// s^2: the residual variance (NaN with no more residuals than parameters).
    pub residual_variance: f64,
    pub dof: usize,
    /// Covariance of u.
    pub cov_u: DMatrix<f64>,
    pub singular_values: Vec<f64>,
    pub flat: Vec<Flat>,
}

/// The covariance and the flat directions from J and the residuals r at the optimum.
pub fn uncertainty(j: &DMatrix<f64>, r: &[f64]) -> Uncertainty {
    let (m, n) = (j.nrows(), j.ncols());
    let dof = m.saturating_sub(n);
    let s2 = if dof > 0 { r.iter().map(|x| x * x).sum::<f64>() / dof as f64 } else { f64::NAN };
    let svd = j.clone().svd(false, true);
    let vt = svd.v_t.expect("asked for V^T");
    let sv: Vec<f64> = svd.singular_values.iter().copied().collect();
    // cov = s^2 V diag(1/sigma^2) V^T, infinite along a zero singular value
    let mut cov = DMatrix::zeros(n, n);
    let mut flat = Vec::new();
    for (k, &sigma) in sv.iter().enumerate() {
        let v = vt.row(k).transpose();
        let var = if sigma > 0.0 { s2 / (sigma * sigma) } else { f64::INFINITY };
        let std_log = var.sqrt();
        if sigma == 0.0 || std_log > FLAT_LOG {
            flat.push(Flat { direction: v.iter().copied().collect(), std_log, singular_value: sigma });
        }
        for a in 0..n {
            for b in 0..n {
                let term = var * v[a] * v[b];
                // an infinite variance spreads only over the components the direction has
                cov[(a, b)] += if term.is_nan() { 0.0 } else { term };
            }
        }
    }
    Uncertainty { residual_variance: s2, dof, cov_u: cov, singular_values: sv, flat }
}

/// The linearised bootstrap over the rows' windows (see the module documentation): the
/// standard error of each u over `resamples` resamples, `None` where no row has windows.
pub fn bootstrap(j: &DMatrix<f64>, rows: &[Row], sources: &[String], resamples: usize, seed: u32) -> Option<Vec<f64>> {
    let n = j.ncols();
    if resamples < 2 || rows.iter().all(|r| r.windows.is_empty()) {
        return None;
    }
    let jtj = j.transpose() * j;
    let eps = 1e-12 * jtj.norm();
    let pinv = jtj.pseudo_inverse(eps).ok()?;
    let gain = pinv * j.transpose();
    let mut rng = XorShift32::new(seed.max(1));
    let mut samples: Vec<DVector<f64>> = Vec::with_capacity(resamples);
    for _ in 0..resamples {
        // one draw of window indices per recording (source)
        let draws: Vec<Vec<usize>> = sources
            .iter()
            .map(|src| {
                let k = rows.iter().find(|r| &r.source == src && !r.windows.is_empty()).map_or(0, |r| r.windows.len());
                (0..k).map(|_| (rng.next_u32() as usize) % k.max(1)).collect()
            })
            .collect();
        let delta = DVector::from_iterator(
            rows.len(),
            rows.iter().map(|r| {
                if r.windows.is_empty() {
                    return 0.0;
                }
                let d = &draws[sources.iter().position(|s| s == &r.source).unwrap_or(0)];
                let all = r.windows.iter().sum::<f64>() / r.windows.len() as f64;
                let re = d.iter().map(|&i| r.windows[i]).sum::<f64>() / d.len() as f64;
                r.weight.sqrt() * (re / all).ln()
            }),
        );
        samples.push(&gain * delta);
    }
    let b = samples.len() as f64;
    Some(
        (0..n)
            .map(|k| {
                let mean = samples.iter().map(|s| s[k]).sum::<f64>() / b;
                (samples.iter().map(|s| (s[k] - mean).powi(2)).sum::<f64>() / (b - 1.0)).sqrt()
            })
            .collect(),
    )
}

/// The problem with free key `fixed` held at `u_fixed`, the others searched by
/// Levenberg-Marquardt (a point of a profile).
struct ProfileLm<'a> {
    p: &'a Problem,
    fixed: usize,
    u_fixed: f64,
    /// The other keys' u.
    w: DVector<f64>,
    r: std::cell::RefCell<Option<Vec<f64>>>,
}

impl ProfileLm<'_> {
    fn full(&self, w: &DVector<f64>) -> Vec<f64> {
        let mut u = Vec::with_capacity(w.len() + 1);
        let mut it = w.iter();
        for k in 0..=w.len() {
            u.push(if k == self.fixed { self.u_fixed } else { *it.next().expect("one per other key") });
        }
        u
    }

    fn r(&self) -> Vec<f64> {
        if let Some(r) = self.r.borrow().as_ref() {
            return r.clone();
        }
        let r = self.p.residuals(&self.full(&self.w)).unwrap_or_else(|_| vec![REJECTED_RESIDUAL; self.p.residual_count()]);
        self.p.note(cost_of(&r));
        *self.r.borrow_mut() = Some(r.clone());
        r
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for ProfileLm<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, w: &DVector<f64>) {
        self.w.copy_from(w);
        *self.r.borrow_mut() = None;
    }

    fn params(&self) -> DVector<f64> {
        self.w.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        Some(DVector::from_vec(self.r()))
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let u = self.full(&self.w);
        let r0 = self.r();
        let j = jacobian(self.p, &u, &r0);
        let cols: Vec<usize> = (0..u.len()).filter(|k| *k != self.fixed).collect();
        Some(j.select_columns(cols.iter()))
    }
}

/// The profile's cost at u_k = `uk` of key `k`, the other keys searched from `w0` (their u);
/// `None` where the point is rejected. Returns the cost and the others' u.
fn profile_point(p: &Problem, k: usize, uk: f64, w0: &[f64], max_iters: u64) -> Option<(f64, Vec<f64>)> {
    let f = &p.free[k];
    if !(uk >= (f.lo / f.start).ln() - 1e-12 && uk <= (f.hi / f.start).ln() + 1e-12) {
        return None;
    }
    if w0.is_empty() {
        let r = p.residuals(&[uk]).ok()?;
        return Some((cost_of(&r), Vec::new()));
    }
    let lm = LevenbergMarquardt::new().with_ftol(1e-7).with_xtol(1e-7).with_patience(((max_iters as usize) / 30).max(4));
    let start = ProfileLm { p, fixed: k, u_fixed: uk, w: DVector::from_column_slice(w0), r: std::cell::RefCell::new(None) };
    let (done, _) = lm.minimize(start);
    let r = done.r();
    let c = cost_of(&r);
    (c < 0.5 * REJECTED_RESIDUAL * REJECTED_RESIDUAL).then(|| (c, done.w.iter().copied().collect()))
}

/// Delta chi^2 of a 95 % interval of one parameter (chi-square, 1 degree of freedom).
pub const PROFILE_DCHI2_95: f64 = 3.841;
/// Largest first step of a profile in ln p (the first step is the Jacobian's standard error
/// below this); it doubles until the threshold is crossed.
const PROFILE_STEP: f64 = 0.005;
/// Bisections of the crossing.
const PROFILE_BISECTIONS: usize = 5;

/// The 95 % profile-likelihood interval of every free key (Raue et al. 2009): from the
/// optimum `u` (cost `cost`), along each key in both directions, the other keys re-fitted at
/// each point, to where chi^2 has risen by [`PROFILE_DCHI2_95`] x max(1, chi^2 / dof) (the
/// threshold widened by a misfit, as the residual variance widens the Jacobian's errors);
/// `chi2_scale` turns a cost into chi^2. A side where the profile stays below the threshold up
/// to the bound (or to a scene rule) is `None`: not identifiable on that side. Only for the
/// time-domain cost (its evaluations are cheap); empty otherwise.
pub fn profile_intervals(
    p: &Problem,
    u: &[f64],
    cost: f64,
    chi2_scale: f64,
    chi2_per_dof: f64,
    first_steps: &[f64],
    max_iters: u64,
) -> Vec<(Option<f64>, Option<f64>)> {
    if !p.time_domain() {
        return Vec::new();
    }
    let t0 = std::time::Instant::now();
    let target = PROFILE_DCHI2_95 * chi2_per_dof.max(1.0) / chi2_scale;
    let n = u.len();
    let out: Vec<(Option<f64>, Option<f64>)> = (0..n)
        .into_par_iter()
        .map(|k| {
            let others = |uu: &[f64]| -> Vec<f64> { (0..n).filter(|j| *j != k).map(|j| uu[j]).collect() };
            let side = |dir: f64| -> Option<f64> {
                let f = &p.free[k];
                let limit = if dir > 0.0 { (f.hi / f.start).ln() } else { (f.lo / f.start).ln() };
                let (mut inside, mut w) = (u[k], others(u));
                // the first step: the Jacobian's standard error of ln p (the threshold lies near
                // twice it where the cost is quadratic)
                let sd = first_steps.get(k).copied().unwrap_or(PROFILE_STEP);
                let mut h = if sd.is_finite() && sd > 0.0 { sd.clamp(1e-7, PROFILE_STEP) } else { PROFILE_STEP };
                loop {
                    let mut uk = u[k] + dir * h;
                    let at_bound = (uk - limit) * dir >= 0.0;
                    if at_bound {
                        uk = limit;
                    }
                    let (c, w1) = profile_point(p, k, uk, &w, max_iters)?;
                    if c - cost >= target {
                        // bisect between the last point inside and this one
                        let (mut a, mut b) = (inside, uk);
                        for _ in 0..PROFILE_BISECTIONS {
                            let mid = 0.5 * (a + b);
                            match profile_point(p, k, mid, &w, max_iters) {
                                Some((cm, wm)) if cm - cost < target => {
                                    a = mid;
                                    w = wm;
                                }
                                _ => b = mid,
                            }
                        }
                        return Some(f.start * (0.5 * (a + b)).exp());
                    }
                    if at_bound {
                        return None;
                    }
                    inside = uk;
                    w = w1;
                    h *= 2.0;
                }
            };
            (side(-1.0), side(1.0))
        })
        .collect();
    eprintln!("fit: profile-likelihood intervals of {n} keys in {:.1} s", t0.elapsed().as_secs_f64());
    out
}
