//! Identification (`stickslip fit`): the free keys of a scene adjusted so that the model's
//! virtual rig reproduces measured statistics (recordings or a table), with standard errors,
//! correlations, flat directions, the bootstrap over a recording's windows and held-out cases.
//!
//! - [`stat`]: the statistics by name;
//! - [`target`]: recordings and tables;
//! - [`model`]: each case's scene and its statistics;
//! - [`solve`]: the least-squares problem, the search (argmin's Nelder-Mead) and the
//!   uncertainty;
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
    /// No flat direction.
    pub fn identifiable(&self) -> bool {
        self.uncertainty.flat.is_empty()
    }
}

/// Each statistic's weight.
type Weights = Vec<(Stat, f64)>;

/// The weight of every statistic, and which were given (not defaults).
fn parse_weights(given: &[String]) -> Result<(Weights, Vec<Stat>)> {
    let mut w: Vec<(Stat, f64)> = Stat::ALL.iter().map(|s| (*s, s.default_weight())).collect();
    let mut named = Vec::new();
    for g in given {
        for item in g.split(',') {
            let bad = |m: String| HostError::Input(format!("--weights {item}: {m}"));
            let (k, v) = item.split_once('=').ok_or_else(|| bad("give STAT=W, e.g. peak_hz=0.5".into()))?;
            let stat = Stat::parse(k.trim()).ok_or_else(|| {
                let names: Vec<&str> = Stat::ALL.iter().map(|s| s.name()).collect();
                bad(format!("unknown statistic `{k}` (the statistics: {})", names.join(", ")))
            })?;
            let x: f64 = v.trim().parse().map_err(|_| bad(format!("`{v}` is not a number")))?;
            if !(x.is_finite() && x >= 0.0) {
                return Err(bad("a weight must be finite and >= 0 (0 leaves the statistic out)".into()));
            }
            w.iter_mut().find(|(s, _)| *s == stat).expect("every statistic").1 = x;
            named.push(stat);
        }
    }
    Ok((w, named))
}

fn free_keys(scene: &NamedScene, free: &[String], bounds: &[String], notes: &mut Vec<String>) -> Result<Vec<FreeKey>> {
    let mut keys: Vec<FreeKey> = Vec::new();
    for item in free.iter().flat_map(|f| f.split(',')).map(str::trim).filter(|s| !s.is_empty()) {
        let bad = |m: String| HostError::Input(format!("--free {item}: {m}"));
        if model::NOT_FREE.contains(&item) {
            return Err(bad("is not a parameter to fit (beta is each case's own; dt, duration, stats_from are the run's)".into()));
        }
        let start = scene_file::get_numeric(&scene.scene, item).ok_or_else(|| {
            bad(format!("not a numeric scene key (the numeric keys: {})", scene_file::NUMERIC_KEYS.join(", ")))
        })?;
        if keys.iter().any(|k| k.key == item) {
            return Err(bad("given twice".into()));
        }
        if let Some(why) = scene_file::inert_key(&scene.scene, item) {
            return Err(bad(format!("does nothing in scene `{}`: {why}", scene.name)));
        }
        if !(start.is_finite() && start > 0.0) {
            return Err(bad(format!(
                "starts at {start} in scene `{}`: a fit searches each key on a log scale and needs a start > 0 (set one in a scene file)",
                scene.name
            )));
        }
        let (lo, hi, note) = bounds::default_bounds(&scene.scene, item, start);
        notes.extend(note);
        keys.push(FreeKey { key: item.to_string(), start, lo, hi });
    }
    if keys.is_empty() {
        return Err(HostError::Input("--free: give at least one scene key to fit, e.g. --free mu_s,mu_k,v_s".into()));
    }
    for b in bounds.iter().flat_map(|f| f.split(',')).map(str::trim).filter(|s| !s.is_empty()) {
        let bad = |m: String| HostError::Input(format!("--bounds {b}: {m}"));
        let (k, range) = b.split_once('=').ok_or_else(|| bad("give KEY=LO:HI".into()))?;
        let (lo, hi) = range.split_once(':').ok_or_else(|| bad("give KEY=LO:HI".into()))?;
        let num = |s: &str| s.trim().parse::<f64>().map_err(|_| bad(format!("`{s}` is not a number")));
        let (lo, hi) = (num(lo)?, num(hi)?);
        let f = keys.iter_mut().find(|f| f.key == k.trim()).ok_or_else(|| bad(format!("`{k}` is not a free key")))?;
        if !(lo > 0.0 && hi.is_finite() && lo < hi) {
            return Err(bad("needs 0 < LO < HI (the search is on a log scale)".into()));
        }
        if !(lo <= f.start && f.start <= hi) {
            return Err(bad(format!("the start {} is outside [{lo}, {hi}]", f.start)));
        }
        f.lo = lo;
        f.hi = hi;
    }
    Ok(keys)
}

fn unknown_case(base: &NamedScene, case: &str, at: &str) -> HostError {
    HostError::Input(format!(
        "{at}: unknown case `{case}` (the cases: {}, or the scene's own name `{}`)",
        model::case_names().join(", "),
        base.name
    ))
}

/// A fit's problem before the search: the targets read, the cases' scenes, the weighted rows.
struct Setup {
    problem: Problem,
    measured: Vec<Measured>,
    skipped: Vec<Skipped>,
    notes: Vec<String>,
    holdout_cases: Vec<String>,
    weights: Vec<(Stat, f64)>,
    free: Vec<FreeKey>,
    jump: f64,
    progress: Option<ProgressBar>,
    /// The horizon stages, shortest first.
    stages: Vec<Stage>,
}

/// A horizon stage before the search: its problem, its cycles and each case's horizon [s].
struct Stage {
    problem: Problem,
    cycles: f64,
    horizons: Vec<(String, f64)>,
}

/// Reads the targets of `req`, checks the free keys and builds the problem on `base`.
fn setup(base: &NamedScene, req: &FitRequest) -> Result<Setup> {
    let (weights, weights_given) = parse_weights(&req.weights)?;
    let mut notes = Vec::new();
    let free = free_keys(base, &req.free, &req.bounds, &mut notes)?;
    let jump = sil::breakaway_jump(base, req.breakaway_jump_m_s2)?;
    let from = req.from_s.unwrap_or(base.scene.stats_from);
    let weight_of = |s: Stat| weights.iter().find(|(k, _)| *k == s).map_or(0.0, |(_, w)| *w);
    if req.recordings.is_empty() && req.tables.is_empty() {
        return Err(HostError::Input("no target: give recordings as CASE=FILE and/or --table FILE".into()));
    }
    // the targets: tables first (cheap), then the recordings
    let mut measured: Vec<Measured> = Vec::new();
    let mut skipped: Vec<Skipped> = Vec::new();
    for t in &req.tables {
        for m in target::load_table(t)? {
            if model::case_scene(base, &m.key.case).is_none() {
                return Err(unknown_case(base, &m.key.case, &m.source));
            }
            measured.push(m);
        }
    }
    let mut recs = Vec::new();
    let mut read: Vec<(target::Recording, crate::recorded::analysis::AnalysisConfig)> = Vec::new();
    let pp_from_recordings = weights_given.contains(&Stat::Pp);
    for arg in &req.recordings {
        let (case, file) = target::parse_recording_arg(arg)?;
        let scene = model::case_scene(base, &case).ok_or_else(|| unknown_case(base, &case, arg))?;
        recs.push((case, file, scene));
    }
    for (case, file, scene) in &recs {
        let cfg = sil::analysis_config(scene, from, req.segment, false);
        let cfg = crate::recorded::analysis::AnalysisConfig { breakaway_jump_m_s2: jump, spectra: weight_of(Stat::PeakHz) > 0.0, ..cfg };
        let rec = target::read_recording(case, file, &cfg, &req.read).map_err(|e| match (e, req.from_s) {
            // the start came from the scene, not from a --from the user gave: say so
            (HostError::Input(m), None) => HostError::Input(m.replace("--from ", "the statistics start (SCENE's stats_from; no --from given) ")),
            (e, _) => e,
        })?;
        let rate = 1.0 / scene.dt;
        if (rec.analysis.sample_rate_hz / rate - 1.0).abs() > 0.01 {
            notes.push(format!(
                "{file} is sampled at {:.6} Hz, the model at 1 / dt = {rate:.6} Hz: the statistics are compared as they are",
                rec.analysis.sample_rate_hz
            ));
        }
        if !rec.windows_hold_cycles() {
            notes.push(format!(
                "{file}: a window of 1/{} of the analysed stretch holds fewer than two slip onsets: no bootstrap over its windows",
                target::WINDOWS
            ));
        }
        let (mut keep, skip) = rec.measured();
        if !pp_from_recordings {
            keep.retain(|m| m.key.stat != Stat::Pp);
        }
        read.push((rec, cfg));
        for m in keep {
            if let Some(prev) = measured.iter().find(|p| p.key == m.key) {
                return Err(HostError::Input(format!("{}: {} is also given by {}", m.source, m.key.label(), prev.source)));
            }
            measured.push(m);
        }
        skipped.extend(skip);
    }
    if !req.recordings.is_empty() && !pp_from_recordings {
        notes.push(format!(
            "the recordings' peak-to-peak values are not fitted (--weights pp=W fits them): a sampled extreme depends on where \
             the samples fall on the sharpest part of the waveform (with falling friction, the last slip samples before a \
             re-stick), not only on the parameters; e.g. push_lead's pad_x peak-to-peak in docs/fit.md's known truth is 142 \
             m/s^2 at k_b = 7e5 N/m and 176 m/s^2 at 0.07 % less. Tables are fitted on theirs (weight {})",
            crate::output::format::num(weights.iter().find(|(k, _)| *k == Stat::Pp).map_or(0.0, |(_, w)| *w))
        ));
    }
    // held-out cases
    let mut holdout_cases: Vec<String> = Vec::new();
    for c in req.holdout.iter().flat_map(|h| h.split(',')).map(str::trim).filter(|s| !s.is_empty()) {
        if !measured.iter().any(|m| m.key.case == c) {
            return Err(HostError::Input(format!("--holdout {c}: no target has that case")));
        }
        if !holdout_cases.iter().any(|h| h == c) {
            holdout_cases.push(c.to_string());
        }
    }
    let mut case_names: Vec<String> = Vec::new();
    for m in &measured {
        if !holdout_cases.contains(&m.key.case) && weight_of(m.key.stat) > 0.0 && !case_names.contains(&m.key.case) {
            case_names.push(m.key.case.clone());
        }
    }
    if case_names.is_empty() {
        return Err(HostError::Input("every case is held out or has no weighted statistic: nothing left to fit".into()));
    }
    let scene_of = |c: &str| model::case_scene(base, c).expect("checked above");
    let cases: Vec<(String, Scene)> = case_names.iter().map(|c| (c.clone(), scene_of(c))).collect();
    let row_of = |m: &Measured, case: usize| Row {
        key: m.key.clone(),
        case,
        measured: m.value,
        weight: weight_of(m.key.stat),
        windows: m.windows.clone(),
        source: m.source.clone(),
    };
    let rows: Vec<Row> = measured
        .iter()
        .filter(|m| weight_of(m.key.stat) > 0.0)
        .filter_map(|m| case_names.iter().position(|c| *c == m.key.case).map(|i| row_of(m, i)))
        .collect();
    // the time-domain cost fits the samples, not the statistics: their count does not limit it
    let waveform_possible =
        req.cost != CostKind::Statistics && req.tables.is_empty() && !req.recordings.is_empty() && waveform::applies(&base.scene);
    if rows.len() <= free.len() && !waveform_possible {
        return Err(HostError::Input(format!(
            "{} weighted statistics for {} free keys: a fit needs more statistics than free keys",
            rows.len(),
            free.len()
        )));
    }
    let progress = req.progress.then(|| {
        let p = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        p.set_style(ProgressStyle::with_template("fit: {spinner} {elapsed} {msg}").expect("valid template"));
        p
    });
    let mut problem = Problem::new(free.clone(), cases, rows, jump, req.segment, progress.clone());
    problem.ratios = model::held_ratios(base, &free);
    for (z, v) in &problem.ratios {
        notes.push(format!("{z} = {} is held as given by the scene file: its coefficient follows the fitted stiffness and mass", crate::output::format::num(*v)));
    }
    // the start must be a valid scene for every case
    let start_stats = problem.run_cases(&problem.cases, &problem.values(&vec![0.0; free.len()]));
    if let Some(Err(e)) = start_stats.iter().find(|s| s.is_err()) {
        return Err(HostError::Input(format!("the start (scene `{}` as given): {e}", base.name)));
    }
    // a channel the scene does not move (no band: disc_x; no rotation: the edges) is exactly 0
    // in the model at any parameters: what a recording shows there is noise, not fitted
    let start_model = Problem::model_values(&problem.rows, &start_stats);
    let (keep, drop): (Vec<_>, Vec<_>) = std::mem::take(&mut problem.rows)
        .into_iter()
        .zip(start_model)
        .partition(|(r, m)| !(r.key.channel.is_some() && *m == Some(0.0)));
    for (r, _) in drop {
        skipped.push(Skipped { key: r.key, source: r.source, why: "the scene does not move this channel (0 in the model)".into() });
    }
    problem.rows = keep.into_iter().map(|(r, _)| r).collect();
    if problem.rows.len() <= free.len() && !waveform_possible {
        return Err(HostError::Input(format!(
            "{} statistics the scene can produce for {} free keys: a fit needs more statistics than free keys",
            problem.rows.len(),
            free.len()
        )));
    }
    let one_dof = problem.cases.iter().all(|(_, s)| waveform::applies(s));
    let waveform_fits = req.tables.is_empty() && !recs.is_empty() && one_dof;
    let use_waveform = match req.cost {
        CostKind::Auto => waveform_fits,
        CostKind::Statistics => false,
        CostKind::Waveform if waveform_fits => true,
        CostKind::Waveform => {
            return Err(HostError::Input(
                "--cost waveform: the time-domain cost is written for recordings alone (no --table) of a 1-DOF scene (rotation = false, band = false)".into(),
            ))
        }
    };
    let stages = if use_waveform {
        for (case, file, _) in &recs {
            if let Some(ci) = problem.cases.iter().position(|(c, _)| c == case) {
                let coulomb = problem.cases[ci].1.friction == stickslip_model::FrictionLaw::Coulomb;
                let tr = waveform::read_trace(case, ci, file, coulomb, &req.read)?;
                if tr.resticks.is_empty() {
                    notes.push(format!("{file}: no re-stick found (no quiet run after a slip): its samples are compared with the run from the band's start as it is"));
                }
                problem.traces.push(tr);
            }
        }
        // the global stage: the cycles' features, where every recording has two re-sticks
        if problem.traces.iter().all(|t| t.features().is_some()) {
            let mut p = Problem::new(problem.free.clone(), problem.cases.clone(), problem.rows.clone(), jump, req.segment, progress.clone());
            p.traces = problem.traces.clone();
            p.features = true;
            p.ratios = problem.ratios.clone();
            vec![Stage { problem: p, cycles: 0.0, horizons: Vec::new() }]
        } else {
            notes.push("a recording has fewer than two re-sticks: no global stage on the cycles' features; the starts are screened on the samples".into());
            Vec::new()
        }
    } else {
        horizon_stages(&problem, &read, &req.horizons, &weight_of, &mut notes, progress.clone())?
    };
    Ok(Setup { problem, measured, skipped, notes, holdout_cases, weights, free, jump, progress, stages })
}

/// The horizon stages of `problem` (see [`solve::search`]): for each of `horizons` [cycles],
/// every fitted recording's start (t = 0 to its first slip onset + that many of its stick-slip
/// periods, rounded up to a whole time step) and the model's run of the same length, on the
/// statistics the whole-record problem fits. A recording without an onset and a frequency,
/// or shorter than the horizon, is left out of that stage; a stage with no more statistics than
/// free keys is dropped. A fit to tables alone has no stages (and says nothing of them).
fn horizon_stages(
    problem: &Problem,
    read: &[(target::Recording, crate::recorded::analysis::AnalysisConfig)],
    horizons: &[f64],
    weight_of: &dyn Fn(Stat) -> f64,
    notes: &mut Vec<String>,
    progress: Option<ProgressBar>,
) -> Result<Vec<Stage>> {
    if read.is_empty() {
        return Ok(Vec::new());
    }
    let mut cycles: Vec<f64> = horizons.to_vec();
    cycles.sort_by(f64::total_cmp);
    cycles.dedup();
    let mut out = Vec::new();
    for &n in &cycles {
        let (mut cases, mut rows, mut hz) = (Vec::new(), Vec::new(), Vec::new());
        for (rec, cfg) in read {
            let Some(ci) = problem.cases.iter().position(|(c, _)| *c == rec.case) else { continue };
            let Some(h) = rec.horizon_s(n) else {
                notes.push(format!(
                    "{}: no horizon of {n} cycles (no slip onset or no stick-slip frequency, or the record ends before it): \
                     left out of that stage",
                    rec.path
                ));
                continue;
            };
            let dt = problem.cases[ci].1.dt;
            let h = (h / dt).ceil() * dt;
            let head = rec.head(cfg, h)?;
            let (keep, _) = head.measured();
            let mut scene = problem.cases[ci].1;
            scene.duration = h;
            scene.stats_from = 0.0;
            let idx = cases.len();
            for m in keep {
                if problem.rows.iter().any(|r| r.key == m.key) {
                    rows.push(Row { weight: weight_of(m.key.stat), key: m.key, case: idx, measured: m.value, windows: Vec::new(), source: format!("{} (to t = {h} s)", m.source) });
                }
            }
            cases.push((rec.case.clone(), scene));
            hz.push((rec.case.clone(), h));
        }
        if rows.len() <= problem.free.len() {
            notes.push(format!("horizon of {n} cycles: {} statistics for {} free keys: stage left out", rows.len(), problem.free.len()));
            continue;
        }
        let mut p = Problem::new(problem.free.clone(), cases, rows, problem.jump_m_s2, problem.segment, progress.clone());
        p.ratios = problem.ratios.clone();
        out.push(Stage { problem: p, cycles: n, horizons: hz });
    }
    Ok(out)
}

/// Runs the fit described by `req` on the base scene `base` (validated).
pub fn run_fit(base: NamedScene, req: &FitRequest) -> Result<FitReport> {
    let t0 = Instant::now();
    let Setup { problem, measured, mut skipped, mut notes, holdout_cases, weights, free, jump, progress, stages } = setup(&base, req)?;
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
    let r = problem.residuals(&sol.u).map_err(HostError::Input)?;
    let (goodness, chi2_scale) = judge(&problem, &sol, &r, &mut notes).map_err(HostError::Input)?;
    let j = solve::jacobian(&problem, &sol.u, &r);
    let unc = solve::uncertainty(&j, &r);
    let first_steps: Vec<f64> = (0..free.len()).map(|k| unc.cov_u[(k, k)].sqrt()).collect();
    // intervals where the model fits: a misfit's profile would measure the model's error, not
    // the data's (and not_converged has no one optimum to profile)
    let intervals = if goodness.verdict == goodness::Verdict::Fits {
        solve::profile_intervals(&problem, &sol.u, sol.cost, chi2_scale, goodness.chi2_per_dof, &first_steps, req.max_iters)
    } else {
        if problem.time_domain() {
            notes.push(format!(
                "no profile-likelihood intervals: the verdict is {} (a profile would measure the model's error, not the data's)",
                goodness.verdict.name()
            ));
        }
        Vec::new()
    };
    let sources: Vec<String> = {
        let mut s: Vec<String> = problem.rows.iter().filter(|r| !r.windows.is_empty()).map(|r| r.source.clone()).collect();
        s.sort();
        s.dedup();
        s
    };
    // the bootstrap resamples the statistics' windows: not the time-domain cost's samples
    let std_boot_u =
        if problem.time_domain() { None } else { solve::bootstrap(&j, &problem.rows, &sources, req.bootstrap, req.seed) };
    let values = problem.values(&sol.u);
    let std: Vec<f64> = values.iter().enumerate().map(|(k, v)| v * unc.cov_u[(k, k)].sqrt()).collect();
    let std_bootstrap = std_boot_u.map(|s| s.iter().zip(&values).map(|(su, v)| v * su).collect());
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
    })
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
            let (sd, used) = waveform::stick_noise(tr, &m);
            let f = tr.sigma0 / sd;
            chi2 += res.iter().map(|x| (x * f).powi(2)).sum::<f64>();
            count += tr.masked.iter().filter(|x| !**x).count() + 1;
            shifts += tr.resticks.len();
            noise2 += sd * sd;
            notes.push(format!(
                "{}: noise {} m/s^2 rms from {used} samples where the fitted model is in stick (before the fit: {} from the second differences); {} re-sticks found, {} samples left out around them",
                tr.path,
                crate::output::format::num(sd),
                crate::output::format::num(tr.sigma0),
                tr.resticks.len(),
                tr.masked.iter().filter(|x| **x).count()
            ));
        }
        let noise = (noise2 / problem.traces.len() as f64).sqrt();
        let dof = count.saturating_sub(n + shifts).max(1);
        let g = goodness::judge(chi2, dof, noise, "the recordings' stick phases (pad_x where the fitted model is in stick)".into(), &sol.starts, 2.0);
        return Ok((g, 2.0));
    }
    // statistics: each log ratio over its standard error
    let mut chi2 = 0.0;
    let (mut assumed, mut from_windows) = (0usize, 0usize);
    let mut s2 = 0.0;
    for (row, x) in problem.rows.iter().zip(r) {
        let lr = x / row.weight.sqrt();
        let sd = if row.windows.len() >= 2 {
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
    let source = match (from_windows, assumed) {
        (_, 0) => "the spread of each statistic over its recording's windows".to_string(),
        (0, _) => format!("assumed: {} in ln(value) for every statistic (a table states no error)", goodness::ASSUMED_SIGMA_LN),
        _ => format!("the windows' spread for {from_windows} statistics, assumed {} in ln(value) for {assumed}", goodness::ASSUMED_SIGMA_LN),
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

/// One point of a cost profile.
#[derive(Clone, Debug)]
pub struct ProfilePoint {
    pub value: f64,
    /// Cost = sum r^2 / 2; `None` where the model is rejected (`error`).
    pub cost: Option<f64>,
    /// RMS of the fitted statistics' log ratios ln(model / measured), unweighted.
    pub rms_log_ratio: Option<f64>,
    /// The statistic with the largest weighted log ratio and that ratio.
    pub worst: Option<(String, f64)>,
    pub error: Option<String>,
}

/// The cost along one free key, the others at the scene's values (`fit --profile`).
#[derive(Clone, Debug)]
pub struct Profile {
    pub scene: String,
    pub key: String,
    /// The other free keys and their (fixed) values.
    pub others: Vec<(String, f64)>,
    pub statistics: usize,
    pub points: Vec<ProfilePoint>,
    pub seconds: f64,
}

/// Parses `KEY=LO:HI:N` (0 < LO < HI, N >= 2).
fn parse_profile(spec: &str) -> Result<(String, f64, f64, usize)> {
    let bad = |m: &str| HostError::Input(format!("--profile {spec}: {m}"));
    let (key, range) = spec.split_once('=').ok_or_else(|| bad("give KEY=LO:HI:N, e.g. k_b=5e5:1.5e6:21"))?;
    let parts: Vec<&str> = range.split(':').collect();
    if parts.len() != 3 {
        return Err(bad("give KEY=LO:HI:N, e.g. k_b=5e5:1.5e6:21"));
    }
    let num = |s: &str| s.trim().parse::<f64>().map_err(|_| bad(&format!("`{s}` is not a number")));
    let (lo, hi) = (num(parts[0])?, num(parts[1])?);
    let n: usize = parts[2].trim().parse().map_err(|_| bad(&format!("`{}` is not a count", parts[2])))?;
    if !(lo > 0.0 && hi.is_finite() && lo < hi) {
        return Err(bad("needs 0 < LO < HI (the points are log-spaced)"));
    }
    if !(2..=crate::limits::PROFILE_MAX_POINTS).contains(&n) {
        return Err(bad(&format!("needs N >= 2 points (at most {})", crate::limits::PROFILE_MAX_POINTS)));
    }
    Ok((key.trim().to_string(), lo, hi, n))
}

/// N values log-spaced from `lo` to `hi` (0 < lo < hi, both finite, N >= 2): the ends exactly
/// `lo` and `hi`, every value finite and inside [lo, hi] (a ratio hi / lo that overflows, 1e-300
/// to 1e300, is spaced on ln instead).
pub fn profile_values(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let ratio = hi / lo;
    (0..n)
        .map(|i| {
            let f = i as f64 / (n - 1) as f64;
            let v = if i == 0 {
                lo
            } else if i + 1 == n {
                hi
            } else if ratio.is_finite() {
                lo * ratio.powf(f)
            } else {
                (lo.ln() + f * (hi.ln() - lo.ln())).exp()
            };
            v.clamp(lo, hi)
        })
        .collect()
}

/// The cost profile along one free key (`spec` = `KEY=LO:HI:N`): N values log-spaced from LO
/// to HI, every other free key at the scene's value, each point one evaluation of every
/// fitted case (the residuals of the fit, no search). It shows what a search sees along that
/// key: the basin's width, a flat direction, a jump where the stick-slip cycle changes.
pub fn run_profile(base: NamedScene, req: &FitRequest, spec: &str) -> Result<Profile> {
    let t0 = Instant::now();
    let (key, lo, hi, n) = parse_profile(spec)?;
    // a profile evaluates the whole record only: no horizon stages to build
    let Setup { mut problem, progress, .. } = setup(&base, &FitRequest { horizons: Vec::new(), ..req.clone() })?;
    let k = problem.free.iter().position(|f| f.key == key).ok_or_else(|| {
        HostError::Input(format!("--profile {spec}: `{key}` is not a free key (give it in --free)"))
    })?;
    let start = problem.free[k].start;
    // the search's parameters are u = ln(value / start): each end as the problem will see it
    // after the round trip start exp(u) (4 can come back as 4.000000000000001) is inside
    let round_trip = |v: f64| start * (v / start).ln().exp();
    problem.free[k].lo = problem.free[k].lo.min(lo).min(round_trip(lo));
    problem.free[k].hi = problem.free[k].hi.max(hi).max(round_trip(hi));
    let values = profile_values(lo, hi, n);
    let points = values
        .iter()
        .map(|&v| {
            let mut u = vec![0.0; problem.free.len()];
            u[k] = (v / start).ln();
            match problem.residuals(&u) {
                Ok(r) if problem.time_domain() => {
                    // the time-domain cost: residuals are samples in units of the noise, not
                    // log ratios of statistics (no RMS log ratio, no worst statistic)
                    ProfilePoint { value: v, cost: Some(solve::cost_of(&r)), rms_log_ratio: None, worst: None, error: None }
                }
                Ok(r) => {
                    // every row has weight > 0 (setup keeps only those): r_j = sqrt(w_j) ln(model /
                    // measured); the RMS is of the log ratios themselves, as the fit's
                    // `rms_log_ratio` (a statistic the model lacks counts as MISSING_LOG_RATIO)
                    let ratio = |j: usize| r[j] / problem.rows[j].weight.sqrt();
                    let rms = (r.iter().enumerate().map(|(j, _)| ratio(j).powi(2)).sum::<f64>() / r.len().max(1) as f64).sqrt();
                    let worst = (0..r.len())
                        .max_by(|&a, &b| r[a].abs().total_cmp(&r[b].abs()))
                        .map(|j| (problem.rows[j].key.label(), ratio(j)));
                    ProfilePoint { value: v, cost: Some(solve::cost_of(&r)), rms_log_ratio: Some(rms), worst, error: None }
                }
                Err(e) => ProfilePoint { value: v, cost: None, rms_log_ratio: None, worst: None, error: Some(e) },
            }
        })
        .collect();
    if let Some(p) = progress {
        p.finish_and_clear();
    }
    let others = problem.free.iter().filter(|f| f.key != key).map(|f| (f.key.clone(), f.start)).collect();
    Ok(Profile { scene: base.name.clone(), key, others, statistics: problem.rows.len(), points, seconds: t0.elapsed().as_secs_f64() })
}
