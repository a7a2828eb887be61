//! Stick at event speed: a jump over whole steps of stick that the guard provably does not
//! leave, for runs that want no state between transitions (the maps' cells).
//!
//! In stick x = x_0 + V t exactly, and the required force f(t) = k_g x + c_x V = f_0 + k_g V t
//! is linear in time. With rotation, phi obeys
//!
//! ```text
//! I phi'' + c_phi phi' + K phi = F(t) = F_N a_N + s w (k_g x(t) + c_x V) = F_0 + F_1 t
//! ```
//!
//! whose forced response to the ramp is phi_p(t) = (F_0 + F_1 t) / K - c_phi F_1 / K^2; the
//! rest, h = phi - phi_p, is the free oscillation, whose energy I h'^2 / 2 + K h^2 / 2 never
//! grows (c_phi >= 0, K > 0), so |h(t)| <= R = sqrt(h_0^2 + I h_0'^2 / K) for every t >= 0.
//! The guard |f| < mu_s c_N phi therefore holds while both straight lines
//!
//! ```text
//! mu_s c_N (phi_p(t) - R) - f(t) > 0   and   mu_s c_N (phi_p(t) - R) + f(t) > 0
//! ```
//!
//! do: a lower bound of the margin in closed form. [`ExactTables::jump_stick`] takes the
//! whole steps before the first of those lines reaches zero (less two steps and a relative
//! 1e-9 of room for rounding), by the exact stick flow over 2^j steps, and leaves the rest of
//! the stick phase, where the oscillation may reach the limit, to the ordinary step, which
//! locates the breakaway inside its step as before. Without rotation the limit is mu_s N_0
//! and the lines are exact. A jump never leaves the state's range (checked on the bounds), so
//! no halt falls inside one.
//!
//! The state after a jump is the state the steps would reach, to rounding (the flows over 2^j
//! steps are squared from one step's in f64): the run's statistics are those of the same
//! continuous motion, not bit for bit those of the stepped run.

use super::*;
use crate::halt::{PHIDOT_LIMIT, PHI_LIMIT, X_LIMIT};

/// The longest flow of the tables is over 2^JUMP_LEVELS steps (longer jumps repeat it).
pub const JUMP_LEVELS: usize = 16;

/// The tables and constants of [`ExactTables::jump_stick`] for one scene and step.
#[derive(Clone, Copy, Debug)]
pub struct StickJump<T: Real> {
    /// fold[j]: the phi and phi' rows of the stick flow over 2^j steps in increment form with
    /// x' = V folded into the constant: phi += a0 x + a1 phi + a2 phi' + a3, phi' += a4 x + a5
    /// phi + a6 phi' + a7 (x at the flow's start).
    fold: [[T; 8]; JUMP_LEVELS + 1],
    /// Whether the bound applies: K > 0, c_phi >= 0, mu_s c_N > 0 (1-DOF: mu_s N_0 > 0).
    usable: bool,
    rotation: bool,
    k_rot: f64,
    inertia: f64,
    c_phi: f64,
    /// F_N a_N + s w c_x V [N m]: the ramp's constant without the k_g x term.
    f_const: f64,
    /// s w k_g [N m / m].
    sw_kg: f64,
    k_g: f64,
    c_x_v: f64,
    v: f64,
    /// mu_s c_N [N/rad] (rotation) or mu_s N_0 [N] (1-DOF).
    mu_s_limit: f64,
    dt: f64,
}

impl<T: Real> StickJump<T> {
    /// The jump's tables for a validated `scene` at its step.
    pub fn new(scene: &Scene) -> Self {
        let co = Coefficients::of(scene);
        let dt = scene.dt;
        let a = system_matrix(scene, &co, Regime::Stick);
        // increment form E = expm(A tau) - I; doubling: E_2tau = E_tau E_tau + 2 E_tau
        let mut e = linalg::expm_minus_identity(&linalg::scale(&a, dt));
        let mut fold = [[T::zero(); 8]; JUMP_LEVELS + 1];
        let v = scene.v;
        for f in fold.iter_mut() {
            *f = ExactTables::<T>::fold_stick_rows(e[2], e[3], v);
            let sq = linalg::mul(&e, &e);
            for r in 0..5 {
                for c in 0..5 {
                    e[r][c] = sq[r][c] + 2.0 * e[r][c];
                }
            }
        }
        let sw = co.s * scene.w;
        let mu_s_limit = if scene.rotation { scene.mu_s * co.c_n } else { scene.mu_s * co.n0 };
        StickJump {
            fold,
            usable: mu_s_limit > 0.0 && (!scene.rotation || (co.k_rot > 0.0 && scene.c_phi >= 0.0 && scene.inertia > 0.0)),
            rotation: scene.rotation,
            k_rot: co.k_rot,
            inertia: scene.inertia,
            c_phi: scene.c_phi,
            f_const: scene.f_n * co.a_n + sw * scene.c_x * v,
            sw_kg: sw * scene.k_g,
            k_g: scene.k_g,
            c_x_v: scene.c_x * v,
            v,
            mu_s_limit,
            dt,
        }
    }

    /// Whole steps from state `z` (in stick) that the guard's lower bound keeps in stick, and
    /// in range; 0 when none.
    fn safe_steps(&self, z: &[f64; 4]) -> u64 {
        if !self.usable {
            return 0;
        }
        let f0 = self.k_g * z[0] + self.c_x_v;
        let f1 = self.k_g * self.v;
        // the margin's lower bound alpha + gamma t on each side: (alpha, gamma) for +f and -f
        let (base, slope, reach) = if self.rotation {
            let big_f0 = self.f_const + self.sw_kg * z[0];
            let big_f1 = self.sw_kg * self.v;
            let phi_p0 = big_f0 / self.k_rot - self.c_phi * big_f1 / (self.k_rot * self.k_rot);
            let phi_p1 = big_f1 / self.k_rot;
            let h0 = z[2] - phi_p0;
            let h1 = z[3] - phi_p1;
            let r = libm::sqrt(h0 * h0 + self.inertia / self.k_rot * h1 * h1);
            if !r.is_finite() {
                return 0;
            }
            (self.mu_s_limit * (phi_p0 - r), self.mu_s_limit * phi_p1, Some((phi_p0, phi_p1, r)))
        } else {
            (self.mu_s_limit, 0.0, None)
        };
        let room = 1e-9 * (libm::fabs(base) + libm::fabs(f0)) + f64::MIN_POSITIVE;
        let mut t_safe = f64::INFINITY;
        for (alpha, gamma) in [(base - f0 - room, slope - f1), (base + f0 - room, slope + f1)] {
            if !(alpha > 0.0) {
                return 0;
            }
            if gamma < 0.0 {
                t_safe = t_safe.min(alpha / -gamma);
            }
        }
        // no more than the range allows (x grows by V t; phi within phi_p +- R)
        t_safe = t_safe.min(0.5 * X_LIMIT / self.v);
        let steps = libm::floor(t_safe / self.dt) - 2.0;
        if !(steps >= 1.0) {
            return 0;
        }
        let steps = if steps > 1e15 { 1e15 } else { steps };
        let t_end = steps * self.dt;
        if libm::fabs(z[0] + self.v * t_end) > 0.5 * X_LIMIT {
            return 0;
        }
        if let Some((phi_p0, phi_p1, r)) = reach {
            let phi_hi = (phi_p0 + phi_p1 * t_end).max(phi_p0) + r;
            let phid_hi = libm::fabs(phi_p1) + r * libm::sqrt(self.k_rot / self.inertia);
            if !(phi_hi < 0.5 * PHI_LIMIT && phid_hi < 0.5 * PHIDOT_LIMIT) {
                return 0;
            }
        }
        steps as u64
    }
}

impl<T: Real> ExactTables<T> {
    /// Jumps the run in `s`, if it is in stick, over as many whole steps (at most
    /// `max_steps`) as the guard's lower bound keeps in stick ([`StickJump`]); returns the
    /// steps taken (0: none, and `s` untouched). The steps have no transition and no halt;
    /// the state at the end is the stepped state's to rounding. `jump` must be built for
    /// this scene ([`StickJump::new`]).
    pub fn jump_stick(&self, jump: &StickJump<T>, s: &mut ExactState<T>, max_steps: u64) -> u64 {
        if s.regime != Regime::Stick || s.halted.is_some() || max_steps == 0 {
            return 0;
        }
        let z64 = [s.z[0].to_f64(), s.z[1].to_f64(), s.z[2].to_f64(), s.z[3].to_f64()];
        // the substep counter is u32 (see ExactState): stay well inside it
        let subs_room = u64::from(u32::MAX - s.anchor_subs.min(u32::MAX)) / 2 / u64::from(self.prop.n_sub);
        let n = jump.safe_steps(&z64).min(max_steps).min(subs_room);
        if n == 0 {
            return 0;
        }
        let mut left = n;
        let mut j = JUMP_LEVELS;
        loop {
            let span = 1u64 << j;
            while left >= span {
                if self.rotation {
                    (s.z[2], s.z[3]) = super::step::stick_rotation(&jump.fold[j], &s.z);
                }
                // after a stick substep x = anchor_x + V (e0 + (subs - 1) h_sub), as the step
                // forms it (subs >= 1 here)
                s.anchor_subs += (span * u64::from(self.prop.n_sub)) as u32;
                s.z[0] = self.stick_x(s, s.anchor_subs - 1);
                left -= span;
            }
            if j == 0 {
                break;
            }
            j -= 1;
        }
        s.z[1] = self.fast.v;
        s.step += n;
        s.n_reported = 0;
        n
    }
}
