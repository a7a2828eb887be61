//! [`ExactStepper`]: a run, its state beside its tables, owned (the default) or shared (a
//! reference: several runs, one set of tables), with the stepper's whole API delegating to
//! [`ExactTables`] and [`ExactState`].

use core::borrow::Borrow;

use super::*;

/// The exact fixed-step stepper, generic over f32 and f64: an [`ExactState`] beside its
/// [`ExactTables`], held as `Tb`: the tables themselves (the default) or a reference to them
/// (`&ExactTables`: runs of one scene share one set, [`Self::shared`]). Every method delegates:
/// the step is [`ExactTables::step`] on this run's state.
#[derive(Clone, Copy, Debug)]
pub struct ExactStepper<T: Real, Tb = ExactTables<T>> {
    tables: Tb,
    state: ExactState<T>,
}

impl<T: Real> ExactStepper<T> {
    /// Validates `scene` and sets up the stepper at the default initial state: stick, x = 0,
    /// x' = V, phi = F_N a_N / K, phi' = 0.
    pub fn new(scene: &Scene) -> Result<Self, SceneError> {
        let (tables, state) = ExactTables::new(scene)?;
        Ok(ExactStepper { tables, state })
    }

    /// A run on these tables that borrows them, in this stepper's state: the same run as a
    /// copy of this stepper, without copying its tables.
    pub fn shared(&self) -> ExactStepper<T, &ExactTables<T>> {
        ExactStepper { tables: &self.tables, state: self.state }
    }
}

impl<'a, T: Real> ExactStepper<T, &'a ExactTables<T>> {
    /// A run on shared `tables` from `state`.
    pub fn on(tables: &'a ExactTables<T>, state: ExactState<T>) -> Self {
        ExactStepper { tables, state }
    }
}

impl<T: Real, Tb: Borrow<ExactTables<T>>> ExactStepper<T, Tb> {
    /// The tables.
    #[inline(always)]
    pub fn tables(&self) -> &ExactTables<T> {
        self.tables.borrow()
    }

    /// The run's state (what a step writes).
    #[inline(always)]
    pub fn run_state(&self) -> &ExactState<T> {
        &self.state
    }

    /// The tables, read-only, and the state, to write: what a step or a restart takes.
    #[inline(always)]
    pub fn parts_mut(&mut self) -> (&ExactTables<T>, &mut ExactState<T>) {
        (self.tables.borrow(), &mut self.state)
    }

    /// Back to the initial state, the tables kept: `z0` is the state the stepper was built in
    /// ([`Self::state`] right after [`Self::new`]), in stick, at step 0, no halt, nothing
    /// reported: the state as [`Self::new`] leaves it, nothing else written
    /// ([`ExactTables::restart`]).
    pub fn restart(&mut self, z0: [T; 4]) {
        let (tables, state) = self.parts_mut();
        tables.restart(state, z0);
    }

    /// Replaces the state and regime (e.g. to start from a measured condition). In stick,
    /// x' is set to V.
    pub fn set_state(&mut self, state: State<T>, regime: Regime) {
        let (tables, s) = self.parts_mut();
        tables.set_state(s, state, regime);
    }

    pub fn state(&self) -> State<T> {
        self.state.state()
    }
    pub fn regime(&self) -> Regime {
        self.state.regime
    }
    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.state.step
    }
    /// Time at the end of the last step [s].
    pub fn time(&self) -> f64 {
        self.tables().time(&self.state)
    }
    pub fn propagator(&self) -> &Propagator<T> {
        &self.tables().prop
    }
    pub fn guards(&self) -> &Guards<T> {
        &self.tables().guards
    }
    /// The transitions of the last step (at most [`TRANSITIONS_PER_STEP`]).
    pub fn transitions(&self) -> &[Transition<T>] {
        self.state.transitions()
    }
    /// Transitions not kept because a step had more than [`TRANSITIONS_PER_STEP`].
    pub fn transitions_dropped(&self) -> u64 {
        self.state.dropped
    }
    pub fn halted(&self) -> Option<Halt> {
        self.state.halted
    }

    /// Normal force N = c_N phi at the current state [N] (N_0 without rotation).
    pub fn normal_force(&self) -> T {
        self.tables().normal_force(&self.state)
    }

    /// Friction force on the pad F_f [N]: the required force in stick, sigma mu_k N in slip.
    pub fn friction_force(&self) -> T {
        self.tables().friction_force(&self.state)
    }

    /// One step of `dt`, with no observer ([`ExactTables::step`]: a short path for the common
    /// step).
    #[inline(always)]
    pub fn step(&mut self) -> Result<usize, Halt> {
        let (tables, state) = self.parts_mut();
        tables.step(state)
    }

    /// One step of `dt`; `obs` sees every segment and transition. Returns the number of
    /// transitions in the step.
    pub fn step_observed<O: Observer<T>>(&mut self, obs: &mut O) -> Result<usize, Halt> {
        let (tables, state) = self.parts_mut();
        tables.step_observed(state, obs)
    }
}
