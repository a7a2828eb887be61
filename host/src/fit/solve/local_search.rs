//! The search from one start: Nelder-Mead to the basin, Levenberg-Marquardt to its bottom,
//! and the polish of the best start over its neighbourhood.

use super::*;

/// Nelder-Mead from `u0`: a simplex of `step`, at most `max_iters` iterations, until the
/// costs of the simplex's vertices agree to [`SD_TOLERANCE`] (their standard deviation).
pub(super) fn nelder_mead(p: &Problem, u0: &[f64], step: f64, max_iters: u64) -> Result<(Vec<f64>, f64, bool), String> {
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
pub(super) struct LmProblem<'a> {
    pub(super) p: &'a Problem,
    pub(super) u: DVector<f64>,
    /// The residuals at `u`, computed once for both calls at a point.
    pub(super) r: std::cell::RefCell<Option<Vec<f64>>>,
}

/// Each residual at a rejected point (outside the bounds, an invalid scene, a run that halts).
pub(super) const REJECTED_RESIDUAL: f64 = 1e6;

impl LmProblem<'_> {
    pub(super) fn r(&self) -> Vec<f64> {
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
pub(super) fn levenberg_marquardt(p: &Problem, u0: &[f64], max_iters: u64) -> (Vec<f64>, f64, bool) {
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
pub(super) fn local_search(p: &Problem, u0: &[f64], step: f64, max_iters: u64) -> Result<(Vec<f64>, f64, bool), String> {
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
pub(super) const POLISH_RESTARTS: usize = 3;
/// A restart that lowers the cost by more than this fraction is followed by another.
pub(super) const POLISH_GAIN: f64 = 0.01;
/// The same for statistics of recordings and tables: their cost is rough at a few per cent
/// near the optimum (docs/fit.md), and on the rig set's truth a restart that gained 2 % moved
/// v_s by 0.03 %.
pub(super) const POLISH_GAIN_STATISTICS: f64 = 0.05;
/// The polish's simplex: 5 % in each ln(value) (the basin is found; the simplex only has to
/// follow the valley).
pub(super) const POLISH_STEP: f64 = 0.05;

/// The polish's screen around the best point: this many Halton points per free key.
pub(super) const NEIGHBOURHOOD_POINTS_PER_KEY: usize = 16;
/// Its box in ln(value) is at most this wide either way along any direction.
pub(super) const NEIGHBOURHOOD_SPAN: f64 = 0.05;

/// The lowest point of a Halton screen around `u` (cost `cost`), or the smoothed Gauss-Newton
/// step from the screen, if lower: the screen's box lies along the singular vectors of the
/// Jacobian at `u`, each side as far as the local quadratic model of the cost rises by `cost`
/// (sqrt(2 cost) / s_i along singular value s_i, at most [`NEIGHBOURHOOD_SPAN`]): a lower valley
/// beside the best point's dip, across a ridge no higher than the cost itself, is found where a
/// box in the keys' own axes would miss a valley narrower than its points' spacing (correlated
/// keys).
///
/// **The smoothed step.** A whole record's statistics are rough at a scale far below the
/// screen's box (on the rig set's truth, rounding the keys to 7 digits moves the cost by 7 %),
/// and a local search ends in whichever dip is nearest; their trend over the box is smooth.
/// A straight line fitted by least squares to each residual over the screen's points (the
/// residuals' regression on u, intercept and slopes: a Jacobian averaged over the box) gives
/// the Gauss-Newton step of that trend, taken at most twice the box's half-width along each
/// singular vector; its point joins the screen.
pub(super) fn neighbourhood_best(p: &Problem, u: &[f64], cost: f64) -> Option<Vec<f64>> {
    let n = u.len();
    let r0 = p.residuals(u).ok()?;
    let svd = jacobian(p, u, &r0).svd(false, true);
    let v_t = svd.v_t?;
    let half: Vec<f64> = svd
        .singular_values
        .iter()
        .map(|&s| if s > 0.0 { ((2.0 * cost).sqrt() / s).min(NEIGHBOURHOOD_SPAN) } else { NEIGHBOURHOOD_SPAN })
        .collect();
    let along = |z: &[f64]| -> Vec<f64> { (0..n).map(|j| u[j] + (0..z.len()).map(|i| v_t[(i, j)] * z[i]).sum::<f64>()).collect() };
    let mut screen: Vec<Vec<f64>> = halton_unit_points(NEIGHBOURHOOD_POINTS_PER_KEY * n, half.len())
        .map(|h| {
            let z: Vec<f64> = h.iter().zip(&half).map(|(h, s)| s * (2.0 * h - 1.0)).collect();
            along(&z)
        })
        .collect();
    let evaluated: Vec<Option<Vec<f64>>> = screen
        .par_iter()
        .map(|x| {
            let r = p.residuals(x).ok().filter(|r| r.iter().all(|v| v.is_finite()));
            p.note(r.as_ref().map_or(OUTSIDE, |r| cost_of(r)));
            r
        })
        .collect();
    let mut costs: Vec<f64> = evaluated.iter().map(|r| r.as_ref().map_or(OUTSIDE, |r| cost_of(r))).collect();
    if let Some(z) = smoothed_step(&screen, &evaluated, u, &v_t, &half) {
        let x = along(&z);
        let c = p.residuals(&x).map_or(OUTSIDE, |r| cost_of(&r));
        p.note(c);
        eprintln!("fit: the polish's smoothed step: cost {c:.6e} (from {cost:.6e})");
        screen.push(x);
        costs.push(if c.is_finite() { c } else { OUTSIDE });
    }
    let best = (0..screen.len()).min_by(|&a, &b| costs[a].total_cmp(&costs[b]))?;
    (costs[best] < cost).then(|| screen[best].clone())
}

/// The Gauss-Newton step of the residuals' linear trend over the screen's points `xs` (their
/// residuals `rs`; see [`neighbourhood_best`]), from `u`, in the singular coordinates `v_t`,
/// each at most twice `half`. `None` when fewer points than twice the unknowns evaluated.
fn smoothed_step(xs: &[Vec<f64>], rs: &[Option<Vec<f64>>], u: &[f64], v_t: &DMatrix<f64>, half: &[f64]) -> Option<Vec<f64>> {
    let n = u.len();
    let ok: Vec<usize> = (0..xs.len()).filter(|&i| rs[i].is_some()).collect();
    if ok.len() < 2 * (n + 1) {
        return None;
    }
    let m = rs[ok[0]].as_ref()?.len();
    let x = DMatrix::from_fn(ok.len(), n + 1, |a, b| if b == 0 { 1.0 } else { xs[ok[a]][b - 1] - u[b - 1] });
    let y = DMatrix::from_fn(ok.len(), m, |a, b| rs[ok[a]].as_ref().map_or(0.0, |r| r[b]));
    // the regression's coefficients: (n + 1) x m, row 0 the residuals' trend at u
    let coef = x.svd(true, true).solve(&y, 1e-12).ok()?;
    let r_at_u = DVector::from_fn(m, |j, _| coef[(0, j)]);
    let jac = DMatrix::from_fn(m, n, |j, k| coef[(k + 1, j)]);
    let du = jac.svd(true, true).solve(&(-r_at_u), 1e-10).ok()?;
    let z: Vec<f64> = (0..n)
        .map(|i| {
            let zi: f64 = (0..n).map(|j| v_t[(i, j)] * du[j]).sum();
            zi.clamp(-2.0 * half[i], 2.0 * half[i])
        })
        .collect();
    z.iter().all(|v| v.is_finite()).then_some(z)
}
