//! Profile-likelihood intervals: the cost along one parameter with the others refitted.

use super::*;

/// The problem with free key `fixed` held at `u_fixed`, the others searched by
/// Levenberg-Marquardt (a point of a profile).
pub(super) struct ProfileLm<'a> {
    pub(super) p: &'a Problem,
    pub(super) fixed: usize,
    pub(super) u_fixed: f64,
    /// The other keys' u.
    pub(super) w: DVector<f64>,
    pub(super) r: std::cell::RefCell<Option<Vec<f64>>>,
}

impl ProfileLm<'_> {
    pub(super) fn full(&self, w: &DVector<f64>) -> Vec<f64> {
        let mut u = Vec::with_capacity(w.len() + 1);
        let mut it = w.iter();
        for k in 0..=w.len() {
            u.push(if k == self.fixed { self.u_fixed } else { *it.next().expect("one per other key") });
        }
        u
    }

    pub(super) fn r(&self) -> Vec<f64> {
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
pub(super) fn profile_point(p: &Problem, k: usize, uk: f64, w0: &[f64], max_iters: u64) -> Option<(f64, Vec<f64>)> {
    let f = &p.free[k];
    let (ulo, uhi) = f.u_range();
    if !(uk >= ulo - 1e-12 && uk <= uhi + 1e-12) {
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

/// One key's profile: its 95 % interval (`None` on a side that does not close inside the
/// bounds) and the points evaluated on the way, `(value, delta chi^2)` in the key's unit,
/// sorted by value, the optimum `(value, 0)` among them. Delta chi^2 is the cost's rise over
/// the optimum scaled so that the interval's threshold is [`PROFILE_DCHI2_95`] (a misfit's
/// widened threshold included).
#[derive(Clone, Debug, Default)]
pub struct KeyProfile {
    pub interval: (Option<f64>, Option<f64>),
    pub points: Vec<(f64, f64)>,
}

/// Delta chi^2 of a 95 % interval of one parameter (chi-square, 1 degree of freedom).
pub const PROFILE_DCHI2_95: f64 = 3.841;
/// Largest first step of a profile in ln p (the first step is the Jacobian's standard error
/// below this); it doubles until the threshold is crossed.
pub(super) const PROFILE_STEP: f64 = 0.005;
/// Bisections of the crossing.
pub(super) const PROFILE_BISECTIONS: usize = 5;

/// The 95 % profile-likelihood interval of every free key (Raue et al. 2009): from the
/// optimum `u` (cost `cost`), along each key in both directions, the other keys re-fitted at
/// each point, to where chi^2 has risen by [`PROFILE_DCHI2_95`] x max(1, chi^2 / dof) (the
/// threshold widened by a misfit, as the residual variance widens the Jacobian's errors);
/// `chi2_scale` turns a cost into chi^2. A side where the profile stays below the threshold up
/// to the bound (or to a scene rule) is `None`: not identifiable on that side. Only for the
/// time-domain cost (its evaluations are cheap); empty otherwise. Each key's profile comes
/// with the points it evaluated ([`KeyProfile`]), for the figure and the JSON.
pub fn profile_intervals(
    p: &Problem,
    u: &[f64],
    cost: f64,
    chi2_scale: f64,
    chi2_per_dof: f64,
    first_steps: &[f64],
    max_iters: u64,
) -> Vec<KeyProfile> {
    if !p.time_domain() {
        return Vec::new();
    }
    let t0 = std::time::Instant::now();
    let target = PROFILE_DCHI2_95 * chi2_per_dof.max(1.0) / chi2_scale;
    // a cost above the optimum in units of the threshold's delta chi^2 (3.841 at the threshold)
    let to_dchi2 = |c: f64| (c - cost) * PROFILE_DCHI2_95 / target;
    let n = u.len();
    let out: Vec<KeyProfile> = (0..n)
        .into_par_iter()
        .map(|k| {
            let others = |uu: &[f64]| -> Vec<f64> { (0..n).filter(|j| *j != k).map(|j| uu[j]).collect() };
            let side = |dir: f64, seen: &mut Vec<(f64, f64)>| -> Option<f64> {
                let f = &p.free[k];
                let limit = if dir > 0.0 { f.u_range().1 } else { f.u_range().0 };
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
                    seen.push((f.value(uk), to_dchi2(c)));
                    if c - cost >= target {
                        // bisect between the last point inside and this one
                        let (mut a, mut b) = (inside, uk);
                        for _ in 0..PROFILE_BISECTIONS {
                            let mid = 0.5 * (a + b);
                            let at = profile_point(p, k, mid, &w, max_iters);
                            if let Some((cm, _)) = &at {
                                seen.push((f.value(mid), to_dchi2(*cm)));
                            }
                            match at {
                                Some((cm, wm)) if cm - cost < target => {
                                    a = mid;
                                    w = wm;
                                }
                                _ => b = mid,
                            }
                        }
                        return Some(f.value(0.5 * (a + b)));
                    }
                    if at_bound {
                        return None;
                    }
                    inside = uk;
                    w = w1;
                    h *= 2.0;
                }
            };
            let mut points = vec![(p.free[k].value(u[k]), 0.0)];
            // u rises with the value except on a drop coordinate (value = origin - drop)
            let up = if p.free[k].start > p.free[k].origin { 1.0 } else { -1.0 };
            let lo = side(-up, &mut points);
            let hi = side(up, &mut points);
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            let side = |x: Option<f64>| x.map_or("not closed".to_string(), |v| format!("{v:.6e}"));
            eprintln!(
                "fit: profile of {}: 95 % interval [{}, {}] from {} points, {:.1} s after the profiles' start",
                p.free[k].key,
                side(lo),
                side(hi),
                points.len(),
                t0.elapsed().as_secs_f64()
            );
            KeyProfile { interval: (lo, hi), points }
        })
        .collect();
    eprintln!("fit: profile-likelihood intervals of {n} keys in {:.1} s", t0.elapsed().as_secs_f64());
    out
}
