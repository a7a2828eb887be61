//! The least-squares problem: the fitted statistics ([`Row`]), the model run at a parameter
//! point and its residuals ([`Problem`]), and the cost argmin minimises.

use super::*;

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
    /// A table's stated standard error of ln(measured): its `sigma` / value.
    pub sigma_ln: Option<f64>,
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
    /// Every run of the cases (the Jacobians' and the screens' too, which [`Self::evals`] does
    /// not count): what the search costs.
    pub runs: AtomicUsize,
    pub(super) best: Mutex<f64>,
    pub(super) progress: Option<ProgressBar>,
    /// The recordings' pad_x series when the cost is the time-domain one
    /// ([`super::super::waveform`]); empty: the statistics' log ratios of `rows`.
    pub traces: Vec<super::super::waveform::Trace>,
    /// With `traces`: the global stage's cost, the recordings' cycle features
    /// ([`super::super::waveform::feature_residuals`]), instead of their samples.
    pub features: bool,
    /// Damping ratios held while the free keys move ([`model::held_ratios`]).
    pub ratios: Vec<(String, f64)>,
    /// The command's cancellation ([`crate::cancel`]), taken where the problem is made: once
    /// cancelled, every evaluation is refused without a run.
    pub cancel: Option<crate::cancel::Cancel>,
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
        let spectra = rows.iter().any(|r| r.key.stat == super::super::stat::Stat::PeakHz);
        Problem {
            free,
            cases,
            rows,
            jump_m_s2,
            segment,
            spectra,
            evals: AtomicUsize::new(0),
            runs: AtomicUsize::new(0),
            best: Mutex::new(f64::INFINITY),
            progress,
            traces: Vec::new(),
            features: false,
            ratios: Vec::new(),
            cancel: crate::cancel::current(),
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
    pub(super) fn trace_residuals(&self, values: &[f64]) -> Result<Vec<f64>, String> {
        let parts: Vec<Result<Vec<f64>, String>> = self
            .traces
            .par_iter()
            .map(|tr| {
                let scene = model::with_values_held(&self.cases[tr.case_index].1, &self.free, values, &self.ratios)?;
                if self.features {
                    super::super::waveform::feature_residuals(tr, &scene)
                } else {
                    super::super::waveform::residuals(tr, &scene, None)
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
        self.free.iter().zip(u).map(|(f, x)| f.value(*x)).collect()
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
        if self.cancel.as_ref().is_some_and(|c| c.is_cancelled()) {
            return Err("cancelled".into());
        }
        let values = self.values(u);
        for (f, v) in self.free.iter().zip(&values) {
            if !(*v >= f.lo && *v <= f.hi) {
                return Err(format!("{} = {v} outside [{}, {}]", f.key, f.lo, f.hi));
            }
        }
        self.runs.fetch_add(1, Ordering::Relaxed);
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

    pub(super) fn note(&self, cost: f64) {
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
        // a residual that is not finite (a run the model could not finish as the cost needs)
        // is a rejected point: a NaN cost would leave the simplex's ordering undefined
        let c = match self.residuals(u) {
            Ok(r) => cost_of(&r),
            Err(_) => OUTSIDE,
        };
        let c = if c.is_finite() { c } else { OUTSIDE };
        self.note(c);
        Ok(c)
    }
}
