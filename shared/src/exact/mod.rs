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
//!
//! **Tables apart from state.** [`ExactTables`] holds what the set-up fixes for one scene and
//! step (the dyadic propagator, the guards, the fast path's constants: kilobytes), read-only
//! while it steps; [`ExactState`] what a step writes (the state vector, regime, step count,
//! stick anchor, the last step's transitions). The step is [`ExactTables::step`] on a
//! `&mut ExactState`: one set of tables serves any number of runs, and a run starts or
//! restarts by writing its state alone ([`ExactTables::start_state`], [`ExactTables::restart`]).
//! [`ExactStepper`] is the two together, the tables owned or borrowed, with the stepper's
//! API.
//!
//! Files: this one holds the public types, the tables' and the state's fields and the state's
//! accessors; [`setup`] the set-up and the start and restart of a state; [`step`] the step
//! (fast path, substeps, checks); [`events`] the crests and the resolution of a substep with a
//! fired guard; [`pair`] [`ExactStepper`]; [`stick_jump`] the jump over stick at event speed
//! ([`ExactTables::jump_stick`], for runs that want no state between transitions).

use crate::coefficients::Coefficients;
use crate::halt::Limits;
pub use crate::halt::Halt;
use crate::linalg;
use crate::propagator::{apply, system_matrix, Propagator};
use crate::real::Real;
use crate::scene::{Scene, SceneError};
use crate::stickslip::{Guard, Guards, Regime};

mod events;
mod located;
mod pair;
mod quiet;
mod setup;
mod step;
mod stick_jump;

pub use located::TaylorFlows;
pub use quiet::SlipPairs;
pub use pair::ExactStepper;
pub use stick_jump::{StickJump, JUMP_LEVELS};

/// Transitions kept per step for [`ExactStepper::transitions`]; more are counted in
/// [`ExactStepper::transitions_dropped`] (an observer still sees every one).
pub const TRANSITIONS_PER_STEP: usize = 8;
const _: () = assert!(TRANSITIONS_PER_STEP <= u8::MAX as usize);
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

/// The exact stepper's tables for one scene and step, generic over f32 and f64: everything
/// the set-up fixes, read-only while it steps ([`Self::step`] on an [`ExactState`]).
#[derive(Clone, Copy, Debug)]
pub struct ExactTables<T: Real> {
    prop: Propagator<T>,
    guards: Guards<T>,
    fast: FastPath<T>,
    rotation: bool,
    /// The step [s].
    dt: f64,
    limits: Limits<T>,
    /// curv[regime][which]: the second time derivative of each guard, c . A^2 [z; 1], for the
    /// crest pre-test of [`Self::crest_crossing`].
    curv: [[[T; 5]; 2]; 3],
    /// The substep h_sub [s] in T.
    h_sub_t: T,
}

/// What an exact step writes: the state of one run on a set of [`ExactTables`].
#[derive(Clone, Copy, Debug)]
pub struct ExactState<T: Real> {
    /// x [m], x' [m/s], phi [rad], phi' [rad/s].
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
    reported: [Transition<T>; TRANSITIONS_PER_STEP],
    /// How many of `reported` the last step filled (a byte: the state's size is a multiple of
    /// 8 B without padding for it, and the stepper, tables and state, no larger than before
    /// their split).
    n_reported: u8,
    dropped: u64,
    halted: Option<Halt>,
}

impl<T: Real> ExactState<T> {
    /// The pad's state.
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
    /// The transitions of the last step (at most [`TRANSITIONS_PER_STEP`]).
    pub fn transitions(&self) -> &[Transition<T>] {
        &self.reported[..self.n_reported as usize]
    }
    /// Transitions not kept because a step had more than [`TRANSITIONS_PER_STEP`].
    pub fn transitions_dropped(&self) -> u64 {
        self.dropped
    }
    pub fn halted(&self) -> Option<Halt> {
        self.halted
    }
}
