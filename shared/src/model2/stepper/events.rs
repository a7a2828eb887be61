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
