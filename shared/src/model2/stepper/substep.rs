//! The step: its substeps, each on the short path (one quiet chunk, compiled apart for stick
//! and slip) or the general loop (chunks tested for transitions until the substep's end), the
//! stick anchor and the segments and transitions the observer sees.

use super::*;

impl<T: Real, C: Composition> Model2Tables<T, C> {
    /// Whether the short path inlines its linear chunk ([`Self::linear_chunk`]) rather than
    /// calling [`Self::chunk`]: in f64 (on the host, the call returned the state through memory
    /// and cost more than the flow's code), not in f32 (there the inlined flow took more
    /// instructions per step than the call: the host's stribeck+float+face/f32).
    const INLINE_LINEAR_CHUNK: bool = T::DYADIC_LEVELS > 24;

    pub(super) fn time_at(&self, s: &Model2State<T>, sub: u32, unit: u64) -> f64 {
        s.step as f64 * self.dt + (sub as f64 + unit as f64 / Self::UNITS as f64) * self.h_sub
    }

    #[allow(clippy::too_many_arguments)] // a segment's regime, place and two ends
    pub(super) fn emit<O: Model2Observer<T>>(&self, s: &Model2State<T>, obs: &mut O, regime: Regime, sub: u32, p0: u64, p1: u64, z0: [T; NS], z1: [T; NS]) {
        let (zd0, zd1) = if O::DERIVATIVES {
            (self.derivative(regime, &z0), self.derivative(regime, &z1))
        } else {
            ([T::zero(); NS], [T::zero(); NS])
        };
        obs.segment(&Model2Segment { regime, t0: self.time_at(s, sub, p0), t1: self.time_at(s, sub, p1), z0, z1, zd0, zd1 });
    }

    /// One step of `dt` of the run in `s` (its state: what a step writes); `obs` sees every
    /// segment and transition. Returns the number of transitions in the step.
    pub fn step<O: Model2Observer<T>>(&self, s: &mut Model2State<T>, obs: &mut O) -> Result<usize, Halt> {
        if let Some(h) = s.halted {
            return Err(h);
        }
        let mut count = 0;
        for sub in 0..self.n_sub {
            match self.one_substep(s, sub, obs) {
                Ok(n) => count += n,
                Err(h) => {
                    s.halted = Some(h);
                    return Err(h);
                }
            }
        }
        s.step += 1;
        Ok(count)
    }

    /// One substep of [`Self::step`]: the short path where the regime has one, else (or where
    /// it hands its first chunk on) the general one. Out of line: inlined into the step's loop,
    /// its table reads were hoisted out of that loop and spilled to the stack, a hundred and
    /// more loads and stores per step for a loop that mostly runs once (one substep per step).
    #[inline(never)]
    fn one_substep<O: Model2Observer<T>>(&self, s: &mut Model2State<T>, sub: u32, obs: &mut O) -> Result<usize, Halt> {
        let first = if s.regime == Regime::Stick {
            self.short_substep::<false, O>(s, sub, obs)?
        } else if s.armed {
            self.short_substep::<true, O>(s, sub, obs)?
        } else {
            return self.substep(s, sub, obs, None);
        };
        match first {
            None => Ok(0),
            Some(first) => self.substep(s, sub, obs, Some(first)),
        }
    }

    /// [`Self::step`] with every substep on the general path (`substep`), never the
    /// short one (`short_substep`): for the test that the two agree bit for bit.
    #[doc(hidden)]
    pub fn step_general<O: Model2Observer<T>>(&self, s: &mut Model2State<T>, obs: &mut O) -> Result<usize, Halt> {
        if let Some(h) = s.halted {
            return Err(h);
        }
        let mut count = 0;
        for sub in 0..self.n_sub {
            match self.substep(s, sub, obs, None) {
                Ok(n) => count += n,
                Err(h) => {
                    s.halted = Some(h);
                    return Err(h);
                }
            }
        }
        s.step += 1;
        Ok(count)
    }

    /// The common substep on a short path: its first chunk (see [`Self::substep`]), and if
    /// that is the whole substep and no guard of the regime fires or crests inside it, the
    /// substep done (`Ok(None)`), exactly as `substep` would do it. Otherwise the chunk is
    /// handed to `substep` (`Ok(Some(..))`), which goes on from it. Not for a slip whose guard
    /// is not armed yet (`substep` handles the arming). `SLIP`: whether the regime is a slip
    /// (compiled apart for stick and slip: each has its own short path).
    #[inline(always)]
    pub(super) fn short_substep<const SLIP: bool, O: Model2Observer<T>>(&self, s: &mut Model2State<T>, sub: u32, obs: &mut O) -> Result<Option<FirstChunk<T>>, Halt> {
        let units = Self::UNITS;
        let regime = s.regime;
        let stribeck_slip = C::STRIBECK && SLIP;
        let z = s.z;
        let ex0 = if stribeck_slip {
            Some(match s.head {
                Some(ex) => ex,
                None => self.excess(&z),
            })
        } else {
            None
        };
        let (j, k) = self.chunk_level(ex0.as_ref(), units);
        let mut z1 = match &ex0 {
            Some(ex0) => self.chunk_with(regime, j, &z, ex0, k),
            // no falling part: a linear regime (stick; Coulomb slip). Inlined in f64 only
            // (`INLINE_LINEAR_CHUNK`).
            None if Self::INLINE_LINEAR_CHUNK => self.linear_chunk(regime, j, &z),
            None => self.chunk(regime, j, &z),
        };
        let ex1 = if stribeck_slip { Some(self.excess(&z1)) } else { None };
        let first = FirstChunk { ex0, j, z1, ex1 };
        if j != Self::LEVELS {
            return Ok(Some(first));
        }
        for which in 0..if SLIP { 1 } else { 2 } {
            // `crossing`'s tests: the guard still holds at z1 and does not crest in the chunk
            let g = self.guard(regime, which);
            let g1 = dot::<T, C>(g, &z1);
            if !(g1 < T::zero()) {
                return Ok(Some(first));
            }
            let (s0, s1) = (self.guard_slope(regime, which, &z, ex0.as_ref()), self.guard_slope(regime, which, &z1, ex1.as_ref()));
            if self.may_crest(regime, which, &z, dot::<T, C>(g, &z), g1, s0, s1) {
                return Ok(Some(first));
            }
        }
        self.anchor_stick_x(s, regime, &mut z1, units);
        self.emit(s, obs, regime, sub, 0, units, z, z1);
        if let Err(h) = self.check(s, &z1, regime, sub, units) {
            s.head = None;
            return Err(h);
        }
        s.z = z1;
        s.head = ex1;
        s.subs_done += 1;
        Ok(None)
    }

    /// One substep: chunks, each tested for transitions, until the substep's end. `first`:
    /// the first chunk, when [`Self::short_substep`] has taken it already.
    pub(super) fn substep<O: Model2Observer<T>>(&self, s: &mut Model2State<T>, sub: u32, obs: &mut O, mut first: Option<FirstChunk<T>>) -> Result<usize, Halt> {
        let units = Self::UNITS;
        let mut pos = 0u64;
        let mut z = s.z;
        let mut regime = s.regime;
        // the falling part at z (Stribeck slip), when known
        let mut head = s.head.take();
        let mut transitions = 0usize;
        let mut events = 0u32;
        let mut touched: Option<(Regime, usize)> = None;
        while pos < units {
            let stribeck_slip = Self::is_stribeck_slip(regime);
            // at event speed, the substep's last units below 2^LOCATE_BELOW_LEVEL in one step of
            // the quadratic Taylor polynomial where no guard can fire in them (`taylor_tail`)
            if O::LOCATE_BELOW_LEVEL > 0 && first.is_none() && units - pos < (1u64 << O::LOCATE_BELOW_LEVEL) {
                let ex0 = if stribeck_slip { Some(head.unwrap_or_else(|| self.excess(&z))) } else { None };
                if let Some(mut z1) = self.taylor_tail(s, regime, &z, ex0.as_ref(), units - pos, touched) {
                    self.anchor_stick_x(s, regime, &mut z1, units);
                    self.emit(s, obs, regime, sub, pos, units, z, z1);
                    pos = units;
                    z = z1;
                    head = None;
                    self.check(s, &z, regime, sub, pos)?;
                    continue;
                }
            }
            let (ex0, j, z1, ex1) = match first.take() {
                Some(f) => (f.ex0, f.j, f.z1, f.ex1),
                None => {
                    let ex0 = if stribeck_slip { Some(head.unwrap_or_else(|| self.excess(&z))) } else { None };
                    let (j, k) = self.chunk_level(ex0.as_ref(), units - pos);
                    let z1 = match &ex0 {
                        Some(ex0) => self.chunk_with(regime, j, &z, ex0, k),
                        None => self.chunk(regime, j, &z),
                    };
                    let ex1 = if stribeck_slip { Some(self.excess(&z1)) } else { None };
                    (ex0, j, z1, ex1)
                }
            };
            let mut best: Option<(u64, [T; NS], usize)> = None;
            // A slip starts at v = 0 (with Stribeck friction also at v' = 0): its guard is armed
            // once v has left zero by more than round-off in the slip's own direction. Until
            // then only a departure beyond round-off to the other side counts as a crossing.
            let unarmed = regime != Regime::Stick && !s.armed;
            for which in 0..Self::guard_count(regime) {
                if touched == Some((regime, which)) {
                    continue;
                }
                if unarmed && !(dot::<T, C>(self.guard(regime, 0), &z1) > self.v_round) {
                    continue;
                }
                let located = if O::LOCATE_BELOW_LEVEL > 0 && !(dot::<T, C>(self.guard(regime, which), &z1) < T::zero()) {
                    Some(self.located_crossing(regime, which, &z, ex0.as_ref(), pos, j, O::LOCATE_BELOW_LEVEL))
                } else {
                    self.crossing(regime, which, &z, pos, j, &z1, ex0.as_ref(), ex1.as_ref())
                };
                if let Some((p, zp)) = located {
                    if best.is_none_or(|b| p < b.0) {
                        best = Some((p, zp, which));
                    }
                }
            }
            let Some((p, zp, which)) = best else {
                if unarmed && dot::<T, C>(self.guard(regime, 0), &z1) < -self.v_round {
                    s.armed = true;
                }
                let mut z1 = z1;
                self.anchor_stick_x(s, regime, &mut z1, pos + (1u64 << j));
                self.emit(s, obs, regime, sub, pos, pos + (1u64 << j), z, z1);
                pos += 1u64 << j;
                z = z1;
                head = ex1;
                self.check(s, &z, regime, sub, pos)?;
                continue;
            };
            let lo = Self::min_level(regime);
            let at = (p + (1u64 << lo)).min(pos + (1u64 << j));
            let mut ze = if at == pos + (1u64 << j) { z1 } else { self.chunk(regime, lo, &zp) };
            self.anchor_stick_x(s, regime, &mut ze, at);
            self.emit(s, obs, regime, sub, pos, at, z, ze);
            let next = match regime {
                Regime::Stick => {
                    if which == 0 {
                        Regime::SlipSlower
                    } else {
                        Regime::SlipFaster
                    }
                }
                _ => self.after_velocity_match(&ze),
            };
            let mut zn = ze;
            if next == Regime::Stick {
                self.enter_stick(&mut zn);
                s.anchor_x = self.face_position(&zn);
                s.anchor_sub = s.subs_done;
                s.anchor_unit = units_t(at);
            }
            if next == regime {
                touched = Some((regime, which));
            } else {
                touched = None;
                s.armed = false;
                obs.transition(&Model2Transition { t: self.time_at(s, sub, at), from: regime, to: next, z: zn });
                transitions += 1;
                s.transitions += 1;
            }
            events += 1;
            if events > MAX_TRANSITIONS_PER_SUBSTEP {
                return Err(Halt::TransitionStorm { t: self.time_at(s, sub, at) });
            }
            regime = next;
            pos = at;
            z = zn;
            head = None;
            self.check(s, &z, regime, sub, pos)?;
        }
        s.z = z;
        s.regime = regime;
        s.head = head;
        s.subs_done += 1;
        Ok(transitions)
    }

    /// In stick without the band, x from its anchor (see `anchor_x`) at `unit` of the current
    /// substep. With the face it is the face's position x + s w phi that moves at V.
    #[inline(always)]
    pub(super) fn anchor_stick_x(&self, s: &Model2State<T>, regime: Regime, z: &mut [T; NS], unit: u64) {
        if regime == Regime::Stick && (!C::BAND || (C::FLOAT && !self.scene_band)) {
            let d = s.subs_done - s.anchor_sub;
            let d = if d > u32::MAX as u64 { u32::MAX } else { d as u32 };
            let elapsed = T::from_u32(d) * self.h_t + (units_t::<T>(unit) - s.anchor_unit) * self.hu_t;
            z[0] = s.anchor_x + self.v * elapsed;
            if C::FACE {
                z[0] = z[0] - self.r_v[3] * z[2];
            }
        }
    }

    /// The coordinate stick moves at V without the band: x, or with the face x + s w phi.
    #[inline(always)]
    pub(super) fn face_position(&self, z: &[T; NS]) -> T {
        if C::FACE {
            z[0] + self.r_v[3] * z[2]
        } else {
            z[0]
        }
    }
}
