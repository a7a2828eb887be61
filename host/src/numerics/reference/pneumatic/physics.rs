//! The pneumatic drive's forces, written from docs/model.md ("Model 3, part 3"): the air
//! column, the ISO 6358 throttle (its conductance solved from V when the scene gives 0), the
//! seal's friction, the band's force, and the pad's accelerations under a friction force, the
//! stick's friction and the projection onto stick. The pad's constants, normal force, friction
//! law and floating-pad mass matrix are the model-2 reference's ([`Phys`]); the band, chamber,
//! throttle and seal are this file's.

use super::*;

/// ISO 8778's reference pressure R T_0 rho_0 [Pa].
pub(super) const P_REF: f64 = 1e5;

/// The pad (model 2's reference physics) on the pneumatic band.
#[derive(Debug)]
pub(super) struct Pneu {
    pub(super) ph: Phys,
    /// Piston area A [m^2], supply p_s [Pa], conductance C [m^3/(s Pa)], critical ratio b,
    /// column L_0 [m], polytropic n.
    pub(super) area: f64,
    pub(super) p_s: f64,
    pub(super) conductance: f64,
    pub(super) b: f64,
    pub(super) l0: f64,
    pub(super) n: f64,
    /// Seal: static, kinetic [N], Stribeck velocity [m/s].
    pub(super) f_ss: f64,
    pub(super) f_sk: f64,
    pub(super) v_ss: f64,
    pub(super) c_b: f64,
    pub(super) m_b: f64,
    /// The scene's V [m/s] (the throttle's solve, the arming threshold's scale).
    pub(super) v: f64,
    /// No pad friction (F_N = 0 or mu_s = 0): the pad slips for good, no pad guard.
    pub(super) frictionless: bool,
    /// The inverse mass of the sliding velocity against a friction impulse: band sliding, stuck.
    pub(super) inv_mass_slide: f64,
    pub(super) inv_mass_stuck: f64,
    /// s w with the friction face, else 0: v = x' + fw phi' - x_b'.
    pub(super) fw: f64,
    /// Guard scales: a force [N] and a velocity [m/s].
    pub(super) force_scale: f64,
    pub(super) speed_scale: f64,
    /// The elementary changes each `transition` made, in order (read by `simulate`).
    pub(super) log: RefCell<Vec<Vec<Change>>>,
}

/// The first 8 components (model 2's reference state layout: phi at 2, 3 and y at 6, 7).
pub(super) fn z8(y: &Y) -> State<8> {
    State::<8>::from_column_slice(&y.as_slice()[..8])
}

impl Pneu {
    pub(super) fn of(sc: &Scene) -> Result<Pneu, String> {
        let mut ph = Phys::of(sc);
        ph.kb = 0.0; // the air column is the drive's spring
        let area = std::f64::consts::PI * sc.bore * sc.bore / 4.0;
        let mut p = Pneu {
            ph,
            area,
            p_s: sc.supply_pressure,
            conductance: sc.throttle_conductance,
            b: sc.throttle_critical_ratio,
            l0: sc.column_length,
            n: sc.polytropic_exponent,
            f_ss: sc.seal_static,
            f_sk: sc.seal_kinetic,
            v_ss: sc.seal_v_s,
            c_b: sc.c_b,
            m_b: sc.m_b,
            v: sc.v,
            frictionless: false,
            inv_mass_slide: 0.0,
            inv_mass_stuck: 0.0,
            fw: if ph.face { ph.pad.s * ph.pad.w } else { 0.0 },
            force_scale: 1.0,
            speed_scale: sc.v.abs().max(1e-6),
            log: RefCell::new(Vec::new()),
        };
        let unit = p.pad_acc(&Y::zeros(), 1.0, 0.0);
        p.inv_mass_stuck = unit[0] + p.fw * unit[1];
        p.inv_mass_slide = p.inv_mass_stuck + 1.0 / p.m_b;
        let y0 = p.start_state();
        let n0 = p.ph.normal(&z8(&y0));
        p.frictionless = !(n0 * p.ph.pad.mu_s > 0.0);
        p.force_scale = (p.ph.pad.mu_s * n0).max(p.f_ss).max(1e-3);
        if p.conductance == 0.0 {
            // steady sliding at V: p_0 = p_atm + (F_seal(V) + mu(V) N_0 + c_b V) / A, and the
            // throttle passes what the column needs there, p_0 A V (p' = 0 at x_b' = V)
            let p0 = ATMOSPHERE_PA + (p.seal(p.v) + p.ph.mu(p.v) * n0 + p.c_b * p.v) / area;
            let phi = p.flow_fraction(p0);
            if !(p0 < p.p_s && phi > 0.0) {
                return Err(format!("pneumatic reference: the supply {} Pa cannot hold steady sliding at {} Pa", p.p_s, p0));
            }
            p.conductance = p0 * area * p.v / (P_REF * p.p_s * phi);
        }
        Ok(p)
    }

    /// The start (docs/model.md, as the product starts): the band at rest just breaking away,
    /// the chamber at p_atm + F_ss / A, the pad at rest and static under its load.
    pub(super) fn start_state(&self) -> Y {
        let mut y = Y::zeros();
        y[2] = self.ph.phi0;
        y[6] = self.ph.y0;
        y[P] = ATMOSPHERE_PA + self.f_ss / self.area;
        y
    }

    /// ISO 6358's flow fraction phi(p / p_s) (no backflow at p >= p_s).
    fn flow_fraction(&self, p: f64) -> f64 {
        let r = p / self.p_s;
        if r <= self.b {
            1.0
        } else if r < 1.0 {
            let q = (r - self.b) / (1.0 - self.b);
            (1.0 - q * q).sqrt()
        } else {
            0.0
        }
    }

    /// p' = n / V_c (p_ref C p_s phi(p / p_s) - p A x_b').
    pub(super) fn p_rate(&self, y: &Y) -> f64 {
        let vc = self.area * (self.l0 + y[XB]);
        self.n / vc * (P_REF * self.conductance * self.p_s * self.flow_fraction(y[P]) - y[P] * self.area * y[XB + 1])
    }

    /// The seal's friction magnitude sliding at speed `w`.
    pub(super) fn seal(&self, w: f64) -> f64 {
        self.f_sk + (self.f_ss - self.f_sk) * (-w.abs() / self.v_ss).exp()
    }

    /// d seal / d|w|.
    fn seal_slope(&self, w: f64) -> f64 {
        -(self.f_ss - self.f_sk) / self.v_ss * (-w.abs() / self.v_ss).exp()
    }

    /// The forces on the sliding band but the pad's friction: A (p - p_atm) - dir F_seal - c_b x_b'.
    pub(super) fn band_force(&self, band: Band, y: &Y) -> f64 {
        self.area * (y[P] - ATMOSPHERE_PA) - band.dir() * self.seal(y[XB + 1]) - self.c_b * y[XB + 1]
    }

    /// Rate of [`Pneu::band_force`] along the motion yd.
    fn band_force_rate(&self, band: Band, y: &Y, yd: &Y) -> f64 {
        let w = y[XB + 1];
        let wd = yd[XB + 1];
        let abs_rate = if w >= 0.0 { wd } else { -wd };
        self.area * yd[P] - band.dir() * self.seal_slope(w) * abs_rate - self.c_b * wd
    }

    /// The pad's accelerations (x'', phi'', y'') under the friction `f` on the face; `c` = 0
    /// drops the constant terms (y then a rate: the accelerations' rates).
    pub(super) fn pad_acc(&self, y: &Y, f: f64, c: f64) -> [f64; 3] {
        let pad = &self.ph.pad;
        let xdd = (-pad.kg * y[0] - pad.cx * y[1] + f) / pad.m;
        if self.ph.floating {
            let (qp, qy) = self.ph.float_forces(&z8(y), c);
            let (pdd, ydd) = self.ph.float_acc(qp + pad.s * pad.w * f, qy);
            [xdd, pdd, ydd]
        } else if pad.rotation {
            [xdd, (c * pad.moment_load - pad.k_rot * y[2] - pad.cphi * y[3] + pad.s * pad.w * f) / pad.i, 0.0]
        } else {
            [xdd, 0.0, 0.0]
        }
    }

    /// The sliding velocity v = x' (+ s w phi') - x_b'.
    pub(super) fn slip_v(&self, y: &Y) -> f64 {
        y[1] + self.fw * y[3] - y[XB + 1]
    }

    fn inv_mass(&self, band: Band) -> f64 {
        if band == Band::Stuck {
            self.inv_mass_stuck
        } else {
            self.inv_mass_slide
        }
    }

    /// The stick's friction: v'' = x'' + fw phi'' - x_b'' = 0 solved for F, with x_b'' = (P_b -
    /// F) / m_b on a sliding band and 0 on a stuck one. With `rate` the same linear form on the
    /// motion yd (the rate of F_req).
    fn f_req_of(&self, band: Band, y: &Y, yd: Option<&Y>) -> f64 {
        let (state, c, pb) = match yd {
            None => (y, 1.0, if band == Band::Stuck { 0.0 } else { self.band_force(band, y) }),
            Some(d) => (d, 0.0, if band == Band::Stuck { 0.0 } else { self.band_force_rate(band, y, d) }),
        };
        let a0 = self.pad_acc(state, 0.0, c);
        let r0 = a0[0] + self.fw * a0[1] - if band == Band::Stuck { 0.0 } else { pb / self.m_b };
        -r0 / self.inv_mass(band)
    }

    pub(super) fn f_req(&self, band: Band, y: &Y) -> f64 {
        self.f_req_of(band, y, None)
    }

    /// The pad's friction force (on the pad, along x; the band gets -F).
    pub(super) fn friction(&self, r: Regime, y: &Y) -> f64 {
        if self.frictionless {
            return 0.0;
        }
        match r.pad {
            Pad::Stick => self.f_req(r.band, y),
            _ => Phys::sigma(r.pad) * self.ph.mu(self.slip_v(y).abs()) * self.ph.normal(&z8(y)),
        }
    }

    /// Rate of the friction force along yd.
    pub(super) fn friction_rate(&self, r: Regime, y: &Y, yd: &Y) -> f64 {
        if self.frictionless {
            return 0.0;
        }
        match r.pad {
            Pad::Stick => self.f_req_of(r.band, y, Some(yd)),
            _ => {
                let v = self.slip_v(y);
                let vd = self.slip_v(yd);
                let speed_rate = if v >= 0.0 { vd } else { -vd };
                let n = self.ph.normal(&z8(y));
                Phys::sigma(r.pad) * (self.ph.mu_slope(v.abs()) * speed_rate * n + self.ph.mu(v.abs()) * self.ph.normal_rate(&z8(yd)))
            }
        }
    }

    /// The net force on a stuck band but the seal's: A (p - p_atm) less the pad's friction.
    pub(super) fn net_stuck(&self, r: Regime, y: &Y) -> f64 {
        self.area * (y[P] - ATMOSPHERE_PA) - self.friction(r, y)
    }

    /// Sets v = 0 on the pad's entry to stick: the friction impulse P = -v / (inverse mass)
    /// on the pad (and -P on a sliding band).
    pub(super) fn project_stick(&self, band: Band, y: &mut Y) {
        let p = -self.slip_v(y) / self.inv_mass(band);
        let d = self.pad_acc(&Y::zeros(), p, 0.0);
        y[1] += d[0];
        if self.ph.pad.rotation {
            y[3] += d[1];
        }
        if self.ph.floating {
            y[7] += d[2];
        }
        if band != Band::Stuck {
            y[XB + 1] -= p / self.m_b;
        }
    }

    /// The right-hand side in regime r.
    pub(super) fn deriv(&self, r: Regime, y: &Y) -> Y {
        let f = self.friction(r, y);
        let a = self.pad_acc(y, f, 1.0);
        let (xbd, xbdd) = if r.band == Band::Stuck { (0.0, 0.0) } else { (y[XB + 1], (self.band_force(r.band, y) - f) / self.m_b) };
        let rot = self.ph.pad.rotation;
        let fl = self.ph.floating;
        Y::from_column_slice(&[
            y[1],
            a[0],
            if rot { y[3] } else { 0.0 },
            a[1],
            xbd,
            xbdd,
            if fl { y[7] } else { 0.0 },
            a[2],
            self.p_rate(y),
            y[P],
        ])
    }
}
