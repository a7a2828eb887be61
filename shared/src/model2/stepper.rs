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
//!   there.
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

use crate::coefficients::Coefficients;
use crate::halt::{Halt, Limits};
use crate::linalg::{self, MatN};
use crate::model2::composition::{Composition, EtdVectors, NEAR_FLOW_LEVELS, NEAR_LEVELS, NEAR_OPS};
use crate::model2::system::{row_dot, row_dot_all, System, NA, NS, ONE, Y};
use crate::real::Real;
use crate::scene::{Scene, SceneError};
use crate::stickslip::Regime;

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
/// entries it moves; without the band, u and u' stay 0 and are not touched).
#[inline(always)]
fn increment<T: Real, C: Composition>(f: &C::Flow<T>, z: &[T; NS]) -> [T; NS] {
    let f = f.as_ref();
    let mut out = [T::zero(); NS];
    if C::FLOAT {
        for (r, o) in out.iter_mut().enumerate() {
            let row = &f[r * 9..r * 9 + 9];
            *o = row[0] * z[0]
                + row[1] * z[1]
                + row[2] * z[2]
                + row[3] * z[3]
                + row[4] * z[4]
                + row[5] * z[5]
                + row[6] * z[6]
                + row[7] * z[7]
                + row[8];
        }
    } else if C::BAND {
        for (r, o) in out.iter_mut().take(6).enumerate() {
            let row = &f[r * 7..r * 7 + 7];
            *o = row[0] * z[0] + row[1] * z[1] + row[2] * z[2] + row[3] * z[3] + row[4] * z[4] + row[5] * z[5] + row[6];
        }
    } else {
        for (r, o) in out.iter_mut().take(4).enumerate() {
            let row = &f[r * 5..r * 5 + 5];
            *o = row[0] * z[0] + row[1] * z[1] + row[2] * z[2] + row[3] * z[3] + row[4];
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
fn increment_slip<T: Real, C: Composition>(f: &C::Flow<T>, z: &[T; NS]) -> [T; NS] {
    let f = f.as_ref();
    let mut out = [T::zero(); NS];
    let n = C::COLS;
    let one = n - 1;
    for r in 0..2 {
        let row = &f[r * n..r * n + n];
        out[r] = row[0] * z[0] + row[1] * z[1] + row[2] * z[2] + row[3] * z[3] + row[one];
    }
    for r in 2..4 {
        let row = &f[r * n..r * n + n];
        out[r] = row[2] * z[2] + row[3] * z[3] + row[one];
    }
    if C::BAND {
        for r in 4..6 {
            let row = &f[r * n..r * n + n];
            out[r] = row[2] * z[2] + row[3] * z[3] + row[4] * z[4] + row[5] * z[5] + row[one];
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
    let n = C::COLS;
    let zero = |r: usize, c: usize| f[r * n + c] == T::zero();
    let mut ok = true;
    for r in 0..C::ROWS {
        let skipped: &[usize] = match r {
            0 | 1 => &[4, 5],
            2 | 3 => &[0, 1, 4, 5],
            _ => &[0, 1],
        };
        for &c in skipped {
            if c < n - 1 {
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
pub struct Segment2<T> {
    pub regime: Regime,
    /// Start and end time [s].
    pub t0: f64,
    pub t1: f64,
    pub z0: [T; NS],
    pub z1: [T; NS],
    /// z' at both ends (only filled for observers that ask, [`Observer2::DERIVATIVES`]).
    pub zd0: [T; NS],
    pub zd1: [T; NS],
}

/// A change of regime of model 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transition2<T> {
    pub t: f64,
    pub from: Regime,
    pub to: Regime,
    /// State on entry to the new regime.
    pub z: [T; NS],
}

/// Sees every segment and transition of a model-2 run.
pub trait Observer2<T: Real> {
    /// Whether segments need z' at their ends (costs two evaluations per segment).
    const DERIVATIVES: bool = true;
    fn segment(&mut self, _seg: &Segment2<T>) {}
    fn transition(&mut self, _tr: &Transition2<T>) {}
}

impl<T: Real> Observer2<T> for () {
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

/// The model-2 stepper, generic over f32 and f64 and over its [`Composition`].
#[derive(Clone, Copy, Debug)]
pub struct Model2Stepper<T: Real, C: Composition> {
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
    /// h_sub and h_sub / 2^L in T.
    h_t: T,
    hu_t: T,
    /// The guards' rows ([`guard_slot`]; fire at row . z >= 0), in T.
    guards: [[T; NA]; 4],
    /// Whether the current slip's return to v = 0 is watched (see `substep`).
    armed: bool,
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

impl<T: Real, C: Composition> Model2Stepper<T, C> {
    const LEVELS: usize = T::DYADIC_LEVELS;
    const UNITS: u64 = 1u64 << T::DYADIC_LEVELS;

    /// Validates `scene` (and that it asks for composition `C`) and starts at rest in stick:
    /// x = 0, x' = V, phi = F_N a_N / K, phi' = 0, u = u' = 0.
    pub fn new(scene: &Scene) -> Result<Self, SceneError> {
        let mut slot = None;
        Self::init_in(&mut slot, scene)?;
        match slot {
            Some(s) => Ok(s),
            None => unreachable!("init_in returned Ok without filling the slot"),
        }
    }

    /// [`Self::new`] built in `slot` (e.g. a `static`): the dyadic tables (kilobytes in f32)
    /// are filled where they stay, not on the stack and then moved, which a Cortex-M4F's stack
    /// cannot hold twice (tests/on-target bin `count_model2` prints the stack it takes). The
    /// same values as [`Self::new`]. On an error `slot` is left as it was.
    #[allow(clippy::needless_range_loop)] // matrix code: indices read as the formulas
    pub fn init_in<'a>(slot: &'a mut Option<Self>, scene: &Scene) -> Result<&'a mut Self, SceneError> {
        scene.validate()?;
        C::matches(scene)?;
        let co = Coefficients::of(scene);
        // (compile-time choice: a hinged composition's build has no floating-pad set-up)
        let sys = if C::FLOAT { System::floating_pad(scene, &co) } else { System::hinged(scene, &co) };
        let rate = if C::FLOAT { sys.floating_rate(scene, &co) } else { sys.hinged_rate(scene, &co) };
        let mut n_sub = libm::ceil(scene.dt * rate / 0.25);
        if !(n_sub >= 1.0) {
            n_sub = 1.0;
        }
        if n_sub > 1e6 {
            n_sub = 1e6;
        }
        let n_sub = n_sub as u32;
        let h_sub = scene.dt / n_sub as f64;
        let t = T::from_f64;
        let tv = |r: &[f64; NA]| -> [T; NA] { core::array::from_fn(|i| t(r[i])) };
        let z = [T::zero(), t(scene.v), t(sys.phi0), T::zero(), T::zero(), T::zero(), t(sys.y0), T::zero()];
        // the guards' rows in f64 and their rates row . A, row . b
        let mut guard_rate = [[T::zero(); NA]; 4];
        let mut guard_rate_b = [T::zero(); 4];
        for (regime, which) in [(Regime::Stick, 0), (Regime::Stick, 1), (Regime::SlipSlower, 0), (Regime::SlipFaster, 0)] {
            let g: [f64; NA] = match (regime, which) {
                (Regime::Stick, 0) => core::array::from_fn(|c| sys.r_freq[c] - scene.mu_s * sys.r_n[c]),
                (Regime::Stick, _) => core::array::from_fn(|c| -sys.r_freq[c] - scene.mu_s * sys.r_n[c]),
                (Regime::SlipSlower, _) => sys.r_v,
                (Regime::SlipFaster, _) => core::array::from_fn(|c| -sys.r_v[c]),
            };
            let a = &sys.a[regime.index()];
            let k = guard_slot(regime, which);
            for c in 0..NA {
                let mut acc = 0.0;
                for r in 0..NA {
                    acc += g[r] * a[r][c];
                }
                guard_rate[k][c] = t(acc);
            }
            if sys.stribeck && regime != Regime::Stick {
                guard_rate_b[k] = t((0..NA).map(|r| g[r] * sys.b[r]).sum());
            }
        }
        // the falling slope at v = 0 with N = N_0, (mu_s - mu_k) N_0 / v_s [N s/m], and its rate
        let near_kv = sys.d_mu * sys.n0 / scene.v_s;
        let near_rate = near_kv * sys.inv_mass_v;
        let near_on = C::STRIBECK && scene.stribeck_exponent == 1.0 && near_rate * h_sub <= NEAR_RATE_H_MAX;
        let near_c: [T; NEAR_OPS + 1] = core::array::from_fn(|k| t(k as f64 / NEAR_OPS as f64));
        let near_cn0: [T; NEAR_OPS + 1] = core::array::from_fn(|k| t(sys.n0 * k as f64 / NEAR_OPS as f64));
        let near_thr: [T; NEAR_OPS] = core::array::from_fn(|k| t(sys.n0 * (k as f64 + 0.5) / NEAR_OPS as f64));
        let near_ckv: [T; NEAR_OPS + 1] = core::array::from_fn(|k| t(k as f64 / NEAR_OPS as f64 * near_kv));
        let s = slot.insert(Model2Stepper {
            flows: [T::per_level(C::zero_flow()); 3],
            etd: C::zero_etd(),
            near_flows: C::zero_near(),
            near_etd: C::zero_near_etd(),
            near_on,
            near_c,
            near_cn0,
            near_thr,
            near_ckv,
            a: [[[T::zero(); NA]; NS]; 3],
            b: core::array::from_fn(|i| t(sys.b[i])),
            r_v: tv(&sys.r_v),
            r_n: tv(&sys.r_n),
            r_freq: tv(&sys.r_freq),
            guard_rate,
            guard_rate_b,
            mu_s: t(scene.mu_s),
            d_mu: t(sys.d_mu),
            inv_v_s: t(1.0 / scene.v_s),
            delta: t(scene.stribeck_exponent),
            delta_is_one: scene.stribeck_exponent == 1.0,
            v: t(scene.v),
            m: t(scene.m),
            m_b: t(scene.m_b),
            scene_band: sys.band,
            springs: [sys.k_l, sys.d_l, sys.k_t, sys.d_t],
            limits: Limits::new(scene, &co),
            u_limit: t(U_LIMIT),
            udot_limit: t(UDOT_LIMIT),
            h_sub,
            n_sub,
            dt: scene.dt,
            z,
            regime: Regime::Stick,
            head: None,
            step: 0,
            halted: None,
            transitions: 0,
            anchor_x: T::zero(),
            anchor_sub: 0,
            anchor_unit: T::zero(),
            subs_done: 0,
            h_t: t(h_sub),
            hu_t: t(libm::ldexp(h_sub, -(Self::LEVELS as i32))),
            guards: core::array::from_fn(|k| {
                let (sign, mu) = match k {
                    0 => (1.0, scene.mu_s),
                    1 => (-1.0, scene.mu_s),
                    2 => (1.0, 0.0),
                    _ => (-1.0, 0.0),
                };
                core::array::from_fn(|c| {
                    if k < 2 {
                        t(sign * sys.r_freq[c] - mu * sys.r_n[c])
                    } else {
                        t(sign * sys.r_v[c])
                    }
                })
            }),
            armed: false,
            v_round: t(libm::ldexp(scene.v, 8 - Self::LEVELS as i32)),
            rate_coef: t(sys.d_mu * scene.stribeck_exponent / scene.v_s * sys.inv_mass_v),
            rate_limit: T::per_level(T::zero()),
            slip_sparse: false,
            float_limits: {
                // a rounding-level negative compression is not a lift-off (as phi_floor)
                let floor = |d: f64| -(1e-6 * libm::fabs(sys.y0 + d * sys.phi0) + 1e-12);
                [t(sys.d_l), t(sys.d_t), t(floor(sys.d_l)), t(floor(sys.d_t)), t(Y_LIMIT), t(YDOT_LIMIT)]
            },
        });
        for (j, r) in s.rate_limit.as_mut().iter_mut().enumerate() {
            *r = t(STRIBECK_RATE_H / (h_sub * libm::ldexp(1.0, j as i32 - Self::LEVELS as i32)));
        }
        // the stick anchor of the start (x = 0; with the face x + s w phi_0)
        s.anchor_x = s.face_position(&s.z);
        s.fill_tables(scene, &sys);
        s.slip_sparse = !C::FLOAT
            && [Regime::SlipSlower, Regime::SlipFaster]
            .iter()
            .all(|r| s.flows[r.index()].as_ref().iter().all(|f| has_slip_zeros::<T, C>(f)));
        Ok(s)
    }

    /// Fills the dyadic tables (flows, ETDRK4 vectors, near operators) of a stepper whose
    /// other fields are set. Out of line: `init_in` then builds its value in the slot rather
    /// than on the stack (with the loops in its frame, the M4F's build of the whole stepper went
    /// through a copy on the stack).
    #[inline(never)]
    #[allow(clippy::needless_range_loop)] // matrix code: indices read as the formulas
    fn fill_tables(&mut self, scene: &Scene, sys: &System) {
        let h_sub = self.h_sub;
        let t = T::from_f64;
        // the flow's columns: the moved entries, then the constant 1
        let cols: [usize; NA] = if C::FLOAT {
            [0, 1, 2, 3, 4, 5, 6, 7, ONE]
        } else if C::BAND {
            [0, 1, 2, 3, 4, 5, ONE, ONE, ONE]
        } else {
            [0, 1, 2, 3, ONE, ONE, ONE, ONE, ONE]
        };
        for regime in Regime::ALL {
            let a = &sys.a[regime.index()];
            let with_phi = C::STRIBECK && regime != Regime::Stick;
            // the kinetic operator (k = 0) on every level, then the near operators A + b g_k,
            // g_k = c_k sigma (mu_s - mu_k) (r_n - N_0 sign(v) r_v / v_s) (sign(v) = -sigma in
            // slip), on the top NEAR_LEVELS levels
            let near_ops = if with_phi && self.near_on { NEAR_OPS } else { 0 };
            let top = Self::LEVELS + 1 - NEAR_LEVELS;
            let kinetic = (0..=Self::LEVELS).map(|j| (0, j));
            let near = (1..=near_ops).flat_map(|k| (top..=Self::LEVELS).map(move |j| (k, j)));
            // e^(tau A) tau phi_1(tau A) b of the previous level in the same chain (operator
            // k): the final combination's w0 at level j carries it (see `etd_chunk`)
            let mut half = [0.0f64; NS];
            for (k, j) in kinetic.chain(near) {
                if j == if k == 0 { 0 } else { top } {
                    // a chain's lowest level is never a chunk's w (a chunk of 2^j units reads
                    // level j >= 1 here, and j - 1 for phi_1)
                    half = [0.0; NS];
                }
                let a_k: [[f64; NA]; NA] = if k == 0 {
                    *a
                } else {
                    let sigma = regime.friction_sign();
                    let c_k = k as f64 / NEAR_OPS as f64;
                    let g: [f64; NA] = core::array::from_fn(|c| {
                        c_k * sigma * sys.d_mu * (sys.r_n[c] + sigma * sys.n0 / scene.v_s * sys.r_v[c])
                    });
                    core::array::from_fn(|r| core::array::from_fn(|c| a[r][c] + sys.b[r] * g[c]))
                };
                let a = &a_k;
                let near_index = (k.max(1) - 1) * 2 + regime.index().max(1) - 1;
                let tau = h_sub * libm::ldexp(1.0, j as i32 - Self::LEVELS as i32);
                // (a near operator's top level has ETDRK4 vectors but no flow)
                let flow: &mut [T] = if k == 0 {
                    self.flows[regime.index()].as_mut()[j].as_mut()
                } else if j < Self::LEVELS {
                    self.near_flows.as_mut()[near_index * NEAR_FLOW_LEVELS + j - top].as_mut()
                } else {
                    &mut []
                };
                let e = if with_phi {
                    // [[A, b, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0]] * tau
                    let mut m: MatN<{ NA + 3 }> = [[0.0; NA + 3]; NA + 3];
                    for r in 0..NA {
                        m[r][..NA].copy_from_slice(&a[r]);
                        m[r][NA] = sys.b[r];
                    }
                    m[NA][NA + 1] = 1.0;
                    m[NA + 1][NA + 2] = 1.0;
                    linalg::expm_minus_identity(&linalg::scale(&m, tau))
                } else {
                    let e9 = linalg::expm_minus_identity(&linalg::scale(a, tau));
                    let mut e: MatN<{ NA + 3 }> = [[0.0; NA + 3]; NA + 3];
                    for r in 0..NA {
                        e[r][..NA].copy_from_slice(&e9[r]);
                    }
                    e
                };
                for (i, f) in flow.iter_mut().enumerate() {
                    *f = t(e[i / C::COLS][cols[i % C::COLS]]);
                }
                if with_phi {
                    let v: &mut EtdVectors<C::Row<T>> = if k > 0 {
                        &mut self.near_etd.as_mut()[near_index * NEAR_LEVELS + j - top]
                    } else {
                        &mut self.etd.as_mut()[regime.index() - 1].as_mut()[j]
                    };
                    for r in 0..C::ROWS {
                        let (c1, c2, c3) = (e[r][NA], e[r][NA + 1] / tau, e[r][NA + 2] / (tau * tau));
                        v.phi1[r] = t(c1);
                        v.w0[r] = t(c1 - 3.0 * c2 + 4.0 * c3 - half[r]);
                        v.wab[r] = t(2.0 * c2 - 4.0 * c3);
                        v.wc[r] = t(4.0 * c3 - c2);
                    }
                    // this level's e^(tau A) tau phi_1(tau A) b for the next (e holds
                    // e^(tau A) - I, its column NA tau phi_1(tau A) b)
                    half = core::array::from_fn(|r| e[r][NA] + (0..C::ROWS).map(|c| e[r][c] * e[c][NA]).sum::<f64>());
                }
            }
            for r in 0..NS {
                for c in 0..NA {
                    self.a[regime.index()][r][c] = t(sys.a[regime.index()][r][c]);
                }
            }
        }
    }

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
    pub fn state(&self) -> [T; NS] {
        self.z
    }
    pub fn regime(&self) -> Regime {
        self.regime
    }
    pub fn steps(&self) -> u64 {
        self.step
    }
    pub fn time(&self) -> f64 {
        self.step as f64 * self.dt
    }
    pub fn halted(&self) -> Option<Halt> {
        self.halted
    }
    /// Transitions so far.
    pub fn transitions(&self) -> u64 {
        self.transitions
    }
    /// Substeps per step.
    pub fn substeps(&self) -> u32 {
        self.n_sub
    }
    /// Whether this stepper carries the floating pad (y, y').
    pub fn floating(&self) -> bool {
        C::FLOAT
    }

    /// Replaces the state and regime (e.g. to start from steady sliding). In stick the sliding
    /// velocity is set to zero as on entry to stick. Without the band, u and u' are set to 0.
    pub fn set_state(&mut self, z: [T; NS], regime: Regime) {
        self.z = z;
        if !C::BAND || !self.scene_band {
            self.z[4] = T::zero();
            self.z[5] = T::zero();
        }
        if !C::FLOAT {
            self.z[Y] = T::zero();
            self.z[Y + 1] = T::zero();
        }
        self.regime = regime;
        self.head = None;
        // a state set in slip is taken as a slip under way
        self.armed = true;
        if regime == Regime::Stick {
            let mut z = self.z;
            self.enter_stick(&mut z);
            self.z = z;
            self.anchor_x = self.face_position(&z);
            self.anchor_sub = self.subs_done;
            self.anchor_unit = T::zero();
        }
        self.halted = None;
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

    /// Stribeck forcing q = sigma (mu(|v|) - mu_k) N from the falling part at a point.
    #[inline(always)]
    fn q_of(&self, sigma: T, ex: &Excess<T>) -> T {
        sigma * (self.d_mu * ex.e) * ex.n
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

    #[inline(always)]
    fn is_stribeck_slip(regime: Regime) -> bool {
        C::STRIBECK && regime != Regime::Stick
    }

    /// The flow over 2^j units in `regime` from `z` (exact in linear regimes; ETDRK4 in
    /// Stribeck slip, which needs j >= 1).
    fn chunk(&self, regime: Regime, j: usize, z: &[T; NS]) -> [T; NS] {
        if Self::is_stribeck_slip(regime) {
            self.chunk_from(regime, j, z, &self.excess(z))
        } else {
            let d = self.flow_increment(regime, j, z);
            core::array::from_fn(|r| z[r] + d[r])
        }
    }

    /// The lowest level a chunk can take a near operator at (it reads levels j - 1 and j).
    const NEAR_MIN_LEVEL: usize = T::DYADIC_LEVELS + 2 - NEAR_LEVELS;

    /// The operator a Stribeck slip chunk of 2^j units starting at the falling part `ex`
    /// takes: k = 0, the kinetic one, where the falling slope's rate fits the chunk
    /// (rate x chunk <= 1/4, see `chunk_level`) or no near operator exists; otherwise a near
    /// one, k = 1 .. NEAR_OPS, the one whose slope c_k N_0 / v_s is nearest the friction's,
    /// N e / v_s (delta = 1), so that the forcing's residual slope |N e - c_k N_0| / v_s is at
    /// most N_0 / (2 NEAR_OPS v_s) (for N e <= (1 + 1 / (2 NEAR_OPS)) N_0). The kinetic one is
    /// preferred because its flows are block-sparse in slip (cheaper on the M4F). Near operators
    /// exist on the top levels only; below, a chunk is short enough for the kinetic one.
    #[inline(always)]
    fn near_op(&self, ex: &Excess<T>, j: usize) -> usize {
        let mut k = 0;
        if self.near_on && j >= Self::NEAR_MIN_LEVEL {
            let ne = ex.n * ex.e;
            if self.rate_coef * ne.abs() > self.rate_limit.as_ref()[j] {
                while k < NEAR_OPS && ne > self.near_thr[k] {
                    k += 1;
                }
            }
        }
        k
    }

    /// The forcing of near operator k's split: q - g_k (z, 1)
    /// = sigma (mu_s - mu_k) N (e - c_k) - c_k (mu_s - mu_k) N_0 v / v_s.
    #[inline(always)]
    fn q_near(&self, sigma: T, ex: &Excess<T>, k: usize) -> T {
        sigma * (self.d_mu * (ex.e - self.near_c[k])) * ex.n - self.near_ckv[k] * ex.v
    }

    /// ETDRK4 (Cox-Matthews) over 2^j units of Stribeck slip from `z`, with the falling part
    /// `ex0` at `z`: about the kinetic operator A with forcing q, or near v = 0
    /// ([`Self::near_op`]) about A + b g_k with forcing q - g_k (z, 1). Both are z' = A z + b q;
    /// the split decides how much of the falling slope the exponential carries exactly.
    #[inline(always)]
    fn chunk_from(&self, regime: Regime, j: usize, z: &[T; NS], ex0: &Excess<T>) -> [T; NS] {
        self.chunk_with(regime, j, z, ex0, self.near_op(ex0, j))
    }

    /// [`Self::chunk_from`] with its operator k (0 kinetic, else near) already chosen.
    fn chunk_with(&self, regime: Regime, j: usize, z: &[T; NS], ex0: &Excess<T>, k: usize) -> [T; NS] {
        if k > 0 {
            self.etd_chunk::<true>(regime, j, z, ex0, k)
        } else {
            self.etd_chunk::<false>(regime, j, z, ex0, 0)
        }
    }

    /// The forcing of an ETDRK4 chunk: q, or with near operator k its residual.
    #[inline(always)]
    fn etd_q<const NEAR: bool>(&self, sigma: T, ex: &Excess<T>, k: usize) -> T {
        if NEAR {
            self.q_near(sigma, ex, k)
        } else {
            self.q_of(sigma, ex)
        }
    }

    /// The flow increment over 2^j units of a chunk's operator (a near operator's flows are on
    /// levels L - NEAR_LEVELS + 1 ..= L - 1).
    #[inline(always)]
    fn etd_inc<const NEAR: bool>(&self, regime: Regime, j: usize, z: &[T; NS], near_index: usize) -> [T; NS] {
        if NEAR {
            let top = T::DYADIC_LEVELS + 1 - NEAR_LEVELS;
            increment::<T, C>(&self.near_flows.as_ref()[near_index * NEAR_FLOW_LEVELS + j - top], z)
        } else {
            self.flow_increment(regime, j, z)
        }
    }

    #[inline(always)]
    fn etd_chunk<const NEAR: bool>(&self, regime: Regime, j: usize, z: &[T; NS], ex0: &Excess<T>, k: usize) -> [T; NS] {
        let rows = C::ROWS;
        let sigma = T::from_f64(regime.friction_sign());
        let near_index = (k.max(1) - 1) * 2 + regime.index() - 1;
        let top = T::DYADIC_LEVELS + 1 - NEAR_LEVELS;
        let (ph, w) = if NEAR {
            let etd = &self.near_etd.as_ref()[near_index * NEAR_LEVELS..(near_index + 1) * NEAR_LEVELS];
            (&etd[j - 1 - top].phi1, &etd[j - top])
        } else {
            let etd = self.etd.as_ref()[regime.index() - 1].as_ref();
            (&etd[j - 1].phi1, &etd[j])
        };
        // (methods, not closures: a closure here was compiled out of line on the M4F, three calls
        // per chunk)
        let q0 = self.etd_q::<NEAR>(sigma, ex0, k);
        let eh = self.etd_inc::<NEAR>(regime, j - 1, z, near_index);
        let da: [T; NS] = core::array::from_fn(|r| if r < rows { eh[r] + ph[r] * q0 } else { T::zero() });
        let a: [T; NS] = core::array::from_fn(|r| z[r] + da[r]);
        let qa = self.etd_q::<NEAR>(sigma, &self.excess(&a), k);
        let bb: [T; NS] = core::array::from_fn(|r| if r < rows { z[r] + (eh[r] + ph[r] * qa) } else { z[r] });
        let qb = self.etd_q::<NEAR>(sigma, &self.excess(&bb), k);
        let ea = self.etd_inc::<NEAR>(regime, j - 1, &a, near_index);
        let two = T::one() + T::one();
        let qcb = two * qb - q0;
        let c: [T; NS] = core::array::from_fn(|r| if r < rows { a[r] + (ea[r] + ph[r] * qcb) } else { z[r] });
        let qc = self.etd_q::<NEAR>(sigma, &self.excess(&c), k);
        let qab = qa + qb;
        // the chunk's linear flow from z, e^(hA) z (affine), is the half flow from a less
        // e^(hA/2) ph q0: w0 carries that term (see `fill_tables`), which saves one flow
        // application. Summed from z, not from a, so that a's rounding stays out of z1.
        core::array::from_fn(|r| {
            if r < rows {
                z[r] + (da[r] + ea[r] + w.w0[r] * q0 + w.wab[r] * qab + w.wc[r] * qc)
            } else {
                z[r]
            }
        })
    }

    /// The smallest level a transition is located to in `regime`.
    fn min_level(regime: Regime) -> usize {
        if Self::is_stribeck_slip(regime) {
            1
        } else {
            0
        }
    }

    /// The level of the next chunk with `remaining` units left in the substep: the largest
    /// power of two that fits, limited in Stribeck slip by the friction slope's rate at the
    /// chunk's start (from its falling part `ex`); and the chunk's operator there
    /// ([`Self::near_op`]; 0 outside Stribeck slip).
    fn chunk_level(&self, ex: Option<&Excess<T>>, remaining: u64) -> (usize, usize) {
        let mut j = 63 - remaining.leading_zeros() as usize; // largest 2^j <= remaining
        let mut k = 0;
        if let Some(ex) = ex {
            // the falling slope's rate, |dq/dv| (1/m + 1/m_b), in T (no f64 on the M4F's path)
            let y = ex.y;
            let shape = if self.delta_is_one {
                ex.e
            } else if y > T::zero() {
                y.powf(self.delta - T::one()) * ex.e
            } else if self.delta > T::one() {
                T::zero()
            } else {
                let r0 = self.rate_limit.as_ref()[0];
                r0 * r0 // delta < 1: infinite slope at v = 0
            };
            let far = self.rate_coef * shape * ex.n.abs();
            let floor = (Self::LEVELS.saturating_sub(STRIBECK_REFINE)).max(1);
            let limits = self.rate_limit.as_ref();
            loop {
                // with a near operator, the residual slope of its split (delta = 1: shape = e)
                k = self.near_op(ex, j);
                let rate = if k > 0 { self.rate_coef * (ex.n * ex.e - self.near_cn0[k]).abs() } else { far };
                if j > floor && rate > limits[j] {
                    j -= 1;
                } else {
                    break;
                }
            }
            // (j >= floor >= 1 unless fewer than 2 units remain, where k = 0 on either level)
            j = j.max(1);
        }
        (j, k)
    }

    /// The guards of `regime` as rows (fire at row . z >= 0): stick, F_req -+ mu_s N; slip
    /// slower, v; slip faster, -v.
    #[inline(always)]
    fn guard(&self, regime: Regime, which: usize) -> &[T; NA] {
        &self.guards[guard_slot(regime, which)]
    }

    fn guard_count(regime: Regime) -> usize {
        if regime == Regime::Stick {
            2
        } else {
            1
        }
    }

    /// The rate of guard `which` at `z` (row . z'), with the falling part `ex` at `z` in
    /// Stribeck slip.
    #[inline(always)]
    fn guard_slope(&self, regime: Regime, which: usize, z: &[T; NS], ex: Option<&Excess<T>>) -> T {
        let k = guard_slot(regime, which);
        let lin = dot::<T, C>(&self.guard_rate[k], z);
        match ex {
            Some(ex) if Self::is_stribeck_slip(regime) => {
                lin + self.guard_rate_b[k] * self.q_of(T::from_f64(regime.friction_sign()), ex)
            }
            _ => lin,
        }
    }

    /// Binary lifting over [from, to): the last probed point p such that `holds` is true at
    /// every accepted point, starting from chunks of 2^top units. Never evaluated at `from`.
    fn lift(&self, regime: Regime, z: &[T; NS], from: u64, to: u64, top: usize, mut holds: impl FnMut(&[T; NS]) -> bool) -> (u64, [T; NS]) {
        let mut pos = from;
        let mut cur = *z;
        let lo = Self::min_level(regime);
        let mut j = top;
        loop {
            let step = 1u64 << j;
            if pos + step < to {
                let cand = self.chunk(regime, j, &cur);
                if holds(&cand) {
                    pos += step;
                    cur = cand;
                }
            }
            if j <= lo {
                break;
            }
            j -= 1;
        }
        (pos, cur)
    }

    /// Where guard `which` of `regime` first fires inside the chunk [pos, pos + 2^j] from z to
    /// z1: the last unit p where it still holds and the state there. Finds a crest (a guard
    /// that rises above zero and falls back inside the chunk) from its rate's sign change;
    /// `ex0`, `ex1`: the falling parts at z and z1 in Stribeck slip.
    #[allow(clippy::too_many_arguments)] // a chunk's two ends and what is known at them
    fn crossing(
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
            return Some(self.lift(regime, z, pos, end, j, |c| dot::<T, C>(&g, c) < T::zero()));
        }
        if j <= lo {
            return None;
        }
        if !(self.guard_slope(regime, which, z, ex0) > T::zero() && self.guard_slope(regime, which, z1, ex1) < T::zero()) {
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
        let (pc, zc) = self.lift(regime, z, pos, end, j, |c| slope(c) > T::zero());
        let after = self.chunk(regime, lo, &zc);
        let top = if dot::<T, C>(&g, &zc) < T::zero() && dot::<T, C>(&g, &after) < T::zero() {
            return None;
        } else {
            pc + (1u64 << lo)
        };
        Some(self.lift(regime, z, pos, top, j, |c| dot::<T, C>(&g, c) < T::zero()))
    }

    /// Sets the sliding velocity to zero on entry to stick: x' = V without the band; with it,
    /// pad and band take their common momentum velocity. With the face: the friction impulse
    /// p that stops the face, -v / (r_v . b), moves phi' (and u') by b p, and x' then takes
    /// the constraint's value exactly, x' = V + u' - s w phi' (with w = 0 and no band this is
    /// x' = V, as without the face).
    fn enter_stick(&self, z: &mut [T; NS]) {
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
    fn after_velocity_match(&self, z: &[T; NS]) -> Regime {
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

    fn time_at(&self, sub: u32, unit: u64) -> f64 {
        self.step as f64 * self.dt + (sub as f64 + unit as f64 / Self::UNITS as f64) * self.h_sub
    }

    #[allow(clippy::too_many_arguments)] // a segment's regime, place and two ends
    fn emit<O: Observer2<T>>(&self, obs: &mut O, regime: Regime, sub: u32, p0: u64, p1: u64, z0: [T; NS], z1: [T; NS]) {
        let (zd0, zd1) = if O::DERIVATIVES {
            (self.derivative(regime, &z0), self.derivative(regime, &z1))
        } else {
            ([T::zero(); NS], [T::zero(); NS])
        };
        obs.segment(&Segment2 { regime, t0: self.time_at(sub, p0), t1: self.time_at(sub, p1), z0, z1, zd0, zd1 });
    }

    /// One step of `dt` with no observer.
    pub fn step(&mut self) -> Result<usize, Halt> {
        self.step_observed(&mut ())
    }

    /// One step of `dt`; `obs` sees every segment and transition. Returns the number of
    /// transitions in the step.
    pub fn step_observed<O: Observer2<T>>(&mut self, obs: &mut O) -> Result<usize, Halt> {
        if let Some(h) = self.halted {
            return Err(h);
        }
        let mut count = 0;
        for sub in 0..self.n_sub {
            let short = if self.regime == Regime::Stick {
                Some(self.short_substep::<false, O>(sub, obs))
            } else if self.armed {
                Some(self.short_substep::<true, O>(sub, obs))
            } else {
                None
            };
            let first = if let Some(short) = short {
                match short {
                    Ok(None) => continue,
                    Ok(Some(first)) => Some(first),
                    Err(h) => {
                        self.halted = Some(h);
                        return Err(h);
                    }
                }
            } else {
                None
            };
            match self.substep(sub, obs, first) {
                Ok(n) => count += n,
                Err(h) => {
                    self.halted = Some(h);
                    return Err(h);
                }
            }
        }
        self.step += 1;
        Ok(count)
    }

    /// [`Self::step_observed`] with every substep on the general path (`substep`), never the
    /// short one (`short_substep`): for the test that the two agree bit for bit.
    #[doc(hidden)]
    pub fn step_observed_general<O: Observer2<T>>(&mut self, obs: &mut O) -> Result<usize, Halt> {
        if let Some(h) = self.halted {
            return Err(h);
        }
        let mut count = 0;
        for sub in 0..self.n_sub {
            match self.substep(sub, obs, None) {
                Ok(n) => count += n,
                Err(h) => {
                    self.halted = Some(h);
                    return Err(h);
                }
            }
        }
        self.step += 1;
        Ok(count)
    }

    /// The common substep on a short path: its first chunk (see [`Self::substep`]), and if
    /// that is the whole substep and no guard of the regime fires or crests inside it, the
    /// substep done (`Ok(None)`), exactly as `substep` would do it. Otherwise the chunk is
    /// handed to `substep` (`Ok(Some(..))`), which goes on from it. Not for a slip whose guard
    /// is not armed yet (`substep` handles the arming). `SLIP`: whether the regime is a slip
    /// (compiled apart for stick and slip: each has its own short path).
    #[inline(always)]
    fn short_substep<const SLIP: bool, O: Observer2<T>>(&mut self, sub: u32, obs: &mut O) -> Result<Option<FirstChunk<T>>, Halt> {
        let units = Self::UNITS;
        let regime = self.regime;
        let stribeck_slip = C::STRIBECK && SLIP;
        let z = self.z;
        let ex0 = if stribeck_slip {
            Some(match self.head {
                Some(ex) => ex,
                None => self.excess(&z),
            })
        } else {
            None
        };
        let (j, k) = self.chunk_level(ex0.as_ref(), units);
        let mut z1 = match &ex0 {
            Some(ex0) => self.chunk_with(regime, j, &z, ex0, k),
            None => self.chunk(regime, j, &z),
        };
        let ex1 = if stribeck_slip { Some(self.excess(&z1)) } else { None };
        let first = FirstChunk { ex0, j, z1, ex1 };
        if j != Self::LEVELS {
            return Ok(Some(first));
        }
        for which in 0..if SLIP { 1 } else { 2 } {
            // `crossing`'s tests: the guard still holds at z1 and does not crest in the chunk
            if !(dot::<T, C>(self.guard(regime, which), &z1) < T::zero())
                || (self.guard_slope(regime, which, &z, ex0.as_ref()) > T::zero()
                    && self.guard_slope(regime, which, &z1, ex1.as_ref()) < T::zero())
            {
                return Ok(Some(first));
            }
        }
        self.anchor_stick_x(regime, &mut z1, units);
        self.emit(obs, regime, sub, 0, units, z, z1);
        if let Err(h) = self.check(&z1, regime, sub, units) {
            self.head = None;
            return Err(h);
        }
        self.z = z1;
        self.head = ex1;
        self.subs_done += 1;
        Ok(None)
    }

    /// One substep: chunks, each tested for transitions, until the substep's end. `first`:
    /// the first chunk, when [`Self::short_substep`] has taken it already.
    fn substep<O: Observer2<T>>(&mut self, sub: u32, obs: &mut O, mut first: Option<FirstChunk<T>>) -> Result<usize, Halt> {
        let units = Self::UNITS;
        let mut pos = 0u64;
        let mut z = self.z;
        let mut regime = self.regime;
        // the falling part at z (Stribeck slip), when known
        let mut head = self.head.take();
        let mut transitions = 0usize;
        let mut events = 0u32;
        let mut touched: Option<(Regime, usize)> = None;
        while pos < units {
            let stribeck_slip = Self::is_stribeck_slip(regime);
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
            let unarmed = regime != Regime::Stick && !self.armed;
            for which in 0..Self::guard_count(regime) {
                if touched == Some((regime, which)) {
                    continue;
                }
                if unarmed && !(dot::<T, C>(self.guard(regime, 0), &z1) > self.v_round) {
                    continue;
                }
                if let Some((p, zp)) = self.crossing(regime, which, &z, pos, j, &z1, ex0.as_ref(), ex1.as_ref()) {
                    if best.is_none_or(|b| p < b.0) {
                        best = Some((p, zp, which));
                    }
                }
            }
            let Some((p, zp, which)) = best else {
                if unarmed && dot::<T, C>(self.guard(regime, 0), &z1) < -self.v_round {
                    self.armed = true;
                }
                let mut z1 = z1;
                self.anchor_stick_x(regime, &mut z1, pos + (1u64 << j));
                self.emit(obs, regime, sub, pos, pos + (1u64 << j), z, z1);
                pos += 1u64 << j;
                z = z1;
                head = ex1;
                self.check(&z, regime, sub, pos)?;
                continue;
            };
            let lo = Self::min_level(regime);
            let at = (p + (1u64 << lo)).min(pos + (1u64 << j));
            let mut ze = if at == pos + (1u64 << j) { z1 } else { self.chunk(regime, lo, &zp) };
            self.anchor_stick_x(regime, &mut ze, at);
            self.emit(obs, regime, sub, pos, at, z, ze);
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
                self.anchor_x = self.face_position(&zn);
                self.anchor_sub = self.subs_done;
                self.anchor_unit = units_t(at);
            }
            if next == regime {
                touched = Some((regime, which));
            } else {
                touched = None;
                self.armed = false;
                obs.transition(&Transition2 { t: self.time_at(sub, at), from: regime, to: next, z: zn });
                transitions += 1;
                self.transitions += 1;
            }
            events += 1;
            if events > MAX_TRANSITIONS_PER_SUBSTEP {
                return Err(Halt::TransitionStorm { t: self.time_at(sub, at) });
            }
            regime = next;
            pos = at;
            z = zn;
            head = None;
            self.check(&z, regime, sub, pos)?;
        }
        self.z = z;
        self.regime = regime;
        self.head = head;
        self.subs_done += 1;
        Ok(transitions)
    }

    /// In stick without the band, x from its anchor (see `anchor_x`) at `unit` of the current
    /// substep. With the face it is the face's position x + s w phi that moves at V.
    #[inline(always)]
    fn anchor_stick_x(&self, regime: Regime, z: &mut [T; NS], unit: u64) {
        if regime == Regime::Stick && (!C::BAND || (C::FLOAT && !self.scene_band)) {
            let d = self.subs_done - self.anchor_sub;
            let d = if d > u32::MAX as u64 { u32::MAX } else { d as u32 };
            let elapsed = T::from_u32(d) * self.h_t + (units_t::<T>(unit) - self.anchor_unit) * self.hu_t;
            z[0] = self.anchor_x + self.v * elapsed;
            if C::FACE {
                z[0] = z[0] - self.r_v[3] * z[2];
            }
        }
    }

    /// The coordinate stick moves at V without the band: x, or with the face x + s w phi.
    #[inline(always)]
    fn face_position(&self, z: &[T; NS]) -> T {
        if C::FACE {
            z[0] + self.r_v[3] * z[2]
        } else {
            z[0]
        }
    }

    /// Finite, in range, in contact; the band within its range. The common case is one
    /// branch; the halt's classification (and its time, in f64) is out of line.
    #[inline(always)]
    fn check(&self, z: &[T; NS], regime: Regime, sub: u32, unit: u64) -> Result<(), Halt> {
        let pad = [z[0], z[1], z[2], z[3]];
        let band_ok = !C::BAND || ((z[4].abs() <= self.u_limit) & (z[5].abs() <= self.udot_limit));
        if self.limits.in_range(&pad) & band_ok & self.float_ok(z) {
            return Ok(());
        }
        self.check_failed(z, regime, sub, unit)
    }

    /// The floating pad: both contact springs compressed (y + d phi >= 0, to round-off), y and
    /// y' in range. Always true for a hinged pad.
    #[inline(always)]
    fn float_ok(&self, z: &[T; NS]) -> bool {
        if !C::FLOAT {
            return true;
        }
        let [d_l, d_t, floor_l, floor_t, y_limit, ydot_limit] = self.float_limits;
        (z[Y] + d_l * z[2] >= floor_l) & (z[Y] + d_t * z[2] >= floor_t) & (z[Y].abs() <= y_limit) & (z[Y + 1].abs() <= ydot_limit)
    }

    #[cold]
    #[inline(never)]
    fn check_failed(&self, z: &[T; NS], regime: Regime, sub: u32, unit: u64) -> Result<(), Halt> {
        let pad = [z[0], z[1], z[2], z[3]];
        self.limits.check(&pad, regime, || self.time_at(sub, unit))?;
        if C::FLOAT && !self.float_ok(z) {
            let t = self.time_at(sub, unit);
            if !(z[Y].is_finite() && z[Y + 1].is_finite()) {
                return Err(Halt::NonFinite { t });
            }
            let [d_l, d_t, floor_l, floor_t, _, _] = self.float_limits;
            let (y, phi) = (z[Y].to_f64(), z[2].to_f64());
            if !(z[Y] + d_l * z[2] >= floor_l) {
                return Err(Halt::ContactLoss { t, n: self.springs[0] * (y + self.springs[1] * phi) });
            }
            if !(z[Y] + d_t * z[2] >= floor_t) {
                return Err(Halt::ContactLoss { t, n: self.springs[2] * (y + self.springs[3] * phi) });
            }
            return Err(Halt::Diverged { t, regime, stiffness_margin: self.limits.margins[regime.index()] });
        }
        if C::BAND && (!(z[4].abs() <= self.u_limit) || !(z[5].abs() <= self.udot_limit)) {
            let t = self.time_at(sub, unit);
            if !(z[4].is_finite() && z[5].is_finite()) {
                return Err(Halt::NonFinite { t });
            }
            return Err(Halt::Diverged { t, regime, stiffness_margin: self.limits.margins[regime.index()] });
        }
        Ok(())
    }
}
