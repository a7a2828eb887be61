//! What the Jacobian at the optimum says about the parameters: standard errors,
//! correlations, flat directions, and the linearised bootstrap over a recording's windows.

use super::*;

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
