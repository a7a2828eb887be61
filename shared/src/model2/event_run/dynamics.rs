//! The event runner's equations: the right-hand side and its rate in each regime, the forces
//! the sinks read, the entry to stick and the range check (the stepper's).

use super::{dot, rate, EventRunner, Point, UDOT_LIMIT, U_LIMIT, YDOT_LIMIT, Y_LIMIT};
use crate::model2::system::{NS, ONE, Y};
use crate::stickslip::Regime;

impl EventRunner {
    /// The friction force on the pad at `z` in `regime` [N] (the stepper's
    /// `friction_force`: F_req in stick, sigma mu(|v|) N in slip).
    pub fn friction_force(&self, regime: Regime, z: &[f64; NS]) -> f64 {
        let sys = self.sys();
        match regime {
            Regime::Stick => dot(&sys.r_freq, z),
            _ => {
                let n = dot(&sys.r_n, z);
                let mu = if sys.stribeck { sys.mu_k + self.excess(regime, z).1 * sys.d_mu } else { sys.mu_k };
                regime.friction_sign() * mu * n
            }
        }
    }

    pub(super) fn stribeck_slip(&self, regime: Regime) -> bool {
        self.sys().stribeck && regime != Regime::Stick
    }

    /// Stribeck forcing q = sigma (mu(|v|) - mu_k) N and the shape's parts (e, N, v).
    pub(super) fn excess(&self, regime: Regime, z: &[f64; NS]) -> (f64, f64, f64, f64) {
        let sys = &self.sys();
        let v = dot(&sys.r_v, z);
        let n = dot(&sys.r_n, z);
        let y = libm::fabs(v) / sys.v_s;
        let e = if sys.delta == 1.0 {
            libm::exp(-y)
        } else if y > 0.0 {
            libm::exp(-libm::pow(y, sys.delta))
        } else {
            1.0
        };
        (regime.friction_sign() * sys.d_mu * e * n, e, n, v)
    }

    /// z' in `regime` at `z`.
    pub(super) fn derivative(&self, regime: Regime, z: &[f64; NS]) -> [f64; NS] {
        let a = &self.sys().a[regime.index()];
        let mut d: [f64; NS] = core::array::from_fn(|r| dot(&a[r], z));
        if self.stribeck_slip(regime) {
            let q = self.excess(regime, z).0;
            for (r, v) in d.iter_mut().enumerate() {
                *v += self.sys().b[r] * q;
            }
        }
        d
    }

    /// z'' in `regime` at `z` with z' = `d`.
    pub(super) fn second(&self, regime: Regime, z: &[f64; NS], d: &[f64; NS]) -> [f64; NS] {
        let sys = &self.sys();
        let a = &sys.a[regime.index()];
        let mut s: [f64; NS] = core::array::from_fn(|r| rate(&a[r], d));
        if self.stribeck_slip(regime) {
            let (_, e, n, v) = self.excess(regime, z);
            let vd = rate(&sys.r_v, d);
            let nd = rate(&sys.r_n, d);
            let y = libm::fabs(v) / sys.v_s;
            let dy = if v >= 0.0 { vd / sys.v_s } else { -vd / sys.v_s };
            let de = if sys.delta == 1.0 {
                -e * dy
            } else if y > 0.0 {
                -sys.delta * libm::pow(y, sys.delta - 1.0) * e * dy
            } else {
                0.0
            };
            let qd = regime.friction_sign() * sys.d_mu * (de * n + e * nd);
            for (r, v) in s.iter_mut().enumerate() {
                *v += sys.b[r] * qd;
            }
        }
        s
    }

    pub(super) fn point(&self, regime: Regime, z: [f64; NS]) -> Point {
        let d = self.derivative(regime, &z);
        let s = self.second(regime, &z, &d);
        Point { z, d, s }
    }

    /// Sets the sliding velocity to zero on entry to stick: the friction impulse p that stops
    /// the face, -v / (r_v . b), moves the state by b p, and x' then takes the constraint's
    /// value exactly (as the stepper's `enter_stick`).
    pub(super) fn enter_stick(&self, z: &mut [f64; NS]) {
        let sys = &self.sys();
        let p = -dot(&sys.r_v, z) / sys.inv_mass_v;
        for (r, v) in z.iter_mut().enumerate() {
            *v += sys.b[r] * p;
        }
        // r_v[1] = 1: x' = -(the rest of the row)
        z[1] = -(sys.r_v[3] * z[3] + sys.r_v[5] * z[5] + sys.r_v[ONE]);
    }

    /// The regime after a slip reached v = 0 at `z`.
    pub(super) fn after_velocity_match(&self, z: &[f64; NS]) -> Regime {
        let mut zs = *z;
        self.enter_stick(&mut zs);
        let f_req = dot(&self.sys().r_freq, &zs);
        let limit = self.sys().mu_s * dot(&self.sys().r_n, &zs);
        if f_req > limit {
            Regime::SlipSlower
        } else if -f_req > limit {
            Regime::SlipFaster
        } else {
            Regime::Stick
        }
    }

    /// In the stepper's range (every halt it reports falls outside).
    pub(super) fn in_range(&self, z: &[f64; NS]) -> bool {
        let pad = [z[0], z[1], z[2], z[3]];
        let band = libm::fabs(z[4]) <= U_LIMIT && libm::fabs(z[5]) <= UDOT_LIMIT;
        let float = !self.sys().floating || {
            let [d_l, d_t, floor_l, floor_t] = self.float_limits;
            (self.unilateral || (z[Y] + d_l * z[2] >= floor_l && z[Y] + d_t * z[2] >= floor_t))
                && libm::fabs(z[Y]) <= Y_LIMIT
                && libm::fabs(z[Y + 1]) <= YDOT_LIMIT
        };
        self.limits.in_range(&pad) && band && float
    }

    /// The error of a Stribeck step relative to the tolerance (max norm; <= 1 accepts).
    pub(super) fn error_ratio(&self, err: &[f64; NS], z0: &[f64; NS], z1: &[f64; NS]) -> f64 {
        let mut worst: f64 = 0.0;
        for i in 0..NS {
            let sc = self.rtol * self.scale[i].max(libm::fabs(z0[i])).max(libm::fabs(z1[i]));
            worst = worst.max(libm::fabs(err[i]) / sc);
        }
        if worst.is_finite() {
            worst
        } else {
            f64::INFINITY
        }
    }
}
