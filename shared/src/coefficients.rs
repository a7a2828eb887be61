//! Coefficients derived from a scene: the lever arms of the contact springs about the pivot,
//! the rotational stiffness, the normal-force gain and the sign of the friction moment.
//!
//! With the pivot at the supported edge (mid-thickness):
//!
//! | caliper | d_L          | d_T          | a_N        | s  |
//! |---------|--------------|--------------|------------|----|
//! | push    | l + l_cL     | l - l_cT     | beta       | +1 |
//! | pull    | l - l_cL     | l + l_cT     | 2 l - beta | -1 |
//!
//! K = k_L d_L^2 + k_T d_T^2 [N m/rad], c_N = k_L d_L + k_T d_T [N/rad], N = c_N phi.

use crate::scene::{Caliper, Scene};

/// Derived coefficients of a scene, in f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coefficients {
    /// Lever arm of the leading contact spring about the pivot [m].
    pub d_l: f64,
    /// Lever arm of the trailing contact spring about the pivot [m].
    pub d_t: f64,
    /// Rotational contact stiffness K [N m/rad].
    pub k_rot: f64,
    /// Normal-force gain c_N: N = c_N phi [N/rad].
    pub c_n: f64,
    /// Lever arm of the normal load about the pivot a_N [m].
    pub a_n: f64,
    /// Sign of the friction moment s w F_f: +1 push, -1 pull.
    pub s: f64,
    /// Static rotation under the load alone, phi_0 = F_N a_N / K [rad].
    pub phi0: f64,
    /// Static normal force N_0 = c_N phi_0 [N].
    pub n0: f64,
}

impl Coefficients {
    pub fn of(scene: &Scene) -> Coefficients {
        let l = scene.l;
        let (d_l, d_t, a_n, s) = match scene.caliper {
            Caliper::Push => (l + scene.l_cl, l - scene.l_ct, scene.beta, 1.0),
            Caliper::Pull => (l - scene.l_cl, l + scene.l_ct, 2.0 * l - scene.beta, -1.0),
        };
        let [k_l, k_t] = scene.contact_stiffnesses();
        let k_rot = k_l * d_l * d_l + k_t * d_t * d_t;
        let c_n = k_l * d_l + k_t * d_t;
        let phi0 = scene.f_n * a_n / k_rot;
        Coefficients { d_l, d_t, k_rot, c_n, a_n, s, phi0, n0: c_n * phi0 }
    }

    /// Rotational stiffness while the friction force is `sigma mu N` (sigma = +1 pad slower
    /// than the band or sticking at the static limit, -1 pad faster):
    /// K_eff = K - s sigma mu w c_N. Zero or below: the pad sprags (phi diverges).
    pub fn effective_rotational_stiffness(&self, scene: &Scene, sigma: f64, mu: f64) -> f64 {
        self.k_rot - self.s * sigma * mu * scene.w * self.c_n
    }

    /// The smallest of the sprag margins K_eff over the regimes the scene can visit
    /// (stick at the static limit in either direction, slip in either direction) [N m/rad].
    pub fn sprag_margin(&self, scene: &Scene) -> f64 {
        let mut m = f64::INFINITY;
        for sigma in [1.0, -1.0] {
            for mu in [scene.mu_s, scene.mu_k] {
                let k = self.effective_rotational_stiffness(scene, sigma, mu);
                if k < m {
                    m = k;
                }
            }
        }
        m
    }

    /// The floating pad's rest under the load without friction, (y_0 [m], phi_0 [rad]):
    /// (k_L + k_T + k_pivot) y + c_N phi = F_N and c_N y + K phi = F_N a_N.
    pub fn floating_rest(&self, scene: &Scene) -> (f64, f64) {
        let [k_l, k_t] = scene.contact_stiffnesses();
        let k_y = k_l + k_t + scene.k_pivot;
        let d = k_y * self.k_rot - self.c_n * self.c_n;
        let y0 = (scene.f_n * self.k_rot - self.c_n * scene.f_n * self.a_n) / d;
        let phi0 = (k_y * scene.f_n * self.a_n - self.c_n * scene.f_n) / d;
        (y0, phi0)
    }

    /// Quasi-static time from rest to the first slip:
    /// t1 = mu_s N0 / (k_g V (1 - s mu_s w c_N / K)) (+ the band's and the damper's terms, see
    /// `band_and_damping`); with the rotation held (N constant) the
    /// bracket is 1. Infinite when the pad self-locks. With friction-face kinematics the face,
    /// not the pivot, moves at V: x + s w phi - s w phi0 = F (1/k_g + w^2/K) = V t, so t1 grows
    /// by the factor 1 + k_g w^2 / K. A pad that is not hinged (finite k_pivot, face kinematics)
    /// solves its static (y, phi) balance instead.
    pub fn quasi_static_first_slip(&self, scene: &Scene) -> f64 {
        if scene.floating() && scene.rotation {
            // the floating pad, statically: (k_L + k_T + k_pivot) y + c_N phi = F_N and
            // c_N y + K phi = F_N a_N + s w F, so d phi/dF = s w k_y / D, dN/dF = s w c_N k_pivot / D
            // (D = k_y K - c_N^2): N stays F_N-borne as the friction builds, exactly with k_pivot = 0
            let [k_l, k_t] = scene.contact_stiffnesses();
            let k_s = k_l + k_t;
            let k_y = k_s + scene.k_pivot;
            let d = k_y * self.k_rot - self.c_n * self.c_n;
            let s_w = self.s * scene.w;
            let (y0, phi0) = self.floating_rest(scene);
            let n0 = k_s * y0 + self.c_n * phi0;
            let dn_df = s_w * self.c_n * scene.k_pivot / d;
            let lock = 1.0 - scene.mu_s * dn_df;
            if lock <= 0.0 {
                return f64::INFINITY;
            }
            let f1 = scene.mu_s * n0 / lock;
            let t1 = f1 * (1.0 / scene.k_g + s_w * s_w * k_y / d) / scene.v;
            return (t1 + Self::band_and_damping(scene, f1)).max(0.0);
        }
        let lock = if scene.rotation { 1.0 - self.s * scene.mu_s * scene.w * self.c_n / self.k_rot } else { 1.0 };
        if lock <= 0.0 {
            return f64::INFINITY;
        }
        let t1 = scene.mu_s * self.n0 / (scene.k_g * scene.v * lock);
        let t1 = if scene.face && scene.rotation { t1 * (1.0 + scene.k_g * scene.w * scene.w / self.k_rot) } else { t1 };
        (t1 + Self::band_and_damping(scene, scene.mu_s * self.n0 / lock)).max(0.0)
    }

    /// What the band and the guide's damper add to [`Self::quasi_static_first_slip`] at the
    /// breakaway's friction `f1` [N]: the band's spring, in series with the guide, gives way by
    /// f1 / k_b while the pad sticks (the band's x lags the drive's V t), + f1 / (k_b V); the
    /// damper, at x' = V in stick, carries c_x V of the friction, so the guide's spring needs
    /// c_x V / k_g less stretch, - c_x / k_g (a damper that carries the whole breakaway friction
    /// at V slips the pad at once: the estimate is then 0). Exactly 0 without the band and
    /// without c_x (the thesis model: the estimate is the thesis's, bit for bit). With the face
    /// and the rotation the damper's term is the hinged pad's (the pivot then moves a little
    /// slower than V); not measured.
    fn band_and_damping(scene: &Scene, f1: f64) -> f64 {
        let band = if scene.band { f1 / (scene.k_b * scene.v) } else { 0.0 };
        let damper = if scene.c_x != 0.0 { scene.c_x / scene.k_g } else { 0.0 };
        band - damper
    }
}
