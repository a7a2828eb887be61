//! The fixed-step stepper of model 2: exact flows for every linear regime, an exponential
//! Runge-Kutta method for Stribeck slip, and in-step location of every transition.
//!
//! - **Linear regimes** (stick with or without the band; Coulomb slip): the flow over 2^j units
//!   of a substep is expm(A h 2^(j-L)), tabulated once in f64 and rounded to `T`, exactly as in
//!   the thesis stepper ([`crate::exact`]).
//! - **Stribeck slip**: z' = A z + b q(z), with A the regime's kinetic (mu_k) part and q the
//!   scalar excess friction. The fourth-order exponential Runge-Kutta method of Cox and
//!   Matthews (ETDRK4) takes the linear part exactly and q as forcing; because b is fixed, its
//!   phi-function terms are vectors h phi_k(h A) b, computed once per dyadic level from one
//!   10 x 10 matrix exponential (the augmented-matrix form of the phi functions). A step of
//!   2^j units costs two flow applications (the half chunk's, from z and from the first stage
//!   a: the whole chunk's linear flow from z is the half flow from a less e^(hA/2) (h/2)
//!   phi_1(hA/2) b q(z), a vector term folded into the final weights) and four evaluations of q.
//! - **Near v = 0** the falling slope is steep: its rate |dq/dv| (1/m + 1/m_b) is
//!   (mu_s - mu_k) N e^(-|v|/v_s) / v_s (1/m + 1/m_b) (delta = 1). Where that rate would
//!   split the chunk with the kinetic operator (see the next item), the chunk takes a
//!   *near operator*, A + b g_k with g_k the friction's affine part at v = 0 scaled by
//!   c_k = k/3 (k = 1, 2, 3), and the forcing q - g_k z: the same equation, split so that the
//!   exponential carries the slope c_k N_0 / v_s nearest the friction's N e / v_s and the
//!   forcing only the residual, at most N_0 / (6 v_s). The near operators are tabulated on the
//!   top four levels (chunks of a whole, a half and a quarter substep; their flows on the three
//!   below the top, the only ones a chunk applies; 3.7 KB in f32 without the band, 5.3 KB with
//!   it) and used where the slope's rate at v = 0 times a substep is at
//!   most 2 (`NEAR_RATE_H_MAX`).
//! - **Stiff friction**: where the forcing's slope is still steep (v_s toward 0, or delta != 1),
//!   a substep is walked in dyadic chunks short enough that the slope's rate (of the residual,
//!   with a near operator) times the chunk is at most a quarter (down to 2^-16 of a substep), so
//!   v_s -> 0 stays stable.
//! - **Transitions**: a guard (a linear row of z) is tested at each chunk end; a fired guard is
//!   located by binary lifting on the dyadic grid (to 2^-L of a substep, 2^-(L-1) in Stribeck
//!   slip). A guard that rises and falls back inside a chunk (a crest) is found from the sign
//!   change of its derivative: the derivative's zero is lifted, and the guard is evaluated
//!   there. In a linear regime (stick; Coulomb slip) a bound comes first (`crest_below`):
//!   the cubic Hermite interpolant of the guard's values and rates at the chunk's ends, plus
//!   weights fixed at set-up for its fourth derivative and for the lift's round-off
//!   (`crest_weights`); where that bound is below zero the lift could only find the guard
//!   below at the crest, and is skipped (the same result: stick's crests of the rig scenes
//!   lie newtons below zero, a lift is 25 or 54 chunks).
//! - **The short path**: most substeps are one chunk with no guard firing or cresting in it.
//!   `short_substep` takes that chunk and tests the guards on a straight path, compiled apart
//!   for stick and for slip; only a substep that splits, fires or crests goes on to the general
//!   loop (`substep`), from the chunk already taken. Both paths give the same bits (tests:
//!   `the_short_substep_is_the_general_one_bit_for_bit`, and the grazing scenes on both).
//!
//! The stepper is generic over its [`Composition`] (band or not, Stribeck or Coulomb): a
//! composition without the band moves 4 state entries with 4 x 5 flows, one with Coulomb
//! friction has no ETDRK4 tables and no exponential in its code. [`super::AnyModel2Stepper`]
//! chooses the composition from a scene at run time.
//!
//! The thesis model (every option off) never runs here: it keeps [`crate::ExactStepper`],
//! bit for bit.
//!
//! **Tables apart from state.** [`Model2Tables`] holds everything the set-up fixes for one
//! scene and step (the dyadic flows, the ETDRK4 vectors, the guards' rows and rates, the
//! friction's constants, the limits: kilobytes), read-only while it steps; [`Model2State`] what
//! a step writes (z, the regime, the friction's falling part carried between chunks, the step
//! and substep counts, the stick anchor, the halt, the slip's arming: 120 B in f32). The step
//! is [`Model2Tables::step`] on a `&mut Model2State`, so one set of tables serves any number of
//! runs; [`Model2Stepper`] is the two together, the tables owned or borrowed.
//!
//! Files: this one holds the types, the tables' and the state's fields, the tables' accessors,
//! start and restart of a state, and friction evaluation; [`pair`] [`Model2Stepper`];
//! [`setup`] the set-up and the dyadic tables; [`etd`] the exponential time
//! differencing of Stribeck slip (ETDRK4 chunks, near operators, chunk levels); [`events`] the
//! location of transitions (guards, binary lifting, crests, entry to stick); [`substep`] the
//! step and its substeps (the short path and the general one); [`checks`] the range and
//! contact checks that halt a run.

use crate::coefficients::Coefficients;
use crate::halt::{Halt, Limits};
use crate::linalg::{self, MatN};
use crate::model2::composition::{Composition, EtdVectors, NEAR_FLOW_LEVELS, NEAR_LEVELS, NEAR_OPS};
use crate::model2::system::{row_dot, row_dot_all, System, NA, NS, ONE, Y};
use crate::real::Real;
use crate::scene::{Scene, SceneError};
use crate::stickslip::Regime;

mod checks;
mod etd;
mod events;
mod pair;
mod setup;
mod substep;
mod wide;

pub use pair::Model2Stepper;
pub use wide::{WideSamples, WideChunks, DY_MAX, WIDE_MAX};

/// Deepest refinement of a Stribeck substep below the whole substep (2^-16).
const STRIBECK_REFINE: usize = 16;
/// Largest rate x chunk length allowed for the falling friction's slope.
const STRIBECK_RATE_H: f64 = 0.25;
/// The near operators are used where the falling slope's rate at v = 0 (with N = N_0) times a
/// substep is at most this: their exponentials then grow by at most e^2 over a substep. Beyond
/// (v_s toward 0), the split would carry a growth the friction's saturation never reaches.
const NEAR_RATE_H_MAX: f64 = 2.0;
/// More transitions than this inside one substep halt the run.
const MAX_TRANSITIONS_PER_SUBSTEP: u32 = 64;
/// |u| beyond this is taken as divergence [m]; |u'| beyond this [m/s].
const U_LIMIT: f64 = 1.0;
const UDOT_LIMIT: f64 = 1e3;
/// |y| beyond this is taken as divergence [m]; |y'| beyond this [m/s] (the floating pad).
const Y_LIMIT: f64 = 0.1;
const YDOT_LIMIT: f64 = 1e3;

/// z(t + h) - z(t) = F (z, 1) for a flow F of composition `C` (rows and columns of the
/// entries it moves; without the band, u and u' stay 0 and are not touched). F is stored by
/// columns ([`Composition::Flow`]), so that each column's term is added to every row at once
/// (a vector operation on the host); each row's sum is the same, in the same order,
/// F_r0 z_0 + F_r1 z_1 + ... + F_r,one, as by rows.
#[inline(always)]
fn increment<T: Real, C: Composition>(f: &C::Flow<T>, z: &[T; NS]) -> [T; NS] {
    let f = f.as_ref();
    let mut out = [T::zero(); NS];
    if C::FLOAT {
        for (r, o) in out.iter_mut().enumerate() {
            *o = f[r] * z[0]
                + f[8 + r] * z[1]
                + f[16 + r] * z[2]
                + f[24 + r] * z[3]
                + f[32 + r] * z[4]
                + f[40 + r] * z[5]
                + f[48 + r] * z[6]
                + f[56 + r] * z[7]
                + f[64 + r];
        }
    } else if C::BAND {
        for (r, o) in out.iter_mut().take(6).enumerate() {
            *o = f[r] * z[0] + f[6 + r] * z[1] + f[12 + r] * z[2] + f[18 + r] * z[3] + f[24 + r] * z[4] + f[30 + r] * z[5] + f[36 + r];
        }
    } else {
        for (r, o) in out.iter_mut().take(4).enumerate() {
            *o = f[r] * z[0] + f[4 + r] * z[1] + f[8 + r] * z[2] + f[12 + r] * z[3] + f[16 + r];
        }
    }
    out
}

/// [`increment`] for a slip regime's flow, which has the block structure of slip: the
/// rotation (phi, phi') moves on its own (N depends on phi alone and the friction's kinetic part
/// on N), the pad's x and the band's u are each driven by it and not by each other. The zeros
/// this skips are exact in the table (checked at set-up: `slip_sparse`), so the sum is the
/// same as [`increment`]'s.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // matrix code: indices read as the formulas
fn increment_slip<T: Real, C: Composition>(f: &C::Flow<T>, z: &[T; NS]) -> [T; NS] {
    let f = f.as_ref();
    let mut out = [T::zero(); NS];
    let n = C::ROWS;
    let one = C::COLS - 1;
    let e = |r: usize, c: usize| f[c * n + r];
    for r in 0..2 {
        out[r] = e(r, 0) * z[0] + e(r, 1) * z[1] + e(r, 2) * z[2] + e(r, 3) * z[3] + e(r, one);
    }
    for r in 2..4 {
        out[r] = e(r, 2) * z[2] + e(r, 3) * z[3] + e(r, one);
    }
    if C::BAND {
        for r in 4..6 {
            out[r] = e(r, 2) * z[2] + e(r, 3) * z[3] + e(r, 4) * z[4] + e(r, 5) * z[5] + e(r, one);
        }
    }
    out
}

/// Whether a slip flow has the zeros [`increment_slip`] skips (exactly).
fn has_slip_zeros<T: Real, C: Composition>(f: &C::Flow<T>) -> bool {
    if C::FLOAT {
        // y couples to everything through N (and to phi through the mass matrix)
        return false;
    }
    let f = f.as_ref();
    let n = C::ROWS;
    let cols = C::COLS;
    let zero = |r: usize, c: usize| f[c * n + r] == T::zero();
    let mut ok = true;
    for r in 0..C::ROWS {
        let skipped: &[usize] = match r {
            0 | 1 => &[4, 5],
            2 | 3 => &[0, 1, 4, 5],
            _ => &[0, 1],
        };
        for &c in skipped {
            if c < cols - 1 {
                ok &= zero(r, c);
            }
        }
    }
    ok
}

/// A row (z, 1) . r over the entries composition `C` moves (the same value as
/// [`row_dot`]: the left-out entries are 0).
#[inline(always)]
fn dot<T: Real, C: Composition>(r: &[T; NA], z: &[T; NS]) -> T {
    if C::FLOAT {
        row_dot_all(r, z)
    } else if C::BAND {
        row_dot(r, z)
    } else {
        r[0] * z[0] + r[1] * z[1] + r[2] * z[2] + r[3] * z[3] + r[ONE]
    }
}

/// The friction's falling part at one state, for Stribeck slip: y = |v| / v_s, the shape
/// e = exp(-y^delta) and the normal force N [N]. Computed once per point: the chunk's forcing,
/// its length rule and the crest test all read it.
#[derive(Clone, Copy, Debug)]
struct Excess<T> {
    /// Sliding velocity v [m/s].
    v: T,
    y: T,
    e: T,
    n: T,
}

/// A piece of motion inside one regime, between two located instants.
#[derive(Clone, Copy, Debug)]
pub struct Model2Segment<T> {
    pub regime: Regime,
    /// Start and end time [s].
    pub t0: f64,
    pub t1: f64,
    pub z0: [T; NS],
    pub z1: [T; NS],
    /// z' at both ends (only filled for observers that ask, [`Model2Observer::DERIVATIVES`]).
    pub zd0: [T; NS],
    pub zd1: [T; NS],
}

/// A change of regime of model 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Model2Transition<T> {
    pub t: f64,
    pub from: Regime,
    pub to: Regime,
    /// State on entry to the new regime.
    pub z: [T; NS],
}

/// Sees every segment and transition of a model-2 run.
pub trait Model2Observer<T: Real> {
    /// Whether segments need z' at their ends (costs two evaluations per segment).
    const DERIVATIVES: bool = true;
    /// 0 (the default): a guard that fires is lifted on the dyadic grid to its last level,
    /// bit for bit the sampled path. Above 0, lifted down to this level and located below it
    /// by one Newton step on the guard ([`Model2Tables::step`]'s `located_crossing`): for runs
    /// of statistics only (a map's cells, f64), where the last levels' chunks cost most of a
    /// transition.
    const LOCATE_BELOW_LEVEL: usize = 0;
    fn segment(&mut self, _seg: &Model2Segment<T>) {}
    fn transition(&mut self, _tr: &Model2Transition<T>) {}
}

impl<T: Real> Model2Observer<T> for () {
    const DERIVATIVES: bool = false;
}

/// A count of units (below 2^53) in T, exactly, with two 32-bit conversions (one instruction
/// each on the Cortex-M4F, where a 64-bit one is a library call).
#[inline(always)]
fn units_t<T: Real>(u: u64) -> T {
    let hi = T::from_u32((u >> 32) as u32);
    let lo = T::from_u32(u as u32);
    if (u >> 32) == 0 {
        lo
    } else {
        hi * T::from_f64(4294967296.0) + lo
    }
}

/// Where each guard's rate (its row times z') is kept: stick's two breakaway guards, then the
/// two slips' velocity guards.
fn guard_slot(regime: Regime, which: usize) -> usize {
    match regime {
        Regime::Stick => which,
        Regime::SlipSlower => 2,
        Regime::SlipFaster => 3,
    }
}

/// A substep's first chunk, of 2^j units from the substep's start to z1, with the falling
/// parts at its two ends in Stribeck slip (see `Model2Stepper::short_substep`).
#[derive(Clone, Copy, Debug)]
struct FirstChunk<T> {
    ex0: Option<Excess<T>>,
    j: usize,
    z1: [T; NS],
    ex1: Option<Excess<T>>,
}

/// The model-2 stepper's tables for one scene and step, generic over f32 and f64 and over its
/// [`Composition`]: everything fixed at set-up (the dyadic flows, the ETDRK4 vectors, the rows
/// and constants), read-only while it steps. Kilobytes (`table_bytes`); one set serves any
/// number of runs, each its own [`Model2State`] ([`Self::step`]).
#[derive(Clone, Copy, Debug)]
pub struct Model2Tables<T: Real, C: Composition> {
    /// flows[regime][level]
    flows: [T::PerLevel<C::Flow<T>>; 3],
    /// Stribeck slip: etd[slip regime - 1][level] (empty with Coulomb friction)
    etd: C::Etd<T>,
    /// Stribeck slip near v = 0: the flows and ETDRK4 vectors of the near operators
    /// A + b g_k on the top levels, entry ((k - 1) 2 + slip regime - 1) n + level -
    /// (L - NEAR_LEVELS + 1), n = NEAR_FLOW_LEVELS for the flows (the top level has none) and
    /// NEAR_LEVELS for the vectors (see `near_op`).
    near_flows: C::NearFlows<T>,
    near_etd: C::NearEtd<T>,
    /// The near operators are used: exponent delta = 1 (with another exponent the slope at
    /// v = 0 is 0 or infinite) and the slope's rate x substep <= NEAR_RATE_H_MAX; otherwise
    /// every chunk takes the kinetic operator.
    near_on: bool,
    /// c_k = k / NEAR_OPS (index 0: the kinetic operator, 0), c_k N_0 [N], the thresholds
    /// between them, (k + 1/2) N_0 / NEAR_OPS [N] (operator k is the one whose c_k N_0 is
    /// nearest N e), and c_k (mu_s - mu_k) N_0 / v_s [N s/m] (the slope each carries).
    near_c: [T; NEAR_OPS + 1],
    near_cn0: [T; NEAR_OPS + 1],
    near_thr: [T; NEAR_OPS],
    near_ckv: [T; NEAR_OPS + 1],
    /// A rows (z' = A z) per regime, for derivatives.
    a: [[[T; NA]; NS]; 3],
    b: [T; NS],
    r_v: [T; NA],
    r_n: [T; NA],
    r_freq: [T; NA],
    /// The guards' rates: row . A of each guard ([`guard_slot`]), and row . b (Stribeck slip:
    /// the rate is row . A z + (row . b) q).
    guard_rate: [[T; NA]; 4],
    guard_rate_b: [T; 4],
    /// The crest bound of a linear regime's guard ([`guard_slot`]; see `crest_below`): the
    /// weights of (|z|, 1) whose sum bounds the guard's fourth-derivative term and the
    /// round-off of the lift, and (4/27) h_sub.
    crest_w: [[T; NA]; 4],
    crest_c1: T,
    mu_s: T,
    d_mu: T,
    inv_v_s: T,
    delta: T,
    delta_is_one: bool,
    v: T,
    m: T,
    m_b: T,
    /// The scene has the band (a floating composition carries the band's rows either way).
    scene_band: bool,
    /// The floating pad's contact springs: k_L [N/m], d_L [m], k_T [N/m], d_T [m] (contact-loss
    /// reports; unread without the floating pad).
    springs: [f64; 4],
    limits: Limits<T>,
    u_limit: T,
    udot_limit: T,
    h_sub: f64,
    n_sub: u32,
    dt: f64,
    /// h_sub and h_sub / 2^L in T.
    h_t: T,
    hu_t: T,
    /// The guards' rows ([`guard_slot`]; fire at row . z >= 0), in T.
    guards: [[T; NA]; 4],
    /// (mu_s - mu_k) delta / v_s (1/m + 1/m_b): the falling slope's rate per unit of N and of
    /// the shape y^(delta-1) exp(-y^delta) [1/(N s)].
    rate_coef: T,
    /// The largest slope rate a chunk of 2^j units takes: STRIBECK_RATE_H / h_j [1/s].
    rate_limit: T::PerLevel<T>,
    /// Round-off level of the sliding velocity: 2^-(L-8) V [m/s].
    v_round: T,
    /// Every slip flow has slip's block zeros ([`increment_slip`] applies).
    slip_sparse: bool,
    /// The floating pad's contact and range checks: d_L, d_T [m], the springs' round-off
    /// floors [m], |y| and |y'| limits [m, m/s] (unread without the floating pad).
    float_limits: [T; 6],
}

/// What a model-2 step writes: the state of one run on a set of [`Model2Tables`] (120 B in
/// f32). Starting or restarting a run is writing this ([`Model2Tables::start_state`]).
#[derive(Clone, Copy, Debug)]
pub struct Model2State<T: Real> {
    /// The state vector z (see [`crate::model2::system`]; SI units).
    z: [T; NS],
    regime: Regime,
    /// Stribeck slip: the friction's falling part at `z`, carried from the end of one chunk to
    /// the start of the next (and from step to step).
    head: Option<Excess<T>>,
    step: u64,
    halted: Option<Halt>,
    transitions: u64,
    /// Stick without the band: x = anchor_x + V (t - t_anchor) (with the face: x + s w phi =
    /// ...), recomputed after each chunk so
    /// that a long stick in f32 does not accumulate x += V h round-off. t - t_anchor is counted
    /// in T from whole substeps and units (no f64 on the M4F's path): the anchor's substep
    /// (global index) and its unit in that substep.
    anchor_x: T,
    anchor_sub: u64,
    anchor_unit: T,
    /// Substeps completed since the start (the global index of the current substep).
    subs_done: u64,
    /// Whether the current slip's return to v = 0 is watched (see `substep`).
    armed: bool,
}

impl<T: Real, C: Composition> Model2Tables<T, C> {
    const LEVELS: usize = T::DYADIC_LEVELS;

    const UNITS: u64 = 1u64 << T::DYADIC_LEVELS;

    /// The increment of the flow over 2^j units of `regime` from `z`.
    #[inline(always)]
    fn flow_increment(&self, regime: Regime, j: usize, z: &[T; NS]) -> [T; NS] {
        let f = &self.flows[regime.index()].as_ref()[j];
        if regime != Regime::Stick && self.slip_sparse {
            increment_slip::<T, C>(f, z)
        } else {
            increment::<T, C>(f, z)
        }
    }

    /// Whether the slip flows have slip's block zeros in the table, exactly (the slip step then
    /// skips them; see `increment_slip`).
    pub fn slip_flows_are_block_sparse(&self) -> bool {
        self.slip_sparse
    }

    /// The composition's name ("band", "stribeck", "stribeck+band").
    pub fn composition(&self) -> &'static str {
        C::NAME
    }

    /// Bytes of the dyadic tables (flows and ETDRK4 vectors).
    pub fn table_bytes(&self) -> usize {
        core::mem::size_of::<[T::PerLevel<C::Flow<T>>; 3]>()
            + core::mem::size_of::<C::Etd<T>>()
            + core::mem::size_of::<C::NearFlows<T>>()
            + core::mem::size_of::<C::NearEtd<T>>()
    }

    /// Substeps per step.
    pub fn substeps(&self) -> u32 {
        self.n_sub
    }

    /// The step dt [s].
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Whether these tables carry the floating pad (y, y').
    pub fn floating(&self) -> bool {
        C::FLOAT
    }

    /// The state a run starts in: `z0` (the state the tables were built for: see
    /// [`Self::init_in`]), in stick, at step 0, no halt, no transitions: every field a step
    /// changes, as the set-up leaves it.
    pub fn start_state(&self, z0: [T; NS]) -> Model2State<T> {
        let mut s = Model2State::at(z0);
        self.restart(&mut s, z0);
        s
    }

    /// Back to the initial state `z0` ([`Self::start_state`]), the tables untouched: the rig's
    /// lockstep model restarts this way at each record's start, writing these few words of
    /// state and nothing else.
    pub fn restart(&self, s: &mut Model2State<T>, z0: [T; NS]) {
        s.z = z0;
        s.regime = Regime::Stick;
        s.head = None;
        s.step = 0;
        s.halted = None;
        s.transitions = 0;
        s.anchor_x = self.face_position(&z0);
        s.anchor_sub = 0;
        s.anchor_unit = T::zero();
        s.subs_done = 0;
        s.armed = false;
    }

    /// Replaces the state and regime of `s` (e.g. to start from steady sliding). In stick the
    /// sliding velocity is set to zero as on entry to stick. Without the band, u and u' are
    /// set to 0.
    pub fn set_state(&self, s: &mut Model2State<T>, z: [T; NS], regime: Regime) {
        s.z = z;
        if !C::BAND || !self.scene_band {
            s.z[4] = T::zero();
            s.z[5] = T::zero();
        }
        if !C::FLOAT {
            s.z[Y] = T::zero();
            s.z[Y + 1] = T::zero();
        }
        s.regime = regime;
        s.head = None;
        // a state set in slip is taken as a slip under way
        s.armed = true;
        if regime == Regime::Stick {
            let mut z = s.z;
            self.enter_stick(&mut z);
            s.z = z;
            s.anchor_x = self.face_position(&z);
            s.anchor_sub = s.subs_done;
            s.anchor_unit = T::zero();
        }
        s.halted = None;
    }

    /// Sliding velocity v = x' (+ s w phi' with the face) - V - u' [m/s].
    #[inline(always)]
    pub fn sliding_velocity(&self, z: &[T; NS]) -> T {
        // r_v = [0, 1, 0, s w (face), 0, -1 (band), -V]: the same value as its row product
        if C::FACE {
            let pad = z[1] + self.r_v[3] * z[3];
            if C::BAND {
                (pad - z[5]) + self.r_v[ONE]
            } else {
                pad + self.r_v[ONE]
            }
        } else if C::BAND {
            (z[1] - z[5]) + self.r_v[ONE]
        } else {
            z[1] + self.r_v[ONE]
        }
    }

    /// Normal force N [N] (r_n = [0, 0, c_N, 0, 0, 0, N_0]: c_N phi with rotation, N_0
    /// without).
    #[inline(always)]
    pub fn normal_force(&self, z: &[T; NS]) -> T {
        if C::FLOAT {
            // N = (k_L + k_T) y + c_N phi
            self.r_n[2] * z[2] + self.r_n[Y] * z[Y]
        } else {
            self.r_n[2] * z[2] + self.r_n[ONE]
        }
    }

    /// Friction force on the pad [N] in `regime` at `z`.
    pub fn friction_force(&self, regime: Regime, z: &[T; NS]) -> T {
        match regime {
            Regime::Stick => dot::<T, C>(&self.r_freq, z),
            _ => {
                let n = self.normal_force(z);
                let sigma = T::from_f64(regime.friction_sign());
                let mu = if C::STRIBECK {
                    self.mu_s - self.d_mu + self.d_mu * self.excess(z).e
                } else {
                    self.mu_s - self.d_mu
                };
                sigma * mu * n
            }
        }
    }

    /// The friction's falling part at `z` (Stribeck): y, exp(-y^delta), N.
    #[inline(always)]
    fn excess(&self, z: &[T; NS]) -> Excess<T> {
        let v = self.sliding_velocity(z);
        let y = v.abs() * self.inv_v_s;
        let e = if self.delta_is_one {
            (-y).exp()
        } else if y > T::zero() {
            (-(y.powf(self.delta))).exp()
        } else {
            T::one()
        };
        Excess { v, y, e, n: self.normal_force(z) }
    }

    /// Stribeck forcing q = sigma (mu(|v|) - mu_k) N from the falling part at a point. With
    /// sigma = +-1, sigma (d_mu e) is (sigma d_mu) e exactly (rounding is symmetric in sign):
    /// the sign goes on the constant, off the chain from e to q.
    #[inline(always)]
    fn q_of(&self, sigma: T, ex: &Excess<T>) -> T {
        (sigma * self.d_mu) * ex.e * ex.n
    }

    /// z' in `regime` at `z`.
    pub fn derivative(&self, regime: Regime, z: &[T; NS]) -> [T; NS] {
        let a = &self.a[regime.index()];
        let mut d: [T; NS] = core::array::from_fn(|r| dot::<T, C>(&a[r], z));
        if C::STRIBECK && regime != Regime::Stick {
            let q = self.q_of(T::from_f64(regime.friction_sign()), &self.excess(z));
            for (r, v) in d.iter_mut().enumerate() {
                *v += self.b[r] * q;
            }
        }
        d
    }

    /// The pad's acceleration x'' [m/s^2] at the state and regime of `s`: row 1 of
    /// [`Self::derivative`] bit for bit, with the friction's falling part the stepper carries
    /// from the last chunk (no exponential) when it has it (a run's per-step samples).
    pub fn pad_acceleration(&self, s: &Model2State<T>) -> T {
        let z = &s.z;
        let regime = s.regime;
        let mut d = dot::<T, C>(&self.a[regime.index()][1], z);
        if C::STRIBECK && regime != Regime::Stick {
            let ex = match s.head {
                Some(ex) => ex,
                None => self.excess(z),
            };
            d += self.b[1] * self.q_of(T::from_f64(regime.friction_sign()), &ex);
        }
        d
    }

    #[inline(always)]
    fn is_stribeck_slip(regime: Regime) -> bool {
        C::STRIBECK && regime != Regime::Stick
    }
}

impl<T: Real> Model2State<T> {
    /// A state at `z0` with every other field zero, in stick ([`Model2Tables::start_state`]
    /// completes it).
    pub(super) fn at(z0: [T; NS]) -> Self {
        Model2State {
            z: z0,
            regime: Regime::Stick,
            head: None,
            step: 0,
            halted: None,
            transitions: 0,
            anchor_x: T::zero(),
            anchor_sub: 0,
            anchor_unit: T::zero(),
            subs_done: 0,
            armed: false,
        }
    }

    /// The state vector z (SI: m, m/s, rad, rad/s; see [`crate::model2::system`]).
    pub fn z(&self) -> [T; NS] {
        self.z
    }

    pub fn regime(&self) -> Regime {
        self.regime
    }

    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.step
    }

    pub fn halted(&self) -> Option<Halt> {
        self.halted
    }

    /// Transitions so far.
    pub fn transitions(&self) -> u64 {
        self.transitions
    }
}
