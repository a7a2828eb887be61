//! Model 2 as a hybrid system for the event-driven DOP853 driver: the right-hand side of each
//! regime, its guard and the guard's rate, the arming of slip phases and the transitions.

use super::*;

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
