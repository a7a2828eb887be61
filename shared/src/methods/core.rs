//! What every approximate method keeps besides its own constants: the state, the regime, the
//! step count, the last transition and the halt; and the end of a step they all share
//! (record a change of regime, check the state, latch a halt).

use crate::coefficients::Coefficients;
use crate::exact::{State, Transition};
use crate::halt::{Halt, Limits};
use crate::real::Real;
use crate::scene::Scene;
use crate::stickslip::Regime;

#[derive(Clone, Debug)]
pub struct StepCore<T: Real> {
    pub z: [T; 4],
    pub regime: Regime,
    pub step: u64,
    dt: f64,
    limits: Limits<T>,
    /// The transition at the end of the last step, if the regime changed (heapless: a fixed
    /// capacity of one, no allocation).
    last: heapless::Vec<Transition<T>, 1>,
    halted: Option<Halt>,
}

impl<T: Real> StepCore<T> {
    /// The default initial state: stick, x = 0, x' = V, phi = phi_0, phi' = 0.
    pub fn new(scene: &Scene, co: &Coefficients) -> Self {
        StepCore {
            z: [T::zero(), T::from_f64(scene.v), T::from_f64(co.phi0), T::zero()],
            regime: Regime::Stick,
            step: 0,
            dt: scene.dt,
            limits: Limits::new(scene, co),
            last: heapless::Vec::new(),
            halted: None,
        }
    }

    /// Starts a step: the current state, or the halt that ended the run.
    #[inline(always)]
    pub fn begin(&mut self) -> Result<[T; 4], Halt> {
        if let Some(h) = self.halted {
            return Err(h);
        }
        self.last.clear();
        Ok(self.z)
    }

    /// Ends a step at state `z` in `regime` (a transition at the step's end if it changed).
    #[inline(always)]
    pub fn end(&mut self, z: [T; 4], regime: Regime) -> Result<usize, Halt> {
        self.step += 1;
        let t = self.step as f64 * self.dt;
        if regime != self.regime {
            self.last.clear();
            // capacity 1, just cleared: the push cannot fail
            let _ = self.last.push(Transition { t, from: self.regime, to: regime, state: State::from_array(z) });
            self.regime = regime;
        }
        self.z = z;
        if let Err(e) = self.limits.check(&self.z, self.regime, || t) {
            self.halted = Some(e);
            return Err(e);
        }
        Ok(self.last.len())
    }

    pub fn transitions(&self) -> &[Transition<T>] {
        &self.last
    }
}

/// The accessors of [`super::Method`] for a type with a `core: StepCore<T>` field.
macro_rules! core_accessors {
    () => {
        fn state(&self) -> crate::exact::State<T> {
            crate::exact::State::from_array(self.core.z)
        }
        fn regime(&self) -> crate::stickslip::Regime {
            self.core.regime
        }
        fn steps(&self) -> u64 {
            self.core.step
        }
        fn transitions(&self) -> &[crate::exact::Transition<T>] {
            self.core.transitions()
        }
    };
}
pub(crate) use core_accessors;
