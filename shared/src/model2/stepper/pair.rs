//! [`Model2Stepper`]: a run, its state beside its tables, owned (the default) or shared (a
//! reference: several runs, one set of tables), with the stepper's whole API delegating to
//! [`Model2Tables`] and [`Model2State`].

use core::borrow::Borrow;
use core::marker::PhantomData;

use super::*;

/// A model-2 run: its [`Model2State`] beside its [`Model2Tables`], held as `Tb`: the tables
/// themselves (the default, a stepper that owns its kilobytes of tables) or a reference to
/// them (`&Model2Tables`: runs of one scene share one set, [`Self::shared`]). Every method
/// delegates: the step is [`Model2Tables::step`] on this run's state.
#[derive(Clone, Copy, Debug)]
pub struct Model2Stepper<T: Real, C: Composition, Tb = Model2Tables<T, C>> {
    tables: Tb,
    state: Model2State<T>,
    composition: PhantomData<C>,
}

impl<T: Real, C: Composition> Model2Stepper<T, C> {
    /// Validates `scene` (and that it asks for composition `C`) and starts at rest in stick:
    /// x = 0, x' = V, phi = F_N a_N / K, phi' = 0, u = u' = 0.
    pub fn new(scene: &Scene) -> Result<Self, SceneError> {
        let mut slot = None;
        Self::init_in(&mut slot, scene)?;
        match slot {
            Some(s) => Ok(s),
            None => unreachable!("init_in returned Ok without filling the slot"),
        }
    }

    /// [`Self::new`] built in `slot` (e.g. a `static`): the dyadic tables (kilobytes in f32)
    /// are filled where they stay, not on the stack and then moved, which a Cortex-M4F's stack
    /// cannot hold twice (tests/on-target bin `count_model2` prints the stack it takes). The
    /// same values as [`Self::new`]. On an error `slot` is left as it was.
    pub fn init_in<'a>(slot: &'a mut Option<Self>, scene: &Scene) -> Result<&'a mut Self, SceneError> {
        let (p, _) = Model2Tables::build_in(
            slot,
            scene,
            None,
            |tables, z0| Model2Stepper { tables, state: Model2State::at(z0), composition: PhantomData },
            |p| &mut p.tables,
        )?;
        // the stick anchor of the start (x = 0; with the face x + s w phi_0)
        p.state.anchor_x = p.tables.face_position(&p.state.z);
        Ok(p)
    }

    /// [`Self::new`] with each Stribeck slip's kinetic tables taken from `donor` where they
    /// are the same computation (f64; see `fill_tables_reusing`): the same stepper.
    pub fn new_reusing(scene: &Scene, donor: &Model2Tables<T, C>) -> Result<Self, SceneError> {
        let mut slot = None;
        let (p, _) = Model2Tables::build_in(
            &mut slot,
            scene,
            Some(donor),
            |tables, z0| Model2Stepper { tables, state: Model2State::at(z0), composition: PhantomData },
            |p| &mut p.tables,
        )?;
        p.state.anchor_x = p.tables.face_position(&p.state.z);
        match slot {
            Some(s) => Ok(s),
            None => unreachable!("build_in returned Ok without filling the slot"),
        }
    }

    /// A run on these tables that borrows them, in this stepper's state: the same run as a
    /// copy of this stepper, without copying its tables.
    pub fn shared(&self) -> Model2Stepper<T, C, &Model2Tables<T, C>> {
        Model2Stepper { tables: &self.tables, state: self.state, composition: PhantomData }
    }
}

impl<'a, T: Real, C: Composition> Model2Stepper<T, C, &'a Model2Tables<T, C>> {
    /// A run on shared `tables` from `state`.
    pub fn on(tables: &'a Model2Tables<T, C>, state: Model2State<T>) -> Self {
        Model2Stepper { tables, state, composition: PhantomData }
    }
}

impl<T: Real, C: Composition, Tb: Borrow<Model2Tables<T, C>>> Model2Stepper<T, C, Tb> {
    /// The tables.
    #[inline(always)]
    pub fn tables(&self) -> &Model2Tables<T, C> {
        self.tables.borrow()
    }

    /// The run's state (what a step writes).
    #[inline(always)]
    pub fn run_state(&self) -> &Model2State<T> {
        &self.state
    }

    /// The tables, read-only, and the state, to write: what a step or a restart takes.
    #[inline(always)]
    pub fn parts_mut(&mut self) -> (&Model2Tables<T, C>, &mut Model2State<T>) {
        (self.tables.borrow(), &mut self.state)
    }

    /// Whether the slip flows have slip's block zeros in the table, exactly (the slip step then
    /// skips them; see `increment_slip`).
    pub fn slip_flows_are_block_sparse(&self) -> bool {
        self.tables().slip_flows_are_block_sparse()
    }

    /// The composition's name ("band", "stribeck", "stribeck+band").
    pub fn composition(&self) -> &'static str {
        C::NAME
    }

    /// Bytes of the dyadic tables (flows and ETDRK4 vectors).
    pub fn table_bytes(&self) -> usize {
        self.tables().table_bytes()
    }

    pub fn state(&self) -> [T; NS] {
        self.state.z
    }

    pub fn regime(&self) -> Regime {
        self.state.regime
    }

    pub fn steps(&self) -> u64 {
        self.state.step
    }

    pub fn time(&self) -> f64 {
        self.state.step as f64 * self.tables().dt
    }

    pub fn halted(&self) -> Option<Halt> {
        self.state.halted
    }

    /// Transitions so far.
    pub fn transitions(&self) -> u64 {
        self.state.transitions
    }

    /// Substeps per step.
    pub fn substeps(&self) -> u32 {
        self.tables().n_sub
    }

    /// Whether this stepper carries the floating pad (y, y').
    pub fn floating(&self) -> bool {
        C::FLOAT
    }

    /// Back to the initial state, the tables kept: `z0` is the state the stepper was built in
    /// ([`Self::state`] right after [`Self::new`] or [`Self::init_in`]), in stick, at step 0,
    /// no halt, no transitions: the state as the set-up leaves it, nothing else written
    /// ([`Model2Tables::restart`]).
    pub fn restart(&mut self, z0: [T; NS]) {
        let (tables, state) = self.parts_mut();
        tables.restart(state, z0);
    }

    /// Replaces the state and regime (e.g. to start from steady sliding). In stick the sliding
    /// velocity is set to zero as on entry to stick. Without the band, u and u' are set to 0.
    pub fn set_state(&mut self, z: [T; NS], regime: Regime) {
        let (tables, state) = self.parts_mut();
        tables.set_state(state, z, regime);
    }

    /// Sliding velocity v = x' (+ s w phi' with the face) - V - u' [m/s].
    #[inline(always)]
    pub fn sliding_velocity(&self, z: &[T; NS]) -> T {
        self.tables().sliding_velocity(z)
    }

    /// Normal force N [N].
    #[inline(always)]
    pub fn normal_force(&self, z: &[T; NS]) -> T {
        self.tables().normal_force(z)
    }

    /// Friction force on the pad [N] in `regime` at `z`.
    pub fn friction_force(&self, regime: Regime, z: &[T; NS]) -> T {
        self.tables().friction_force(regime, z)
    }

    /// z' in `regime` at `z`.
    pub fn derivative(&self, regime: Regime, z: &[T; NS]) -> [T; NS] {
        self.tables().derivative(regime, z)
    }

    /// The pad's acceleration x'' [m/s^2] at the current state and regime
    /// ([`Model2Tables::pad_acceleration`]).
    pub fn pad_acceleration(&self) -> T {
        self.tables().pad_acceleration(&self.state)
    }

    /// One step of `dt` with no observer.
    #[inline]
    pub fn step(&mut self) -> Result<usize, Halt> {
        self.step_observed(&mut ())
    }

    /// One step of `dt`; `obs` sees every segment and transition. Returns the number of
    /// transitions in the step.
    #[inline]
    pub fn step_observed<O: Model2Observer<T>>(&mut self, obs: &mut O) -> Result<usize, Halt> {
        let (tables, state) = self.parts_mut();
        tables.step(state, obs)
    }

    /// [`Self::step_observed`] with every substep on the general path, never the short one:
    /// for the test that the two agree bit for bit.
    #[doc(hidden)]
    pub fn step_observed_general<O: Model2Observer<T>>(&mut self, obs: &mut O) -> Result<usize, Halt> {
        let (tables, state) = self.parts_mut();
        tables.step_general(state, obs)
    }
}
