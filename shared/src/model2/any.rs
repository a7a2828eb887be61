//! A model-2 stepper whose composition is chosen from the scene at run time (the host's
//! commands, which read any scene file). Each variant is the compile-time specialised
//! [`Model2Stepper`] of one [`Composition`]; a call costs one match on the variant. Its
//! tables are owned ([`Owned`], the default) or borrowed from another ([`Shared`]: the runs of
//! one scene share one set, [`AnyModel2Stepper::shared`]).

use core::borrow::Borrow;
use core::marker::PhantomData;

use crate::halt::Halt;
use crate::model2::composition::{
    Band, BandFace, Composition, Coulomb, CoulombFace, FloatFace, Stribeck, StribeckBand, StribeckBandFace,
    StribeckFace, StribeckFloatFace,
};
use crate::model2::stepper::{Model2Observer, Model2Stepper, Model2Tables, WideSamples, WideChunks};
use crate::model2::system::NS;
use crate::real::Real;
use crate::scene::{FrictionLaw, Scene, SceneError};
use crate::stickslip::Regime;

/// How an [`AnyModel2Stepper`] holds its tables: `Of<C>` for composition `C`.
pub trait TableStore<T: Real> {
    type Of<C: Composition>: Borrow<Model2Tables<T, C>> + Clone + core::fmt::Debug;
}

/// The stepper owns its tables.
#[derive(Clone, Copy, Debug)]
pub struct Owned;

/// The stepper borrows its tables (`&'a Model2Tables`) from a stepper that owns them.
#[derive(Clone, Copy, Debug)]
pub struct Shared<'a>(PhantomData<&'a ()>);

impl<T: Real> TableStore<T> for Owned {
    type Of<C: Composition> = Model2Tables<T, C>;
}

impl<'a, T: Real> TableStore<T> for Shared<'a> {
    type Of<C: Composition> = &'a Model2Tables<T, C>;
}

/// [`Model2Stepper`] of the composition a scene asks for, its tables held as `K` says.
#[derive(Clone, Debug)]
pub enum AnyModel2Stepper<T: Real, K: TableStore<T> = Owned> {
    /// The thesis model in model 2's matrices (a cross-check; the host runs such scenes on
    /// [`crate::ExactStepper`]).
    Coulomb(Model2Stepper<T, Coulomb, K::Of<Coulomb>>),
    Band(Model2Stepper<T, Band, K::Of<Band>>),
    Stribeck(Model2Stepper<T, Stribeck, K::Of<Stribeck>>),
    StribeckBand(Model2Stepper<T, StribeckBand, K::Of<StribeckBand>>),
    CoulombFace(Model2Stepper<T, CoulombFace, K::Of<CoulombFace>>),
    BandFace(Model2Stepper<T, BandFace, K::Of<BandFace>>),
    StribeckFace(Model2Stepper<T, StribeckFace, K::Of<StribeckFace>>),
    StribeckBandFace(Model2Stepper<T, StribeckBandFace, K::Of<StribeckBandFace>>),
    FloatFace(Model2Stepper<T, FloatFace, K::Of<FloatFace>>),
    StribeckFloatFace(Model2Stepper<T, StribeckFloatFace, K::Of<StribeckFloatFace>>),
}

/// The Stribeck compositions (whose slip tables a donor can give), for
/// [`AnyModel2Stepper::new_reusing`].
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Stribeck,
    StribeckBand,
    StribeckFace,
    StribeckBandFace,
    StribeckFloatFace,
    Other,
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
    /// A run that borrows these tables, in this stepper's state ([`Model2Stepper::shared`]).
    pub fn shared(&self) -> AnyModel2Stepper<T, Shared<'_>> {
        match self {
            AnyModel2Stepper::Coulomb(s) => AnyModel2Stepper::Coulomb(s.shared()),
            AnyModel2Stepper::Band(s) => AnyModel2Stepper::Band(s.shared()),
            AnyModel2Stepper::Stribeck(s) => AnyModel2Stepper::Stribeck(s.shared()),
            AnyModel2Stepper::StribeckBand(s) => AnyModel2Stepper::StribeckBand(s.shared()),
            AnyModel2Stepper::CoulombFace(s) => AnyModel2Stepper::CoulombFace(s.shared()),
            AnyModel2Stepper::BandFace(s) => AnyModel2Stepper::BandFace(s.shared()),
            AnyModel2Stepper::StribeckFace(s) => AnyModel2Stepper::StribeckFace(s.shared()),
            AnyModel2Stepper::StribeckBandFace(s) => AnyModel2Stepper::StribeckBandFace(s.shared()),
            AnyModel2Stepper::FloatFace(s) => AnyModel2Stepper::FloatFace(s.shared()),
            AnyModel2Stepper::StribeckFloatFace(s) => AnyModel2Stepper::StribeckFloatFace(s.shared()),
        }
    }

    /// [`Self::new`], with each Stribeck slip's kinetic tables taken from `donor` where they
    /// are the same computation ([`Model2Stepper::new_reusing`]: f64, the same composition,
    /// substep, A and b): the same stepper, for a map's cells that differ in V.
    pub fn new_reusing(scene: &Scene, donor: &Self) -> Result<Self, SceneError> {
        let fresh = Self::new_fresh_kind(scene);
        macro_rules! reuse {
            ($($v:ident),*) => {
                match (fresh, donor) {
                    $((Kind::$v, AnyModel2Stepper::$v(d)) => Ok(AnyModel2Stepper::$v(Model2Stepper::new_reusing(scene, d.tables())?)),)*
                    _ => Self::new(scene),
                }
            };
        }
        reuse!(Stribeck, StribeckBand, StribeckFace, StribeckBandFace, StribeckFloatFace)
    }

    /// The composition `scene` asks for (as [`Self::new`] chooses it).
    fn new_fresh_kind(scene: &Scene) -> Kind {
        let stribeck = scene.friction == FrictionLaw::Stribeck;
        if scene.floating() {
            return if stribeck { Kind::StribeckFloatFace } else { Kind::Other };
        }
        match (stribeck, scene.band, scene.face) {
            (true, false, false) => Kind::Stribeck,
            (true, true, false) => Kind::StribeckBand,
            (true, false, true) => Kind::StribeckFace,
            (true, true, true) => Kind::StribeckBandFace,
            _ => Kind::Other,
        }
    }

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
}

impl<T: Real, K: TableStore<T>> AnyModel2Stepper<T, K> {
    /// The composition's name.
    pub fn composition(&self) -> &'static str {
        each!(self, s => s.composition())
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

impl<K: TableStore<f64>> AnyModel2Stepper<f64, K> {
    /// The tables of wide chunks of `m` steps of Stribeck slip for `scene`, the scene this
    /// stepper was built for ([`Model2Tables::wide_chunks`]; `None` where the scene takes none).
    pub fn wide_chunks(&self, scene: &Scene, m: usize) -> Option<WideChunks> {
        each!(self, s => s.tables().wide_chunks(scene, m))
    }

    /// m steps in one wide chunk, or false with the state untouched
    /// ([`Model2Tables::wide_step`]).
    pub fn wide_step<O: Model2Observer<f64>>(&mut self, w: &WideChunks, obs: &mut O, samples: bool, out: &mut WideSamples) -> bool {
        each!(self, s => {
            let (t, st) = s.parts_mut();
            if st.regime() == crate::stickslip::Regime::Stick {
                t.wide_stick(w, st, obs, samples, out)
            } else {
                t.wide_step(w, st, obs, samples, out)
            }
        })
    }
}
