//! The exact stepper's step: the fast path (one whole substep by the regime's exact flow, with
//! its guard and crest tests), the substep loop, and the end-of-substep checks (finite, in
//! range, in contact); a substep with a fired or cresting guard goes to [`super::events`].

use super::*;
use crate::propagator::Flow;

impl<T: Real> ExactTables<T> {
    /// One step of `dt` of the run in `s` (its state: what a step writes), with no observer.
    /// The common step (one substep, no guard fired, the state in range) takes a short path;
    /// anything else goes through [`Self::step_observed`].
    #[inline(always)]
    pub fn step(&self, s: &mut ExactState<T>) -> Result<usize, Halt> {
        if self.prop.n_sub == 1 && s.halted.is_none() {
            let regime = s.regime;
            let z1 = self.fast_substep(s, regime, &s.z);
            if !self.fires(regime, &z1) && !self.crest_possible(regime, &s.z, &z1) && self.limits.in_range(&z1) {
                s.z = z1;
                if regime == Regime::Stick {
                    s.anchor_subs = s.anchor_subs.saturating_add(1);
                }
                s.step += 1;
                s.n_reported = 0;
                return Ok(0);
            }
        }
        self.step_observed(s, &mut ())
    }

    /// One step of `dt` of the run in `s`; `obs` sees every segment and transition. Returns
    /// the number of transitions in the step.
    pub fn step_observed<O: Observer<T>>(&self, s: &mut ExactState<T>, obs: &mut O) -> Result<usize, Halt> {
        if let Some(h) = s.halted {
            return Err(h);
        }
        s.n_reported = 0;
        let mut count = 0usize;
        for sub in 0..self.prop.n_sub {
            let z0 = s.z;
            let regime = s.regime;
            let z1 = self.fast_substep(s, regime, &z0);
            if !self.fires(regime, &z1) && !self.crest_possible(regime, &z0, &z1) {
                obs.segment(
                    &Segment { regime, step: s.step, sub, p0: 0, p1: Propagator::<T>::UNITS, z0, z1 },
                    &self.prop,
                );
                s.z = z1;
                if regime == Regime::Stick {
                    s.anchor_subs = s.anchor_subs.saturating_add(1);
                }
            } else {
                count += self.resolve(s, sub, z0, z1, obs)?;
            }
            if let Err(h) = self.check(s, sub) {
                s.halted = Some(h);
                return Err(h);
            }
        }
        s.step += 1;
        Ok(count)
    }

    /// The exact flow over one whole substep in `regime`, exploiting the regime's structure.
    #[inline(always)]
    pub(super) fn fast_substep(&self, s: &ExactState<T>, regime: Regime, z: &[T; 4]) -> [T; 4] {
        match regime {
            Regime::Stick => {
                let x = self.stick_x(s, s.anchor_subs);
                if self.rotation {
                    let (phi, phid) = stick_rotation(&self.fast.stick_rot, z);
                    [x, self.fast.v, phi, phid]
                } else {
                    [x, self.fast.v, z[2], z[3]]
                }
            }
            _ => slip_flow(self.prop.substep_flow(regime), z, self.rotation),
        }
    }

    /// x in stick after `subs` whole substeps past the entry substep: x = anchor_x + V (e0 +
    /// subs h_sub) (the stick anchor; the state holds x at subs = anchor_subs - 1).
    #[inline(always)]
    pub(super) fn stick_x(&self, s: &ExactState<T>, subs: u32) -> T {
        s.anchor_x + self.fast.v * (s.anchor_e0 + T::from_u32(subs) * self.h_sub_t)
    }

    /// Whether a guard of `regime` has fired at `z` (the fast path's test).
    #[inline(always)]
    pub(super) fn fires(&self, regime: Regime, z: &[T; 4]) -> bool {
        match regime {
            Regime::Stick => {
                let f_req = self.fast.k_g * z[0] + self.fast.c_x_v;
                let limit = if self.rotation { self.fast.mu_s_c_n * z[2] } else { self.fast.mu_s_n0 };
                !(f_req < limit) || !(-f_req < limit)
            }
            Regime::SlipSlower => !(z[1] < self.fast.v),
            Regime::SlipFaster => !(z[1] > self.fast.v),
        }
    }

    pub(super) fn time_at(&self, s: &ExactState<T>, sub: u32, unit: u64) -> f64 {
        let u = Propagator::<T>::UNITS as f64;
        s.step as f64 * self.dt + (sub as f64 + unit as f64 / u) * self.prop.h_sub
    }


    /// End-of-substep checks: finite, in range, in contact.
    #[inline(always)]
    pub(super) fn check(&self, s: &ExactState<T>, sub: u32) -> Result<(), Halt> {
        self.limits.check(&s.z, s.regime, || self.time_at(s, sub, Propagator::<T>::UNITS))
    }
}

/// `z` after a slip flow `f` (increment form): slip's block structure (phi moves on its own)
/// skips the zeros of f's phi rows; without rotation phi and phi' stay.
#[inline(always)]
pub(super) fn slip_flow<T: Real>(f: &Flow<T>, z: &[T; 4], rotation: bool) -> [T; 4] {
    if rotation {
        [
            z[0] + (f[0] * z[0] + f[1] * z[1] + f[2] * z[2] + f[3] * z[3] + f[4]),
            z[1] + (f[5] * z[0] + f[6] * z[1] + f[7] * z[2] + f[8] * z[3] + f[9]),
            z[2] + (f[12] * z[2] + f[13] * z[3] + f[14]),
            z[3] + (f[17] * z[2] + f[18] * z[3] + f[19]),
        ]
    } else {
        [z[0] + (f[0] * z[0] + f[1] * z[1] + f[4]), z[1] + (f[5] * z[0] + f[6] * z[1] + f[9]), z[2], z[3]]
    }
}

/// phi and phi' after a stick flow folded as [`FastPath::stick_rot`] (`a`), from `z` (x at the
/// flow's start).
#[inline(always)]
pub(super) fn stick_rotation<T: Real>(a: &[T; 8], z: &[T; 4]) -> (T, T) {
    let phi = z[2] + (a[0] * z[0] + a[1] * z[2] + a[2] * z[3] + a[3]);
    let phid = z[3] + (a[4] * z[0] + a[5] * z[2] + a[6] * z[3] + a[7]);
    (phi, phid)
}
