//! A fit's problem before the search: the weights and free keys checked, the targets read,
//! each case's scene and the weighted rows, and the horizon stages.

use super::*;

/// Each statistic's weight.
pub(super) type Weights = Vec<(Stat, f64)>;

/// The weight of every statistic, and which were given (not defaults).
pub(super) fn parse_weights(given: &[String]) -> Result<(Weights, Vec<Stat>)> {
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

pub(super) fn free_keys(scene: &NamedScene, free: &[String], bounds: &[String], notes: &mut Vec<String>) -> Result<Vec<FreeKey>> {
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
        keys.push(FreeKey::new(item, start, lo, hi));
    }
    if keys.is_empty() {
        return Err(HostError::Input("--free: give at least one scene key to fit, e.g. --free mu_s,mu_k,v_s".into()));
    }
    let mut bounded: Vec<&str> = Vec::new();
    for b in bounds.iter().flat_map(|f| f.split(',')).map(str::trim).filter(|s| !s.is_empty()) {
        let bad = |m: String| HostError::Input(format!("--bounds {b}: {m}"));
        let (k, range) = b.split_once('=').ok_or_else(|| bad("give KEY=LO:HI".into()))?;
        if bounded.contains(&k.trim()) {
            return Err(bad(format!("`{}` is bounded twice; give one range", k.trim())));
        }
        bounded.push(k.trim());
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
    notes.extend(model::drop_coordinate(&mut keys, scene.scene.mu_s));
    Ok(keys)
}

pub(super) fn unknown_case(base: &NamedScene, case: &str, at: &str) -> HostError {
    HostError::Input(format!(
        "{at}: unknown case `{case}` (the cases: {}, or the scene's own name `{}`)",
        model::case_names().join(", "),
        base.name
    ))
}

/// A fit's problem before the search: the targets read, the cases' scenes, the weighted rows.
pub(super) struct Setup {
    pub(super) problem: Problem,
    pub(super) measured: Vec<Measured>,
    pub(super) skipped: Vec<Skipped>,
    pub(super) notes: Vec<String>,
    pub(super) holdout_cases: Vec<String>,
    pub(super) weights: Vec<(Stat, f64)>,
    pub(super) free: Vec<FreeKey>,
    pub(super) jump: f64,
    pub(super) progress: Option<ProgressBar>,
    /// The horizon stages, shortest first.
    pub(super) stages: Vec<Stage>,
    /// Whether every target is a recording with no stick-slip in it (read with its own noise
    /// floor): nothing identifies the friction.
    pub(super) no_stick_slip: bool,
}

/// A horizon stage before the search: its problem, its cycles and each case's horizon [s].
pub(super) struct Stage {
    pub(super) problem: Problem,
    pub(super) cycles: f64,
    pub(super) horizons: Vec<(String, f64)>,
}

/// Reads the targets of `req`, checks the free keys and builds the problem on `base`.
pub(super) fn setup(base: &NamedScene, req: &FitRequest) -> Result<Setup> {
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
    let mut without_stick_slip = 0usize;
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
        // the measured statistics are read with the estimator's thresholds from the start
        // scene's breakaway jump (as the model's are): where the start values' jump is far
        // above the recording's own, its onset level (J/2) misses slips and the "measured"
        // figures are wrong whatever the fit does. The recording read with its own noise floor
        // (as `analyze` reads it) tells: a start of mu_s 0.70, mu_k 0.28 for a truth of 0.55,
        // 0.38 read 1.890 Hz and 0.995 stuck where `analyze` reads 2.362 Hz and 0.970
        let own = own_floor_reading(file, &cfg, &req.read)?;
        if let Some(why) = jump_misreads(&rec.analysis, &own, file, jump) {
            notes.push(why);
        }
        if let Some(why) = offset_note(&own, file, waveform_cost_possible(req, &base.scene)) {
            notes.push(why);
        }
        // no stick-slip in it: pure noise gave the verdict not_converged (the search blamed),
        // a sine misfit, both "identifiable" with error bars of 1e-5. (Not where the estimate
        // is only not told: the estimator is built for the rig's cycles, and a clean Stribeck
        // oracle of 1.5 s cycles is "cannot decide" to it, its slips too slow.)
        if own.no_stick_slip_seen {
            without_stick_slip += 1;
            notes.push(format!(
                "{file}: no stick-slip in it, read with its own noise floor as `analyze` reads it ({} slip onsets{}): nothing in it identifies \
                 the friction, and the values fitted to it are not the rig's",
                own.slip_onsets,
                match &own.undecided {
                    Some(why) => format!("; cannot decide: {why}"),
                    None => String::new(),
                }
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
        sigma_ln: m.sigma.map(|s| s / m.value),
    };
    let rows: Vec<Row> = measured
        .iter()
        .filter(|m| weight_of(m.key.stat) > 0.0)
        .filter_map(|m| case_names.iter().position(|c| *c == m.key.case).map(|i| row_of(m, i)))
        .collect();
    // the time-domain cost fits the samples, not the statistics: their count does not limit it
    let waveform_possible = waveform_cost_possible(req, &base.scene);
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
    let no_stick_slip = req.tables.is_empty() && !recs.is_empty() && without_stick_slip == recs.len();
    Ok(Setup { problem, measured, skipped, notes, holdout_cases, weights, free, jump, progress, stages, no_stick_slip })
}

/// The horizon stages of `problem` (see [`solve::search`]): for each of `horizons` [cycles],
/// every fitted recording's start (t = 0 to its first slip onset + that many of its stick-slip
/// periods, rounded up to a whole time step) and the model's run of the same length, on the
/// statistics the whole-record problem fits. A recording without an onset and a frequency,
/// or shorter than the horizon, is left out of that stage; a stage with no more statistics than
/// free keys is dropped. A fit to tables alone has no stages (and says nothing of them).
pub(super) fn horizon_stages(
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
                    rows.push(Row { weight: weight_of(m.key.stat), key: m.key, case: idx, measured: m.value, windows: Vec::new(), source: format!("{} (to t = {h} s)", m.source), sigma_ln: None });
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

/// The recording read with its own noise floor, as `analyze` reads it (no spectra, no figures).
fn own_floor_reading(
    file: &str,
    cfg: &crate::recorded::analysis::AnalysisConfig,
    read: &crate::recorded::ReadOptions,
) -> Result<crate::recorded::analysis::Analysis> {
    let own = crate::recorded::analysis::AnalysisConfig { floor: crate::recorded::analysis::FloorSource::Auto, figures: false, spectra: false, ..cfg.clone() };
    crate::recorded::analyze_with(file, own, read)
}

/// Whether the time-domain cost may run (the same test as the setup's, before the targets are
/// all read).
fn waveform_cost_possible(req: &FitRequest, scene: &Scene) -> bool {
    req.cost != CostKind::Statistics && req.tables.is_empty() && !req.recordings.is_empty() && waveform::applies(scene)
}

/// pad_x's mean in the recording's quiet rows (its noise floor, taken in stick, where pad_x is
/// 0) where it is over a third of their noise and clear of the mean's own scatter: an offset
/// (the sensor's or the logger's). The estimator tracks a bias, but the time-domain cost fits
/// pad_x itself, whose model is 0 in stick: an offset of the noise's size made a right fit a
/// misfit (chi^2/dof 2.0), 2.5 times it a wrong basin (a campaign, 2026-11-28). Returns the
/// note, worded for the cost in use (`waveform`).
fn offset_note(own: &crate::recorded::analysis::Analysis, file: &str, waveform: bool) -> Option<String> {
    use crate::output::format::short;
    use stickslip_model::rig::PAD_X;
    let f = own.floor.as_ref()?;
    let (mean, sigma, n) = (f64::from(f.report.mean_m_s2[PAD_X]), f64::from(f.report.sigma_m_s2[PAD_X]), f64::from(f.report.samples));
    if !(sigma > 0.0 && mean.abs() > OFFSET_OF_NOISE * sigma && mean.abs() > 4.0 * sigma / n.sqrt()) {
        return None;
    }
    Some(format!(
        "{file}: pad_x's mean in its quiet rows (its noise floor, {} rows, taken in stick where pad_x is 0) is {} m/s^2, {} times their noise: \
         an offset (the sensor's or the logger's). {}",
        f.report.samples,
        short(mean),
        short(mean.abs() / sigma),
        if waveform {
            "The time-domain cost fits pad_x itself, 0 in stick in the model: the offset reads as a misfit, and a large one can lead \
             to a wrong basin; subtract it from the recording's pad_x and fit again"
        } else {
            "The statistics' estimator tracks it as a bias"
        }
    ))
}

/// pad_x's offset is named where it exceeds this fraction of the noise (it adds its square, a
/// ninth, to the time-domain cost's chi^2 per sample).
const OFFSET_OF_NOISE: f64 = 1.0 / 3.0;

/// Whether the recording read with the jump's fixed thresholds (`with_jump`) disagrees with the
/// same recording read with its own noise floor (as `analyze` reads it): more than 5 % apart in
/// slip onsets or stick-slip frequency, or in stick fraction 0.05 or 10 % of the slip fraction
/// (plus 0.001), where the floor's reading is told. Returns the note that says so.
fn jump_misreads(with_jump: &crate::recorded::analysis::Analysis, floor: &crate::recorded::analysis::Analysis, file: &str, jump: f64) -> Option<String> {
    use crate::output::format::short;
    if floor.undecided.is_some() || floor.floor.is_none() || floor.slip_onsets < 2 {
        return None;
    }
    let apart = |a: f64, b: f64| !((a - b).abs() <= 0.05 * b.abs());
    let hz = |a: &crate::recorded::analysis::Analysis| a.stick_slip_hz.unwrap_or(0.0);
    let misread = with_jump.undecided.is_some()
        || apart(with_jump.slip_onsets as f64, floor.slip_onsets as f64)
        || apart(hz(with_jump), hz(&floor))
        || (with_jump.stick_fraction - floor.stick_fraction).abs() > 0.05
        // the slip fraction 10 % apart (plus 0.001): near a stick fraction of 1 a slip missed
        // in part is a small change of the stick fraction and a large one of the slips (0.994
        // for 0.970 at a jump 2.5 times the truth's; 0.9703 at the truth's own)
        || (with_jump.stick_fraction - floor.stick_fraction).abs() > 0.1 * (1.0 - floor.stick_fraction) + 1e-3;
    misread.then(|| {
        format!(
            "{file}: read with the estimator's thresholds from the start scene's breakaway jump ({} m/s^2: slip onset above {} m/s^2), \
             it gives {} slip onsets, {} Hz and a stick fraction of {}; read with its own noise floor (as `analyze` reads it: onset \
             above {} m/s^2), {} onsets, {} Hz and {}. The measured statistics are the former, and likely wrong: start values \
             whose mu_s - mu_k is nearer the recording's, or --breakaway-jump J with J/2 below its slips' acceleration",
            short(jump),
            short(f64::from(with_jump.thresholds.slip_onset_m_s2)),
            with_jump.slip_onsets,
            with_jump.stick_slip_hz.map_or("no".into(), short),
            short(with_jump.stick_fraction),
            short(f64::from(floor.thresholds.slip_onset_m_s2)),
            floor.slip_onsets,
            short(hz(&floor)),
            short(floor.stick_fraction),
        )
    })
}
