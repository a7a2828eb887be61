//! Explicit Euler and semi-implicit (symplectic) Euler on the switched system: the regime is
//! fixed during a step, and the guards of [`crate::stickslip`] are tested at the step's end
//! only (no location inside the step, so transitions are late by up to one step).
//!
//! - Explicit Euler: q+ = q + h v, v+ = v + h a(q, v). First order; on an undamped oscillator
//!   its amplification is sqrt(1 + (omega h)^2) > 1 per step: unstable at every step size.
//! - Symplectic Euler: v+ = v + h a(q, v), q+ = q + h v+. First order; stable for
//!   omega h < 2 on an undamped oscillator.
//!
//! In stick, x' = V is imposed and x advances by V h (accumulated, as a naive method does).

use crate::coefficients::Coefficients;
use crate::exact::{State, Transition};
use crate::halt::{Halt, Limits};
use crate::methods::plant::Plant;
use crate::methods::Method;
use crate::real::Real;
use crate::scene::{Scene, SceneError};
use crate::stickslip::{Guards, Regime};

/// The two Euler variants.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EulerKind {
    Explicit,
    Symplectic,
}

#[derive(Clone, Debug)]
pub struct Euler<T: Real> {
    kind: EulerKind,
    plant: Plant<T>,
    guards: Guards<T>,
    limits: Limits<T>,
    h: T,
    dt: f64,
    z: [T; 4],
    regime: Regime,
    step: u64,
    last: [Transition<T>; 1],
    n_last: usize,
    halted: Option<Halt>,
}

impl<T: Real> Euler<T> {
    pub fn new(kind: EulerKind, scene: &Scene) -> Result<Self, SceneError> {
        scene.validate()?;
        let co = Coefficients::of(scene);
        let plant = Plant::<T>::new(scene, &co);
        Ok(Euler {
            kind,
            plant,
            guards: Guards::new(scene, &co),
            limits: Limits::new(scene, &co),
            h: T::from_f64(scene.dt),
            dt: scene.dt,
            z: [T::zero(), plant.v, plant.phi0, T::zero()],
            regime: Regime::Stick,
            step: 0,
            last: [Transition { t: 0.0, from: Regime::Stick, to: Regime::Stick, state: State::default() }],
            n_last: 0,
            halted: None,
        })
    }
}

impl<T: Real> Method<T> for Euler<T> {
    fn step(&mut self) -> Result<usize, Halt> {
        if let Some(h) = self.halted {
            return Err(h);
        }
        self.n_last = 0;
        let z = self.z;
        let h = self.h;
        let (xdd, phidd) = self.plant.accelerations(self.regime, &z);
        let mut n = match self.kind {
            EulerKind::Explicit => [z[0] + h * z[1], z[1] + h * xdd, z[2] + h * z[3], z[3] + h * phidd],
            EulerKind::Symplectic => {
                let xd = z[1] + h * xdd;
                let phid = z[3] + h * phidd;
                [z[0] + h * xd, xd, z[2] + h * phid, phid]
            }
        };
        if !self.plant.rotation {
            n[2] = z[2];
            n[3] = z[3];
        }
        if self.regime == Regime::Stick {
            n[1] = self.plant.v;
        }
        self.step += 1;
        // guards at the step's end
        let (gs, count) = self.guards.of(self.regime);
        if let Some(which) = (0..count).find(|&i| gs[i].fired(&n)) {
            let next = self.guards.next_regime(self.regime, which, &n);
            if next == Regime::Stick {
                n[1] = self.plant.v;
            }
            if next != self.regime {
                self.last[0] = Transition { t: self.step as f64 * self.dt, from: self.regime, to: next, state: State::from_array(n) };
                self.n_last = 1;
                self.regime = next;
            }
        }
        self.z = n;
        let t = self.step as f64 * self.dt;
        if let Err(e) = self.limits.check(&self.z, self.regime, || t) {
            self.halted = Some(e);
            return Err(e);
        }
        Ok(self.n_last)
    }
    fn state(&self) -> State<T> {
        State::from_array(self.z)
    }
    fn regime(&self) -> Regime {
        self.regime
    }
    fn steps(&self) -> u64 {
        self.step
    }
    fn transitions(&self) -> &[Transition<T>] {
        &self.last[..self.n_last]
    }
}
