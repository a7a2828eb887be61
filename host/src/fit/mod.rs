//! Identification (`stickslip fit`): the free keys of a scene adjusted so that the model's
//! virtual rig reproduces measured statistics (recordings or a table), with standard errors,
//! correlations, flat directions, the bootstrap over a recording's windows and held-out cases.
//!
//! - [`stat`]: the statistics by name;
//! - [`target`]: recordings and tables;
//! - [`model`]: each case's scene and its statistics;
//! - `setup`: the weights, free keys, targets and horizon stages of a request;
//! - [`solve`]: the least-squares problem, the search (argmin's Nelder-Mead) and the
//!   uncertainty;
//! - `profile`: `fit --profile`, the cost along one key;
//! - [`output`]: Markdown, JSON, the figure and the fitted scene file.

pub mod bounds;
pub mod goodness;
pub mod model;
pub mod output;
pub mod solve;
pub mod stat;
pub mod target;
pub mod waveform;

use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use nalgebra::DMatrix;
use stickslip_model::Scene;

use crate::error::{HostError, Result};
use crate::recorded::sil;
use crate::scenes::scene_file;
use crate::scenes::scene_source::NamedScene;
use model::FreeKey;
use solve::{Problem, Row, StartReport};
use stat::{Stat, StatKey};
use target::{Measured, Skipped};

mod profile;
mod setup;
pub use profile::*;
use setup::*;

/// What to fit, as given on the command line (checked by [`run_fit`]).
#[derive(Clone, Debug, Default)]
pub struct FitRequest {
    pub free: Vec<String>,
    /// `KEY=LO:HI`.
    pub bounds: Vec<String>,
    /// `CASE=FILE`.
    pub recordings: Vec<String>,
    pub tables: Vec<String>,
    pub holdout: Vec<String>,
    /// `STAT=W`.
    pub weights: Vec<String>,
    /// Start of a recording's statistics [s]; default the scene's stats_from.
    pub from_s: Option<f64>,
    pub segment: Option<usize>,
    pub breakaway_jump_m_s2: Option<f64>,
    pub starts: usize,
    pub max_iters: u64,
    pub bootstrap: usize,
    pub seed: u32,
    pub progress: bool,
    /// Horizon stages [stick-slip cycles after each recording's first slip onset], searched
    /// before the whole record (see [`solve::search`]); empty: none.
    pub horizons: Vec<f64>,
    /// How the recordings are read (`--channel`, `--gaps`).
    pub read: crate::recorded::ReadOptions,
    /// What a recording is compared by (`--cost`).
    pub cost: CostKind,
}

/// What a fit to recordings compares (`--cost`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CostKind {
    /// The time-domain cost where it applies (recordings only, every case a 1-DOF scene),
    /// else the statistics.
    #[default]
    Auto,
    /// The whole-record statistics (and their horizon stages).
    Statistics,
    /// The recorded pad_x sample by sample, by multiple shooting over the cycles
    /// ([`waveform`]).
    Waveform,
}

impl CostKind {
    pub fn parse(s: &str) -> Option<CostKind> {
        match s {
            "auto" => Some(CostKind::Auto),
            "statistics" => Some(CostKind::Statistics),
            "waveform" => Some(CostKind::Waveform),
            _ => None,
        }
    }
}

/// Default number of starts.
pub const DEFAULT_STARTS: usize = 3;
/// Default iteration limit of one Nelder-Mead run.
pub const DEFAULT_MAX_ITERS: u64 = 300;
/// Default bootstrap resamples.
pub const DEFAULT_BOOTSTRAP: usize = 400;
/// Default horizon stages [cycles after the first slip onset]: the fit matches each
/// recording's start up to 1.5, then 4.5 stick-slip periods after its first slip, then the
/// analysed stretch. Half periods put each horizon in mid-stick: at a whole number of periods
/// the horizon sits on a slip onset, which enters or leaves the stretch as the parameters
/// move (1 and 4 periods left 2 of 12 known-truth starts in a wrong basin; docs/fit.md).
pub const DEFAULT_HORIZONS: [f64; 2] = [1.5, 4.5];

/// A statistic with the model's value beside the measured one.
#[derive(Clone, Debug)]
pub struct Compared {
    pub key: StatKey,
    pub measured: f64,
    pub model: Option<f64>,
    pub weight: f64,
    pub source: String,
}

impl Compared {
    /// ln(model / measured); `None` where the model has none.
    pub fn log_ratio(&self) -> Option<f64> {
        self.model.filter(|m| m.is_finite() && *m > 0.0).map(|m| (m / self.measured).ln())
    }
}

/// The root mean square of the weighted log ratios of `rows` (the rows with weight > 0 and a
/// model value).
pub fn rms_log_ratio(rows: &[Compared]) -> Option<f64> {
    let v: Vec<f64> = rows.iter().filter(|r| r.weight > 0.0).filter_map(|r| r.log_ratio()).collect();
    (!v.is_empty()).then(|| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt())
}

/// A profile interval this many times as wide as the Jacobian's +-1.96 standard errors is
/// noted as the honest one of the two (the quadratic's own error at a few per cent of
/// curvature change stays far below it).
pub const PROFILE_OVER_JACOBIAN: f64 = 3.0;

/// The result of a fit.
pub struct FitReport {
    pub scene: NamedScene,
    pub fitted_scene: Scene,
    pub free: Vec<FreeKey>,
    pub values: Vec<f64>,
    /// Standard error from the Jacobian (delta method), per key.
    pub std: Vec<f64>,
    pub std_bootstrap: Option<Vec<f64>>,
    pub bootstrap_resamples: usize,
    pub correlation: DMatrix<f64>,
    pub uncertainty: solve::Uncertainty,
    pub fitted: Vec<Compared>,
    pub holdout: Vec<Compared>,
    pub holdout_cases: Vec<String>,
    pub skipped: Vec<Skipped>,
    pub starts: Vec<StartReport>,
    pub converged: bool,
    pub cost: f64,
    pub evaluations: usize,
    pub seconds: f64,
    pub jump_m_s2: f64,
    pub weights: Vec<(Stat, f64)>,
    pub notes: Vec<String>,
    /// The horizon stages searched before the whole record, shortest first.
    pub stages: Vec<StageReport>,
    /// chi^2 per degree of freedom against the noise, and the verdict.
    pub goodness: goodness::Goodness,
    /// Whether the cost was the time-domain one ([`waveform`]).
    pub time_domain: bool,
    /// Each free key's 95 % profile-likelihood interval (`None` on a side where the profile
    /// does not close inside the bounds); empty where not computed.
    pub intervals: Vec<(Option<f64>, Option<f64>)>,
    /// Each free key's profile points `(value, delta chi^2)` behind its interval (sorted by
    /// value, the optimum at 0; 3.841 is the interval's threshold); empty where not computed.
    pub profiles: Vec<Vec<(f64, f64)>>,
    /// Every target a recording with no stick-slip in it (read with its own noise floor):
    /// nothing identifies the friction, so no key is identifiable.
    pub no_stick_slip: bool,
}

/// One horizon stage: each recording's start fitted up to its horizon.
#[derive(Clone, Debug)]
pub struct StageReport {
    /// Stick-slip periods after the first slip onset.
    pub cycles: f64,
    /// Each recording's case and horizon [s].
    pub horizons: Vec<(String, f64)>,
    pub statistics: usize,
    /// The stage's best point and its cost.
    pub result: solve::StageResult,
}

impl FitReport {
    /// No flat direction, and every profile interval (where computed) closed on both sides.
    pub fn identifiable(&self) -> bool {
        !self.no_stick_slip && self.uncertainty.flat.is_empty() && self.open_profiles().is_empty()
    }

    /// The keys whose profile interval stays open on a side (the cost within the noise's 95 %
    /// threshold out to the key's bound or a scene rule): (index, open below, open above).
    pub fn open_profiles(&self) -> Vec<(usize, bool, bool)> {
        self.intervals.iter().enumerate().filter(|(_, (lo, hi))| lo.is_none() || hi.is_none()).map(|(k, (lo, hi))| (k, lo.is_none(), hi.is_none())).collect()
    }
}

/// The note for a key whose profile interval stays open on a side: what the data say of the key
/// (a lower bound, an upper bound, nothing), and that its Jacobian standard error is only the
/// optimum's local curvature. `seen`: the profile's points (value, delta chi^2).
pub(crate) fn open_profile_note(key: &str, value: f64, std: f64, open_below: bool, open_above: bool, seen: &[(f64, f64)]) -> String {
    use crate::output::format::num;
    let lowest = seen.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
    let highest = seen.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max);
    let what = match (open_below, open_above) {
        (true, true) => format!("on either side (from {} to {}, as far as the bounds and the scene's rules let it go)", num(lowest), num(highest)),
        (true, false) => format!("below (down to {}, as far as the bound or the scene's rules let it go): the data give an upper bound only", num(lowest)),
        (false, true) => format!("above (up to {}, as far as the bound or the scene's rules let it go): the data give a lower bound only", num(highest)),
        (false, false) => unreachable!("a closed interval"),
    };
    let pct = if value != 0.0 { format!(" ({:.3} %)", 100.0 * std / value.abs()) } else { String::new() };
    format!(
        "{key}: not identifiable: its profile stays within the noise's 95 % threshold {what}; its Jacobian standard error {}{pct} is the optimum's local curvature, not an error bar",
        num(std)
    )
}

/// Runs the fit described by `req` on the base scene `base` (validated).
pub fn run_fit(base: NamedScene, req: &FitRequest) -> Result<FitReport> {
    let t0 = Instant::now();
    let Setup { problem, measured, mut skipped, mut notes, holdout_cases, weights, free, jump, progress, stages, no_stick_slip } = setup(&base, req)?;
    let weight_of = |s: Stat| weights.iter().find(|(k, _)| *k == s).map_or(0.0, |(_, w)| *w);
    let scene_of = |c: &str| model::case_scene(&base, c).expect("checked in setup");
    let stage_problems: Vec<&Problem> = stages.iter().map(|st| &st.problem).collect();
    let (sol, stage_results) = solve::search(&problem, &stage_problems, req.starts, req.max_iters).map_err(HostError::Input)?;
    let stage_reports: Vec<StageReport> = stages
        .iter()
        .zip(stage_results)
        .map(|(st, result)| StageReport { cycles: st.cycles, horizons: st.horizons.clone(), statistics: st.problem.rows.len(), result })
        .collect();
    let stage_evals: usize = stage_problems.iter().map(|p| p.evals.load(std::sync::atomic::Ordering::Relaxed)).sum();
    let (t_unc, r_unc) = (Instant::now(), problem.runs.load(std::sync::atomic::Ordering::Relaxed));
    let r = problem.residuals(&sol.u).map_err(HostError::Input)?;
    let (goodness, chi2_scale) = judge(&problem, &sol, &r, &mut notes).map_err(HostError::Input)?;
    if !problem.time_domain() && goodness.verdict == goodness::Verdict::Fits && goodness.starts_agreeing < sol.starts.len() {
        // a statistics cost is piecewise smooth (docs/fit.md): the starts that ended elsewhere
        // found other optima, and one the starts never reached may be lower still
        notes.push(format!(
            "{} of {} starts ended at the best cost: the statistics' cost has other optima (the starts' ends below), and the standard errors are this optimum's local ones; another optimum the starts did not reach may fit as well or better (a campaign found one 100 times lower, its truth 17 standard errors away): run more --starts, or --profile KEY=LO:HI:N over the range you doubt",
            goodness.starts_agreeing,
            sol.starts.len()
        ));
    }
    let j = solve::jacobian(&problem, &sol.u, &r);
    let mut unc = solve::uncertainty(&j, &r);
    // a statistics cost that fits: are the standard errors what the data determine?
    let checks = if !problem.time_domain() && goodness.verdict == goodness::Verdict::Fits {
        check_errors(&problem, &sol, &j, &unc, chi2_scale, &goodness, &mut notes)
    } else {
        Vec::new()
    };
    for c in &checks {
        let k = c.key;
        // the standard error widened (the covariance's row and column scaled, so that the
        // correlations stay)
        if let Some(sd_u) = c.widen_u {
            let f = sd_u / unc.cov_u[(k, k)].sqrt();
            if f.is_finite() && f > 1.0 {
                for i in 0..free.len() {
                    unc.cov_u[(k, i)] *= f;
                    unc.cov_u[(i, k)] *= f;
                }
            }
        }
        let widened_flat = c.widen_u.is_some_and(|sd_u| sd_u > solve::FLAT_LOG);
        if widened_flat && !unc.flat.iter().any(|f| f.direction.iter().enumerate().all(|(i, d)| (i == k) == (d.abs() > 0.5))) {
            let direction = (0..free.len()).map(|i| if i == k { 1.0 } else { 0.0 }).collect();
            let std_log = unc.cov_u[(k, k)].sqrt();
            unc.flat.push(solve::Flat { direction, std_log, singular_value: f64::NAN });
        }
    }
    let first_steps: Vec<f64> = (0..free.len()).map(|k| unc.cov_u[(k, k)].sqrt()).collect();
    // intervals where the model fits: a misfit's profile would measure the model's error, not
    // the data's (and not_converged has no one optimum to profile)
    let profiles = if !problem.time_domain() {
        notes.push(format!(
            "no profile-likelihood intervals: a statistics cost gets standard errors and flat directions only (each point of a profile would be a local search over every case); the verdict is {}",
            goodness.verdict.name()
        ));
        Vec::new()
    } else if goodness.verdict == goodness::Verdict::Fits {
        solve::profile_intervals(&problem, &sol.u, sol.cost, chi2_scale, goodness.chi2_per_dof, &first_steps, req.max_iters)
    } else {
        notes.push(format!(
            "no profile-likelihood intervals: the verdict is {} (a profile would measure the model's error, not the data's)",
            goodness.verdict.name()
        ));
        Vec::new()
    };
    eprintln!(
        "fit: the Jacobian and the intervals: {} runs in {:.1} s",
        problem.runs.load(std::sync::atomic::Ordering::Relaxed) - r_unc,
        t_unc.elapsed().as_secs_f64()
    );
    let intervals: Vec<(Option<f64>, Option<f64>)> = profiles.iter().map(|p| p.interval).collect();
    // the two error bars of a key: where the profile's interval is far wider than the
    // Jacobian's +-1.96 standard errors, the cost is not quadratic at the Jacobian's scale, and
    // the standard error understates what the data leave open (a campaign: mu_k 1.1e-6 from the
    // Jacobian, 3.2e-5 from the profile, the truth 2.3 to 7 standard errors off on three seeds)
    let values = problem.values(&sol.u);
    // each key's standard error (Jacobian), in its unit
    let std: Vec<f64> = values.iter().enumerate().map(|(k, v)| free[k].scale(*v) * unc.cov_u[(k, k)].sqrt()).collect();
    for (k, (lo, hi)) in intervals.iter().enumerate() {
        let (Some(lo), Some(hi)) = (lo, hi) else { continue };
        let sd = std[k];
        let ratio = (hi - lo) / (2.0 * 1.959964 * sd);
        if ratio > PROFILE_OVER_JACOBIAN {
            notes.push(format!(
                "{}: the 95 % profile interval [{}, {}] is {} times as wide as the Jacobian's +-1.96 standard errors: the cost is not quadratic at the Jacobian's scale, and its standard error understates what the data leave open; take the interval",
                free[k].key,
                crate::output::format::num(*lo),
                crate::output::format::num(*hi),
                crate::output::format::short(ratio)
            ));
        }
    }
    let profiles: Vec<Vec<(f64, f64)>> = profiles.into_iter().map(|p| p.points).collect();
    // a profile that stays open on a side: the data bound the key on one side only, or not at
    // all, whatever the Jacobian's curvature at the optimum says (a campaign: white noise fitted
    // by a pad that never breaks away, mu_s +- 4.1 % from the Jacobian, its profile open on
    // both sides)
    for (k, (lo, hi)) in intervals.iter().enumerate() {
        if lo.is_none() || hi.is_none() {
            notes.push(open_profile_note(&free[k].key, values[k], std[k], lo.is_none(), hi.is_none(), &profiles[k]));
        }
    }
    let sources: Vec<String> = {
        let mut s: Vec<String> = problem.rows.iter().filter(|r| !r.windows.is_empty()).map(|r| r.source.clone()).collect();
        s.sort();
        s.dedup();
        s
    };
    // the bootstrap resamples the statistics' windows: not the time-domain cost's samples
    let std_boot_u =
        if problem.time_domain() { None } else { solve::bootstrap(&j, &problem.rows, &sources, req.bootstrap, req.seed) };
    let std_bootstrap = std_boot_u.map(|s| s.iter().zip(&values).enumerate().map(|(k, (su, v))| free[k].scale(*v) * su).collect());
    let n = free.len();
    let correlation = DMatrix::from_fn(n, n, |a, b| unc.cov_u[(a, b)] / (unc.cov_u[(a, a)] * unc.cov_u[(b, b)]).sqrt());
    // the model at the optimum: fitted rows, then the held-out cases
    let stats = problem.run_cases(&problem.cases, &values);
    let model = Problem::model_values(&problem.rows, &stats);
    let fitted: Vec<Compared> = problem
        .rows
        .iter()
        .zip(model)
        .map(|(r, m)| Compared { key: r.key.clone(), measured: r.measured, model: m, weight: r.weight, source: r.source.clone() })
        .collect();
    let hold_cases: Vec<(String, Scene)> = holdout_cases.iter().map(|c| (c.clone(), scene_of(c))).collect();
    let hold_stats = problem.run_cases(&hold_cases, &values);
    for ((c, _), s) in hold_cases.iter().zip(&hold_stats) {
        if let Err(e) = s {
            notes.push(format!("held-out case {c}: the fitted model's run: {e}"));
        }
    }
    let holdout: Vec<Compared> = measured
        .iter()
        .filter(|m| holdout_cases.contains(&m.key.case) && weight_of(m.key.stat) > 0.0)
        .map(|m| {
            let i = hold_cases.iter().position(|(c, _)| *c == m.key.case).expect("a held-out case");
            let model = hold_stats[i].as_ref().ok().and_then(|a| m.key.stat.of(a, m.key.channel));
            Compared { key: m.key.clone(), measured: m.value, model, weight: weight_of(m.key.stat), source: m.source.clone() }
        })
        .filter(|c| {
            // a channel the scene does not move is not predicted either (as in the fit)
            let structural_zero = c.key.channel.is_some() && c.model == Some(0.0);
            if structural_zero {
                skipped.push(Skipped {
                    key: c.key.clone(),
                    source: c.source.clone(),
                    why: "the scene does not move this channel (0 in the model)".into(),
                });
            }
            !structural_zero
        })
        .collect();
    let fitted_scene = model::with_values_held(&base.scene, &free, &values, &problem.ratios)
        .map_err(|e| HostError::Input(format!("the fitted values in scene `{}`: {e}", base.name)))?;
    if let Some(p) = progress {
        p.finish_and_clear();
    }
    let evaluations = problem.evals.load(std::sync::atomic::Ordering::Relaxed) + stage_evals;
    Ok(FitReport {
        scene: base,
        fitted_scene,
        free,
        values,
        std,
        std_bootstrap,
        bootstrap_resamples: req.bootstrap,
        correlation,
        uncertainty: unc,
        fitted,
        holdout,
        holdout_cases,
        skipped,
        starts: sol.starts,
        converged: goodness.verdict == goodness::Verdict::Fits,
        cost: sol.cost,
        evaluations,
        seconds: t0.elapsed().as_secs_f64(),
        jump_m_s2: jump,
        weights,
        notes,
        stages: stage_reports,
        time_domain: problem.time_domain(),
        goodness,
        intervals,
        profiles,
        no_stick_slip,
    })
}

/// A start whose values lie this many standard errors (Jacobian) or more from the best's, at
/// a cost the noise explains too, shows that the data accept more than the standard errors
/// say: the key's standard error is widened to half the accepted starts' spread.
pub const SPREAD_STDS: f64 = 3.0;

/// What [`check_errors`] found for one free key.
#[derive(Clone, Copy, Debug)]
pub struct ErrorCheck {
    pub key: usize,
    /// The standard error in u (ln p) it is widened to: half the accepted starts' spread, or
    /// at least the Jacobian's step where the cost is a needle finer than that step.
    pub widen_u: Option<f64>,
}

/// Whether the standard errors of a statistics cost that fits say what the data determine, per
/// free key: (1) another start ends [`SPREAD_STDS`] standard errors or more away at a cost the
/// noise explains as well (chi^2 within the limit): the standard error is widened to half the
/// spread; (2) the cost one standard error either side of the optimum leaves the accepted
/// region although the Jacobian's quadratic predicts a rise of less than half the room: a
/// stick-slip statistic (stick fraction, frequency, first slip) moves in steps of the sample
/// grid and the events, so its cost can be a needle at that scale, finer than the Jacobian's
/// step ([`solve::JACOBIAN_STEP`], 1 %) that measured the slope: the standard error is widened
/// to that step (a campaign's fits of push_center recordings missed their truth by 8 to 400
/// Jacobian standard errors, all within a few per cent). Each finding gets a note.
#[allow(clippy::too_many_arguments)] // the optimum, its Jacobian, uncertainty and goodness
fn check_errors(
    problem: &Problem,
    sol: &solve::Solution,
    j: &DMatrix<f64>,
    unc: &solve::Uncertainty,
    chi2_scale: f64,
    goodness: &goodness::Goodness,
    notes: &mut Vec<String>,
) -> Vec<ErrorCheck> {
    let n = problem.free.len();
    let values = problem.values(&sol.u);
    let accept = goodness::chi2_limit(goodness.dof) * goodness.dof.max(1) as f64;
    let room = accept - sol.cost * chi2_scale;
    let mut out = Vec::new();
    for k in 0..n {
        let key = &problem.free[k].key;
        let sd_u = unc.cov_u[(k, k)].sqrt();
        if !(sd_u.is_finite() && sd_u > 0.0) {
            continue;
        }
        let scale = problem.free[k].scale(values[k]);
        let std_v = scale * sd_u;
        let mut check = ErrorCheck { key: k, widen_u: None };
        // (1) accepted starts far from the best
        let accepted: Vec<f64> = sol.starts.iter().filter(|s| s.cost.is_finite() && s.cost * chi2_scale <= accept).map(|s| s.values[k]).collect();
        let far = accepted.iter().filter(|v| (**v - values[k]).abs() > SPREAD_STDS * std_v).count();
        if far > 0 {
            let (lo, hi) = accepted.iter().fold((values[k], values[k]), |(a, b), v| (a.min(*v), b.max(*v)));
            let half_u = 0.5 * (hi - lo) / scale;
            check.widen_u = Some(half_u);
            notes.push(format!(
                "{key}: {far} start(s) ended {SPREAD_STDS} standard errors or more from the best at a cost the noise explains as well (chi^2 within the limit): \
                 the data accept {key} from {} to {} at least, so its standard error is half that spread ({}), not the optimum's local slope ({})",
                crate::output::format::short(lo),
                crate::output::format::short(hi),
                crate::output::format::short(0.5 * (hi - lo)),
                crate::output::format::short(std_v)
            ));
        }
        // (2) the cost one standard error either side
        let jk2: f64 = j.column(k).iter().map(|x| x * x).sum();
        let pred = 0.5 * sd_u * sd_u * jk2 * chi2_scale;
        if !(room > 0.0 && pred < 0.5 * room) {
            out.push(check);
            continue;
        }
        let mut seen = Vec::new();
        for sign in [-1.0, 1.0] {
            let mut u = sol.u.clone();
            u[k] += sign * sd_u;
            let Ok(r) = problem.residuals(&u) else { continue };
            let c = solve::cost_of(&r);
            if c.is_finite() {
                seen.push((sign, (c - sol.cost) * chi2_scale));
            }
        }
        if seen.iter().any(|(_, d)| *d > room) && sd_u < solve::JACOBIAN_STEP {
            check.widen_u = Some(check.widen_u.unwrap_or(0.0).max(solve::JACOBIAN_STEP));
            notes.push(format!(
                "{key}: the cost one standard error ({}) either side of the optimum rises by {} in chi^2, out of the accepted region ({} of room), \
                 where the Jacobian predicts {}: the cost is a needle at that scale (a statistic moving in steps of the sample grid and the events), \
                 finer than the Jacobian's step ({} % of {key}) that measured its slope; the standard error is widened to that step ({})",
                crate::output::format::short(std_v),
                seen.iter().map(|(s, d)| format!("{}{}", if *s < 0.0 { "-: " } else { "+: " }, crate::output::format::short(*d))).collect::<Vec<_>>().join(", "),
                crate::output::format::short(room),
                crate::output::format::short(pred),
                100.0 * solve::JACOBIAN_STEP,
                crate::output::format::short(scale * solve::JACOBIAN_STEP)
            ));
        }
        out.push(check);
    }
    out
}

/// The goodness of the fit at the optimum `sol` (residuals `r`), and the factor that turns
/// the cost into chi^2 (see [`goodness`]).
fn judge(problem: &Problem, sol: &solve::Solution, r: &[f64], notes: &mut Vec<String>) -> std::result::Result<(goodness::Goodness, f64), String> {
    let n = problem.free.len();
    if problem.time_domain() {
        let values = problem.values(&sol.u);
        let (mut chi2, mut count, mut shifts) = (0.0, 0usize, 0usize);
        let mut noise2 = 0.0;
        for tr in &problem.traces {
            let scene = model::with_values_held(&problem.cases[tr.case_index].1, &problem.free, &values, &problem.ratios)?;
            let mut m = Vec::new();
            let res = waveform::residuals(tr, &scene, Some(&mut m))?;
            let (stick_sd, used) = waveform::stick_noise(tr, &m);
            // the stick phases' noise, unless the recording moves there (goodness module)
            let signal_in_stick = stick_sd > goodness::STICK_NOISE_FACTOR * tr.sigma0;
            let sd = if signal_in_stick { tr.sigma0 } else { stick_sd };
            let f = tr.sigma0 / sd;
            chi2 += res.iter().map(|x| (x * f).powi(2)).sum::<f64>();
            count += tr.masked.iter().filter(|x| !**x).count() + 1;
            shifts += tr.resticks.len();
            noise2 += sd * sd;
            notes.push(format!(
                "{}: noise {} m/s^2 rms from {used} samples where the fitted model is in stick (before the fit: {} from the second differences); {} re-sticks found, {} samples left out around them",
                tr.path,
                crate::output::format::num(stick_sd),
                crate::output::format::num(tr.sigma0),
                tr.resticks.len(),
                tr.masked.iter().filter(|x| **x).count()
            ));
            if signal_in_stick {
                notes.push(format!(
                    "{}: where the fitted model is in stick the recording holds {} m/s^2 rms, {} times its noise from the second differences: it moves where the model sticks (signal the model misses, not noise); chi^2 takes the second differences' noise",
                    tr.path,
                    crate::output::format::num(stick_sd),
                    crate::output::format::short(stick_sd / tr.sigma0)
                ));
            }
        }
        let noise = (noise2 / problem.traces.len() as f64).sqrt();
        let dof = count.saturating_sub(n + shifts).max(1);
        let g = goodness::judge(chi2, dof, noise, "the recordings' stick phases (pad_x where the fitted model is in stick)".into(), &sol.starts, 2.0);
        return Ok((g, 2.0));
    }
    // statistics: each log ratio over its standard error
    let mut chi2 = 0.0;
    let (mut assumed, mut from_windows, mut stated) = (0usize, 0usize, 0usize);
    let mut s2 = 0.0;
    for (row, x) in problem.rows.iter().zip(r) {
        let lr = x / row.weight.sqrt();
        let sd = if let Some(s) = row.sigma_ln {
            // a table's stated error, to first order in ln(value)
            stated += 1;
            s
        } else if row.windows.len() >= 2 {
            let l: Vec<f64> = row.windows.iter().map(|w| w.ln()).collect();
            let mean = l.iter().sum::<f64>() / l.len() as f64;
            let var = l.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (l.len() - 1) as f64;
            from_windows += 1;
            (var / l.len() as f64).sqrt().max(1e-6)
        } else {
            assumed += 1;
            goodness::ASSUMED_SIGMA_LN
        };
        chi2 += (lr / sd).powi(2);
        s2 += sd * sd;
    }
    let m = problem.rows.len();
    let source = match (from_windows, stated, assumed) {
        (_, 0, 0) => "the spread of each statistic over its recording's windows".to_string(),
        (0, _, 0) => "the table's stated errors (its sigma column, as sigma / value in ln(value))".to_string(),
        (0, 0, _) => format!("assumed: {} in ln(value) for every statistic (a table states no error; a recording whose windows hold fewer than two slip onsets has no spread to measure)", goodness::ASSUMED_SIGMA_LN),
        _ => format!(
            "the windows' spread for {from_windows} statistics, the table's sigma for {stated}, assumed {} in ln(value) for {assumed}",
            goodness::ASSUMED_SIGMA_LN
        ),
    };
    if assumed > 0 {
        notes.push(format!(
            "goodness: {assumed} statistics have no stated error: a standard error of {} in ln(value) (about +-28 %) is assumed for them",
            goodness::ASSUMED_SIGMA_LN
        ));
    }
    let cost = solve::cost_of(r);
    let scale = if cost > 0.0 { chi2 / cost } else { 2.0 / goodness::ASSUMED_SIGMA_LN.powi(2) };
    let g = goodness::judge(chi2, m.saturating_sub(n).max(1), (s2 / m.max(1) as f64).sqrt(), source, &sol.starts, scale);
    Ok((g, scale))
}

