//! Model 2's constants and forces, written from the equations of docs/model.md: the normal
//! force, the friction law, the force stick requires, the floating pad and the friction face, and
//! the projection onto stick.

use super::*;

/// The pad's constants (docs/model.md) and model 2's.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Phys {
    pub(crate) pad: Pad,
    pub(crate) phi0: f64,
    pub(crate) stribeck: bool,
    pub(crate) v_s: f64,
    pub(crate) delta: f64,
    pub(crate) band: bool,
    pub(crate) mb: f64,
    pub(crate) kb: f64,
    pub(crate) cb: f64,
    /// Friction-face kinematics (only with rotation).
    pub(crate) face: bool,
    /// The floating pad (finite k_pivot): the pivot translates by y normal to the band, the
    /// centre of gravity l from it (mass matrix [[I, m l], [m l, m]] in (phi, y)).
    pub(crate) floating: bool,
    pub(crate) k_pivot: f64,
    pub(crate) c_y: f64,
    pub(crate) l: f64,
    pub(crate) k_s: f64,
    pub(crate) f_n: f64,
    pub(crate) y0: f64,
}

impl Phys {
    pub(crate) fn of(sc: &Scene) -> Phys {
        let pad = Pad::of(sc);
        let (d_l, d_t, a_n, k_rot) = (pad.d_l, pad.d_t, pad.a_n, pad.k_rot);
        Phys {
            pad,
            phi0: if sc.floating() {
                let k_y = (sc.contact_stiffnesses()[0] + sc.contact_stiffnesses()[1]) + sc.k_pivot;
                let c_n = sc.contact_stiffnesses()[0] * d_l + sc.contact_stiffnesses()[1] * d_t;
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
            k_s: (sc.contact_stiffnesses()[0] + sc.contact_stiffnesses()[1]),
            f_n: sc.f_n,
            y0: if sc.floating() {
                let k_y = (sc.contact_stiffnesses()[0] + sc.contact_stiffnesses()[1]) + sc.k_pivot;
                let c_n = sc.contact_stiffnesses()[0] * d_l + sc.contact_stiffnesses()[1] * d_t;
                (sc.f_n * k_rot - c_n * sc.f_n * a_n) / (k_y * k_rot - c_n * c_n)
            } else {
                0.0
            },
        }
    }

    pub(crate) fn normal(&self, z: &Z) -> f64 {
        if self.floating {
            return self.k_s * z[6] + self.pad.c_n * z[2];
        }
        self.pad.c_n * if self.pad.rotation { z[2] } else { self.phi0 }
    }

    /// Rate of N along the motion.
    pub(crate) fn normal_rate(&self, zd: &Z) -> f64 {
        if self.floating {
            self.k_s * zd[6] + self.pad.c_n * zd[2]
        } else if self.pad.rotation {
            self.pad.c_n * zd[2]
        } else {
            0.0
        }
    }

    /// The floating pad's (phi, y) mass block: its determinant I m - (m l)^2.
    pub(crate) fn det_float(&self) -> f64 {
        self.pad.i * self.pad.m - (self.pad.m * self.l) * (self.pad.m * self.l)
    }

    /// The floating pad: (phi'', y'') from the generalized forces on phi (with the friction's
    /// moment) and on y, by the inverse of [[I, m l], [m l, m]].
    pub(crate) fn float_acc(&self, q_phi: f64, q_y: f64) -> (f64, f64) {
        let det = self.det_float();
        let ml = self.pad.m * self.l;
        ((self.pad.m * q_phi - ml * q_y) / det, (self.pad.i * q_y - ml * q_phi) / det)
    }

    /// The floating pad's generalized forces without friction on phi and y (`c = 0`: without
    /// the constant terms, for rates).
    pub(crate) fn float_forces(&self, z: &Z, c: f64) -> (f64, f64) {
        let q_phi = c * self.pad.moment_load - self.pad.k_rot * z[2] - self.pad.c_n * z[6] - self.pad.cphi * z[3];
        let q_y = c * self.f_n - (self.k_s + self.k_pivot) * z[6] - self.pad.c_n * z[2] - self.c_y * z[7];
        (q_phi, q_y)
    }

    /// The floating pad's stick friction: x'' + s w phi'' - u'' = 0 with the equations of
    /// motion, solved for F (linear in F).
    pub(crate) fn f_req_float(&self, z: &Z, affine: bool) -> f64 {
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
    pub(crate) fn slip_v(&self, z: &Z) -> f64 {
        self.face_rate(z) - self.pad.v
    }

    /// The face's velocity relative to the band's drive point, x' (+ s w phi') - u' (also the
    /// rate of v along the motion when given z').
    pub(crate) fn face_rate(&self, z: &Z) -> f64 {
        z[1] + if self.face { self.pad.s * self.pad.w * z[3] } else { 0.0 } - if self.band { z[5] } else { 0.0 }
    }

    /// 1/m + w^2/I (face) + 1/m_b (band): the sliding velocity's response to a friction impulse.
    pub(crate) fn inv_mass_v(&self) -> f64 {
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
    pub(crate) fn f_req_face(&self, z: &Z, affine: bool) -> f64 {
        let c = if affine { 1.0 } else { 0.0 };
        let px = -self.pad.kg * z[0] - self.pad.cx * z[1];
        let pphi = -self.pad.k_rot * z[2] - self.pad.cphi * z[3] + c * self.pad.moment_load;
        let pu = if self.band { -self.kb * z[4] - self.cb * z[5] } else { 0.0 };
        // (px + F)/m + s w (pphi + s w F)/I - (pu - F)/m_b = 0
        let rhs = -px / self.pad.m - self.pad.s * self.pad.w * pphi / self.pad.i + if self.band { pu / self.mb } else { 0.0 };
        rhs / self.inv_mass_v()
    }

    pub(crate) fn mu(&self, speed: f64) -> f64 {
        if self.stribeck {
            self.pad.mu_k + (self.pad.mu_s - self.pad.mu_k) * (-(speed / self.v_s).powf(self.delta)).exp()
        } else {
            self.pad.mu_k
        }
    }

    /// d mu / d|v|.
    pub(crate) fn mu_slope(&self, speed: f64) -> f64 {
        if !self.stribeck {
            return 0.0;
        }
        let r = speed.max(f64::MIN_POSITIVE) / self.v_s;
        -(self.pad.mu_s - self.pad.mu_k) * (-r.powf(self.delta)).exp() * self.delta * r.powf(self.delta - 1.0) / self.v_s
    }

    pub(crate) fn sigma(regime: Regime) -> f64 {
        match regime {
            Regime::Slower => 1.0,
            Regime::Faster => -1.0,
            Regime::Stick => 0.0,
        }
    }

    /// The stick's required friction force.
    pub(crate) fn f_req(&self, z: &Z) -> f64 {
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
    pub(crate) fn f_req_rate(&self, zd: &Z) -> f64 {
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

    pub(crate) fn friction(&self, regime: Regime, z: &Z) -> f64 {
        match regime {
            Regime::Stick => self.f_req(z),
            _ => Self::sigma(regime) * self.mu(self.slip_v(z).abs()) * self.normal(z),
        }
    }

    /// The statistics' quantities: x, x', phi, phi', band velocity x_b' = V + u', band
    /// acceleration u''.
    pub(crate) fn quantities(&self, regime: Regime, z: &Z) -> [f64; 6] {
        let zd = self.rhs(regime, z);
        [z[0], z[1], z[2], z[3], self.pad.v + if self.band { z[5] } else { 0.0 }, zd[5]]
    }

    /// Rates of [`Phys::quantities`].
    pub(crate) fn quantity_rates(&self, regime: Regime, z: &Z) -> [f64; 6] {
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
    pub(crate) fn project_stick(&self, z: &mut Z) {
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
