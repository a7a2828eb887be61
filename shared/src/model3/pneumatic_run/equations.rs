//! The pneumatic runner's equations: the right-hand side in each (pad, band) regime, the
//! forces, the guards, the entry to stick and the range check.

use super::{dot, BandMotion, PneumaticRunner, NP, P, UDOT_LIMIT, U_LIMIT, XB, YDOT_LIMIT, Y_LIMIT};
use crate::halt::Halt;
use crate::model2::system::{System, NS, ONE, Y};
use crate::stickslip::Regime;

impl PneumaticRunner {
    pub(super) fn sys(&self, band: BandMotion) -> &System {
        if band == 0 {
            &self.stuck
        } else {
            &self.sliding
        }
    }

    /// The band's velocity x_b' = V + u' [m/s].
    pub(super) fn band_velocity(&self, w: &[f64; NP]) -> f64 {
        self.v + w[5]
    }

    /// The cylinder's net force on the sliding band, A (p - p_atm) - F_seal - c_b V [N] (the
    /// guides' damping on u' is in the equations).
    pub(super) fn cylinder_force(&self, band: BandMotion, w: &[f64; NP]) -> f64 {
        let vb = self.band_velocity(w);
        self.cyl.force(w[P]) - band as f64 * self.cyl.seal_friction(vb) - self.cyl.c_b * self.v
    }

    pub(super) fn z(w: &[f64; NP]) -> [f64; NS] {
        core::array::from_fn(|i| w[i])
    }

    /// The pad's friction coefficient's Stribeck excess sigma (mu(|v|) - mu_k) N at `z` [N].
    pub(super) fn stribeck_excess(&self, sys: &System, regime: Regime, z: &[f64; NS]) -> f64 {
        if !sys.stribeck || regime == Regime::Stick {
            return 0.0;
        }
        let v = dot(&sys.r_v, z);
        let y = libm::fabs(v) / sys.v_s;
        let e = if sys.delta == 1.0 { libm::exp(-y) } else if y > 0.0 { libm::exp(-libm::pow(y, sys.delta)) } else { 1.0 };
        regime.friction_sign() * sys.d_mu * e * dot(&sys.r_n, z)
    }

    /// The friction force on the pad [N] at `w` in (`regime`, `band`): F_req in stick (with the
    /// cylinder's share while the band slides), sigma mu(|v|) N in slip.
    pub fn friction_force(&self, regime: Regime, band: BandMotion, w: &[f64; NP]) -> f64 {
        let sys = self.sys(band);
        let z = Self::z(w);
        match regime {
            Regime::Stick => {
                let f = dot(&sys.r_freq, &z);
                if band == 0 {
                    f
                } else {
                    f + self.f_g * self.cylinder_force(band, w)
                }
            }
            _ => regime.friction_sign() * sys.mu_k * dot(&sys.r_n, &z) + self.stribeck_excess(sys, regime, &z),
        }
    }

    /// The normal force N [N].
    pub fn normal_force(&self, w: &[f64; NP]) -> f64 {
        dot(&self.sliding.r_n, &Self::z(w))
    }

    /// The pad's sliding velocity on the band [m/s].
    pub fn sliding_velocity(&self, w: &[f64; NP]) -> f64 {
        dot(&self.sliding.r_v, &Self::z(w))
    }

    /// w' in (`regime`, `band`).
    pub(super) fn derivative(&self, regime: Regime, band: BandMotion, w: &[f64; NP]) -> [f64; NP] {
        let sys = self.sys(band);
        let z = Self::z(w);
        let a = &sys.a[regime.index()];
        let mut d = [0.0; NP];
        for r in 0..NS {
            d[r] = dot(&a[r], &z);
        }
        let q = self.stribeck_excess(sys, regime, &z);
        if q != 0.0 {
            for r in 0..NS {
                d[r] += sys.b[r] * q;
            }
        }
        if band == 0 {
            d[4] = w[5];
            d[5] = 0.0;
            d[P] = self.cyl.pressure_rate(w[P], w[XB], 0.0);
            d[XB] = 0.0;
        } else {
            let gf = self.cylinder_force(band, w);
            let g = &self.g[regime.index()];
            for r in 0..NS {
                d[r] += g[r] * gf;
            }
            let vb = self.band_velocity(w);
            d[P] = self.cyl.pressure_rate(w[P], w[XB], vb);
            d[XB] = vb;
        }
        d
    }

    /// The watched functions of (`regime`, `band`): the pad's guards (none when frictionless),
    /// then the band's. Each fires as it reaches zero from below.
    pub(super) fn guards(&self, regime: Regime, band: BandMotion, w: &[f64; NP]) -> ([f64; 3], usize) {
        let mut g = [f64::NEG_INFINITY; 3];
        let mut n = 0;
        if !self.frictionless {
            let sys = self.sys(band);
            let z = Self::z(w);
            match regime {
                Regime::Stick => {
                    let f = self.friction_force(Regime::Stick, band, w);
                    let lim = sys.mu_s * dot(&sys.r_n, &z);
                    g[0] = f - lim;
                    g[1] = -f - lim;
                    n = 2;
                }
                Regime::SlipSlower => {
                    g[0] = dot(&sys.r_v, &z);
                    n = 1;
                }
                Regime::SlipFaster => {
                    g[0] = -dot(&sys.r_v, &z);
                    n = 1;
                }
            }
        }
        g[n] = if band == 0 {
            libm::fabs(self.net_band_force(regime, w)) - self.cyl.f_ss
        } else {
            -(band as f64) * self.band_velocity(w)
        };
        (g, n + 1)
    }

    /// With the band stuck: the net force on it but the seal's, A (p - p_atm) less the pad's
    /// friction on it [N].
    pub(super) fn net_band_force(&self, regime: Regime, w: &[f64; NP]) -> f64 {
        self.cyl.force(w[P]) - self.friction_force(regime, 0, w)
    }

    /// Sets the sliding velocity to zero on entry to stick (the friction impulse that stops
    /// the face, as model 2's `enter_stick`).
    pub(super) fn enter_stick(&self, band: BandMotion, w: &mut [f64; NP]) {
        let sys = self.sys(band);
        let z = Self::z(w);
        let p = -dot(&sys.r_v, &z) / sys.inv_mass_v;
        for r in 0..NS {
            w[r] += sys.b[r] * p;
        }
        w[1] = -(sys.r_v[3] * w[3] + sys.r_v[5] * w[5] + sys.r_v[ONE]);
    }

    /// The pad's regime after its slip reached v = 0 (band `band`).
    pub(super) fn after_velocity_match(&self, band: BandMotion, w: &[f64; NP]) -> Regime {
        let mut ws = *w;
        self.enter_stick(band, &mut ws);
        let f = self.friction_force(Regime::Stick, band, &ws);
        let lim = self.sys(band).mu_s * self.normal_force(&ws);
        if f > lim {
            Regime::SlipSlower
        } else if -f > lim {
            Regime::SlipFaster
        } else {
            Regime::Stick
        }
    }

    /// The state's range (the stepper's halts), the pressure and the volume.
    pub(super) fn check(&self, w: &[f64; NP], t: f64) -> Result<(), Halt> {
        if !w.iter().all(|v| v.is_finite()) || !(w[P] > 0.0) || !(self.cyl.volume(w[XB]) > 0.0) {
            return Err(Halt::NonFinite { t });
        }
        let pad = [w[0], w[1], w[2], w[3]];
        self.limits.check(&pad, self.regime, || t)?;
        if libm::fabs(w[4]) > U_LIMIT || libm::fabs(w[5]) > UDOT_LIMIT {
            return Err(Halt::Diverged { t, regime: self.regime, stiffness_margin: f64::INFINITY });
        }
        if self.sliding.floating {
            let [d_l, d_t, floor_l, floor_t] = self.float_limits;
            if !(w[Y] + d_l * w[2] >= floor_l && w[Y] + d_t * w[2] >= floor_t) {
                return Err(Halt::ContactLoss { t, n: 0.0 });
            }
            if libm::fabs(w[Y]) > Y_LIMIT || libm::fabs(w[Y + 1]) > YDOT_LIMIT {
                return Err(Halt::Diverged { t, regime: self.regime, stiffness_margin: f64::INFINITY });
            }
        }
        Ok(())
    }
}
