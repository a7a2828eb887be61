//! The model run alongside the measurement, one exact step per sample: the prediction the
//! measured `pad_x` is compared with.
//!
//! The scene is the configured pad (a template [`Scene`]) with the *measured* normal load,
//! F_N = p_actuator A (see [`super::pneumatics`]), and the configured band speed V; its step is
//! the sampling interval. Building it computes the exact flows in f64 (about 75 matrix
//! exponentials): a set-up cost paid once, when the rig is set up at boot
//! ([`super::pipeline::Rig::init`]), not per record and not per sample; each record restarts
//! the built model ([`LockstepModel::restart`]). Per sample it is one [`ExactStepper::step`]
//! in f32 and x'' from the regime's row of the system matrix (five multiply-adds, no division:
//! the same x'' as `Plant::accelerations`, to f32 rounding). Its Cortex-M4F instructions, for a
//! step without a transition and for one with, are counted by `scripts/count-instructions.sh`
//! (see [`super::estimator`]); at 168 MHz and 25.6 kHz a sample has 6,560 cycles.
//!
//! The model starts from its own initial state (stick, x = 0, at rest under the load), so it
//! is meaningful from the moment the band starts moving. The push cases are irregular (their
//! event times depend on round-off), so the residual there grows after a few cycles while the
//! statistics still agree; the pull cases settle to a periodic cycle.
//!
//! A model that halts (a finding: sprag, contact loss; see [`Halt`]) stops predicting; the
//! halt is kept and reported, and no value of the halted step is passed on.
//!
//! **Which model.** [`LockstepModel`] is generic over its stepper ([`LockstepStepper`]); its
//! default, [`RigStepper`], is fixed at build time by a feature of this crate, so that a
//! firmware links only the model its pad uses:
//!
//! | feature of `stickslip-model` | stepper | template ([`default_template`]) |
//! |---|---|---|
//! | none | `ExactStepper<f32>` (thesis; damping included) | `DEFAULT_SCENE` |
//! | `lockstep-band` | `Model2Stepper<f32, Band>` | rig set push_center, Coulomb |
//! | `lockstep-stribeck` | `Model2Stepper<f32, Stribeck>` | rig set push_center, no band |
//! | `lockstep-stribeck-band` | `Model2Stepper<f32, StribeckBand>` | rig set push_center |
//!
//! At most one of the three features may be on.

use super::pneumatics::normal_load_n;
use crate::exact::{ExactState, ExactStepper, ExactTables, Halt};
use crate::model2::{Composition, Model2Observer, Model2State, Model2Stepper, Model2Tables, Model2Transition};
use crate::scene::{Scene, SceneError};
use crate::stickslip::Regime;

#[cfg(any(
    all(feature = "lockstep-band", feature = "lockstep-stribeck"),
    all(feature = "lockstep-band", feature = "lockstep-stribeck-band"),
    all(feature = "lockstep-stribeck", feature = "lockstep-stribeck-band"),
))]
compile_error!("at most one of the features lockstep-band, lockstep-stribeck, lockstep-stribeck-band");

/// The rig's lockstep stepper, chosen by this crate's features (see the module documentation).
#[cfg(not(any(feature = "lockstep-band", feature = "lockstep-stribeck", feature = "lockstep-stribeck-band")))]
pub type RigStepper = ExactStepper<f32>;
#[cfg(feature = "lockstep-band")]
pub type RigStepper = Model2Stepper<f32, crate::model2::Band>;
#[cfg(feature = "lockstep-stribeck")]
pub type RigStepper = Model2Stepper<f32, crate::model2::Stribeck>;
#[cfg(feature = "lockstep-stribeck-band")]
pub type RigStepper = Model2Stepper<f32, crate::model2::StribeckBand>;

/// The pad a rig built with this crate's features runs by default: the thesis's default scene,
/// or the rig set's push_center with the options of [`RigStepper`]'s composition
/// ([`crate::rig_set`]).
pub fn default_template() -> Scene {
    #[cfg(not(any(feature = "lockstep-band", feature = "lockstep-stribeck", feature = "lockstep-stribeck-band")))]
    {
        crate::catalogue::DEFAULT_SCENE
    }
    #[cfg(any(feature = "lockstep-band", feature = "lockstep-stribeck", feature = "lockstep-stribeck-band"))]
    {
        let mut s = crate::catalogue::rig_set::rig_scene(crate::scene::Caliper::Push, 0.040);
        if !<<RigStepper as LockstepStepper>::Composition as Composition>::STRIBECK {
            s.friction = crate::scene::FrictionLaw::Coulomb;
        }
        s.band = <<RigStepper as LockstepStepper>::Composition as Composition>::BAND;
        s
    }
}

/// What the lockstep model needs of a stepper (f32): its tables (built once, read-only) and
/// its state (what a step or a restart writes), apart.
pub trait LockstepStepper: Sized {
    /// The model-2 composition ([`crate::model2::Coulomb`] for the thesis stepper).
    type Composition: Composition;
    /// The stepper's tables: fixed at the build.
    type Tables;
    /// The stepper's state: what a step writes.
    type State;
    /// What a restart returns to: the stepper's initial state vector, taken when it is built
    /// ([`Self::start_point`]): a few words, not the tables.
    type Start: Copy + core::fmt::Debug;
    /// Builds the stepper for `scene` in `slot` (in place: see [`LockstepModel`]).
    fn build_in(slot: &mut Option<Self>, scene: &Scene) -> Result<(), SceneError>;
    /// The state vector a freshly built stepper is in.
    fn start_point(&self) -> Self::Start;
    /// The tables, read-only, and the state, to write.
    fn parts_mut(&mut self) -> (&Self::Tables, &mut Self::State);
    /// The tables and the state, to read.
    fn parts(&self) -> (&Self::Tables, &Self::State);
    /// Back to `start` (its [`Self::start_point`]): the same state a fresh build leaves, bit
    /// for bit, written into `state` alone (the tables are read).
    fn restart(tables: &Self::Tables, state: &mut Self::State, start: &Self::Start);
    /// One step; whether a stick-to-slip transition happened in it.
    fn advance(tables: &Self::Tables, state: &mut Self::State) -> Result<bool, Halt>;
    fn current_regime(state: &Self::State) -> Regime;
    /// The pad's acceleration x'' at the current state [m/s^2].
    fn pad_acceleration(tables: &Self::Tables, state: &Self::State) -> f32;
    /// The normal force at the current state [N].
    fn current_normal_force(tables: &Self::Tables, state: &Self::State) -> f32;
}

impl LockstepStepper for ExactStepper<f32> {
    type Composition = crate::model2::Coulomb;
    type Tables = ExactTables<f32>;
    type State = ExactState<f32>;
    type Start = [f32; 4];
    fn build_in(slot: &mut Option<Self>, scene: &Scene) -> Result<(), SceneError> {
        *slot = Some(ExactStepper::new(scene)?);
        Ok(())
    }
    fn start_point(&self) -> [f32; 4] {
        self.state().to_array()
    }
    #[inline(always)]
    fn parts_mut(&mut self) -> (&ExactTables<f32>, &mut ExactState<f32>) {
        ExactStepper::parts_mut(self)
    }
    #[inline(always)]
    fn parts(&self) -> (&ExactTables<f32>, &ExactState<f32>) {
        (self.tables(), self.run_state())
    }
    fn restart(tables: &ExactTables<f32>, state: &mut ExactState<f32>, start: &[f32; 4]) {
        tables.restart(state, *start);
    }
    #[inline(always)]
    fn advance(tables: &ExactTables<f32>, state: &mut ExactState<f32>) -> Result<bool, Halt> {
        tables.step(state)?;
        Ok(state.transitions().iter().any(|t| t.from == Regime::Stick))
    }
    #[inline(always)]
    fn current_regime(state: &ExactState<f32>) -> Regime {
        state.regime()
    }
    #[inline(always)]
    fn pad_acceleration(tables: &ExactTables<f32>, state: &ExactState<f32>) -> f32 {
        let z = state.state().to_array();
        tables.propagator().accelerations(state.regime(), &z).0
    }
    fn current_normal_force(tables: &ExactTables<f32>, state: &ExactState<f32>) -> f32 {
        tables.normal_force(state)
    }
}

/// Flags a stick-to-slip transition of a model-2 step.
struct SlipOnset(bool);

impl Model2Observer<f32> for SlipOnset {
    const DERIVATIVES: bool = false;
    #[inline(always)]
    fn transition(&mut self, tr: &Model2Transition<f32>) {
        if tr.from == Regime::Stick {
            self.0 = true;
        }
    }
}

impl<C: Composition> LockstepStepper for Model2Stepper<f32, C> {
    type Composition = C;
    type Tables = Model2Tables<f32, C>;
    type State = Model2State<f32>;
    type Start = [f32; crate::model2::NS];
    fn build_in(slot: &mut Option<Self>, scene: &Scene) -> Result<(), SceneError> {
        Model2Stepper::init_in(slot, scene).map(|_| ())
    }
    fn start_point(&self) -> [f32; crate::model2::NS] {
        self.state()
    }
    #[inline(always)]
    fn parts_mut(&mut self) -> (&Model2Tables<f32, C>, &mut Model2State<f32>) {
        Model2Stepper::parts_mut(self)
    }
    #[inline(always)]
    fn parts(&self) -> (&Model2Tables<f32, C>, &Model2State<f32>) {
        (self.tables(), self.run_state())
    }
    fn restart(tables: &Model2Tables<f32, C>, state: &mut Model2State<f32>, start: &[f32; crate::model2::NS]) {
        tables.restart(state, *start);
    }
    #[inline(always)]
    fn advance(tables: &Model2Tables<f32, C>, state: &mut Model2State<f32>) -> Result<bool, Halt> {
        let mut onset = SlipOnset(false);
        tables.step(state, &mut onset)?;
        Ok(onset.0)
    }
    #[inline(always)]
    fn current_regime(state: &Model2State<f32>) -> Regime {
        state.regime()
    }
    #[inline(always)]
    fn pad_acceleration(tables: &Model2Tables<f32, C>, state: &Model2State<f32>) -> f32 {
        tables.derivative(state.regime(), &state.z())[1]
    }
    fn current_normal_force(tables: &Model2Tables<f32, C>, state: &Model2State<f32>) -> f32 {
        tables.normal_force(&state.z())
    }
}

/// The model's prediction at one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelSample {
    /// The model's pad acceleration x'' [m/s^2] (0 once halted).
    pub xdd_m_s2: f32,
    /// Measured pad_x minus the model's x'' [m/s^2] (0 once halted).
    pub residual_m_s2: f32,
    pub regime: Regime,
    /// A stick-to-slip transition happened in this sample's step.
    pub slip_onset: bool,
    /// The model has halted (at this step or before).
    pub halted: bool,
}

/// The stepper in lockstep with the samples ([`RigStepper`] unless named), or no model
/// (stopped): one set of tables and the state stepped on them
/// ([`LockstepStepper::Tables`], [`LockstepStepper::State`]). The stepper is built in its slot
/// ([`LockstepStepper::build_in`]) and never moved. Stopping keeps it (its tables: kilobytes,
/// built in f64 once): [`Self::restart`] puts it back at its initial state by writing the
/// state alone (the tables are passed to it read-only: [`LockstepStepper::restart`]), no
/// tables copied (the rig's record start, [`super::pipeline`]). (Its value may still be assembled on the stack first: a model-2 stepper
/// in f32 takes kilobytes (`core::mem::size_of`), and the optimiser decides whether
/// `Option::insert` builds it in place; `Estimator::start_model`'s frame with the `model2`
/// stepper is read off `arm-none-eabi-objdump -d` of bin `rig` of `tests/on-target` built
/// `--features model2`.)
///
/// (`repr(C)`: the halt first and the stepper after it, where the compiler put them before the
/// restart's fields came, and those last: the per-sample step keeps its field offsets, and its
/// instruction count, `scripts/count-instructions.sh`.)
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct LockstepModel<S: LockstepStepper = RigStepper> {
    halt: Option<Halt>,
    stepper: Option<S>,
    /// The model steps (a stopped model keeps its stepper for a restart).
    running: bool,
    /// The stepper's initial state (with `stepper`).
    start: Option<S::Start>,
}

impl<S: LockstepStepper> Default for LockstepModel<S> {
    fn default() -> Self {
        Self::stopped()
    }
}

impl<S: LockstepStepper> LockstepModel<S> {
    /// No model.
    pub const fn stopped() -> Self {
        LockstepModel { halt: None, stepper: None, running: false, start: None }
    }

    /// The scene the model runs: `template` with F_N = `actuator_bar` x `piston_area_m2`, band
    /// speed `band_speed_m_s` and step 1 / `fs_hz`.
    pub fn scene(template: &Scene, actuator_bar: f64, piston_area_m2: f64, band_speed_m_s: f64, fs_hz: f64) -> Scene {
        let mut s = *template;
        s.f_n = normal_load_n(actuator_bar, piston_area_m2);
        s.v = band_speed_m_s;
        s.dt = 1.0 / fs_hz;
        if !(s.duration >= s.dt) {
            s.duration = s.dt;
        }
        if !(s.stats_from < s.duration) {
            s.stats_from = 0.0;
        }
        s
    }

    /// (Re)starts the model for [`Self::scene`] from its initial state; a scene that does not
    /// validate (e.g. a negative or non-finite measured pressure) is refused with the reason,
    /// and the model is then stopped.
    pub fn start(
        &mut self,
        template: &Scene,
        actuator_bar: f64,
        piston_area_m2: f64,
        band_speed_m_s: f64,
        fs_hz: f64,
    ) -> Result<(), SceneError> {
        let scene = Self::scene(template, actuator_bar, piston_area_m2, band_speed_m_s, fs_hz);
        self.stepper = None;
        self.start = None;
        self.running = false;
        self.halt = None;
        S::build_in(&mut self.stepper, &scene)?;
        self.start = self.stepper.as_ref().map(|s| s.start_point());
        self.running = self.stepper.is_some();
        Ok(())
    }

    /// Stops the model; its stepper is kept for [`Self::restart`].
    pub fn stop(&mut self) {
        self.running = false;
        self.halt = None;
    }

    /// Runs the model again from its initial state (the state [`Self::start`] built it in),
    /// its tables kept: its state written (120 B of model 2's in f32, 328 B of the thesis
    /// stepper's), its tables only read, nothing rebuilt. Nothing happens without a stepper
    /// (never started, or its scene refused).
    #[inline]
    pub fn restart(&mut self) {
        if let (Some(stepper), Some(start)) = (self.stepper.as_mut(), self.start.as_ref()) {
            let (tables, state) = stepper.parts_mut();
            S::restart(tables, state, start);
            self.running = true;
        }
        self.halt = None;
    }

    pub fn is_running(&self) -> bool {
        self.running
    }
    /// The stepper, while the model runs.
    pub fn stepper(&self) -> Option<&S> {
        if self.running {
            self.stepper.as_ref()
        } else {
            None
        }
    }
    /// The model's normal force now [N] (0 when stopped).
    pub fn normal_force(&self) -> f32 {
        self.stepper().map_or(0.0, |s| {
            let (tables, state) = s.parts();
            S::current_normal_force(tables, state)
        })
    }
    pub fn halt(&self) -> Option<Halt> {
        self.halt
    }

    /// One step; compares the model's x'' with the measured `pad_x_m_s2`. None when stopped
    /// (the caller checks [`Self::is_running`] first: the estimator does, outside the step).
    #[inline(always)]
    pub fn step(&mut self, pad_x_m_s2: f32) -> Option<ModelSample> {
        if !self.running {
            return None;
        }
        self.step_running(pad_x_m_s2)
    }

    /// [`Self::step`] of a running model (the check of `running` stays with the caller, where
    /// it folds with the estimator's own: this body is the step as it was before the restart).
    #[inline]
    fn step_running(&mut self, pad_x_m_s2: f32) -> Option<ModelSample> {
        let (tables, state) = self.stepper.as_mut()?.parts_mut();
        let mut slip_onset = false;
        if self.halt.is_none() {
            match S::advance(tables, state) {
                Ok(onset) => slip_onset = onset,
                Err(h) => self.halt = Some(h),
            }
        }
        let regime = S::current_regime(state);
        if self.halt.is_some() {
            return Some(ModelSample { xdd_m_s2: 0.0, residual_m_s2: 0.0, regime, slip_onset: false, halted: true });
        }
        let xdd = S::pad_acceleration(tables, state);
        Some(ModelSample { xdd_m_s2: xdd, residual_m_s2: pad_x_m_s2 - xdd, regime, slip_onset, halted: false })
    }
}

/// Where an estimator keeps its lockstep model: a [`LockstepModel`], or [`NoModel`] (the rig's
/// fresh estimator a record starts from, which needs none: the running estimator restarts its
/// own model, [`super::pipeline`]).
pub trait ModelSlot: Copy + core::fmt::Debug {
    /// No model running. (A function, not an associated `const`: a constant of a model type is
    /// its whole size in flash, copied in, where this writes a few words.)
    fn stopped() -> Self;
    fn is_running(&self) -> bool;
    fn halt(&self) -> Option<Halt>;
    /// One step (None when stopped): [`LockstepModel::step`].
    fn step(&mut self, pad_x_m_s2: f32) -> Option<ModelSample>;
}

impl<S: LockstepStepper + Copy + core::fmt::Debug> ModelSlot for LockstepModel<S> {
    #[inline(always)]
    fn stopped() -> Self {
        LockstepModel::stopped()
    }
    #[inline(always)]
    fn is_running(&self) -> bool {
        LockstepModel::is_running(self)
    }
    #[inline(always)]
    fn halt(&self) -> Option<Halt> {
        LockstepModel::halt(self)
    }
    #[inline(always)]
    fn step(&mut self, pad_x_m_s2: f32) -> Option<ModelSample> {
        LockstepModel::step(self, pad_x_m_s2)
    }
}

/// No lockstep model: no bytes, never running.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NoModel;

impl ModelSlot for NoModel {
    #[inline(always)]
    fn stopped() -> Self {
        NoModel
    }
    #[inline(always)]
    fn is_running(&self) -> bool {
        false
    }
    #[inline(always)]
    fn halt(&self) -> Option<Halt> {
        None
    }
    #[inline(always)]
    fn step(&mut self, _pad_x_m_s2: f32) -> Option<ModelSample> {
        None
    }
}
