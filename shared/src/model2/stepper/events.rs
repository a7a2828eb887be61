//! Event location: the guards of each regime as rows, their rates, binary lifting on the
//! dyadic grid to the last unit where a guard holds, crests found from the rate's sign
//! change, and what a slip that reaches v = 0 turns into (entry to stick).

use super::*;

impl<T: Real, C: Composition> Model2Tables<T, C> {
    /// The guards of `regime` as rows (fire at row . z >= 0): stick, F_req -+ mu_s N; slip
    /// slower, v; slip faster, -v.
    #[inline(always)]
    pub(super) fn guard(&self, regime: Regime, which: usize) -> &[T; NA] {
        &self.guards[guard_slot(regime, which)]
    }

    pub(super) fn guard_count(regime: Regime) -> usize {
        if regime == Regime::Stick {
            2
        } else {
            1
        }
    }

    /// The rate of guard `which` at `z` (row . z'), with the falling part `ex` at `z` in
    /// Stribeck slip.
    #[inline(always)]
    pub(super) fn guard_slope(&self, regime: Regime, which: usize, z: &[T; NS], ex: Option<&Excess<T>>) -> T {
        let k = guard_slot(regime, which);
        let lin = dot::<T, C>(&self.guard_rate[k], z);
        match ex {
            Some(ex) if Self::is_stribeck_slip(regime) => {
                lin + self.guard_rate_b[k] * self.q_of(T::from_f64(regime.friction_sign()), ex)
            }
            _ => lin,
        }
    }

    /// Whether guard `which` of `regime` may crest inside a chunk from z (rate `s0`) to z1
    /// (rate `s1`), where it holds at both ends (`g0`, `g1` < 0): its rate falls from
    /// positive to negative, and in a linear regime the bound [`Self::crest_below`] does not
    /// clear it. The short path and `crossing` both ask this, so they decide alike.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)] // a chunk's two ends and what is known at them
    pub(super) fn may_crest(&self, regime: Regime, which: usize, z: &[T; NS], g0: T, g1: T, s0: T, s1: T) -> bool {
        s0 > T::zero() && s1 < T::zero() && !self.crest_below(regime, which, z, g0, g1, s0, s1)
    }

    /// Whether guard `which` of a linear regime certainly stays below zero over a chunk of at
    /// most a substep from z, so that the crest's lift (`crossing`) would find it below at its
    /// crest and return nothing: with g0, g1 < 0 its values and s0 > 0 > s1 its rates at the
    /// ends, the cubic Hermite interpolant of the four is at most
    /// max(g0, g1) + (4/27) h (s0 - s1) (its basis functions: h00 + h01 = 1, 0 <= h10 <= 4/27,
    /// -4/27 <= h11 <= 0), the guard exceeds it by at most h^4 / 384 sup |g''''|, and the lift's
    /// states and row products carry round-off: the last two bounded by sum_c w_c |(z, 1)_c|
    /// (`crest_weights`). Never true in Stribeck slip (nonlinear) or for NaN.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)] // a chunk's two ends and what is known at them
    pub(super) fn crest_below(&self, regime: Regime, which: usize, z: &[T; NS], g0: T, g1: T, s0: T, s1: T) -> bool {
        if Self::is_stribeck_slip(regime) {
            return false;
        }
        let w = &self.crest_w[guard_slot(regime, which)];
        let n = C::ROWS;
        let mut m = w[ONE];
        for c in 0..n {
            m += w[c] * z[c].abs();
        }
        let top = if g1 > g0 { g1 } else { g0 };
        (top + self.crest_c1 * (s0 - s1)) + m < T::zero()
    }

    /// Binary lifting over [from, to): the last probed point p such that `holds` is true at
    /// every accepted point, starting from chunks of 2^top units. Never evaluated at `from`.
    /// `ex0`: the falling part at z in Stribeck slip, when known. In Stribeck slip the falling
    /// part at the current point is computed once and kept while the point stays (each level's
    /// chunk starts from it): the same values as [`Self::chunk`], one exponential fewer at
    /// each level that starts where the level before did (about half of them).
    #[allow(clippy::too_many_arguments)] // the interval, its start and what is known there
    pub(super) fn lift(
        &self,
        regime: Regime,
        z: &[T; NS],
        ex0: Option<&Excess<T>>,
        from: u64,
        to: u64,
        top: usize,
        mut holds: impl FnMut(&[T; NS]) -> bool,
    ) -> (u64, [T; NS]) {
        let mut pos = from;
        let mut cur = *z;
        let lo = Self::min_level(regime);
        let mut j = top;
        let mut ex = if Self::is_stribeck_slip(regime) { ex0.copied() } else { None };
        loop {
            let step = 1u64 << j;
            if pos + step < to {
                let cand = self.lift_chunk(regime, j, &cur, &mut ex);
                if holds(&cand) {
                    pos += step;
                    cur = cand;
                    ex = None;
                }
            }
            if j <= lo {
                break;
            }
            j -= 1;
        }
        (pos, cur)
    }

    /// One chunk of [`Self::lift`] from `cur`: [`Self::chunk`], with the falling part at `cur`
    /// (Stribeck slip) kept in `ex` for the next levels from the same point. Out of line: one
    /// copy serves every lift.
    #[inline(never)]
    fn lift_chunk(&self, regime: Regime, j: usize, cur: &[T; NS], ex: &mut Option<Excess<T>>) -> [T; NS] {
        if Self::is_stribeck_slip(regime) {
            let e = match *ex {
                Some(e) => e,
                None => self.excess(cur),
            };
            *ex = Some(e);
            self.chunk_from(regime, j, cur, &e)
        } else {
            self.chunk(regime, j, cur)
        }
    }

    /// Where guard `which` of `regime` first fires inside the chunk [pos, pos + 2^j] from z to
    /// z1: the last unit p where it still holds and the state there. Finds a crest (a guard
    /// that rises above zero and falls back inside the chunk) from its rate's sign change;
    /// `ex0`, `ex1`: the falling parts at z and z1 in Stribeck slip.
    #[allow(clippy::too_many_arguments)] // a chunk's two ends and what is known at them
    pub(super) fn crossing(
        &self,
        regime: Regime,
        which: usize,
        z: &[T; NS],
        pos: u64,
        j: usize,
        z1: &[T; NS],
        ex0: Option<&Excess<T>>,
        ex1: Option<&Excess<T>>,
    ) -> Option<(u64, [T; NS])> {
        let g = *self.guard(regime, which);
        let end = pos + (1u64 << j);
        let lo = Self::min_level(regime);
        if !(dot::<T, C>(&g, z1) < T::zero()) {
            return Some(self.lift(regime, z, ex0, pos, end, j, |c| dot::<T, C>(&g, c) < T::zero()));
        }
        if j <= lo {
            return None;
        }
        let (s0, s1) = (self.guard_slope(regime, which, z, ex0), self.guard_slope(regime, which, z1, ex1));
        if !self.may_crest(regime, which, z, dot::<T, C>(&g, z), dot::<T, C>(&g, z1), s0, s1) {
            return None;
        }
        // the crest: the last point where the guard still rises
        let slope = |c: &[T; NS]| -> T {
            if Self::is_stribeck_slip(regime) {
                self.guard_slope(regime, which, c, Some(&self.excess(c)))
            } else {
                self.guard_slope(regime, which, c, None)
            }
        };
        let (pc, zc) = self.lift(regime, z, ex0, pos, end, j, |c| slope(c) > T::zero());
        let after = self.chunk(regime, lo, &zc);
        let top = if dot::<T, C>(&g, &zc) < T::zero() && dot::<T, C>(&g, &after) < T::zero() {
            return None;
        } else {
            pc + (1u64 << lo)
        };
        Some(self.lift(regime, z, ex0, pos, top, j, |c| dot::<T, C>(&g, c) < T::zero()))
    }

    /// [`Self::crossing`] of a guard that fires at the chunk's end, for an observer whose
    /// [`Model2Observer::LOCATE_BELOW_LEVEL`] is `stop` > 0: lifted as `crossing` lifts down to
    /// level `stop`, then located on the guard's quadratic Taylor polynomial from the last point
    /// p where it holds (`quadratic_step`: at most 2^stop - 1 units; for f64 and stop = 44,
    /// 2^-9 of a substep, whose third-order term is far below the tolerance a map's statistics
    /// are held to). Where that step is not clean (a rate <= 0, or the guard not holding at
    /// the point it gives), the lift goes on to the last level as `crossing`'s does.
    #[allow(clippy::too_many_arguments)] // a chunk's start and what is known there
    pub(super) fn located_crossing(&self, regime: Regime, which: usize, z: &[T; NS], ex0: Option<&Excess<T>>, pos: u64, j: usize, stop: usize) -> (u64, [T; NS]) {
        let g = *self.guard(regime, which);
        let end = pos + (1u64 << j);
        let lo = Self::min_level(regime);
        // (a chunk at or below `stop` is lifted to the last level)
        let stop = if j > stop.max(lo) { stop.max(lo) } else { lo };
        let mut p = pos;
        let mut cur = *z;
        let mut ex = if Self::is_stribeck_slip(regime) { ex0.copied() } else { None };
        let mut level = j;
        let lift_to = |p: &mut u64, cur: &mut [T; NS], ex: &mut Option<Excess<T>>, level: &mut usize, last: usize| loop {
            let step = 1u64 << *level;
            if *p + step < end {
                let cand = self.lift_chunk(regime, *level, cur, ex);
                if dot::<T, C>(&g, &cand) < T::zero() {
                    *p += step;
                    *cur = cand;
                    *ex = None;
                }
            }
            if *level <= last {
                break;
            }
            *level -= 1;
        };
        lift_to(&mut p, &mut cur, &mut ex, &mut level, stop);
        if stop > lo {
            let exc = if Self::is_stribeck_slip(regime) { Some(ex.unwrap_or_else(|| self.excess(&cur))) } else { None };
            if let Some((d, zp)) = self.quadratic_step(regime, &g, &cur, exc.as_ref(), ((1u64 << stop) - 1).min(end - p - 1)) {
                return (p + d, zp);
            }
            level -= 1;
            lift_to(&mut p, &mut cur, &mut ex, &mut level, lo);
        }
        (p, cur)
    }

    /// The located step of [`Self::located_crossing`] from `cur` (where guard `g` holds, with
    /// the falling part `ex` in Stribeck slip): z' and z'' there (z'' = A z' + b q', q' from
    /// the rates of v and N), the guard's quadratic g0 + g1 t + g2 t^2 / 2, its first root t
    /// (the stable form 2 (-g0) / (g1 + sqrt(g1^2 - 2 g0 g2))) less the time its round-off spans
    /// (64 ulps of its terms over its rate), the last whole unit d before that (at most `span`),
    /// and the state cur + d z' + d^2 z'' / 2 there, where the guard must still hold.
    /// `None` where any of that fails (the lift then goes on).
    /// A row's rate along `x` (its terms without the constant): row . (x, 0).
    #[inline(always)]
    fn rate_along(r: &[T; NA], x: &[T; NS]) -> T {
        let mut acc = T::zero();
        for c in 0..C::ROWS {
            acc = acc + r[c] * x[c];
        }
        acc
    }

    /// The Stribeck forcing's rate q' from the falling part `ex` at a point and the rates of v
    /// and N there (`vd`, `nd`): q = sigma d_mu e N with e = exp(-y^delta), y = |v| / v_s, so
    /// q' = sigma d_mu (e' N + e N'), e' = -e delta y^(delta - 1) y'.
    #[inline(always)]
    pub(super) fn forcing_rate(&self, sigma: T, ex: &Excess<T>, vd: T, nd: T) -> T {
        let dy = if ex.v > T::zero() { vd } else { T::zero() - vd } * self.inv_v_s;
        let de = if self.delta_is_one { T::zero() - ex.e * dy } else { T::zero() - ex.e * self.delta * ex.y.powf(self.delta - T::one()) * dy };
        sigma * self.d_mu * (de * ex.n + ex.e * nd)
    }

    /// z' and z'' at `z` in `regime` (z'' = A z' + b q', q' from the rates of v and N and the
    /// falling part `ex` in Stribeck slip): the quadratic Taylor polynomial of the motion.
    fn taylor2(&self, regime: Regime, z: &[T; NS], ex: Option<&Excess<T>>) -> ([T; NS], [T; NS]) {
        let zd = self.derivative(regime, z);
        let a = &self.a[regime.index()];
        let mut zdd: [T; NS] = core::array::from_fn(|r| if r < C::ROWS { Self::rate_along(&a[r], &zd) } else { T::zero() });
        if let Some(ex) = ex {
            let (vd, nd) = (Self::rate_along(&self.r_v, &zd), Self::rate_along(&self.r_n, &zd));
            let qd = self.forcing_rate(T::from_f64(regime.friction_sign()), ex, vd, nd);
            for (r, v) in zdd.iter_mut().enumerate().take(C::ROWS) {
                *v = *v + self.b[r] * qd;
            }
        }
        (zd, zdd)
    }

    /// The last `rem` units of a substep from `z` in one step of the quadratic Taylor
    /// polynomial ([`Self::taylor2`]), for an observer whose
    /// [`Model2Observer::LOCATE_BELOW_LEVEL`] is above 0 and `rem` below 2^that: where every
    /// guard the general loop would test (`touched` aside; an unarmed slip's guard only where
    /// it would be tested) stays below zero over the step by its bound
    /// g0 + |g1| t + |g2| t^2 / 2 < 0, so that none fires or crests in it. Arms an unarmed slip
    /// as the loop would. `None`: the loop's dyadic chunks take the units.
    pub(super) fn taylor_tail(&self, s: &mut Model2State<T>, regime: Regime, z: &[T; NS], ex: Option<&Excess<T>>, rem: u64, touched: Option<(Regime, usize)>) -> Option<[T; NS]> {
        let (zd, zdd) = self.taylor2(regime, z, ex);
        let t = units_t::<T>(rem) * self.hu_t;
        let half = T::from_f64(0.5) * t * t;
        let z1: [T; NS] = core::array::from_fn(|r| if r < C::ROWS { z[r] + (t * zd[r] + half * zdd[r]) } else { z[r] });
        let unarmed = regime != Regime::Stick && !s.armed;
        for which in 0..Self::guard_count(regime) {
            let g = self.guard(regime, which);
            if touched == Some((regime, which)) || (unarmed && !(dot::<T, C>(self.guard(regime, 0), &z1) > self.v_round)) {
                continue;
            }
            let bound = dot::<T, C>(g, z) + t * Self::rate_along(g, &zd).abs() + half * Self::rate_along(g, &zdd).abs();
            if !(bound < T::zero()) || !(dot::<T, C>(g, &z1) < T::zero()) {
                return None;
            }
        }
        if unarmed && dot::<T, C>(self.guard(regime, 0), &z1) < -self.v_round {
            s.armed = true;
        }
        Some(z1)
    }

    fn quadratic_step(&self, regime: Regime, g: &[T; NA], cur: &[T; NS], ex: Option<&Excess<T>>, span: u64) -> Option<(u64, [T; NS])> {
        let (zd, zdd) = self.taylor2(regime, cur, ex);
        let g0 = dot::<T, C>(g, cur).to_f64();
        let g1 = Self::rate_along(g, &zd).to_f64();
        let g2 = Self::rate_along(g, &zdd).to_f64();
        let disc = g1 * g1 - 2.0 * g0 * g2;
        if !(g0 < 0.0 && g1 > 0.0 && disc >= 0.0) {
            return None;
        }
        // the root, less the time the guard's round-off at cur spans (64 ulps of its terms), so
        // that the guard still holds where the step lands
        let noise: f64 = (0..C::ROWS).map(|c| libm::fabs(g[c].to_f64() * cur[c].to_f64())).sum::<f64>() + libm::fabs(g[ONE].to_f64());
        let t = 2.0 * (-g0) / (g1 + libm::sqrt(disc)) - 64.0 * f64::EPSILON * noise / g1;
        let units = t / self.hu_t.to_f64();
        if !(units >= 0.0 && units.is_finite()) {
            return None;
        }
        let d = (libm::floor(units) as u64).min(span);
        let h = units_t::<T>(d) * self.hu_t;
        let half = T::from_f64(0.5) * h * h;
        let zp: [T; NS] = core::array::from_fn(|r| if r < C::ROWS { cur[r] + (h * zd[r] + half * zdd[r]) } else { cur[r] });
        (dot::<T, C>(g, &zp) < T::zero()).then_some((d, zp))
    }

    /// Sets the sliding velocity to zero on entry to stick: x' = V without the band; with it,
    /// pad and band take their common momentum velocity. With the face: the friction impulse
    /// p that stops the face, -v / (r_v . b), moves phi' (and u') by b p, and x' then takes
    /// the constraint's value exactly, x' = V + u' - s w phi' (with w = 0 and no band this is
    /// x' = V, as without the face).
    pub(super) fn enter_stick(&self, z: &mut [T; NS]) {
        if C::FACE {
            let s_w = self.r_v[3];
            let mut inv_mass = self.b[1] + s_w * self.b[3];
            if C::BAND {
                inv_mass = inv_mass - self.b[5];
            }
            let p = -self.sliding_velocity(z) / inv_mass;
            z[3] = z[3] + self.b[3] * p;
            if C::FLOAT {
                z[Y + 1] = z[Y + 1] + self.b[Y + 1] * p;
            }
            if C::BAND {
                z[5] = z[5] + self.b[5] * p;
                z[1] = (self.v + z[5]) - s_w * z[3];
            } else {
                z[1] = self.v - s_w * z[3];
            }
        } else if C::BAND {
            let xb = self.v + z[5];
            let common = (self.m * z[1] + self.m_b * xb) / (self.m + self.m_b);
            z[1] = common;
            z[5] = common - self.v;
        } else {
            z[1] = self.v;
        }
    }

    /// The regime after a slip reached v = 0 at `z`.
    pub(super) fn after_velocity_match(&self, z: &[T; NS]) -> Regime {
        let mut zs = *z;
        self.enter_stick(&mut zs);
        let f_req = dot::<T, C>(&self.r_freq, &zs);
        let limit = self.mu_s * self.normal_force(&zs);
        if f_req > limit {
            Regime::SlipSlower
        } else if -f_req > limit {
            Regime::SlipFaster
        } else {
            Regime::Stick
        }
    }
}
