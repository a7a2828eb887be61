//! `fit --profile KEY=LO:HI:N`: the cost along one key, the other free keys at the scene's
//! values (no search).

use super::*;

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
    /// The time-domain cost's residual count (the recordings' samples and cycle timings, in
    /// units of their noise), when the cost is that one; None: the statistics' log ratios.
    pub time_domain_residuals: Option<usize>,
    pub points: Vec<ProfilePoint>,
    pub seconds: f64,
}

/// Parses `KEY=LO:HI:N` (0 < LO < HI, N >= 2).
pub(super) fn parse_profile(spec: &str) -> Result<(String, f64, f64, usize)> {
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
    // a profile scans values, not a search's coordinate: the plain log scale, so that a value
    // past mu_s is the scene's own error (mu_k > mu_s), not a drop with no logarithm
    problem.free[k].origin = 0.0;
    // the search's parameters are u = ln(value / start): each end as the problem will see it
    // after the round trip (4 can come back as 4.000000000000001) is inside
    let fk = problem.free[k].clone();
    let round_trip = |v: f64| fk.value(fk.coord(v));
    problem.free[k].lo = problem.free[k].lo.min(lo).min(round_trip(lo));
    problem.free[k].hi = problem.free[k].hi.max(hi).max(round_trip(hi));
    let values = profile_values(lo, hi, n);
    let points = values
        .iter()
        .map(|&v| {
            let mut u = vec![0.0; problem.free.len()];
            u[k] = fk.coord(v);
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
    let time_domain_residuals = problem.time_domain().then(|| problem.residual_count());
    Ok(Profile { scene: base.name.clone(), key, others, statistics: problem.rows.len(), time_domain_residuals, points, seconds: t0.elapsed().as_secs_f64() })
}
