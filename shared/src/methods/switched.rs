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
use crate::halt::Halt;
use crate::methods::core::{core_accessors, StepCore};
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
    h: T,
    core: StepCore<T>,
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
            h: T::from_f64(scene.dt),
            core: StepCore::new(scene, &co),
        })
    }
}

impl<T: Real> Method<T> for Euler<T> {
    fn step(&mut self) -> Result<usize, Halt> {
        let z = self.core.begin()?;
        let regime = self.core.regime;
        let h = self.h;
        let (xdd, phidd) = self.plant.accelerations(regime, &z);
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
        if regime == Regime::Stick {
            n[1] = self.plant.v;
        }
        // guards at the step's end
        let (gs, count) = self.guards.of(regime);
        let mut next = regime;
        if let Some(which) = (0..count).find(|&i| gs[i].fired(&n)) {
            next = self.guards.next_regime(regime, which, &n);
            if next == Regime::Stick {
                n[1] = self.plant.v;
            }
        }
        self.core.end(n, next)
    }
    core_accessors!();
}
