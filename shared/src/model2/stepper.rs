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
//!   2^j units costs four flow applications and four evaluations of q.
//! - **Stiff friction**: where the falling slope is steep (|v| near 0 with a small v_s), a
//!   substep is walked in dyadic chunks short enough that the slope's rate times the chunk is
//!   at most a quarter (down to 2^-16 of a substep), so v_s -> 0 stays stable.
//! - **Transitions**: a guard (a linear row of z) is tested at each chunk end; a fired guard is
//!   located by binary lifting on the dyadic grid (to 2^-L of a substep, 2^-(L-1) in Stribeck
//!   slip). A guard that rises and falls back inside a chunk (a crest) is found from the sign
//!   change of its derivative: the derivative's zero is lifted, and the guard is evaluated
//!   there.
//!
//! The thesis model (every option off) never runs here: it keeps [`crate::ExactStepper`],
//! bit for bit.

use crate::coefficients::Coefficients;
use crate::halt::{Halt, Limits};
use crate::linalg::{self, MatN};
use crate::model2::system::{row_dot, System, NA, NS};
use crate::real::Real;
use crate::scene::{Scene, SceneError};
use crate::stickslip::Regime;

/// Levels of the dyadic tables (enough for f64: L = 53).
const MAX_LEVELS: usize = 54;
/// Deepest refinement of a Stribeck substep below the whole substep (2^-16).
const STRIBECK_REFINE: usize = 16;
/// Largest rate x chunk length allowed for the falling friction's slope.
const STRIBECK_RATE_H: f64 = 0.25;
/// More transitions than this inside one substep halt the run.
const MAX_TRANSITIONS_PER_SUBSTEP: u32 = 64;
/// |u| beyond this is taken as divergence [m]; |u'| beyond this [m/s].
const U_LIMIT: f64 = 1.0;
const UDOT_LIMIT: f64 = 1e3;

/// Flow in increment form: rows x .. u', columns x .. u', 1 (6 x 7, row-major).
type Flow<T> = [T; NS * NA];

#[inline(always)]
fn increment<T: Real>(f: &Flow<T>, z: &[T; NS]) -> [T; NS] {
    let mut out = [T::zero(); NS];
    for (r, o) in out.iter_mut().enumerate() {
        let row = &f[r * NA..r * NA + NA];
        *o = row[0] * z[0] + row[1] * z[1] + row[2] * z[2] + row[3] * z[3] + row[4] * z[4] + row[5] * z[5] + row[6];
    }
    out
}

/// The ETDRK4 vectors of one dyadic level: h phi_1(hA) b and the three weights of the final
/// combination, h (phi_1 - 3 phi_2 + 4 phi_3) b, h (2 phi_2 - 4 phi_3) b, h (4 phi_3 - phi_2) b.
#[derive(Clone, Copy, Debug)]
struct EtdVectors<T> {
    phi1: [T; NS],
    w0: [T; NS],
    wab: [T; NS],
    wc: [T; NS],
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

/// The model-2 stepper, generic over f32 and f64.
#[derive(Clone, Debug)]
pub struct Model2Stepper<T: Real> {
    /// flows[regime][level]
    flows: [[Flow<T>; MAX_LEVELS]; 3],
    /// Stribeck slip: etd[slip regime - 1][level]
    etd: [[EtdVectors<T>; MAX_LEVELS]; 2],
    /// A rows (z' = A z) per regime, for derivatives.
    a: [[[T; NA]; NS]; 3],
    b: [T; NS],
    r_v: [T; NA],
    r_n: [T; NA],
    r_freq: [T; NA],
    mu_s: T,
    d_mu: T,
    inv_v_s: T,
    delta: T,
    delta_is_one: bool,
    stribeck: bool,
    band: bool,
    v: T,
    m: T,
    m_b: T,
    /// Stribeck slope rate per unit of N at |v| = 0, for the chunk choice (f64, set-up).
    sys: System,
    limits: Limits<T>,
    u_limit: T,
    udot_limit: T,
    h_sub: f64,
    n_sub: u32,
    dt: f64,
    z: [T; NS],
    regime: Regime,
    step: u64,
    halted: Option<Halt>,
    transitions: u64,
    /// Stick without the band: x = anchor_x + V (t - anchor_t), recomputed after each chunk so
    /// that a long stick in f32 does not accumulate x += V h round-off.
    anchor_x: T,
    anchor_t: f64,
    /// Whether the current slip's return to v = 0 is watched (see `substep`).
    armed: bool,
    /// (mu_s - mu_k) delta / v_s (1/m + 1/m_b): the falling slope's rate per unit of N and of
    /// the shape y^(delta-1) exp(-y^delta) [1/(N s)].
    rate_coef: T,
    /// The largest slope rate a chunk of 2^j units takes: STRIBECK_RATE_H / h_j [1/s].
    rate_limit: [T; MAX_LEVELS],
    /// Round-off level of the sliding velocity: 2^-(L-8) V [m/s].
    v_round: T,
}

impl<T: Real> Model2Stepper<T> {
    const LEVELS: usize = T::DYADIC_LEVELS;
    const UNITS: u64 = 1u64 << T::DYADIC_LEVELS;

    /// Validates `scene` and starts at rest in stick: x = 0, x' = V, phi = F_N a_N / K,
    /// phi' = 0, u = u' = 0.
    pub fn new(scene: &Scene) -> Result<Self, SceneError> {
        let mut slot = None;
        Self::init_in(&mut slot, scene)?;
        match slot {
            Some(s) => Ok(s),
            None => unreachable!("init_in returned Ok without filling the slot"),
        }
    }

    /// [`Self::new`] built in `slot` (e.g. a `static`): the dyadic tables (tens of KB in
    /// f32) are filled where they stay, not on the stack and then moved, which a Cortex-M4F's
    /// stack cannot hold twice (tests/on-target bin `count_model2` prints the stack it takes).
    /// The same values as [`Self::new`]. On an error `slot` is left as it was.
    #[allow(clippy::needless_range_loop)] // matrix code: indices read as the formulas
    pub fn init_in<'a>(slot: &'a mut Option<Self>, scene: &Scene) -> Result<&'a mut Self, SceneError> {
        scene.validate()?;
        let co = Coefficients::of(scene);
        let sys = System::of(scene, &co);
        let rate = sys.linear_rate(scene, &co);
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
        let zero_etd = EtdVectors { phi1: [T::zero(); NS], w0: [T::zero(); NS], wab: [T::zero(); NS], wc: [T::zero(); NS] };
        let tv = |r: &[f64; NA]| -> [T; NA] { core::array::from_fn(|i| t(r[i])) };
        let z = [T::zero(), t(scene.v), t(co.phi0), T::zero(), T::zero(), T::zero()];
        let s = slot.insert(Model2Stepper {
            flows: [[[T::zero(); NS * NA]; MAX_LEVELS]; 3],
            etd: [[zero_etd; MAX_LEVELS]; 2],
            a: [[[T::zero(); NA]; NS]; 3],
            b: core::array::from_fn(|i| t(sys.b[i])),
            r_v: tv(&sys.r_v),
            r_n: tv(&sys.r_n),
            r_freq: tv(&sys.r_freq),
            mu_s: t(scene.mu_s),
            d_mu: t(sys.d_mu),
            inv_v_s: t(1.0 / scene.v_s),
            delta: t(scene.stribeck_exponent),
            delta_is_one: scene.stribeck_exponent == 1.0,
            stribeck: sys.stribeck,
            band: sys.band,
            v: t(scene.v),
            m: t(scene.m),
            m_b: t(scene.m_b),
            sys,
            limits: Limits::new(scene, &co),
            u_limit: t(U_LIMIT),
            udot_limit: t(UDOT_LIMIT),
            h_sub,
            n_sub,
            dt: scene.dt,
            z,
            regime: Regime::Stick,
            step: 0,
            halted: None,
            transitions: 0,
            anchor_x: T::zero(),
            anchor_t: 0.0,
            armed: false,
            v_round: t(libm::ldexp(scene.v, 8 - Self::LEVELS as i32)),
            rate_coef: t(sys.d_mu * scene.stribeck_exponent / scene.v_s
                * (1.0 / scene.m + if scene.band { 1.0 / scene.m_b } else { 0.0 })),
            rate_limit: core::array::from_fn(|j| {
                t(STRIBECK_RATE_H / (h_sub * libm::ldexp(1.0, j as i32 - Self::LEVELS as i32)))
            }),
        });
        let sys = &s.sys;
        for regime in Regime::ALL {
            let a = &sys.a[regime.index()];
            let with_phi = sys.stribeck && regime != Regime::Stick;
            for j in 0..=Self::LEVELS {
                let tau = h_sub * libm::ldexp(1.0, j as i32 - Self::LEVELS as i32);
                let flow = &mut s.flows[regime.index()][j];
                if with_phi {
                    // [[A, b, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0]] * tau
                    let mut m: MatN<10> = [[0.0; 10]; 10];
                    for r in 0..NA {
                        m[r][..NA].copy_from_slice(&a[r]);
                        m[r][NA] = sys.b[r];
                    }
                    m[NA][NA + 1] = 1.0;
                    m[NA + 1][NA + 2] = 1.0;
                    let e = linalg::expm_minus_identity(&linalg::scale(&m, tau));
                    for r in 0..NS {
                        for c in 0..NA {
                            flow[r * NA + c] = t(e[r][c]);
                        }
                    }
                    let v = &mut s.etd[regime.index() - 1][j];
                    for r in 0..NS {
                        let (c1, c2, c3) = (e[r][NA], e[r][NA + 1] / tau, e[r][NA + 2] / (tau * tau));
                        v.phi1[r] = t(c1);
                        v.w0[r] = t(c1 - 3.0 * c2 + 4.0 * c3);
                        v.wab[r] = t(2.0 * c2 - 4.0 * c3);
                        v.wc[r] = t(4.0 * c3 - c2);
                    }
                } else {
                    let e = linalg::expm_minus_identity(&linalg::scale(a, tau));
                    for r in 0..NS {
                        for c in 0..NA {
                            flow[r * NA + c] = t(e[r][c]);
                        }
                    }
                }
            }
            for r in 0..NS {
                for c in 0..NA {
                    s.a[regime.index()][r][c] = t(sys.a[regime.index()][r][c]);
                }
            }
        }
        Ok(s)
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
    /// The equations in f64.
    pub fn system(&self) -> &System {
        &self.sys
    }

    /// Replaces the state and regime (e.g. to start from steady sliding). In stick the sliding
    /// velocity is set to zero as on entry to stick.
    pub fn set_state(&mut self, z: [T; NS], regime: Regime) {
        self.z = z;
        self.regime = regime;
        // a state set in slip is taken as a slip under way
        self.armed = true;
        if regime == Regime::Stick {
            let mut z = self.z;
            self.enter_stick(&mut z);
            self.z = z;
            self.anchor_x = z[0];
            self.anchor_t = self.time();
        }
        self.halted = None;
    }

    /// Sliding velocity v = x' - V - u' [m/s].
    pub fn sliding_velocity(&self, z: &[T; NS]) -> T {
        row_dot(&self.r_v, z)
    }
    /// Normal force N [N].
    pub fn normal_force(&self, z: &[T; NS]) -> T {
        row_dot(&self.r_n, z)
    }
    /// Friction force on the pad [N] in `regime` at `z`.
    pub fn friction_force(&self, regime: Regime, z: &[T; NS]) -> T {
        match regime {
            Regime::Stick => row_dot(&self.r_freq, z),
            _ => {
                let n = self.normal_force(z);
                let sigma = T::from_f64(regime.friction_sign());
                let mu = if self.stribeck { self.mu_s - self.d_mu + self.excess(z) } else { self.mu_s - self.d_mu };
                sigma * mu * n
            }
        }
    }

    /// (mu(|v|) - mu_k) / (mu_s - mu_k) times (mu_s - mu_k): the falling part of mu.
    #[inline(always)]
    fn excess(&self, z: &[T; NS]) -> T {
        let y = row_dot(&self.r_v, z).abs() * self.inv_v_s;
        let e = if self.delta_is_one {
            (-y).exp()
        } else if y > T::zero() {
            (-(y.powf(self.delta))).exp()
        } else {
            T::one()
        };
        self.d_mu * e
    }

    /// Stribeck forcing q(z) = sigma (mu(|v|) - mu_k) N.
    #[inline(always)]
    fn q(&self, sigma: T, z: &[T; NS]) -> T {
        sigma * self.excess(z) * row_dot(&self.r_n, z)
    }

    /// z' in `regime` at `z`.
    pub fn derivative(&self, regime: Regime, z: &[T; NS]) -> [T; NS] {
        let a = &self.a[regime.index()];
        let mut d: [T; NS] = core::array::from_fn(|r| row_dot(&a[r], z));
        if self.stribeck && regime != Regime::Stick {
            let q = self.q(T::from_f64(regime.friction_sign()), z);
            for (r, v) in d.iter_mut().enumerate() {
                *v += self.b[r] * q;
            }
        }
        d
    }

    fn is_stribeck_slip(&self, regime: Regime) -> bool {
        self.stribeck && regime != Regime::Stick
    }

    /// The flow over 2^j units in `regime` from `z` (exact in linear regimes; ETDRK4 in
    /// Stribeck slip, which needs j >= 1).
    fn chunk(&self, regime: Regime, j: usize, z: &[T; NS]) -> [T; NS] {
        let f = &self.flows[regime.index()][j];
        if !self.is_stribeck_slip(regime) {
            let d = increment(f, z);
            return core::array::from_fn(|r| z[r] + d[r]);
        }
        let sigma = T::from_f64(regime.friction_sign());
        let half = &self.flows[regime.index()][j - 1];
        let ph = &self.etd[regime.index() - 1][j - 1].phi1;
        let w = &self.etd[regime.index() - 1][j];
        let q0 = self.q(sigma, z);
        let eh = increment(half, z);
        let a: [T; NS] = core::array::from_fn(|r| z[r] + (eh[r] + ph[r] * q0));
        let qa = self.q(sigma, &a);
        let bb: [T; NS] = core::array::from_fn(|r| z[r] + (eh[r] + ph[r] * qa));
        let qb = self.q(sigma, &bb);
        let ea = increment(half, &a);
        let two = T::one() + T::one();
        let qcb = two * qb - q0;
        let c: [T; NS] = core::array::from_fn(|r| a[r] + (ea[r] + ph[r] * qcb));
        let qc = self.q(sigma, &c);
        let e = increment(f, z);
        let qab = qa + qb;
        core::array::from_fn(|r| z[r] + (e[r] + w.w0[r] * q0 + w.wab[r] * qab + w.wc[r] * qc))
    }

    /// The smallest level a transition is located to in `regime`.
    fn min_level(&self, regime: Regime) -> usize {
        if self.is_stribeck_slip(regime) {
            1
        } else {
            0
        }
    }

    /// The level of the next chunk from `z` with `remaining` units left in the substep: the
    /// largest power of two that fits, limited in Stribeck slip by the friction slope's rate.
    fn chunk_level(&self, regime: Regime, z: &[T; NS], remaining: u64) -> usize {
        let mut j = 63 - remaining.leading_zeros() as usize; // largest 2^j <= remaining
        if self.is_stribeck_slip(regime) {
            // the falling slope's rate, |dq/dv| (1/m + 1/m_b), in T (no f64 on the M4F's path)
            let y = self.sliding_velocity(z).abs() * self.inv_v_s;
            let shape = if self.delta_is_one {
                (-y).exp()
            } else if y > T::zero() {
                y.powf(self.delta - T::one()) * (-(y.powf(self.delta))).exp()
            } else if self.delta > T::one() {
                T::zero()
            } else {
                self.rate_limit[0] * self.rate_limit[0] // delta < 1: infinite slope at v = 0
            };
            let rate = self.rate_coef * shape * self.normal_force(z).abs();
            let floor = (Self::LEVELS.saturating_sub(STRIBECK_REFINE)).max(1);
            while j > floor && rate > self.rate_limit[j] {
                j -= 1;
            }
            j = j.max(1);
        }
        j
    }

    /// The guards of `regime` as rows (fire at row . z >= 0) and how many there are.
    fn guard(&self, regime: Regime, which: usize) -> [T; NA] {
        match (regime, which) {
            (Regime::Stick, 0) => core::array::from_fn(|c| self.r_freq[c] - self.mu_s * self.r_n[c]),
            (Regime::Stick, _) => core::array::from_fn(|c| -self.r_freq[c] - self.mu_s * self.r_n[c]),
            (Regime::SlipSlower, _) => self.r_v,
            (Regime::SlipFaster, _) => core::array::from_fn(|c| -self.r_v[c]),
        }
    }

    fn guard_count(regime: Regime) -> usize {
        if regime == Regime::Stick {
            2
        } else {
            1
        }
    }

    /// Binary lifting over [from, to): the last probed point p such that `holds` is true at
    /// every accepted point, starting from chunks of 2^top units. Never evaluated at `from`.
    fn lift(&self, regime: Regime, z: &[T; NS], from: u64, to: u64, top: usize, mut holds: impl FnMut(&[T; NS]) -> bool) -> (u64, [T; NS]) {
        let mut pos = from;
        let mut cur = *z;
        let lo = self.min_level(regime);
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
    /// that rises above zero and falls back inside the chunk) from its derivative.
    fn crossing(&self, regime: Regime, which: usize, z: &[T; NS], pos: u64, j: usize, z1: &[T; NS]) -> Option<(u64, [T; NS])> {
        let g = self.guard(regime, which);
        let end = pos + (1u64 << j);
        let lo = self.min_level(regime);
        if !(row_dot(&g, z1) < T::zero()) {
            return Some(self.lift(regime, z, pos, end, j, |c| row_dot(&g, c) < T::zero()));
        }
        if j <= lo {
            return None;
        }
        let slope = |c: &[T; NS]| -> T {
            let d = self.derivative(regime, c);
            g[0] * d[0] + g[1] * d[1] + g[2] * d[2] + g[3] * d[3] + g[4] * d[4] + g[5] * d[5]
        };
        if !(slope(z) > T::zero() && slope(z1) < T::zero()) {
            return None;
        }
        // the crest: the last point where the guard still rises
        let (pc, zc) = self.lift(regime, z, pos, end, j, |c| slope(c) > T::zero());
        let after = self.chunk(regime, lo, &zc);
        let top = if row_dot(&g, &zc) < T::zero() && row_dot(&g, &after) < T::zero() {
            return None;
        } else {
            pc + (1u64 << lo)
        };
        Some(self.lift(regime, z, pos, top, j, |c| row_dot(&g, c) < T::zero()))
    }

    /// Sets the sliding velocity to zero on entry to stick: x' = V without the band; with it,
    /// pad and band take their common momentum velocity.
    fn enter_stick(&self, z: &mut [T; NS]) {
        if self.band {
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
        let f_req = row_dot(&self.r_freq, &zs);
        let limit = self.mu_s * row_dot(&self.r_n, &zs);
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
            match self.substep(sub, obs) {
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

    fn substep<O: Observer2<T>>(&mut self, sub: u32, obs: &mut O) -> Result<usize, Halt> {
        let units = Self::UNITS;
        let mut pos = 0u64;
        let mut z = self.z;
        let mut regime = self.regime;
        let mut transitions = 0usize;
        let mut events = 0u32;
        let mut touched: Option<(Regime, usize)> = None;
        while pos < units {
            let j = self.chunk_level(regime, &z, units - pos);
            let z1 = self.chunk(regime, j, &z);
            let mut best: Option<(u64, [T; NS], usize)> = None;
            // A slip starts at v = 0 (with Stribeck friction also at v' = 0): its guard is armed
            // once v has left zero by more than round-off in the slip's own direction. Until
            // then only a departure beyond round-off to the other side counts as a crossing.
            let unarmed = regime != Regime::Stick && !self.armed;
            for which in 0..Self::guard_count(regime) {
                if touched == Some((regime, which)) {
                    continue;
                }
                if unarmed && !(row_dot(&self.guard(regime, 0), &z1) > self.v_round) {
                    continue;
                }
                if let Some((p, zp)) = self.crossing(regime, which, &z, pos, j, &z1) {
                    if best.is_none_or(|b| p < b.0) {
                        best = Some((p, zp, which));
                    }
                }
            }
            let Some((p, zp, which)) = best else {
                if unarmed && row_dot(&self.guard(regime, 0), &z1) < -self.v_round {
                    self.armed = true;
                }
                let mut z1 = z1;
                self.anchor_stick_x(regime, &mut z1, sub, pos + (1u64 << j));
                self.emit(obs, regime, sub, pos, pos + (1u64 << j), z, z1);
                pos += 1u64 << j;
                z = z1;
                self.check(&z, regime, sub, pos)?;
                continue;
            };
            let lo = self.min_level(regime);
            let at = (p + (1u64 << lo)).min(pos + (1u64 << j));
            let mut ze = if at == pos + (1u64 << j) { z1 } else { self.chunk(regime, lo, &zp) };
            self.anchor_stick_x(regime, &mut ze, sub, at);
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
                self.anchor_x = zn[0];
                self.anchor_t = self.time_at(sub, at);
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
            self.check(&z, regime, sub, pos)?;
        }
        self.z = z;
        self.regime = regime;
        Ok(transitions)
    }

    /// In stick without the band, x from its anchor (see `anchor_x`).
    #[inline(always)]
    fn anchor_stick_x(&self, regime: Regime, z: &mut [T; NS], sub: u32, unit: u64) {
        if regime == Regime::Stick && !self.band {
            z[0] = self.anchor_x + self.v * T::from_f64(self.time_at(sub, unit) - self.anchor_t);
        }
    }

    /// Finite, in range, in contact; the band within its range.
    fn check(&self, z: &[T; NS], regime: Regime, sub: u32, unit: u64) -> Result<(), Halt> {
        let pad = [z[0], z[1], z[2], z[3]];
        self.limits.check(&pad, regime, || self.time_at(sub, unit))?;
        if !(z[4].abs() <= self.u_limit) || !(z[5].abs() <= self.udot_limit) {
            let t = self.time_at(sub, unit);
            if !(z[4].is_finite() && z[5].is_finite()) {
                return Err(Halt::NonFinite { t });
            }
            return Err(Halt::Diverged { t, regime, stiffness_margin: self.limits.margins[regime.index()] });
        }
        Ok(())
    }
}
