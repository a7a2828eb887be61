//! The fixed-step exact stepper: each regime is propagated by its exact flow, and the
//! transitions of the state machine ([`crate::stickslip`]) are located inside the step.
//!
//! One call of [`ExactStepper::step`] advances the run by `dt`. A step is split into `n_sub`
//! equal substeps, just enough that the fastest mode turns by at most a quarter radian per
//! substep (one substep per step at the rig's rate for the default scenes), so that a guard has
//! at most one extremum inside one. In a substep without a transition the work is one small
//! matrix product, one guard test and one crest test; a substep whose end state has a fired
//! guard is resolved by binary lifting over the substep's `2^L` units (L = 24 in f32, 53 in f64),
//! the new regime is entered at the first unit where the guard holds, and the rest of the
//! substep continues in it.
//!
//! Crests: a guard can also poke above zero and come back between two substep ends (by up to
//! about A (omega h)^2 / 8 for a guard ringing with amplitude A). Its time derivative
//! g' = c . A [z; 1] is linear in z (stick: +-k_g V - mu_s c_N phi'; slip: +-x''), so the crest
//! test is the sign of g' at both ends: + to - means a crest inside. Such a substep goes to
//! the in-substep search like a fired one, which bounds the crest by the two end tangents
//! (when g'' <= 0 at both ends) and, unless that bound is below zero, finds the zero of g' by
//! binary lifting, tests g there and, if it fired, lifts on g over [start, crest].
//!
//! Round-off containment: while sticking, x is not accumulated step by step but recomputed as
//! x_entry + V (elapsed since entry), so a long stick phase in f32 does not lose digits; time
//! is kept as an integer step count and formed in f64 only when reported.

use crate::coefficients::Coefficients;
use crate::halt::Limits;
pub use crate::halt::Halt;
use crate::linalg;
use crate::propagator::{apply, system_matrix, Propagator};
use crate::real::Real;
use crate::scene::{Scene, SceneError};
use crate::stickslip::{Guard, Guards, Regime};

/// Transitions kept per step for [`ExactStepper::transitions`]; more are counted in
/// [`ExactStepper::transitions_dropped`] (an observer still sees every one).
pub const TRANSITIONS_PER_STEP: usize = 8;
/// More transitions than this inside one substep halt the run ([`Halt::TransitionStorm`]).
pub const MAX_TRANSITIONS_PER_SUBSTEP: u32 = 64;

/// The pad's state: translation and rotation with their rates (SI).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct State<T> {
    /// Pad translation x [m].
    pub x: T,
    /// Pad velocity x' [m/s].
    pub xdot: T,
    /// Pad rotation phi [rad].
    pub phi: T,
    /// Pad angular velocity phi' [rad/s].
    pub phidot: T,
}

impl<T: Real> State<T> {
    #[inline(always)]
    pub fn from_array(z: [T; 4]) -> Self {
        State { x: z[0], xdot: z[1], phi: z[2], phidot: z[3] }
    }
    #[inline(always)]
    pub fn to_array(self) -> [T; 4] {
        [self.x, self.xdot, self.phi, self.phidot]
    }
}

/// A change of regime.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transition<T> {
    /// Time of the transition [s] (resolution: 2^-L of a substep).
    pub t: f64,
    pub from: Regime,
    pub to: Regime,
    /// The state on entry to the new regime.
    pub state: State<T>,
}

/// A piece of motion inside one regime, from unit `p0` to unit `p1` of substep `sub` of step
/// `step` (there are `Propagator::UNITS` units per substep).
#[derive(Clone, Copy, Debug)]
pub struct Segment<T> {
    pub regime: Regime,
    pub step: u64,
    pub sub: u32,
    pub p0: u64,
    pub p1: u64,
    pub z0: [T; 4],
    pub z1: [T; 4],
}

/// Sees every segment and every transition of a run (statistics, plots, logs).
pub trait Observer<T: Real> {
    #[inline(always)]
    fn segment(&mut self, _seg: &Segment<T>, _prop: &Propagator<T>) {}
    #[inline(always)]
    fn transition(&mut self, _tr: &Transition<T>) {}
}

/// The observer that looks at nothing.
impl<T: Real> Observer<T> for () {}

/// Constants of the no-transition fast path, in `T`.
#[derive(Clone, Copy, Debug)]
struct FastPath<T> {
    /// Stick with rotation: the phi and phi' rows of the increment flow with x' = V folded
    /// into the constant: [phi += a0 x + a1 phi + a2 phi' + a3, phi' += a4 x + a5 phi + a6 phi' + a7].
    stick_rot: [T; 8],
    v: T,
    k_g: T,
    c_x_v: T,
    mu_s_c_n: T,
    /// mu_s N_0 for the 1-DOF scene (N constant).
    mu_s_n0: T,
    c_n: T,
    n0: T,
    mu_k: T,
    /// k_g V: with mu_s c_N phi' it gives the stick guards' rates (crest test).
    k_g_v: T,
}

/// The exact fixed-step stepper, generic over f32 and f64.
#[derive(Clone, Copy, Debug)]
pub struct ExactStepper<T: Real> {
    prop: Propagator<T>,
    guards: Guards<T>,
    fast: FastPath<T>,
    rotation: bool,
    dt: f64,
    limits: Limits<T>,
    /// curv[regime][which]: the second time derivative of each guard, c . A^2 [z; 1], for the
    /// crest pre-test of [`Self::crest_crossing`].
    curv: [[[T; 5]; 2]; 3],
    z: [T; 4],
    regime: Regime,
    step: u64,
    // stick anchor: x = anchor_x + V (anchor_e0 + anchor_subs h_sub)
    anchor_x: T,
    anchor_e0: T,
    /// Whole substeps in stick since the entry substep. u32: one hardware conversion to f32 on
    /// the Cortex-M4F (a u64 costs a 33-instruction library call); it saturates after 46 h of
    /// sticking at 25.6 kHz, long after x has left its range.
    anchor_subs: u32,
    h_sub_t: T,
    reported: [Transition<T>; TRANSITIONS_PER_STEP],
    n_reported: usize,
    dropped: u64,
    halted: Option<Halt>,
}

impl<T: Real> ExactStepper<T> {
    /// Validates `scene` and sets up the stepper at the default initial state: stick, x = 0,
    /// x' = V, phi = F_N a_N / K, phi' = 0.
    pub fn new(scene: &Scene) -> Result<Self, SceneError> {
        scene.validate()?;
        let co = Coefficients::of(scene);
        let prop = Propagator::<T>::new(scene, &co, scene.dt);
        let guards = Guards::<T>::new(scene, &co);
        let t = T::from_f64;
        let a = Self::stick_fold(&prop, scene.v);
        let limits = Limits::new(scene, &co);
        let fast = FastPath {
            stick_rot: a,
            v: t(scene.v),
            k_g: t(scene.k_g),
            c_x_v: t(scene.c_x * scene.v),
            mu_s_c_n: t(scene.mu_s * co.c_n),
            mu_s_n0: t(scene.mu_s * co.n0),
            c_n: t(co.c_n),
            n0: t(co.n0),
            mu_k: t(scene.mu_k),
            k_g_v: t(scene.k_g * scene.v),
        };
        let curv = Self::curvatures(scene, &co);
        let z = [T::zero(), t(scene.v), t(co.phi0), T::zero()];
        let empty = Transition { t: 0.0, from: Regime::Stick, to: Regime::Stick, state: State::default() };
        Ok(ExactStepper {
            h_sub_t: t(prop.h_sub),
            prop,
            guards,
            fast,
            rotation: scene.rotation,
            dt: scene.dt,
            limits,
            curv,
            z,
            regime: Regime::Stick,
            step: 0,
            anchor_x: T::zero(),
            anchor_e0: t(prop.h_sub),
            anchor_subs: 0,
            reported: [empty; TRANSITIONS_PER_STEP],
            n_reported: 0,
            dropped: 0,
            halted: None,
        })
    }

    /// Back to the initial state, the tables kept: `z0` is the state the stepper was built in
    /// ([`Self::state`] right after [`Self::new`]), in stick, at step 0, no halt, nothing
    /// reported: every field a step changes, as [`Self::new`] leaves it (the rig's lockstep
    /// model restarts this way at each record's start instead of copying a stepper).
    pub fn restart(&mut self, z0: [T; 4]) {
        let empty = Transition { t: 0.0, from: Regime::Stick, to: Regime::Stick, state: State::default() };
        self.z = z0;
        self.regime = Regime::Stick;
        self.step = 0;
        self.anchor_x = T::zero();
        self.anchor_e0 = self.h_sub_t;
        self.anchor_subs = 0;
        self.reported = [empty; TRANSITIONS_PER_STEP];
        self.n_reported = 0;
        self.dropped = 0;
        self.halted = None;
    }

    /// c . A^2 for every guard of every regime, in f64, rounded to T.
    fn curvatures(scene: &Scene, co: &Coefficients) -> [[[T; 5]; 2]; 3] {
        let g64 = Guards::<f64>::new(scene, co);
        let mut out = [[[T::zero(); 5]; 2]; 3];
        for regime in Regime::ALL {
            let a = system_matrix(scene, co, regime);
            let a2 = linalg::mul(&a, &a);
            let (gs, n) = g64.of(regime);
            for (which, g) in gs.iter().take(n).enumerate() {
                for col in 0..5 {
                    let v: f64 = (0..5).map(|r| g.c[r] * a2[r][col]).sum();
                    out[regime.index()][which][col] = T::from_f64(v);
                }
            }
        }
        out
    }

    fn stick_fold(prop: &Propagator<T>, v: f64) -> [T; 8] {
        let f = prop.substep_flow(Regime::Stick);
        let g = |i: usize| f[i].to_f64();
        let t = T::from_f64;
        // row 2 (phi) and row 3 (phi'): columns x, x', phi, phi', 1
        [
            t(g(10)),
            t(g(12)),
            t(g(13)),
            t(g(14) + g(11) * v),
            t(g(15)),
            t(g(17)),
            t(g(18)),
            t(g(19) + g(16) * v),
        ]
    }

    /// Replaces the state and regime (e.g. to start from a measured condition). In stick,
    /// x' is set to V.
    pub fn set_state(&mut self, state: State<T>, regime: Regime) {
        self.z = state.to_array();
        self.regime = regime;
        if regime == Regime::Stick {
            self.z[1] = self.fast.v;
            self.anchor_x = self.z[0];
            self.anchor_e0 = self.h_sub_t;
            self.anchor_subs = 0;
        }
        self.halted = None;
    }

    pub fn state(&self) -> State<T> {
        State::from_array(self.z)
    }
    pub fn regime(&self) -> Regime {
        self.regime
    }
    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.step
    }
    /// Time at the end of the last step [s].
    pub fn time(&self) -> f64 {
        self.step as f64 * self.dt
    }
    pub fn propagator(&self) -> &Propagator<T> {
        &self.prop
    }
    pub fn guards(&self) -> &Guards<T> {
        &self.guards
    }
    /// The transitions of the last step (at most [`TRANSITIONS_PER_STEP`]).
    pub fn transitions(&self) -> &[Transition<T>] {
        &self.reported[..self.n_reported]
    }
    /// Transitions not kept because a step had more than [`TRANSITIONS_PER_STEP`].
    pub fn transitions_dropped(&self) -> u64 {
        self.dropped
    }
    pub fn halted(&self) -> Option<Halt> {
        self.halted
    }

    /// Normal force N = c_N phi at the current state [N] (N_0 without rotation).
    pub fn normal_force(&self) -> T {
        if self.rotation {
            self.fast.c_n * self.z[2]
        } else {
            self.fast.n0
        }
    }

    /// Friction force on the pad F_f [N]: the required force in stick, sigma mu_k N in slip.
    pub fn friction_force(&self) -> T {
        match self.regime {
            Regime::Stick => self.guards.required_force(&self.z),
            Regime::SlipSlower => self.fast.mu_k * self.normal_force(),
            Regime::SlipFaster => -(self.fast.mu_k * self.normal_force()),
        }
    }

    /// One step of `dt`, with no observer. The common step (one substep, no guard fired, the
    /// state in range) takes a short path; anything else goes through [`Self::step_observed`].
    #[inline]
    pub fn step(&mut self) -> Result<usize, Halt> {
        if self.prop.n_sub == 1 && self.halted.is_none() {
            let regime = self.regime;
            let z1 = self.fast_substep(regime, &self.z);
            if !self.fires(regime, &z1) && !self.crest_possible(regime, &self.z, &z1) && self.limits.in_range(&z1) {
                self.z = z1;
                if regime == Regime::Stick {
                    self.anchor_subs = self.anchor_subs.saturating_add(1);
                }
                self.step += 1;
                self.n_reported = 0;
                return Ok(0);
            }
        }
        self.step_observed(&mut ())
    }

    /// One step of `dt`; `obs` sees every segment and transition. Returns the number of
    /// transitions in the step.
    pub fn step_observed<O: Observer<T>>(&mut self, obs: &mut O) -> Result<usize, Halt> {
        if let Some(h) = self.halted {
            return Err(h);
        }
        self.n_reported = 0;
        let mut count = 0usize;
        for sub in 0..self.prop.n_sub {
            let z0 = self.z;
            let regime = self.regime;
            let z1 = self.fast_substep(regime, &z0);
            if !self.fires(regime, &z1) && !self.crest_possible(regime, &z0, &z1) {
                obs.segment(
                    &Segment { regime, step: self.step, sub, p0: 0, p1: Propagator::<T>::UNITS, z0, z1 },
                    &self.prop,
                );
                self.z = z1;
                if regime == Regime::Stick {
                    self.anchor_subs = self.anchor_subs.saturating_add(1);
                }
            } else {
                count += self.resolve(sub, z0, z1, obs)?;
            }
            if let Err(h) = self.check(sub) {
                self.halted = Some(h);
                return Err(h);
            }
        }
        self.step += 1;
        Ok(count)
    }

    /// The exact flow over one whole substep in `regime`, exploiting the regime's structure.
    #[inline(always)]
    fn fast_substep(&self, regime: Regime, z: &[T; 4]) -> [T; 4] {
        match regime {
            Regime::Stick => {
                let x = self.anchor_x
                    + self.fast.v * (self.anchor_e0 + T::from_u32(self.anchor_subs) * self.h_sub_t);
                if self.rotation {
                    let a = &self.fast.stick_rot;
                    let phi = z[2] + (a[0] * z[0] + a[1] * z[2] + a[2] * z[3] + a[3]);
                    let phid = z[3] + (a[4] * z[0] + a[5] * z[2] + a[6] * z[3] + a[7]);
                    [x, self.fast.v, phi, phid]
                } else {
                    [x, self.fast.v, z[2], z[3]]
                }
            }
            _ => {
                let f = self.prop.substep_flow(regime);
                if self.rotation {
                    [
                        z[0] + (f[0] * z[0] + f[1] * z[1] + f[2] * z[2] + f[3] * z[3] + f[4]),
                        z[1] + (f[5] * z[0] + f[6] * z[1] + f[7] * z[2] + f[8] * z[3] + f[9]),
                        z[2] + (f[12] * z[2] + f[13] * z[3] + f[14]),
                        z[3] + (f[17] * z[2] + f[18] * z[3] + f[19]),
                    ]
                } else {
                    [
                        z[0] + (f[0] * z[0] + f[1] * z[1] + f[4]),
                        z[1] + (f[5] * z[0] + f[6] * z[1] + f[9]),
                        z[2],
                        z[3],
                    ]
                }
            }
        }
    }

    /// Whether a guard of `regime` has fired at `z` (the fast path's test).
    #[inline(always)]
    fn fires(&self, regime: Regime, z: &[T; 4]) -> bool {
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
    fn crest_possible(&self, regime: Regime, z0: &[T; 4], z1: &[T; 4]) -> bool {
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

    fn time_at(&self, sub: u32, unit: u64) -> f64 {
        let u = Propagator::<T>::UNITS as f64;
        self.step as f64 * self.dt + (sub as f64 + unit as f64 / u) * self.prop.h_sub
    }

    /// A substep whose end state has a fired guard: find every transition inside it.
    fn resolve<O: Observer<T>>(&mut self, sub: u32, z0: [T; 4], z1: [T; 4], obs: &mut O) -> Result<usize, Halt> {
        let units = Propagator::<T>::UNITS;
        let mut pos = 0u64;
        let mut z = z0;
        let mut z_end = z1;
        let mut regime = self.regime;
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
                obs.segment(&Segment { regime, step: self.step, sub, p0: pos, p1: units, z0: z, z1: z_end }, &self.prop);
                break;
            };
            let at = p + 1;
            let ze = if at == units { z_end } else { apply(self.prop.flow(regime, 0), &zp) };
            obs.segment(&Segment { regime, step: self.step, sub, p0: pos, p1: at, z0: z, z1: ze }, &self.prop);
            let next = self.guards.next_regime(regime, which, &ze);
            let mut zn = ze;
            if next == Regime::Stick {
                zn[1] = self.fast.v;
                entered_stick_at = Some(at);
                self.anchor_x = zn[0];
            }
            if next == regime {
                touched = Some((regime, which));
            } else {
                touched = None;
                let tr = Transition { t: self.time_at(sub, at), from: regime, to: next, state: State::from_array(zn) };
                obs.transition(&tr);
                if self.n_reported < TRANSITIONS_PER_STEP {
                    self.reported[self.n_reported] = tr;
                    self.n_reported += 1;
                } else {
                    self.dropped += 1;
                }
                transitions += 1;
            }
            count += 1;
            if count > MAX_TRANSITIONS_PER_SUBSTEP {
                let h = Halt::TransitionStorm { t: self.time_at(sub, at) };
                self.halted = Some(h);
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
        self.regime = regime;
        if regime == Regime::Stick {
            match entered_stick_at {
                Some(at) => {
                    // x from the anchor: elapsed = (units - at) units
                    let e0 = (units - at) as f64 / units as f64 * self.prop.h_sub;
                    self.anchor_e0 = T::from_f64(e0);
                    self.anchor_subs = 0;
                    z_end[0] = self.anchor_x + self.fast.v * self.anchor_e0;
                }
                None => {
                    // a stick substep whose guard fired and came back (or a touch): keep the anchor
                    z_end[0] = self.anchor_x
                        + self.fast.v * (self.anchor_e0 + T::from_u32(self.anchor_subs) * self.h_sub_t);
                }
            }
            z_end[1] = self.fast.v;
            self.anchor_subs = self.anchor_subs.saturating_add(1);
        }
        self.z = z_end;
        Ok(transitions)
    }

    /// End-of-substep checks: finite, in range, in contact.
    #[inline(always)]
    fn check(&self, sub: u32) -> Result<(), Halt> {
        self.limits.check(&self.z, self.regime, || self.time_at(sub, Propagator::<T>::UNITS))
    }
}
