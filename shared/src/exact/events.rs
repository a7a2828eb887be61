//! Event location of the exact stepper: the guards' rates, the crest tests (rate sign change,
//! tangent bound) and the crest's location, and the resolution of a substep with a fired
//! guard (binary lifting to the first unit where it holds, the next regime, the stick anchor).

use super::*;

impl<T: Real> ExactTables<T> {
    /// The time derivative of guard `which` of `regime` at `z`: g'(z) = c . A [z; 1], itself
    /// linear in z. Stick: d/dt (+-F_req - mu_s N) = +-k_g V - mu_s c_N phi' (x' = V, x'' = 0;
    /// without rotation the constant +-k_g V: no crest). Slip: +-x''.
    #[inline(always)]
    fn guard_rate(&self, regime: Regime, which: usize, z: &[T; 4]) -> T {
        match regime {
            Regime::Stick => {
                let m = if self.rotation { self.fast.mu_s_c_n * z[3] } else { T::zero() };
                if which == 0 {
                    self.fast.k_g_v - m
                } else {
                    -self.fast.k_g_v - m
                }
            }
            Regime::SlipSlower => self.prop.accelerations(regime, z).0,
            Regime::SlipFaster => -self.prop.accelerations(regime, z).0,
        }
    }

    /// Whether a guard of `regime` may have a crest at or above zero inside the segment from
    /// `z0` to `z1` (the fast path's crest test; see [`Self::crest_suspect`]).
    #[inline(always)]
    pub(super) fn crest_possible(&self, regime: Regime, z0: &[T; 4], z1: &[T; 4]) -> bool {
        match regime {
            Regime::Stick => {
                self.rotation
                    && (self.crest_suspect(regime, 0, &self.guards.stick_behind, z0, z1)
                        || self.crest_suspect(regime, 1, &self.guards.stick_ahead, z0, z1))
            }
            Regime::SlipSlower => self.crest_suspect(regime, 0, &self.guards.slower_caught_up, z0, z1),
            Regime::SlipFaster => self.crest_suspect(regime, 0, &self.guards.faster_caught_up, z0, z1),
        }
    }

    /// Whether guard `which` (`g`) of `regime`, below zero at both ends of the segment from
    /// `z0` to `z1` (at most a substep), may have a crest at or above zero inside it.
    ///
    /// 1. Its rate must go from > 0 to < 0 (the quarter-radian substep holds at most one
    ///    extremum of a guard). Stick: m = mu_s c_N phi' crossing +-k_g V upward. This is the
    ///    common exit, a few instructions.
    /// 2. A guard at (or above) zero where the segment starts is one the regime was just
    ///    entered on (or one at its own boundary): it is not taken for a new crossing here, as
    ///    the lifting never tests the start; a real departure is seen at the end of the
    ///    substep. Without this, mu_k = mu_s (the slip guard leaves zero with a rate that is
    ///    zero up to round-off) would storm between stick and slip.
    /// 3. Tangent bound: where the guard is concave over the segment (g'' <= 0 at both ends,
    ///    so everywhere: one sign change at most per substep), g' <= d0 before the crest and
    ///    g' >= d1 after it, so the crest lies below both end tangents, below their
    ///    intersection (g0 |d1| + g1 d0 + d0 |d1| tau) / (d0 + |d1|), tau the segment's length
    ///    (taken as the substep's: the bound only grows with tau). If that is below zero, no.
    #[inline(always)]
    fn crest_suspect(&self, regime: Regime, which: usize, g: &Guard<T>, z0: &[T; 4], z1: &[T; 4]) -> bool {
        let zero = T::zero();
        let d0 = self.guard_rate(regime, which, z0);
        let d1 = self.guard_rate(regime, which, z1);
        if !(d0 > zero && d1 < zero) {
            return false;
        }
        self.crest_not_excluded(regime, which, g, z0, z1, d0, -d1)
    }

    /// Steps 2 and 3 of [`Self::crest_suspect`] (kept out of line: rarely reached).
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn crest_not_excluded(
        &self,
        regime: Regime,
        which: usize,
        g: &Guard<T>,
        z0: &[T; 4],
        z1: &[T; 4],
        d0: T,
        d1: T,
    ) -> bool {
        let zero = T::zero();
        let g0 = g.value(z0);
        if !(g0 < zero) {
            return false;
        }
        let k = &self.curv[regime.index()][which];
        let curv = |c: &[T; 4]| k[0] * c[0] + k[1] * c[1] + k[2] * c[2] + k[3] * c[3] + k[4];
        if !(curv(z0) > zero) && !(curv(z1) > zero) && g0 * d1 + g.value(z1) * d0 + d0 * d1 * self.h_sub_t < zero {
            return false;
        }
        true
    }

    /// The first unit p in (from, units) after which guard `which` of `regime` has fired, with
    /// the state at p, when the guard did not fire at the end of the substep (`z_end`) but
    /// may have a crest inside ([`Self::crest_suspect`]): the zero of its rate is found by
    /// binary lifting, the guard is tested at the two units around it, and if it fired there
    /// the first crossing is found by lifting over [from, crest], where it rises.
    #[inline(never)]
    fn crest_crossing(
        &self,
        regime: Regime,
        which: usize,
        g: &Guard<T>,
        z: &[T; 4],
        z_end: &[T; 4],
        from: u64,
    ) -> Option<(u64, [T; 4])> {
        let units = Propagator::<T>::UNITS;
        let zero = T::zero();
        if !self.crest_suspect(regime, which, g, z, z_end) {
            return None;
        }
        // last unit where the rate is still > 0 (never evaluated at `from`)
        let (pc, zc) = self.prop.lift(regime, z, from, units, |c| self.guard_rate(regime, which, c) > zero);
        let to = if pc > from && g.fired(&zc) {
            pc + 1
        } else if pc + 1 < units && g.fired(&apply(self.prop.flow(regime, 0), &zc)) {
            pc + 2
        } else {
            return None;
        };
        Some(self.prop.lift(regime, z, from, to, |c| !g.fired(c)))
    }

    /// A substep whose end state has a fired guard: find every transition inside it.
    pub(super) fn resolve<O: Observer<T>>(&self, s: &mut ExactState<T>, sub: u32, z0: [T; 4], z1: [T; 4], obs: &mut O) -> Result<usize, Halt> {
        let units = Propagator::<T>::UNITS;
        let mut pos = 0u64;
        let mut z = z0;
        let mut z_end = z1;
        let mut regime = s.regime;
        let mut entered_stick_at: Option<u64> = None;
        let mut count = 0u32;
        let mut transitions = 0usize;
        // a guard that fired but left the regime unchanged (a slip that touched V_r = 0 and
        // slides on in the same direction) is a touch, not a crossing: it is not tested again
        // in this substep, or a grazing contact would fire it at every unit
        let mut touched: Option<(Regime, usize)> = None;
        loop {
            // earliest fired guard of the current regime
            let (gs, n) = self.guards.of(regime);
            let mut best: Option<(u64, [T; 4], usize)> = None;
            for (which, g) in gs.iter().take(n).enumerate() {
                if touched == Some((regime, which)) {
                    continue;
                }
                let found = if g.fired(&z_end) {
                    Some(self.prop.lift(regime, &z, pos, units, |c| !g.fired(c)))
                } else {
                    // not fired at the end: it may still have poked above zero and come back
                    self.crest_crossing(regime, which, g, &z, &z_end, pos)
                };
                if let Some((p, zp)) = found {
                    if best.is_none_or(|b| p < b.0) {
                        best = Some((p, zp, which));
                    }
                }
            }
            let Some((p, zp, which)) = best else {
                obs.segment(&Segment { regime, step: s.step, sub, p0: pos, p1: units, z0: z, z1: z_end }, &self.prop);
                break;
            };
            let at = p + 1;
            let ze = if at == units { z_end } else { apply(self.prop.flow(regime, 0), &zp) };
            obs.segment(&Segment { regime, step: s.step, sub, p0: pos, p1: at, z0: z, z1: ze }, &self.prop);
            let next = self.guards.next_regime(regime, which, &ze);
            let zn = self.enter(s, next, ze);
            if next == Regime::Stick {
                entered_stick_at = Some(at);
            }
            if next == regime {
                touched = Some((regime, which));
            } else {
                touched = None;
                let tr = Transition { t: self.time_at(s, sub, at), from: regime, to: next, state: State::from_array(zn) };
                obs.transition(&tr);
                Self::report(s, tr);
                transitions += 1;
            }
            count += 1;
            if count > MAX_TRANSITIONS_PER_SUBSTEP {
                let h = Halt::TransitionStorm { t: self.time_at(s, sub, at) };
                s.halted = Some(h);
                return Err(h);
            }
            regime = next;
            pos = at;
            z = zn;
            if pos == units {
                z_end = zn;
                break;
            }
            z_end = self.prop.advance(regime, &z, units - pos);
        }
        // x from the anchor: elapsed = (units - at) units
        let e0 = entered_stick_at.map(|at| T::from_f64((units - at) as f64 / units as f64 * self.prop.h_sub));
        self.end_substep(s, regime, e0, z_end);
        Ok(transitions)
    }

    /// The state entering `next` from `ze`: in stick x' = V, and the stick anchor at its x.
    #[inline(always)]
    pub(super) fn enter(&self, s: &mut ExactState<T>, next: Regime, ze: [T; 4]) -> [T; 4] {
        let mut zn = ze;
        if next == Regime::Stick {
            zn[1] = self.fast.v;
            s.anchor_x = zn[0];
        }
        zn
    }

    /// Keeps `tr` among the step's reported transitions (or counts it dropped).
    #[inline(always)]
    pub(super) fn report(s: &mut ExactState<T>, tr: Transition<T>) {
        if (s.n_reported as usize) < TRANSITIONS_PER_STEP {
            s.reported[s.n_reported as usize] = tr;
            s.n_reported += 1;
        } else {
            s.dropped += 1;
        }
    }

    /// The end of a substep resolved in place: its regime, and in stick x from the anchor
    /// (`entered_e0`: the substep entered stick, that long before its end; else a stick
    /// substep whose guard fired and came back, or a touch: the anchor kept) and x' = V.
    pub(super) fn end_substep(&self, s: &mut ExactState<T>, regime: Regime, entered_e0: Option<T>, mut z_end: [T; 4]) {
        s.regime = regime;
        if regime == Regime::Stick {
            match entered_e0 {
                Some(e0) => {
                    s.anchor_e0 = e0;
                    s.anchor_subs = 0;
                    z_end[0] = s.anchor_x + self.fast.v * s.anchor_e0;
                }
                None => z_end[0] = self.stick_x(s, s.anchor_subs),
            }
            z_end[1] = self.fast.v;
            s.anchor_subs = s.anchor_subs.saturating_add(1);
        }
        s.z = z_end;
    }
}
