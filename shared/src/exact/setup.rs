//! Set-up of the exact stepper's tables (the dyadic propagator, the guards, the fast path's
//! constants, the guards' curvatures) and the state a run starts or restarts in.

use super::*;

impl<T: Real> ExactTables<T> {
    /// Validates `scene` and builds its tables, with the state a run starts in: stick, x = 0,
    /// x' = V, phi = F_N a_N / K, phi' = 0 ([`Self::start_state`]).
    pub fn new(scene: &Scene) -> Result<(Self, ExactState<T>), SceneError> {
        scene.validate()?;
        let co = Coefficients::of(scene);
        let prop = Propagator::<T>::new(scene, &co, scene.dt);
        Ok(Self::on_propagator(scene, &co, prop))
    }

    /// [`Self::new`] on a propagator already built for a scene with this scene's
    /// [`Propagator::key`] (a cache's: the dyadic tables are most of the set-up's cost): the
    /// same tables, bit for bit, as [`Self::new`] builds. The caller keys its cache with
    /// [`Propagator::key`]; a propagator of another key gives another scene's flows.
    pub fn with_propagator(scene: &Scene, prop: &Propagator<T>) -> Result<(Self, ExactState<T>), SceneError> {
        scene.validate()?;
        let co = Coefficients::of(scene);
        debug_assert_eq!(prop.n_sub, Propagator::<T>::substeps(scene, &co, scene.dt));
        Ok(Self::on_propagator(scene, &co, *prop))
    }

    /// The tables of a validated scene on its propagator.
    fn on_propagator(scene: &Scene, co: &Coefficients, prop: Propagator<T>) -> (Self, ExactState<T>) {
        let mut tables = ExactTables {
            h_sub_t: T::zero(),
            prop,
            guards: Guards::<T>::new(scene, co),
            fast: Self::fast_path(scene, co, &prop),
            rotation: scene.rotation,
            dt: scene.dt,
            limits: Limits::new(scene, co),
            curv: [[[T::zero(); 5]; 2]; 3],
        };
        let state = tables.rebuild_on(scene, co);
        (tables, state)
    }

    /// These tables rebuilt in place for `scene` (validated here), keeping their propagator,
    /// which must be the one of `scene`'s [`Propagator::key`] (a cache of tables by key: the
    /// propagator is most of their size, and is not copied): the tables
    /// [`Self::with_propagator`] builds, bit for bit. Returns the start state.
    pub fn retarget(&mut self, scene: &Scene) -> Result<ExactState<T>, SceneError> {
        scene.validate()?;
        let co = Coefficients::of(scene);
        debug_assert_eq!(self.prop.n_sub, Propagator::<T>::substeps(scene, &co, scene.dt));
        Ok(self.rebuild_on(scene, &co))
    }

    /// Every field but the propagator, from `scene`; the start state.
    fn rebuild_on(&mut self, scene: &Scene, co: &Coefficients) -> ExactState<T> {
        let t = T::from_f64;
        self.guards = Guards::<T>::new(scene, co);
        self.fast = Self::fast_path(scene, co, &self.prop);
        self.rotation = scene.rotation;
        self.dt = scene.dt;
        self.limits = Limits::new(scene, co);
        self.curv = Self::curvatures(scene, co);
        self.h_sub_t = t(self.prop.h_sub);
        let z = [T::zero(), t(scene.v), t(co.phi0), T::zero()];
        self.start_state(z)
    }

    fn fast_path(scene: &Scene, co: &Coefficients, prop: &Propagator<T>) -> FastPath<T> {
        let t = T::from_f64;
        FastPath {
            stick_rot: Self::stick_fold(prop, scene.v),
            v: t(scene.v),
            k_g: t(scene.k_g),
            c_x_v: t(scene.c_x * scene.v),
            mu_s_c_n: t(scene.mu_s * co.c_n),
            mu_s_n0: t(scene.mu_s * co.n0),
            c_n: t(co.c_n),
            n0: t(co.n0),
            mu_k: t(scene.mu_k),
            k_g_v: t(scene.k_g * scene.v),
        }
    }

    /// The state a run starts in at `z0`: in stick, at step 0, no halt, nothing reported (with
    /// `z0` the state [`Self::new`] returns, the state it builds).
    pub fn start_state(&self, z0: [T; 4]) -> ExactState<T> {
        let empty = Transition { t: 0.0, from: Regime::Stick, to: Regime::Stick, state: State::default() };
        ExactState {
            z: z0,
            regime: Regime::Stick,
            step: 0,
            anchor_x: T::zero(),
            anchor_e0: self.h_sub_t,
            anchor_subs: 0,
            reported: [empty; TRANSITIONS_PER_STEP],
            n_reported: 0,
            dropped: 0,
            halted: None,
        }
    }

    /// Back to the initial state at `z0` ([`Self::start_state`]), the tables untouched: every
    /// field a step changes, as [`Self::new`] leaves it (the rig's lockstep model restarts this
    /// way at each record's start, writing state only).
    pub fn restart(&self, s: &mut ExactState<T>, z0: [T; 4]) {
        let empty = Transition { t: 0.0, from: Regime::Stick, to: Regime::Stick, state: State::default() };
        s.z = z0;
        s.regime = Regime::Stick;
        s.step = 0;
        s.anchor_x = T::zero();
        s.anchor_e0 = self.h_sub_t;
        s.anchor_subs = 0;
        s.reported = [empty; TRANSITIONS_PER_STEP];
        s.n_reported = 0;
        s.dropped = 0;
        s.halted = None;
    }

    /// c . A^2 for every guard of every regime, in f64, rounded to T.
    fn curvatures(scene: &Scene, co: &Coefficients) -> [[[T; 5]; 2]; 3] {
        let g64 = Guards::<f64>::new(scene, co);
        let mut out = [[[T::zero(); 5]; 2]; 3];
        for regime in Regime::ALL {
            let a = system_matrix(scene, co, regime);
            let a2 = linalg::mul(&a, &a);
            let (gs, n) = g64.of(regime);
            for (which, g) in gs.iter().take(n).enumerate() {
                for col in 0..5 {
                    let v: f64 = (0..5).map(|r| g.c[r] * a2[r][col]).sum();
                    out[regime.index()][which][col] = T::from_f64(v);
                }
            }
        }
        out
    }

    fn stick_fold(prop: &Propagator<T>, v: f64) -> [T; 8] {
        let f = prop.substep_flow(Regime::Stick);
        let g = |i: usize| f[i].to_f64();
        Self::fold_stick_rows([g(10), g(11), g(12), g(13), g(14)], [g(15), g(16), g(17), g(18), g(19)], v)
    }

    /// The phi and phi' rows (columns x, x', phi, phi', 1) of a stick flow in increment form,
    /// with x' = V folded into the constant: [phi += a0 x + a1 phi + a2 phi' + a3, phi' += a4 x
    /// + a5 phi + a6 phi' + a7] ([`FastPath::stick_rot`], the stick jump's flows).
    pub(super) fn fold_stick_rows(phi: [f64; 5], phid: [f64; 5], v: f64) -> [T; 8] {
        let t = T::from_f64;
        [t(phi[0]), t(phi[2]), t(phi[3]), t(phi[4] + phi[1] * v), t(phid[0]), t(phid[2]), t(phid[3]), t(phid[4] + phid[1] * v)]
    }

    /// Replaces the state and regime of `s` (e.g. to start from a measured condition). In
    /// stick, x' is set to V.
    pub fn set_state(&self, s: &mut ExactState<T>, state: State<T>, regime: Regime) {
        s.z = state.to_array();
        s.regime = regime;
        if regime == Regime::Stick {
            s.z[1] = self.fast.v;
            s.anchor_x = s.z[0];
            s.anchor_e0 = self.h_sub_t;
            s.anchor_subs = 0;
        }
        s.halted = None;
    }

    /// Normal force N = c_N phi at the state of `s` [N] (N_0 without rotation).
    pub fn normal_force(&self, s: &ExactState<T>) -> T {
        if self.rotation {
            self.fast.c_n * s.z[2]
        } else {
            self.fast.n0
        }
    }

    /// Friction force on the pad F_f [N] at the state of `s`: the required force in stick,
    /// sigma mu_k N in slip.
    pub fn friction_force(&self, s: &ExactState<T>) -> T {
        match s.regime {
            Regime::Stick => self.guards.required_force(&s.z),
            Regime::SlipSlower => self.fast.mu_k * self.normal_force(s),
            Regime::SlipFaster => -(self.fast.mu_k * self.normal_force(s)),
        }
    }

    /// Time at the end of the last step of `s` [s].
    pub fn time(&self, s: &ExactState<T>) -> f64 {
        s.step as f64 * self.dt
    }

    pub fn propagator(&self) -> &Propagator<T> {
        &self.prop
    }

    pub fn guards(&self) -> &Guards<T> {
        &self.guards
    }
}
