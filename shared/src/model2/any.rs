//! A model-2 stepper whose composition is chosen from the scene at run time (the host's
//! commands, which read any scene file). Each variant is the compile-time specialised
//! [`Model2Stepper`] of one [`Composition`]; a call costs one match on the variant.

use crate::halt::Halt;
use crate::model2::composition::{
    Band, BandFace, Composition, Coulomb, CoulombFace, FloatFace, Stribeck, StribeckBand, StribeckBandFace,
    StribeckFace, StribeckFloatFace,
};
use crate::model2::stepper::{Model2Stepper, Model2Observer};
use crate::model2::system::NS;
use crate::real::Real;
use crate::scene::{FrictionLaw, Scene, SceneError};
use crate::stickslip::Regime;

/// [`Model2Stepper`] of the composition a scene asks for.
#[derive(Clone, Debug)]
pub enum AnyModel2Stepper<T: Real> {
    /// The thesis model in model 2's matrices (a cross-check; the host runs such scenes on
    /// [`crate::ExactStepper`]).
    Coulomb(Model2Stepper<T, Coulomb>),
    Band(Model2Stepper<T, Band>),
    Stribeck(Model2Stepper<T, Stribeck>),
    StribeckBand(Model2Stepper<T, StribeckBand>),
    CoulombFace(Model2Stepper<T, CoulombFace>),
    BandFace(Model2Stepper<T, BandFace>),
    StribeckFace(Model2Stepper<T, StribeckFace>),
    StribeckBandFace(Model2Stepper<T, StribeckBandFace>),
    FloatFace(Model2Stepper<T, FloatFace>),
    StribeckFloatFace(Model2Stepper<T, StribeckFloatFace>),
}

macro_rules! each {
    ($self:expr, $s:ident => $e:expr) => {
        match $self {
            AnyModel2Stepper::Coulomb($s) => $e,
            AnyModel2Stepper::Band($s) => $e,
            AnyModel2Stepper::Stribeck($s) => $e,
            AnyModel2Stepper::StribeckBand($s) => $e,
            AnyModel2Stepper::CoulombFace($s) => $e,
            AnyModel2Stepper::BandFace($s) => $e,
            AnyModel2Stepper::StribeckFace($s) => $e,
            AnyModel2Stepper::StribeckBandFace($s) => $e,
            AnyModel2Stepper::FloatFace($s) => $e,
            AnyModel2Stepper::StribeckFloatFace($s) => $e,
        }
    };
}

impl<T: Real> AnyModel2Stepper<T> {
    /// The stepper of `scene`'s composition.
    pub fn new(scene: &Scene) -> Result<Self, SceneError> {
        let stribeck = scene.friction == FrictionLaw::Stribeck;
        if scene.floating() {
            return Ok(if stribeck {
                AnyModel2Stepper::StribeckFloatFace(Model2Stepper::new(scene)?)
            } else {
                AnyModel2Stepper::FloatFace(Model2Stepper::new(scene)?)
            });
        }
        Ok(match (stribeck, scene.band, scene.face) {
            (false, true, false) => AnyModel2Stepper::Band(Model2Stepper::new(scene)?),
            (true, false, false) => AnyModel2Stepper::Stribeck(Model2Stepper::new(scene)?),
            (true, true, false) => AnyModel2Stepper::StribeckBand(Model2Stepper::new(scene)?),
            (false, false, false) => AnyModel2Stepper::Coulomb(Model2Stepper::new(scene)?),
            (false, true, true) => AnyModel2Stepper::BandFace(Model2Stepper::new(scene)?),
            (true, false, true) => AnyModel2Stepper::StribeckFace(Model2Stepper::new(scene)?),
            (true, true, true) => AnyModel2Stepper::StribeckBandFace(Model2Stepper::new(scene)?),
            (false, false, true) => AnyModel2Stepper::CoulombFace(Model2Stepper::new(scene)?),
        })
    }
    /// The composition's name.
    pub fn composition(&self) -> &'static str {
        fn name<T: Real, C: Composition>(_: &Model2Stepper<T, C>) -> &'static str {
            C::NAME
        }
        each!(self, s => name(s))
    }
    pub fn table_bytes(&self) -> usize {
        each!(self, s => s.table_bytes())
    }
    pub fn state(&self) -> [T; NS] {
        each!(self, s => s.state())
    }
    pub fn regime(&self) -> Regime {
        each!(self, s => s.regime())
    }
    pub fn steps(&self) -> u64 {
        each!(self, s => s.steps())
    }
    pub fn time(&self) -> f64 {
        each!(self, s => s.time())
    }
    pub fn halted(&self) -> Option<Halt> {
        each!(self, s => s.halted())
    }
    pub fn transitions(&self) -> u64 {
        each!(self, s => s.transitions())
    }
    pub fn substeps(&self) -> u32 {
        each!(self, s => s.substeps())
    }
    /// Whether the stepper carries the floating pad (y, y').
    pub fn floating(&self) -> bool {
        each!(self, s => s.floating())
    }
    pub fn set_state(&mut self, z: [T; NS], regime: Regime) {
        each!(self, s => s.set_state(z, regime))
    }
    pub fn sliding_velocity(&self, z: &[T; NS]) -> T {
        each!(self, s => s.sliding_velocity(z))
    }
    pub fn normal_force(&self, z: &[T; NS]) -> T {
        each!(self, s => s.normal_force(z))
    }
    pub fn friction_force(&self, regime: Regime, z: &[T; NS]) -> T {
        each!(self, s => s.friction_force(regime, z))
    }
    pub fn derivative(&self, regime: Regime, z: &[T; NS]) -> [T; NS] {
        each!(self, s => s.derivative(regime, z))
    }
    /// The pad's x'' at the current state ([`Model2Stepper::pad_acceleration`]).
    pub fn pad_acceleration(&self) -> T {
        each!(self, s => s.pad_acceleration())
    }
    pub fn step(&mut self) -> Result<usize, Halt> {
        each!(self, s => s.step())
    }
    pub fn step_observed<O: Model2Observer<T>>(&mut self, obs: &mut O) -> Result<usize, Halt> {
        each!(self, s => s.step_observed(obs))
    }
}
