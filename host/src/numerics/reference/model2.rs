//! The reference simulation of model 2, part 1 (docs/model.md, "Model 2, part 1: falling
//! friction, a band that moves, damping"), independent of `stickslip_model`'s matrices and
//! steppers, and of the thesis reference's right-hand side ([`super::thesis`]): its own
//! right-hand side written from the equations of docs/model.md (it takes only the scene's data
//! and computes the lever arms itself), run by the event-driven DOP853 driver
//! ([`super::driver`]) in chunks of 400 largest steps.
//!
//! The state is `z = [x, x', phi, phi', u, u']` with `u = x_b - V t` the band's offset from its
//! drive point (`u = u' = 0` for good without the band; `phi = phi_0`, `phi' = 0` for good
//! without rotation). The sliding velocity is `v = x' - V - u'`, with friction-face kinematics
//! (`face`) `v = x' + s w phi' - V - u'`; stick then holds the face, and its friction is solved
//! from the three equations of motion and the constraint `v' = 0` as written (not from the
//! model crate's scaled form).
//!
//! Event location (the driver's, with what this model gives it):
//! - a regime's guard `g(z)` is negative while the regime holds (stick:
//!   `|F_req| - mu_s N`; slip with the pad slower: `v`; faster: `-v`);
//! - its rate is written analytically, so that the driver locates crests of `g` inside a step
//!   (a graze is not missed); the step is capped at a fraction of the fastest time scale;
//! - **Arming of slip phases.** With Stribeck friction a slip phase starts at `v = 0` with
//!   `v' = 0` (the friction is continuous at breakaway), so its guard is 0 (or round-off above
//!   it) at the start. A slip phase's guard is therefore *armed* only once it has been below
//!   `-ARM * V` (`ARM = 1e-9`) at a step end; before that the phase cannot end. A slip phase
//!   whose `|v|` never exceeds `1e-9 V` would be missed (it cannot occur with Coulomb friction,
//!   where `v'` jumps away from 0 at breakaway).
//!
//! Transitions follow the table of docs/model.md. Entering stick sets `v = 0`: without the band
//! `x' = V`; with the band both velocities to the momentum velocity
//! `(m x' + m_b x_b') / (m + m_b)`; with the face, the friction impulse
//! `P = -v / (1/m + w^2/I + 1/m_b)` changes x', phi', u' by `P/m`, `s w P / I`, `-P/m_b`.
//!
//! Slow and allocating: a yardstick for tests, not the product.

use super::driver::{self, arr, Bracket, Hybrid, Plan, State};
pub use super::driver::Tolerances;
use super::common::{Pad, WindowStats};
use stickslip_model::{FrictionLaw, Scene};

/// [x, x', phi, phi', u, u', y, y'] (y: the floating pad's pivot normal to the band).
type Z = State<8>;

/// Guards of slip phases are armed once `v` has been beyond `ARM * V` (see the module doc).
const ARM: f64 = 1e-9;
/// Integration is done in chunks of this many largest steps, so an early event does not pay for
/// integrating to the end of the run.
const CHUNK_STEPS: f64 = 400.0;

/// The regime of the contact.
pub use super::common::Regime;

/// The pad's constants (docs/model.md) and model 2's.
#[derive(Clone, Copy, Debug)]
struct Phys {
    pad: Pad,
    phi0: f64,
    stribeck: bool,
    v_s: f64,
    delta: f64,
    band: bool,
    mb: f64,
    kb: f64,
    cb: f64,
    /// Friction-face kinematics (only with rotation).
    face: bool,
    /// The floating pad (finite k_pivot): the pivot translates by y normal to the band, the
    /// centre of gravity l from it (mass matrix [[I, m l], [m l, m]] in (phi, y)).
    floating: bool,
    k_pivot: f64,
    c_y: f64,
    l: f64,
    k_s: f64,
    f_n: f64,
    y0: f64,
}

impl Phys {
    fn of(sc: &Scene) -> Phys {
        let pad = Pad::of(sc);
        let (d_l, d_t, a_n, k_rot) = (pad.d_l, pad.d_t, pad.a_n, pad.k_rot);
        Phys {
            pad,
            phi0: if sc.floating() {
                let k_y = sc.k_l + sc.k_t + sc.k_pivot;
                let c_n = sc.k_l * d_l + sc.k_t * d_t;
                (k_y * sc.f_n * a_n - c_n * sc.f_n) / (k_y * k_rot - c_n * c_n)
            } else {
                sc.f_n * a_n / k_rot
            },
            stribeck: sc.friction == FrictionLaw::Stribeck,
            v_s: sc.v_s,
            delta: sc.stribeck_exponent,
            band: sc.band,
            mb: sc.m_b,
            kb: sc.k_b,
            cb: sc.c_b,
            face: sc.face && sc.rotation,
            floating: sc.floating(),
            k_pivot: sc.k_pivot,
            c_y: sc.c_y,
            l: sc.l,
            k_s: sc.k_l + sc.k_t,
            f_n: sc.f_n,
            y0: if sc.floating() {
                let k_y = sc.k_l + sc.k_t + sc.k_pivot;
                let c_n = sc.k_l * d_l + sc.k_t * d_t;
                (sc.f_n * k_rot - c_n * sc.f_n * a_n) / (k_y * k_rot - c_n * c_n)
            } else {
                0.0
            },
        }
    }

    fn normal(&self, z: &Z) -> f64 {
        if self.floating {
            return self.k_s * z[6] + self.pad.c_n * z[2];
        }
        self.pad.c_n * if self.pad.rotation { z[2] } else { self.phi0 }
    }

    /// Rate of N along the motion.
    fn normal_rate(&self, zd: &Z) -> f64 {
        if self.floating {
            self.k_s * zd[6] + self.pad.c_n * zd[2]
        } else if self.pad.rotation {
            self.pad.c_n * zd[2]
        } else {
            0.0
        }
    }

    /// The floating pad's (phi, y) mass block: its determinant I m - (m l)^2.
    fn det_float(&self) -> f64 {
        self.pad.i * self.pad.m - (self.pad.m * self.l) * (self.pad.m * self.l)
    }

    /// The floating pad: (phi'', y'') from the generalized forces on phi (with the friction's
    /// moment) and on y, by the inverse of [[I, m l], [m l, m]].
    fn float_acc(&self, q_phi: f64, q_y: f64) -> (f64, f64) {
        let det = self.det_float();
        let ml = self.pad.m * self.l;
        ((self.pad.m * q_phi - ml * q_y) / det, (self.pad.i * q_y - ml * q_phi) / det)
    }

    /// The floating pad's generalized forces without friction on phi and y (`c = 0`: without
    /// the constant terms, for rates).
    fn float_forces(&self, z: &Z, c: f64) -> (f64, f64) {
        let q_phi = c * self.pad.moment_load - self.pad.k_rot * z[2] - self.pad.c_n * z[6] - self.pad.cphi * z[3];
        let q_y = c * self.f_n - (self.k_s + self.k_pivot) * z[6] - self.pad.c_n * z[2] - self.c_y * z[7];
        (q_phi, q_y)
    }

    /// The floating pad's stick friction: x'' + s w phi'' - u'' = 0 with the equations of
    /// motion, solved for F (linear in F).
    fn f_req_float(&self, z: &Z, affine: bool) -> f64 {
        let c = if affine { 1.0 } else { 0.0 };
        let q_x = -self.pad.kg * z[0] - self.pad.cx * z[1];
        let (q_phi, q_y) = self.float_forces(z, c);
        let q_u = if self.band { -self.kb * z[4] - self.cb * z[5] } else { 0.0 };
        let sw = self.pad.s * self.pad.w;
        // constraint residual at F = 0 and its slope in F
        let (phi0, _) = self.float_acc(q_phi, q_y);
        let (phi1, _) = self.float_acc(sw, 0.0);
        let r0 = q_x / self.pad.m + sw * phi0 - if self.band { q_u / self.mb } else { 0.0 };
        let r1 = 1.0 / self.pad.m + sw * phi1 + if self.band { 1.0 / self.mb } else { 0.0 };
        -r0 / r1
    }

    /// Sliding velocity v = x' (+ s w phi') - V - u'.
    fn slip_v(&self, z: &Z) -> f64 {
        self.face_rate(z) - self.pad.v
    }

    /// The face's velocity relative to the band's drive point, x' (+ s w phi') - u' (also the
    /// rate of v along the motion when given z').
    fn face_rate(&self, z: &Z) -> f64 {
        z[1] + if self.face { self.pad.s * self.pad.w * z[3] } else { 0.0 } - if self.band { z[5] } else { 0.0 }
    }

    /// 1/m + w^2/I (face) + 1/m_b (band): the sliding velocity's response to a friction impulse.
    fn inv_mass_v(&self) -> f64 {
        if self.floating {
            let (phi1, _) = self.float_acc(self.pad.s * self.pad.w, 0.0);
            return 1.0 / self.pad.m + self.pad.s * self.pad.w * phi1 + if self.band { 1.0 / self.mb } else { 0.0 };
        }
        1.0 / self.pad.m
            + if self.face { self.pad.w * self.pad.w / self.pad.i } else { 0.0 }
            + if self.band { 1.0 / self.mb } else { 0.0 }
    }

    /// With the face: the stick's friction from x'' + s w phi'' - u'' = 0 and the three
    /// equations of motion; `affine = false` drops the constant terms (for rates).
    fn f_req_face(&self, z: &Z, affine: bool) -> f64 {
        let c = if affine { 1.0 } else { 0.0 };
        let px = -self.pad.kg * z[0] - self.pad.cx * z[1];
        let pphi = -self.pad.k_rot * z[2] - self.pad.cphi * z[3] + c * self.pad.moment_load;
        let pu = if self.band { -self.kb * z[4] - self.cb * z[5] } else { 0.0 };
        // (px + F)/m + s w (pphi + s w F)/I - (pu - F)/m_b = 0
        let rhs = -px / self.pad.m - self.pad.s * self.pad.w * pphi / self.pad.i + if self.band { pu / self.mb } else { 0.0 };
        rhs / self.inv_mass_v()
    }

    fn mu(&self, speed: f64) -> f64 {
        if self.stribeck {
            self.pad.mu_k + (self.pad.mu_s - self.pad.mu_k) * (-(speed / self.v_s).powf(self.delta)).exp()
        } else {
            self.pad.mu_k
        }
    }

    /// d mu / d|v|.
    fn mu_slope(&self, speed: f64) -> f64 {
        if !self.stribeck {
            return 0.0;
        }
        let r = speed.max(f64::MIN_POSITIVE) / self.v_s;
        -(self.pad.mu_s - self.pad.mu_k) * (-r.powf(self.delta)).exp() * self.delta * r.powf(self.delta - 1.0) / self.v_s
    }

    fn sigma(regime: Regime) -> f64 {
        match regime {
            Regime::Slower => 1.0,
            Regime::Faster => -1.0,
            Regime::Stick => 0.0,
        }
    }

    /// The stick's required friction force.
    fn f_req(&self, z: &Z) -> f64 {
        if self.floating {
            self.f_req_float(z, true)
        } else if self.face {
            self.f_req_face(z, true)
        } else if self.band {
            (self.mb * (self.pad.kg * z[0] + self.pad.cx * z[1]) - self.pad.m * (self.kb * z[4] + self.cb * z[5])) / (self.pad.m + self.mb)
        } else {
            self.pad.kg * z[0] + self.pad.cx * self.pad.v
        }
    }

    /// Rate of F_req along the motion zd (F_req is affine in z).
    fn f_req_rate(&self, zd: &Z) -> f64 {
        if self.floating {
            self.f_req_float(zd, false)
        } else if self.face {
            self.f_req_face(zd, false)
        } else if self.band {
            (self.mb * (self.pad.kg * zd[0] + self.pad.cx * zd[1]) - self.pad.m * (self.kb * zd[4] + self.cb * zd[5])) / (self.pad.m + self.mb)
        } else {
            self.pad.kg * zd[0]
        }
    }

    fn friction(&self, regime: Regime, z: &Z) -> f64 {
        match regime {
            Regime::Stick => self.f_req(z),
            _ => Self::sigma(regime) * self.mu(self.slip_v(z).abs()) * self.normal(z),
        }
    }

    /// The statistics' quantities: x, x', phi, phi', band velocity x_b' = V + u', band
    /// acceleration u''.
    fn quantities(&self, regime: Regime, z: &Z) -> [f64; 6] {
        let zd = self.rhs(regime, z);
        [z[0], z[1], z[2], z[3], self.pad.v + if self.band { z[5] } else { 0.0 }, zd[5]]
    }

    /// Rates of [`Phys::quantities`].
    fn quantity_rates(&self, regime: Regime, z: &Z) -> [f64; 6] {
        let zd = self.rhs(regime, z);
        let jerk_u = if !self.band {
            0.0
        } else if regime == Regime::Stick && self.face {
            (-self.kb * zd[4] - self.cb * zd[5] - self.f_req_rate(&zd)) / self.mb
        } else if regime == Regime::Stick {
            (-self.pad.kg * zd[0] - self.pad.cx * zd[1] - self.kb * zd[4] - self.cb * zd[5]) / (self.pad.m + self.mb)
        } else {
            let sg = Self::sigma(regime);
            let speed = self.slip_v(z).abs();
            // |v| = -sigma v in slip
            let speed_rate = -sg * self.face_rate(&zd);
            let ff_rate =
                sg * (self.mu(speed) * self.normal_rate(&zd) + self.normal(z) * self.mu_slope(speed) * speed_rate);
            (-self.kb * zd[4] - self.cb * zd[5] - ff_rate) / self.mb
        };
        [zd[0], zd[1], zd[2], zd[3], zd[5], jerk_u]
    }

    /// Sets v = 0 on entering stick.
    fn project_stick(&self, z: &mut Z) {
        if self.floating {
            let p = -self.slip_v(z) / self.inv_mass_v();
            let (dphi, dy) = self.float_acc(self.pad.s * self.pad.w * p, 0.0);
            z[1] += p / self.pad.m;
            z[3] += dphi;
            z[7] += dy;
            if self.band {
                z[5] -= p / self.mb;
            }
        } else if self.face {
            let p = -self.slip_v(z) / self.inv_mass_v();
            z[1] += p / self.pad.m;
            z[3] += self.pad.s * self.pad.w * p / self.pad.i;
            if self.band {
                z[5] -= p / self.mb;
            }
        } else if self.band {
            let common = (self.pad.m * z[1] + self.mb * (self.pad.v + z[5])) / (self.pad.m + self.mb);
            z[1] = common;
            z[5] = common - self.pad.v;
        } else {
            z[1] = self.pad.v;
        }
    }
}

impl Hybrid<8> for Phys {
    type Regime = Regime;
    const NAME: &'static str = "model-2 reference";

    fn rhs(&self, regime: Regime, z: &Z) -> Z {
        let ff = self.friction(regime, z);
        let (xdd, udd) = match regime {
            Regime::Stick if self.face => {
                let xdd = (-self.pad.kg * z[0] - self.pad.cx * z[1] + ff) / self.pad.m;
                let udd = if self.band { (-self.kb * z[4] - self.cb * z[5] - ff) / self.mb } else { 0.0 };
                (xdd, udd)
            }
            Regime::Stick => {
                if self.band {
                    let a = (-self.pad.kg * z[0] - self.pad.cx * z[1] - self.kb * z[4] - self.cb * z[5]) / (self.pad.m + self.mb);
                    (a, a)
                } else {
                    (0.0, 0.0)
                }
            }
            _ => {
                let xdd = (-self.pad.kg * z[0] - self.pad.cx * z[1] + ff) / self.pad.m;
                let udd = if self.band { (-self.kb * z[4] - self.cb * z[5] - ff) / self.mb } else { 0.0 };
                (xdd, udd)
            }
        };
        let ud = if self.band { z[5] } else { 0.0 };
        if self.floating {
            let (q_phi, q_y) = self.float_forces(z, 1.0);
            let (phidd, ydd) = self.float_acc(q_phi + self.pad.s * self.pad.w * ff, q_y);
            return Z::from_column_slice(&[z[1], xdd, z[3], phidd, ud, udd, z[7], ydd]);
        }
        let (phid, phidd) = if self.pad.rotation {
            (z[3], (-self.pad.k_rot * z[2] - self.pad.cphi * z[3] + self.pad.moment_load + self.pad.s * self.pad.w * ff) / self.pad.i)
        } else {
            (0.0, 0.0)
        };
        Z::from_column_slice(&[z[1], xdd, phid, phidd, ud, udd, 0.0, 0.0])
    }

    /// The regime holds while the guard is negative.
    fn guard(&self, regime: Regime, z: &Z) -> f64 {
        match regime {
            Regime::Stick => self.f_req(z).abs() - self.pad.mu_s * self.normal(z),
            Regime::Slower => self.slip_v(z),
            Regime::Faster => -self.slip_v(z),
        }
    }

    /// Rate of the guard along the motion (written analytically, for crests inside a step).
    fn guard_rate(&self, regime: Regime, z: &Z) -> Option<f64> {
        let zd = self.rhs(regime, z);
        Some(match regime {
            Regime::Stick => self.f_req(z).signum() * self.f_req_rate(&zd) - self.pad.mu_s * self.normal_rate(&zd),
            _ => {
                let vd = self.face_rate(&zd);
                if regime == Regime::Slower {
                    vd
                } else {
                    -vd
                }
            }
        })
    }

    /// A slip phase's guard arms once `v` has been beyond `ARM * V` (see the module doc).
    fn armed(&self, regime: Regime, z: &Z) -> bool {
        regime == Regime::Stick || self.guard(regime, z) < -ARM * self.pad.v
    }

    fn transition(&self, regime: Regime, z: &mut Z) -> Regime {
        let next = regime.after(self.f_req(z), self.pad.mu_s * self.normal(z));
        if next == Regime::Stick {
            self.project_stick(z);
        }
        next
    }

    /// The fastest rate of the model [1/s]: natural frequencies, damping rates and the
    /// Stribeck slope's negative damping.
    fn fastest_rate(&self) -> f64 {
        let mut r = (self.pad.kg / self.pad.m).sqrt().max(self.pad.cx / self.pad.m);
        if self.pad.rotation {
            r = r.max(((self.pad.k_rot + self.pad.mu_s * self.pad.w * self.pad.c_n) / self.pad.i).sqrt()).max(self.pad.cphi / self.pad.i);
        }
        let inv_mass = self.inv_mass_v();
        if self.floating {
            // the (phi, y) block's stiffest direction over its lightest inertia
            let det = self.det_float();
            r = r
                .max(((self.k_s + self.k_pivot) * self.pad.i / det).sqrt())
                .max(((self.pad.k_rot + self.pad.mu_s * self.pad.w * self.pad.c_n) * self.pad.m / det).sqrt())
                .max(self.c_y * self.pad.i / det)
                .max(self.pad.cphi * self.pad.m / det);
        }
        if self.band {
            r = r.max((self.kb / self.mb).sqrt()).max(self.cb / self.mb);
        }
        if self.stribeck {
            // N |mu'| near v = 0 (capped for delta < 1, where it is unbounded); N taken as 2 N0
            let slope = (self.pad.mu_s - self.pad.mu_k) * self.delta.max(1.0) / self.v_s;
            r = r.max(2.0 * self.pad.c_n * self.phi0 * slope * inv_mass);
        }
        r
    }
}

/// One transition: at `t` the regime changed from `from` to `to`; `state` is the state the new
/// regime starts from (after the stick projection `v = 0` when `to` is stick).
pub type Transition = driver::Transition<Regime, 8>;

/// Window statistics of a run. Quantities are indexed [x, x', phi, phi', x_b', u''] (x_b' =
/// V + u' the band's velocity, u'' its acceleration; V and 0 without the band).
pub type Stats = WindowStats<6>;

/// Where a run starts: the state `[x, x', phi, phi', u, u', y, y']` at t = 0 and its regime.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Start {
    pub state: [f64; 8],
    pub regime: Regime,
}

impl Start {
    /// The default initial state of docs/model.md: stick, x = 0, x' = V, phi = F_N a_N / K,
    /// phi' = 0, u = u' = 0 (the floating pad: (y, phi) static under the load, y' = 0).
    pub fn default_of(scene: &Scene) -> Start {
        let p = Phys::of(scene);
        Start { state: [0.0, p.pad.v, p.phi0, 0.0, 0.0, 0.0, p.y0, 0.0], regime: Regime::Stick }
    }
}

/// A reference run of model 2, part 1, from t = 0 to `duration`.
#[derive(Clone, Debug)]
pub struct Run {
    /// The start state and regime (after normalisation: phi held without rotation, u = u' = 0
    /// without the band).
    pub start: Start,
    pub transitions: Vec<Transition>,
    /// The state at `duration`, and its regime.
    pub final_state: [f64; 8],
    pub final_regime: Regime,
    pub duration: f64,
    /// DOP853 steps accepted on the main path (not counting bisections).
    pub accepted_steps: u64,
    p: Phys,
    tol: Tolerances,
    h_max: f64,
}

/// Runs `scene` from the default initial state to `scene.duration` at the default (tight)
/// tolerances (rtol 1e-12, atol 1e-16, transitions to 1e-13 s, steps up to 0.05 / the fastest
/// rate).
pub fn simulate(scene: &Scene) -> Result<Run, String> {
    simulate_from(scene, Start::default_of(scene), Tolerances::default())
}

/// Runs `scene` from `start` (at t = 0) to `scene.duration` with the given tolerances.
pub fn simulate_from(scene: &Scene, start: Start, tol: Tolerances) -> Result<Run, String> {
    scene.validate().map_err(|e| format!("invalid scene: {e}"))?;
    let p = Phys::of(scene);
    let mut z = Z::from_row_slice(&start.state);
    if !p.pad.rotation {
        z[2] = p.phi0;
        z[3] = 0.0;
    }
    if !p.band {
        z[4] = 0.0;
        z[5] = 0.0;
    }
    if !p.floating {
        z[6] = 0.0;
        z[7] = 0.0;
    }
    if start.regime == Regime::Stick {
        p.project_stick(&mut z);
    }
    let plan = Plan { stop_at: None, chunk_steps: Some(CHUNK_STEPS) };
    let path = driver::run(&p, z, start.regime, scene.duration, plan, &tol, |_| Ok(()))?;
    Ok(Run {
        start: Start { state: path.start.0, regime: path.start.1 },
        transitions: path.transitions,
        final_state: arr(&path.final_state),
        final_regime: path.final_regime,
        duration: scene.duration,
        accepted_steps: path.accepted_steps,
        p,
        tol,
        h_max: path.h_max,
    })
}

impl Run {
    /// The regime segments: (start time, start state, regime, end time).
    fn segments(&self) -> Vec<(f64, Z, Regime, f64)> {
        let mut out = Vec::with_capacity(self.transitions.len() + 1);
        let mut t0 = 0.0;
        let mut z0 = Z::from_row_slice(&self.start.state);
        let mut r0 = self.start.regime;
        for tr in &self.transitions {
            out.push((t0, z0, r0, tr.t));
            t0 = tr.t;
            z0 = Z::from_row_slice(&tr.state);
            r0 = tr.to;
        }
        out.push((t0, z0, r0, self.duration));
        out
    }

    /// Integrates a segment from its start to `t1` in chunks; the step ends of every chunk at
    /// and after `from` are handed to `f` (times, states).
    fn walk<F: FnMut(&[f64], &[Z]) -> Result<(), String>>(
        &self,
        seg: (f64, Z, Regime),
        from: f64,
        t1: f64,
        mut f: F,
    ) -> Result<Z, String> {
        let (mut t, mut z, regime) = seg;
        let chunk = CHUNK_STEPS * self.h_max;
        if from > t {
            // to the window's start without output
            while t < from {
                let stop = if from - t > 1.5 * chunk { t + chunk } else { from };
                z = driver::state_at(&self.p, regime, t, z, stop, self.h_max, &self.tol)?;
                t = stop;
            }
        }
        while t < t1 {
            let stop = if t1 - t > 1.5 * chunk { t + chunk } else { t1 };
            let (ts, zs, _) = driver::integrate(&self.p, regime, t, z, stop, self.h_max, &self.tol)?;
            f(&ts, &zs)?;
            t = stop;
            z = *zs.last().expect("DOP853 output holds the start");
        }
        Ok(z)
    }

    /// Statistics over [from, to] (0 <= from < to <= duration): the true extremes of the
    /// continuous motion (extrema inside a step are bisected on the sign of the quantity's rate;
    /// both one-sided values at a transition count), the stick fraction and the stick-slip
    /// frequency.
    pub fn window_stats(&self, from: f64, to: f64) -> Result<Stats, String> {
        if !(from >= 0.0 && from < to && to <= self.duration) {
            return Err(format!("model-2 reference: window [{from}, {to}] s not inside [0, {}] s", self.duration));
        }
        let p = self.p;
        let mut lo = [f64::INFINITY; 6];
        let mut hi = [f64::NEG_INFINITY; 6];
        let mut stick_time = 0.0;
        for (t0, z0, regime, t1) in self.segments() {
            if t0 > to || (t1 <= from && t0 < from) {
                continue;
            }
            let (a, b) = (t0.max(from), t1.min(to));
            if regime == Regime::Stick {
                stick_time += b - a;
            }
            let mut include = |q: [f64; 6]| {
                for c in 0..6 {
                    lo[c] = lo[c].min(q[c]);
                    hi[c] = hi[c].max(q[c]);
                }
            };
            if t0 >= from {
                include(p.quantities(regime, &z0));
            }
            if b <= a {
                continue;
            }
            let tol = self.tol;
            let h_max = self.h_max;
            let z_end = self.walk((t0, z0, regime), a, b, |ts, zs| {
                include(p.quantities(regime, &zs[0]));
                for k in 1..zs.len() {
                    include(p.quantities(regime, &zs[k]));
                    let ra = p.quantity_rates(regime, &zs[k - 1]);
                    let rb = p.quantity_rates(regime, &zs[k]);
                    for c in 0..6 {
                        if ra[c] * rb[c] < 0.0 {
                            let up = ra[c] > 0.0;
                            let step = Bracket { t_a: ts[k - 1], y_a: zs[k - 1], lo: ts[k - 1], hi: ts[k], y_hi: zs[k] };
                            let found = driver::bisect(&p, regime, step, h_max, &tol, |y| {
                                (p.quantity_rates(regime, y)[c] > 0.0) != up
                            })?;
                            include(p.quantities(regime, &found.state));
                        }
                    }
                }
                Ok(())
            })?;
            include(p.quantities(regime, &z_end));
        }
        let onsets: Vec<f64> = self
            .transitions
            .iter()
            .filter(|tr| tr.from == Regime::Stick && tr.t >= from && tr.t <= to)
            .map(|tr| tr.t)
            .collect();
        Ok(Stats::of(lo, hi, stick_time, to - from, &onsets))
    }

    /// The regime at time t (the regime a transition at exactly t enters).
    pub fn regime_at(&self, t: f64) -> Regime {
        self.transitions.iter().take_while(|tr| tr.t <= t).last().map_or(self.start.regime, |tr| tr.to)
    }

    /// The states `[x, x', phi, phi', u, u', y, y']` at the given times (each in [0, duration]; any
    /// order). At a transition's time the state is the one the new regime starts from. Each
    /// state is integrated from the previous requested time in the same segment (or the
    /// segment's start), at the run's tolerances.
    pub fn sample(&self, times: &[f64]) -> Result<Vec<[f64; 8]>, String> {
        if let Some(t) = times.iter().find(|t| !(**t >= 0.0 && **t <= self.duration)) {
            return Err(format!("model-2 reference: sample time {t} s not inside [0, {}] s", self.duration));
        }
        let mut order: Vec<usize> = (0..times.len()).collect();
        order.sort_by(|a, b| times[*a].total_cmp(&times[*b]));
        let segs = self.segments();
        let mut out = vec![[0.0; 8]; times.len()];
        let mut si = 0;
        let (mut t, mut z) = (segs[0].0, segs[0].1);
        for idx in order {
            let tq = times[idx];
            // the segment holding tq: the last one starting at or before it
            while si + 1 < segs.len() && segs[si + 1].0 <= tq {
                si += 1;
                t = segs[si].0;
                z = segs[si].1;
            }
            let regime = segs[si].2;
            z = self.walk((t, z, regime), t, tq, |_, _| Ok(()))?;
            t = tq;
            out[idx] = arr(&z);
        }
        Ok(out)
    }

    /// Window statistics over the scene's window [stats_from, duration].
    pub fn stats(&self, scene: &Scene) -> Result<Stats, String> {
        self.window_stats(scene.stats_from, self.duration)
    }
}
