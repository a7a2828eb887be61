//! Classical fourth-order Runge-Kutta on a Karnopp-style friction law.
//!
//! Karnopp replaces the stick constraint by a band of relative velocities |V_r| < eta inside
//! which the contact transmits whatever force keeps the relative acceleration at zero, clipped
//! to the static limit mu_s N; outside the band the friction is kinetic, -sign(V_r) mu_k N. The
//! right-hand side is then a function of the state alone, with no regime memory, and RK4 is
//! applied to it as to any ODE. The band must be wide enough for one step to land in it at the
//! end of a slip: eta = max(0.01 V, (mu_s - mu_k) N_0 dt / m), the velocity change of one step
//! at the re-stick acceleration. Inside the band the pad sticks at x' = V + (its entry offset),
//! not exactly at V: the model error that shrinks with dt. Stable for omega h < 2.83 on an
//! undamped oscillator; fourth order only between transitions (the right-hand side is
//! discontinuous at the band's edges), so first order overall.

use crate::coefficients::Coefficients;
use crate::halt::Halt;
use crate::methods::core::{core_accessors, StepCore};
use crate::methods::plant::Plant;
use crate::methods::Method;
use crate::real::Real;
use crate::scene::{Scene, SceneError};
use crate::stickslip::Regime;

#[derive(Clone, Debug)]
pub struct Rk4Karnopp<T: Real> {
    plant: Plant<T>,
    h: T,
    half_h: T,
    sixth_h: T,
    eta: T,
    core: StepCore<T>,
}

impl<T: Real> Rk4Karnopp<T> {
    pub fn new(scene: &Scene) -> Result<Self, SceneError> {
        scene.validate()?;
        let co = Coefficients::of(scene);
        let plant = Plant::<T>::new(scene, &co);
        let eta = (0.001 * scene.v).max(0.5 * (scene.mu_s - scene.mu_k) * co.n0 * scene.dt / scene.m);
        Ok(Rk4Karnopp {
            plant,
            h: T::from_f64(scene.dt),
            half_h: T::from_f64(scene.dt / 2.0),
            sixth_h: T::from_f64(scene.dt / 6.0),
            eta: T::from_f64(eta),
            core: StepCore::new(scene, &co),
        })
    }

    /// Half-width of the stick band [m/s].
    pub fn band(&self) -> T {
        self.eta
    }

    /// Friction force of the Karnopp law and the regime it stands for.
    #[inline(always)]
    fn friction(&self, z: &[T; 4]) -> (T, Regime) {
        let v_r = z[1] - self.plant.v;
        let n = self.plant.normal(z);
        if v_r.abs() < self.eta {
            let f = self.plant.required_force(z);
            let lim = self.plant.mu_s * n;
            if f > lim {
                (lim, Regime::SlipSlower)
            } else if f < -lim {
                (-lim, Regime::SlipFaster)
            } else {
                (f, Regime::Stick)
            }
        } else if v_r < T::zero() {
            (self.plant.mu_k * n, Regime::SlipSlower)
        } else {
            (-(self.plant.mu_k * n), Regime::SlipFaster)
        }
    }

    #[inline(always)]
    fn rhs(&self, z: &[T; 4]) -> [T; 4] {
        let (f, _) = self.friction(z);
        let (xdd, phidd) = self.plant.accelerations_with(z, f, false);
        if self.plant.rotation {
            [z[1], xdd, z[3], phidd]
        } else {
            [z[1], xdd, T::zero(), T::zero()]
        }
    }
}

impl<T: Real> Method<T> for Rk4Karnopp<T> {
    fn step(&mut self) -> Result<usize, Halt> {
        let z = self.core.begin()?;
        let add = |a: &[T; 4], k: &[T; 4], s: T| [a[0] + s * k[0], a[1] + s * k[1], a[2] + s * k[2], a[3] + s * k[3]];
        let k1 = self.rhs(&z);
        let k2 = self.rhs(&add(&z, &k1, self.half_h));
        let k3 = self.rhs(&add(&z, &k2, self.half_h));
        let k4 = self.rhs(&add(&z, &k3, self.h));
        let two = T::from_f64(2.0);
        let mut n = [T::zero(); 4];
        for i in 0..4 {
            n[i] = z[i] + self.sixth_h * (k1[i] + two * k2[i] + two * k3[i] + k4[i]);
        }
        let (_, regime) = self.friction(&n);
        self.core.end(n, regime)
    }
    core_accessors!();
}
