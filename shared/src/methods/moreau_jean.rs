//! Moreau-Jean time-stepping: implicit in velocity, friction as a set-valued law solved per
//! step (Moreau 1988, Jean 1999), with theta = 1/2.
//!
//! Over a step h, with q = (x, phi), v = (x', phi'), v_theta = theta v+ + (1 - theta) v:
//!
//! ```text
//! M (v+ - v) = h [ -K_q (q + theta h v_theta) - C v_theta + F ] + W P
//! q+ = q + h v_theta
//! ```
//!
//! with M = diag(m, I), K_q = diag(k_g, K), C = diag(c_x, c_phi), F = (0, F_N a_N), and the
//! friction impulse P acting through W = (1, s w). The normal force is taken at the step's
//! start (N = c_N phi). The local problem is one-dimensional: the impulse that makes the
//! relative velocity zero, P* = -(V_r free) / g, is accepted if |P*| <= mu_s h N (stick);
//! otherwise the contact slides with the kinetic impulse sign(P*) mu_k h N. Because M, K_q, C
//! are diagonal, the step needs no matrix solve. Unconditionally stable for the linear part
//! (the trapezoidal rule), first order through transitions, no event location.

use crate::coefficients::Coefficients;
use crate::halt::Halt;
use crate::methods::core::{core_accessors, StepCore};
use crate::methods::plant::Plant;
use crate::methods::Method;
use crate::real::Real;
use crate::scene::{Scene, SceneError};
use crate::stickslip::Regime;

const THETA: f64 = 0.5;

#[derive(Clone, Debug)]
pub struct MoreauJean<T: Real> {
    plant: Plant<T>,
    h: T,
    theta_h: T,
    one_minus_theta_h: T,
    /// r0 = a0 x' - b0 x;  r1 = a1 phi' - b1 phi + h F_N a_N
    a0: T,
    b0: T,
    a1: T,
    b1: T,
    h_load: T,
    /// 1 / A00, 1 / A11 with A = M + h theta C + h^2 theta^2 K_q.
    inv0: T,
    inv1: T,
    /// A00 (the inverse of g = e_x A^-1 W).
    a00: T,
    core: StepCore<T>,
}

impl<T: Real> MoreauJean<T> {
    pub fn new(scene: &Scene) -> Result<Self, SceneError> {
        scene.validate()?;
        let co = Coefficients::of(scene);
        let plant = Plant::<T>::new(scene, &co);
        let h = scene.dt;
        let th = THETA;
        let a00 = scene.m + h * th * scene.c_x + h * h * th * th * scene.k_g;
        let a11 = scene.inertia + h * th * scene.c_phi + h * h * th * th * co.k_rot;
        let t = T::from_f64;
        Ok(MoreauJean {
            plant,
            h: t(h),
            theta_h: t(th * h),
            one_minus_theta_h: t((1.0 - th) * h),
            a0: t(scene.m - h * h * th * (1.0 - th) * scene.k_g - h * (1.0 - th) * scene.c_x),
            b0: t(h * scene.k_g),
            a1: t(scene.inertia - h * h * th * (1.0 - th) * co.k_rot - h * (1.0 - th) * scene.c_phi),
            b1: t(h * co.k_rot),
            h_load: t(h * scene.f_n * co.a_n),
            inv0: t(1.0 / a00),
            inv1: t(1.0 / a11),
            a00: t(a00),
            core: StepCore::new(scene, &co),
        })
    }
}

impl<T: Real> Method<T> for MoreauJean<T> {
    fn step(&mut self) -> Result<usize, Halt> {
        let z = self.core.begin()?;
        let p = &self.plant;
        // free velocities (no friction impulse)
        let vf0 = (self.a0 * z[1] - self.b0 * z[0]) * self.inv0;
        let vf1 = if p.rotation { (self.a1 * z[3] - self.b1 * z[2] + self.h_load) * self.inv1 } else { T::zero() };
        let n = p.normal(&z);
        // the one-dimensional contact problem
        let p_star = -(vf0 - p.v) * self.a00;
        let hn = self.h * n;
        let (impulse, regime) = if p_star.abs() <= p.mu_s * hn {
            (p_star, Regime::Stick)
        } else if p_star > T::zero() {
            (p.mu_k * hn, Regime::SlipSlower)
        } else {
            (-(p.mu_k * hn), Regime::SlipFaster)
        };
        let mut v0 = vf0 + self.inv0 * impulse;
        if regime == Regime::Stick {
            v0 = p.v;
        }
        let v1 = if p.rotation { vf1 + self.inv1 * p.s_w * impulse } else { T::zero() };
        let x = z[0] + (self.theta_h * v0 + self.one_minus_theta_h * z[1]);
        let phi = if p.rotation { z[2] + (self.theta_h * v1 + self.one_minus_theta_h * z[3]) } else { z[2] };
        self.core.end([x, v0, phi, v1], regime)
    }
    core_accessors!();
}
