//! The equations of motion as a right-hand side, in the stepper's precision: what the
//! approximate methods integrate (the exact method uses the flows of [`crate::propagator`]).

use crate::coefficients::Coefficients;
use crate::real::Real;
use crate::scene::Scene;
use crate::stickslip::Regime;

/// Scene constants in `T` for evaluating accelerations.
#[derive(Clone, Copy, Debug)]
pub struct Plant<T> {
    pub m: T,
    pub inertia: T,
    pub k_g: T,
    pub c_x: T,
    pub c_phi: T,
    pub k_rot: T,
    pub c_n: T,
    /// s w [m]: the friction force's lever about the pivot, signed.
    pub s_w: T,
    /// F_N a_N [N m].
    pub load_moment: T,
    pub v: T,
    pub mu_s: T,
    pub mu_k: T,
    pub rotation: bool,
    /// 1 / m [1/kg] and 1 / I [1/(kg m^2)]: multiplied, not divided, on every evaluation.
    pub inv_m: T,
    pub inv_inertia: T,
    /// N_0 = c_N phi_0 [N], the constant normal force without rotation.
    pub n0: T,
    pub phi0: T,
}

impl<T: Real> Plant<T> {
    pub fn new(scene: &Scene, co: &Coefficients) -> Self {
        let t = T::from_f64;
        Plant {
            m: t(scene.m),
            inertia: t(scene.inertia),
            k_g: t(scene.k_g),
            c_x: t(scene.c_x),
            c_phi: t(scene.c_phi),
            k_rot: t(co.k_rot),
            c_n: t(co.c_n),
            s_w: t(co.s * scene.w),
            load_moment: t(scene.f_n * co.a_n),
            v: t(scene.v),
            mu_s: t(scene.mu_s),
            mu_k: t(scene.mu_k),
            rotation: scene.rotation,
            inv_m: t(1.0 / scene.m),
            inv_inertia: t(1.0 / scene.inertia),
            n0: t(co.n0),
            phi0: t(co.phi0),
        }
    }

    /// Normal force N [N].
    #[inline(always)]
    pub fn normal(&self, z: &[T; 4]) -> T {
        if self.rotation {
            self.c_n * z[2]
        } else {
            self.n0
        }
    }

    /// Required force to hold the pad on the band, F_req = k_g x + c_x x' [N].
    #[inline(always)]
    pub fn required_force(&self, z: &[T; 4]) -> T {
        self.k_g * z[0] + self.c_x * z[1]
    }

    /// x'' and phi'' with a given friction force `f_f` [N] acting on the pad.
    #[inline(always)]
    pub fn accelerations_with(&self, z: &[T; 4], f_f: T, sticking: bool) -> (T, T) {
        let xdd = if sticking { T::zero() } else { (f_f - self.k_g * z[0] - self.c_x * z[1]) * self.inv_m };
        let phidd = if self.rotation {
            (self.load_moment + self.s_w * f_f - self.k_rot * z[2] - self.c_phi * z[3]) * self.inv_inertia
        } else {
            T::zero()
        };
        (xdd, phidd)
    }

    /// x'' and phi'' in `regime` (stick: the required force; slip: sigma mu_k N).
    #[inline(always)]
    pub fn accelerations(&self, regime: Regime, z: &[T; 4]) -> (T, T) {
        match regime {
            Regime::Stick => self.accelerations_with(z, self.required_force(z), true),
            Regime::SlipSlower => self.accelerations_with(z, self.mu_k * self.normal(z), false),
            Regime::SlipFaster => self.accelerations_with(z, -(self.mu_k * self.normal(z)), false),
        }
    }
}
