//! Whether a fit's best cost is what the measurement noise explains (the chi-square per
//! degree of freedom), and whether the search found one optimum (its starts agree): the
//! verdict `fits`, `misfit` or `not_converged` (docs/fit.md, "Goodness").
//!
//! - **Time-domain cost** (recordings of a 1-DOF scene): the noise is the recording's own, the
//!   standard deviation of its samples where the fitted model is in stick (pad_x exactly 0
//!   there, so what the recording shows is noise). chi^2 = sum ((recorded - model) / noise)^2
//!   over the fitted samples and the first re-stick's timing; dof = that count less the free
//!   keys and the segments' shifts. Where that noise exceeds [`STICK_NOISE_FACTOR`] times the
//!   noise of the recording's second differences (measured before the fit, robustly), the
//!   recording moves where the model sticks: that residual is signal the model misses, not
//!   noise, and chi^2 takes the second differences' noise instead (a sine fitted by a model
//!   that sticks most of the time was a `fits` at chi^2 / dof 0.95 with its own amplitude,
//!   284 times the noise, taken for noise).
//! - **Statistics** (tables, or recordings with `--cost statistics`): each log ratio over its
//!   own standard error: a recording's from the spread of its windows (sd / sqrt(windows)), a
//!   table's from its `sigma` column where it has one, else [`ASSUMED_SIGMA_LN`] (Table 3.1
//!   states none: assumed, and said so); dof = statistics less free keys.
//!
//! `fits`: chi^2 / dof <= [`chi2_limit`] (a cost the noise explains: no other optimum can be
//! better by more than the noise, whatever the other starts found); `misfit`: above it, and
//! at least two starts end at the best cost (within [`AGREE_CHI2`] of chi^2, or 1e-3 of it
//! relative; or the only start converged): the model family does not fit; `not_converged`:
//! above it, and no other start confirms the best.

use super::solve::StartReport;

/// The standard error of ln(value) assumed for a table value that states none: 0.25 (about
/// +-28 %), the scatter of a rig run three times at an uncontrolled speed with the "feasible"
/// run kept (Table 3.1; docs/fit.md).
pub const ASSUMED_SIGMA_LN: f64 = 0.25;
/// Two starts agree when their chi^2 differ by less than this (or 1e-3 relative).
pub const AGREE_CHI2: f64 = 1.0;
/// The stick phases' noise may exceed the second differences' by this factor before it is
/// taken for signal the model misses (module documentation): white noise gives a ratio of 1,
/// a stick phase that follows a slow band vibration a little more.
pub const STICK_NOISE_FACTOR: f64 = 3.0;
/// Beyond the chi-square's own scatter (3 sigma), what `fits` allows for the noise estimate's
/// and the model side's error: 10 %.
pub const FIT_MARGIN: f64 = 0.1;

/// The verdict.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    Fits,
    Misfit,
    NotConverged,
}

impl Verdict {
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Fits => "fits",
            Verdict::Misfit => "misfit",
            Verdict::NotConverged => "not_converged",
        }
    }
}

/// The goodness of a fit.
#[derive(Clone, Debug)]
pub struct Goodness {
    pub chi2_per_dof: f64,
    pub dof: usize,
    /// The noise: [m/s^2] for the time-domain cost (the recordings' RMS), the RMS standard
    /// error of ln(value) for statistics.
    pub noise: f64,
    /// Where the noise comes from.
    pub noise_source: String,
    /// Starts that end at the best cost.
    pub starts_agreeing: usize,
    pub verdict: Verdict,
}

/// The largest chi^2 / dof that `fits` at `dof` degrees of freedom: 1 + 3 sqrt(2 / dof) +
/// [`FIT_MARGIN`].
pub fn chi2_limit(dof: usize) -> f64 {
    1.0 + 3.0 * (2.0 / dof.max(1) as f64).sqrt() + FIT_MARGIN
}

/// How many starts end at the best cost; `cost_to_chi2` turns a cost into chi^2.
pub fn agreeing(starts: &[StartReport], cost_to_chi2: f64) -> usize {
    let best = starts.iter().map(|s| s.cost).fold(f64::INFINITY, f64::min);
    let tol = (AGREE_CHI2 / cost_to_chi2).max(1e-3 * best);
    starts.iter().filter(|s| s.cost - best <= tol).count()
}

/// The verdict from chi^2, dof and the starts.
pub fn judge(chi2: f64, dof: usize, noise: f64, noise_source: String, starts: &[StartReport], cost_to_chi2: f64) -> Goodness {
    let agree = agreeing(starts, cost_to_chi2);
    let chi2_per_dof = chi2 / dof.max(1) as f64;
    let searched_once = starts.len() == 1 && starts[0].converged;
    // a cost the noise explains cannot be beaten by more than the noise: it fits whether or
    // not the other starts found it; a cost it does not explain is the model's only if the
    // starts agree on it
    let verdict = if chi2_per_dof <= chi2_limit(dof) {
        Verdict::Fits
    } else if agree >= 2 || searched_once {
        Verdict::Misfit
    } else {
        Verdict::NotConverged
    };
    Goodness { chi2_per_dof, dof, noise, noise_source, starts_agreeing: agree, verdict }
}
