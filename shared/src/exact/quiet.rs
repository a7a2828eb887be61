//! Quiet steps at loop speed: a run of the common step (one substep, no guard fired, no crest
//! possible, the state in range) in one regime, each step's end handed to the caller, without
//! the per-step branches of [`ExactTables::step`] (its halt and substep tests, the reported
//! transitions' reset) and with the regime's flow rows read once.
//!
//! Each step is [`ExactTables::step`]'s short path, the same operations in the same order:
//! the states are the stepped run's bit for bit. The loop stops *before* the first step that
//! is not common, leaving it to [`ExactTables::step`] or [`ExactTables::step_observed`]
//! (or to [`ExactTables::step_located`], the maps' in-step search by polynomial root-finding).

use super::*;
use crate::propagator::Flow;

impl<T: Real> ExactTables<T> {
    /// Takes up to `max` steps of the run in `s` while each is the common step, calling
    /// `each(z, pad_acc)` with the state at each step's end and the pad's x'' there (as
    /// [`Propagator::accelerations`] forms it: 0 in stick); returns the steps taken. Stops before the first step that fires, may
    /// crest or leaves the range (none is taken: the state is the one before it), and takes
    /// none where a step has several substeps or the run has halted.
    #[inline(always)]
    pub fn quiet_steps<F: FnMut(&[T; 4], T)>(&self, s: &mut ExactState<T>, max: u64, each: F) -> u64 {
        if s.regime == Regime::Stick {
            self.quiet_stick_steps(s, max, each)
        } else {
            self.quiet_slip_steps(s, max, each)
        }
    }

    /// [`Self::quiet_steps`] of a run in stick (none otherwise).
    #[inline(always)]
    pub fn quiet_stick_steps<F: FnMut(&[T; 4], T)>(&self, s: &mut ExactState<T>, max: u64, mut each: F) -> u64 {
        if self.prop.n_sub != 1 || s.halted.is_some() || s.regime != Regime::Stick {
            return 0;
        }
        let r = self.prop.accel_row(Regime::Stick);
        let mut n = 0u64;
        while n < max {
            let z1 = self.fast_substep(s, Regime::Stick, &s.z);
            if self.fires(Regime::Stick, &z1) || self.crest_possible(Regime::Stick, &s.z, &z1) || !self.limits.in_range(&z1) {
                break;
            }
            s.z = z1;
            s.anchor_subs = s.anchor_subs.saturating_add(1);
            n += 1;
            let z = &s.z;
            each(z, r[0] * z[0] + r[1] * z[1] + r[2] * z[2] + r[3] * z[3] + r[4]);
        }
        Self::quiet_done(s, n)
    }

    /// [`Self::quiet_steps`] of a run in slip (none otherwise).
    #[inline(always)]
    pub fn quiet_slip_steps<F: FnMut(&[T; 4], T)>(&self, s: &mut ExactState<T>, max: u64, each: F) -> u64 {
        if self.prop.n_sub != 1 || s.halted.is_some() || s.regime == Regime::Stick {
            return 0;
        }
        let f = *self.prop.substep_flow(s.regime);
        self.slip_loop::<false, F>(s, &f, max, each)
    }

    /// The loop of [`Self::quiet_slip_steps`] (`PAIR` false: flow `f` over a step, each end
    /// handed to `each`, a crest suspect tested to the end) and of [`Self::quiet_slip_pairs`]
    /// (`PAIR`: `f` over two steps, no state between, any crest suspect stops it).
    #[inline(always)]
    fn slip_loop<const PAIR: bool, F: FnMut(&[T; 4], T)>(&self, s: &mut ExactState<T>, f: &Flow<T>, max: u64, mut each: F) -> u64 {
        let regime = s.regime;
        let stride = if PAIR { 2 } else { 1 };
        let rotation = self.rotation;
        let r = self.prop.accel_row(regime);
        let sign = if regime == Regime::SlipSlower { T::one() } else { -T::one() };
        let g = *self.guards.of(regime).0[0];
        let zero = T::zero();
        let mut z = s.z;
        // x'' at z: the guard's rate (+-x'') and the sample's pad_acc
        let mut acc0 = r[0] * z[0] + r[1] * z[1] + r[2] * z[2] + r[3] * z[3] + r[4];
        let mut n = 0u64;
        while n + stride <= max {
            let z1 = super::step::slip_flow(f, &z, rotation);
            let acc1 = r[0] * z1[0] + r[1] * z1[1] + r[2] * z1[2] + r[3] * z1[3] + r[4];
            if g.fired(&z1) || !self.limits.in_range(&z1) {
                break;
            }
            // the crest test of `crest_suspect`: the guard's rate +-x'' from > 0 to < 0 (then,
            // for a single step, the rest of the test, on copies: the loop's state stays in
            // registers)
            let (d0, d1) = (sign * acc0, sign * acc1);
            if d0 > zero && d1 < zero {
                if PAIR {
                    break;
                }
                let (za, zb) = (core::hint::black_box(z), z1);
                if self.crest_possible(regime, &za, &zb) {
                    break;
                }
            }
            z = z1;
            acc0 = acc1;
            n += stride;
            if !PAIR {
                each(&z, acc1);
            }
        }
        s.z = z;
        Self::quiet_done(s, n)
    }

    #[inline(always)]
    fn quiet_done(s: &mut ExactState<T>, n: u64) -> u64 {
        if n > 0 {
            s.step += n;
            s.n_reported = 0;
        }
        n
    }
}

/// The slip flows over two steps, for runs that need no state at every step end (the part of
/// a map's run before its sink reads samples): [`ExactTables::quiet_slip_pairs`].
#[derive(Clone, Copy, Debug)]
pub struct SlipPairs<T: Real> {
    /// Increment form over two substeps, E2 = E E + 2 E (E the substep's), squared in f64;
    /// index: slip slower, slip faster.
    flows: [Flow<T>; 2],
    /// Whether two steps keep the quarter-radian rule (one substep per step, and the fastest
    /// mode turning at most a quarter radian over two): a guard then has at most one extremum
    /// in a pair, and the crest test holds over it.
    usable: bool,
}

impl<T: Real> SlipPairs<T> {
    /// The pairs of a validated `scene` on its tables.
    pub fn new(scene: &Scene, tables: &ExactTables<T>) -> Self {
        let co = Coefficients::of(scene);
        let usable = tables.prop.n_sub == 1 && Propagator::<T>::substeps(scene, &co, 2.0 * scene.dt) == 1;
        let mut flows = [[T::zero(); 20]; 2];
        for (i, regime) in [Regime::SlipSlower, Regime::SlipFaster].into_iter().enumerate() {
            let f = tables.prop.substep_flow(regime);
            let e = |r: usize, c: usize| if r < 4 { f[r * 5 + c].to_f64() } else { 0.0 };
            for r in 0..4 {
                for c in 0..5 {
                    let sq: f64 = (0..5).map(|k| e(r, k) * if k < 4 { e(k, c) } else { 0.0 }).sum();
                    flows[i][r * 5 + c] = T::from_f64(sq + 2.0 * e(r, c));
                }
            }
        }
        SlipPairs { flows, usable }
    }
}

impl<T: Real> ExactTables<T> {
    /// Takes up to `max / 2` pairs of steps of the run in `s`, in slip, while each pair keeps
    /// its guard below zero with no crest (its rate +-x'' not going from > 0 to < 0 over the
    /// pair) and its end in range; returns the steps taken (even). The pair's end is its flow
    /// over two steps ([`SlipPairs`]): the stepped state to rounding, not bit for bit, and no
    /// state at the step between. For the steps before a map's samples: the caller goes on
    /// step by step ([`Self::quiet_slip_steps`]) from where this stops.
    #[inline(always)]
    pub fn quiet_slip_pairs(&self, pairs: &SlipPairs<T>, s: &mut ExactState<T>, max: u64) -> u64 {
        if !pairs.usable || s.halted.is_some() || s.regime == Regime::Stick {
            return 0;
        }
        let f = pairs.flows[s.regime.index() - 1];
        self.slip_loop::<true, _>(s, &f, max, |_, _| {})
    }
}
