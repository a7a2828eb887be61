//! Set-up of the model-2 stepper: validation, the substep, the guards' rows and rates, the
//! near operators' constants, and the dyadic tables (the flows of every regime, the ETDRK4
//! vectors of Stribeck slip and of its near operators), filled once in f64 and rounded to `T`.

use super::*;

impl<T: Real, C: Composition> Model2Tables<T, C> {
    /// Validates `scene` (and that it asks for composition `C`) and builds its tables, with the
    /// state a run starts in: at rest in stick, x = 0, x' = V, phi = F_N a_N / K, phi' = 0,
    /// u = u' = 0 ([`Self::start_state`]). The tables are kilobytes, returned by value: on a
    /// small stack build them in place ([`Self::init_in`]).
    pub fn new(scene: &Scene) -> Result<(Self, Model2State<T>), SceneError> {
        let mut slot = None;
        let (_, state) = Self::init_in(&mut slot, scene)?;
        match slot {
            Some(t) => Ok((t, state)),
            None => unreachable!("init_in returned Ok without filling the slot"),
        }
    }

    /// [`Self::new`] built in `slot` (e.g. a `static`): the dyadic tables (kilobytes in f32)
    /// are filled where they stay, not on the stack and then moved, which a Cortex-M4F's stack
    /// cannot hold twice. On an error `slot` is left as it was.
    pub fn init_in<'a>(slot: &'a mut Option<Self>, scene: &Scene) -> Result<(&'a mut Self, Model2State<T>), SceneError> {
        let (t, z0) = Self::build_in(slot, scene, None, |t, _| t, |t| t)?;
        let state = t.start_state(z0);
        Ok((t, state))
    }

    /// The set-up, building the tables inside a value `P` in `slot` (the tables alone, or a
    /// [`Model2Stepper`] pair): `pack` makes the value from the tables (their dyadic tables
    /// still zero) and the initial state vector, `tables` finds them in it again; the dyadic
    /// tables are then filled in place (tests/on-target bin `count_model2` prints the stack it
    /// takes). Returns the value and the initial state vector.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // matrix code: indices read as the formulas
    pub(super) fn build_in<'a, P>(
        slot: &'a mut Option<P>,
        scene: &Scene,
        donor: Option<&Self>,
        pack: impl FnOnce(Self, [T; NS]) -> P,
        tables: impl FnOnce(&mut P) -> &mut Self,
    ) -> Result<(&'a mut P, [T; NS]), SceneError> {
        scene.validate()?;
        C::matches(scene)?;
        let co = Coefficients::of(scene);
        // (compile-time choice: a hinged composition's build has no floating-pad set-up)
        let sys = if C::FLOAT { System::floating_pad(scene, &co) } else { System::hinged(scene, &co) };
        let rate = if C::FLOAT { sys.floating_rate(scene, &co) } else { sys.hinged_rate(scene, &co) };
        let mut n_sub = libm::ceil(scene.dt * rate / 0.25);
        if !(n_sub >= 1.0) {
            n_sub = 1.0;
        }
        if n_sub > 1e6 {
            n_sub = 1e6;
        }
        let n_sub = n_sub as u32;
        let h_sub = scene.dt / n_sub as f64;
        let t = T::from_f64;
        let tv = |r: &[f64; NA]| -> [T; NA] { core::array::from_fn(|i| t(r[i])) };
        let z = [T::zero(), t(scene.v), t(sys.phi0), T::zero(), T::zero(), T::zero(), t(sys.y0), T::zero()];
        // the guards' rows in f64 and their rates row . A, row . b
        let mut guard_rate = [[T::zero(); NA]; 4];
        let mut guard_rate_b = [T::zero(); 4];
        for (regime, which) in [(Regime::Stick, 0), (Regime::Stick, 1), (Regime::SlipSlower, 0), (Regime::SlipFaster, 0)] {
            let g: [f64; NA] = match (regime, which) {
                (Regime::Stick, 0) => core::array::from_fn(|c| sys.r_freq[c] - scene.mu_s * sys.r_n[c]),
                (Regime::Stick, _) => core::array::from_fn(|c| -sys.r_freq[c] - scene.mu_s * sys.r_n[c]),
                (Regime::SlipSlower, _) => sys.r_v,
                (Regime::SlipFaster, _) => core::array::from_fn(|c| -sys.r_v[c]),
            };
            let a = &sys.a[regime.index()];
            let k = guard_slot(regime, which);
            for c in 0..NA {
                let mut acc = 0.0;
                for r in 0..NA {
                    acc += g[r] * a[r][c];
                }
                guard_rate[k][c] = t(acc);
            }
            if sys.stribeck && regime != Regime::Stick {
                guard_rate_b[k] = t((0..NA).map(|r| g[r] * sys.b[r]).sum());
            }
        }
        // the falling slope at v = 0 with N = N_0, (mu_s - mu_k) N_0 / v_s [N s/m], and its rate
        let near_kv = sys.d_mu * sys.n0 / scene.v_s;
        let near_rate = near_kv * sys.inv_mass_v;
        let near_on = C::STRIBECK && scene.stribeck_exponent == 1.0 && near_rate * h_sub <= NEAR_RATE_H_MAX;
        let near_c: [T; NEAR_OPS + 1] = core::array::from_fn(|k| t(k as f64 / NEAR_OPS as f64));
        let near_cn0: [T; NEAR_OPS + 1] = core::array::from_fn(|k| t(sys.n0 * k as f64 / NEAR_OPS as f64));
        let near_thr: [T; NEAR_OPS] = core::array::from_fn(|k| t(sys.n0 * (k as f64 + 0.5) / NEAR_OPS as f64));
        let near_ckv: [T; NEAR_OPS + 1] = core::array::from_fn(|k| t(k as f64 / NEAR_OPS as f64 * near_kv));
        let crest_w = crest_weights(&sys, h_sub, C::STRIBECK, Self::LEVELS);
        let p = slot.insert(pack(Model2Tables {
            flows: [T::per_level(C::zero_flow()); 3],
            etd: C::zero_etd(),
            near_flows: C::zero_near(),
            near_etd: C::zero_near_etd(),
            near_on,
            near_c,
            near_cn0,
            near_thr,
            near_ckv,
            a: [[[T::zero(); NA]; NS]; 3],
            b: core::array::from_fn(|i| t(sys.b[i])),
            r_v: tv(&sys.r_v),
            r_n: tv(&sys.r_n),
            r_freq: tv(&sys.r_freq),
            guard_rate,
            guard_rate_b,
            crest_w: core::array::from_fn(|k| tv(&crest_w[k])),
            crest_c1: t(4.0 / 27.0 * h_sub),
            mu_s: t(scene.mu_s),
            d_mu: t(sys.d_mu),
            inv_v_s: t(1.0 / scene.v_s),
            delta: t(scene.stribeck_exponent),
            delta_is_one: scene.stribeck_exponent == 1.0,
            v: t(scene.v),
            m: t(scene.m),
            m_b: t(scene.m_b),
            scene_band: sys.band,
            springs: [sys.k_l, sys.d_l, sys.k_t, sys.d_t],
            limits: Limits::new(scene, &co),
            u_limit: t(U_LIMIT),
            udot_limit: t(UDOT_LIMIT),
            h_sub,
            n_sub,
            dt: scene.dt,
            h_t: t(h_sub),
            hu_t: t(libm::ldexp(h_sub, -(Self::LEVELS as i32))),
            guards: core::array::from_fn(|k| {
                let (sign, mu) = match k {
                    0 => (1.0, scene.mu_s),
                    1 => (-1.0, scene.mu_s),
                    2 => (1.0, 0.0),
                    _ => (-1.0, 0.0),
                };
                core::array::from_fn(|c| {
                    if k < 2 {
                        t(sign * sys.r_freq[c] - mu * sys.r_n[c])
                    } else {
                        t(sign * sys.r_v[c])
                    }
                })
            }),
            v_round: t(libm::ldexp(scene.v, 8 - Self::LEVELS as i32)),
            rate_coef: t(sys.d_mu * scene.stribeck_exponent / scene.v_s * sys.inv_mass_v),
            rate_limit: T::per_level(T::zero()),
            slip_sparse: false,
            float_limits: {
                // a rounding-level negative compression is not a lift-off (as phi_floor)
                let floor = |d: f64| -(1e-6 * libm::fabs(sys.y0 + d * sys.phi0) + 1e-12);
                [t(sys.d_l), t(sys.d_t), t(floor(sys.d_l)), t(floor(sys.d_t)), t(Y_LIMIT), t(YDOT_LIMIT)]
            },
        }, z));
        let s = tables(p);
        for (j, r) in s.rate_limit.as_mut().iter_mut().enumerate() {
            *r = t(STRIBECK_RATE_H / (h_sub * libm::ldexp(1.0, j as i32 - Self::LEVELS as i32)));
        }
        match donor {
            Some(d) => s.fill_tables_reusing(scene, &sys, d),
            None => s.fill_tables(scene, &sys),
        }
        s.slip_sparse = !C::FLOAT
            && [Regime::SlipSlower, Regime::SlipFaster]
            .iter()
            .all(|r| s.flows[r.index()].as_ref().iter().all(|f| has_slip_zeros::<T, C>(f)));
        Ok((p, z))
    }

    /// Fills the dyadic tables (flows, ETDRK4 vectors, near operators) of a stepper whose
    /// other fields are set. Out of line: `init_in` then builds its value in the slot rather
    /// than on the stack (with the loops in its frame, the M4F's build of the whole stepper went
    /// through a copy on the stack).
    #[inline(never)]
    pub(super) fn fill_tables(&mut self, scene: &Scene, sys: &System) {
        self.fill_tables_from(scene, sys, None);
    }

    /// [`Self::fill_tables`], taking each Stribeck slip's kinetic tables (its flows and ETDRK4
    /// vectors on every level) from `donor` where they are computed from the same values: f64
    /// tables whose substep, regime matrix A and b are `donor`'s bit for bit (they depend on
    /// nothing else: not on V, which enters stick and the near operators). The same tables as
    /// computing them; a map's cells that differ in V share them (the host's table cache).
    #[inline(never)]
    pub(super) fn fill_tables_reusing(&mut self, scene: &Scene, sys: &System, donor: &Self) {
        self.fill_tables_from(scene, sys, Some(donor));
    }

    /// Whether `donor`'s kinetic tables of slip `regime` are the ones `sys` gives these tables.
    fn kinetic_as_in(&self, sys: &System, regime: Regime, donor: &Self) -> bool {
        let i = regime.index();
        T::DYADIC_LEVELS > 24
            && donor.h_sub.to_bits() == self.h_sub.to_bits()
            && (0..NS).all(|r| donor.b[r].to_f64().to_bits() == sys.b[r].to_bits())
            && (0..NS).all(|r| (0..NA).all(|c| donor.a[i][r][c].to_f64().to_bits() == sys.a[i][r][c].to_bits()))
    }

    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // matrix code: indices read as the formulas
    fn fill_tables_from(&mut self, scene: &Scene, sys: &System, donor: Option<&Self>) {
        let h_sub = self.h_sub;
        let t = T::from_f64;
        // the flow's columns: the moved entries, then the constant 1
        let cols: [usize; NA] = if C::FLOAT {
            [0, 1, 2, 3, 4, 5, 6, 7, ONE]
        } else if C::BAND {
            [0, 1, 2, 3, 4, 5, ONE, ONE, ONE]
        } else {
            [0, 1, 2, 3, ONE, ONE, ONE, ONE, ONE]
        };
        for regime in Regime::ALL {
            let a = &sys.a[regime.index()];
            let with_phi = C::STRIBECK && regime != Regime::Stick;
            // the kinetic operator (k = 0) on every level, then the near operators A + b g_k,
            // g_k = c_k sigma (mu_s - mu_k) (r_n - N_0 sign(v) r_v / v_s) (sign(v) = -sigma in
            // slip), on the top NEAR_LEVELS levels
            let near_ops = if with_phi && self.near_on { NEAR_OPS } else { 0 };
            let top = Self::LEVELS + 1 - NEAR_LEVELS;
            let reused = match donor {
                Some(d) if with_phi && self.kinetic_as_in(sys, regime, d) => {
                    self.flows[regime.index()] = d.flows[regime.index()];
                    self.etd.as_mut()[regime.index() - 1] = d.etd.as_ref()[regime.index() - 1];
                    true
                }
                _ => false,
            };
            let kinetic = (if reused { Self::LEVELS + 1 } else { 0 }..=Self::LEVELS).map(|j| (0, j));
            let near = (1..=near_ops).flat_map(|k| (top..=Self::LEVELS).map(move |j| (k, j)));
            // e^(tau A) tau phi_1(tau A) b of the previous level in the same chain (operator
            // k): the final combination's w0 at level j carries it (see `etd_chunk`)
            let mut half = [0.0f64; NS];
            for (k, j) in kinetic.chain(near) {
                if j == if k == 0 { 0 } else { top } {
                    // a chain's lowest level is never a chunk's w (a chunk of 2^j units reads
                    // level j >= 1 here, and j - 1 for phi_1)
                    half = [0.0; NS];
                }
                let a_k: [[f64; NA]; NA] = if k == 0 {
                    *a
                } else {
                    let sigma = regime.friction_sign();
                    let c_k = k as f64 / NEAR_OPS as f64;
                    let g: [f64; NA] = core::array::from_fn(|c| {
                        c_k * sigma * sys.d_mu * (sys.r_n[c] + sigma * sys.n0 / scene.v_s * sys.r_v[c])
                    });
                    core::array::from_fn(|r| core::array::from_fn(|c| a[r][c] + sys.b[r] * g[c]))
                };
                let a = &a_k;
                let near_index = (k.max(1) - 1) * 2 + regime.index().max(1) - 1;
                let tau = h_sub * libm::ldexp(1.0, j as i32 - Self::LEVELS as i32);
                // (a near operator's top level has ETDRK4 vectors but no flow)
                let flow: &mut [T] = if k == 0 {
                    self.flows[regime.index()].as_mut()[j].as_mut()
                } else if j < Self::LEVELS {
                    self.near_flows.as_mut()[near_index * NEAR_FLOW_LEVELS + j - top].as_mut()
                } else {
                    &mut []
                };
                let e = if with_phi {
                    // [[A, b, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0]] * tau
                    let mut m: MatN<{ NA + 3 }> = [[0.0; NA + 3]; NA + 3];
                    for r in 0..NA {
                        m[r][..NA].copy_from_slice(&a[r]);
                        m[r][NA] = sys.b[r];
                    }
                    m[NA][NA + 1] = 1.0;
                    m[NA + 1][NA + 2] = 1.0;
                    linalg::expm_minus_identity(&linalg::scale(&m, tau))
                } else {
                    let e9 = linalg::expm_minus_identity(&linalg::scale(a, tau));
                    let mut e: MatN<{ NA + 3 }> = [[0.0; NA + 3]; NA + 3];
                    for r in 0..NA {
                        e[r][..NA].copy_from_slice(&e9[r]);
                    }
                    e
                };
                // by columns (see `increment`)
                for (i, f) in flow.iter_mut().enumerate() {
                    *f = t(e[i % C::ROWS][cols[i / C::ROWS]]);
                }
                if with_phi {
                    let v: &mut EtdVectors<C::Row<T>> = if k > 0 {
                        &mut self.near_etd.as_mut()[near_index * NEAR_LEVELS + j - top]
                    } else {
                        &mut self.etd.as_mut()[regime.index() - 1].as_mut()[j]
                    };
                    for r in 0..C::ROWS {
                        let (c1, c2, c3) = (e[r][NA], e[r][NA + 1] / tau, e[r][NA + 2] / (tau * tau));
                        v.phi1[r] = t(c1);
                        v.w0[r] = t(c1 - 3.0 * c2 + 4.0 * c3 - half[r]);
                        v.wab[r] = t(2.0 * c2 - 4.0 * c3);
                        v.wc[r] = t(4.0 * c3 - c2);
                    }
                    // this level's e^(tau A) tau phi_1(tau A) b for the next (e holds
                    // e^(tau A) - I, its column NA tau phi_1(tau A) b)
                    half = core::array::from_fn(|r| e[r][NA] + (0..C::ROWS).map(|c| e[r][c] * e[c][NA]).sum::<f64>());
                }
            }
            for r in 0..NS {
                for c in 0..NA {
                    self.a[regime.index()][r][c] = t(sys.a[regime.index()][r][c]);
                }
            }
        }
    }
}

/// Samples of a substep the crest bound's suprema are taken over (see `crest_weights`).
const CREST_SAMPLES: usize = 64;

/// The weights of the crest bound (`Model2Tables::crest_below`) of each guard slot of a linear
/// regime (stick; slip with Coulomb friction; a Stribeck slip's slots stay 0 and unread): for
/// the guard's row g and the regime's A, with E(t) = expm(A t), t in [0, h_sub],
///
/// ```text
/// w_c = 2 sup_t |(g A^4 E(t))_c| h_sub^4 / 384 + 2^(11 - L) (|g_c| + sum_r |g_r| sup_t |(E(t) - I)_rc|)
/// ```
///
/// The first term times |z_c|, summed, bounds the cubic Hermite interpolant's error
/// h^4 / 384 sup |g''''| over any chunk of at most a substep (the suprema from 65 samples,
/// doubled); the second, 2^10 ulps (L = the significand's bits) of the guard's terms and of the
/// flow's, the round-off of the states a lift computes in T and of the guard's row products
/// there (a few ulps per level, at most L levels).
/// Out of line, so that its matrices (a few KB of f64) are not part of the set-up's frame on the
/// Cortex-M4F's stack.
#[inline(never)]
#[allow(clippy::needless_range_loop)] // matrix code: indices read as the formulas
fn crest_weights(sys: &System, h_sub: f64, stribeck: bool, levels: usize) -> [[f64; NA]; 4] {
    let mut w = [[0.0; NA]; 4];
    let ulps = libm::ldexp(1.0, 11 - levels as i32);
    let h4 = h_sub * h_sub * h_sub * h_sub / 384.0;
    let row_times = |v: &[f64; NA], m: &MatN<NA>| -> [f64; NA] { core::array::from_fn(|c| (0..NA).map(|r| v[r] * m[r][c]).sum::<f64>()) };
    for regime in Regime::ALL {
        if stribeck && regime != Regime::Stick {
            continue;
        }
        let a = &sys.a[regime.index()];
        let step = linalg::expm_minus_identity(&linalg::scale(a, h_sub / CREST_SAMPLES as f64));
        let step: MatN<NA> = core::array::from_fn(|r| core::array::from_fn(|c| step[r][c] + if r == c { 1.0 } else { 0.0 }));
        let slots: &[usize] = if regime == Regime::Stick { &[0, 1] } else { &[guard_slot(regime, 0)] };
        for &k in slots {
            let g: [f64; NA] = match k {
                0 => core::array::from_fn(|c| sys.r_freq[c] - sys.mu_s * sys.r_n[c]),
                1 => core::array::from_fn(|c| -sys.r_freq[c] - sys.mu_s * sys.r_n[c]),
                2 => sys.r_v,
                _ => core::array::from_fn(|c| -sys.r_v[c]),
            };
            let mut v = g;
            for _ in 0..4 {
                v = row_times(&v, a);
            }
            // E(t) at the samples, from E(0) = I
            let mut e: MatN<NA> = linalg::identity::<NA>();
            let mut sup_v = [0.0f64; NA];
            let mut sup_f = [[0.0f64; NA]; NA];
            for i in 0..=CREST_SAMPLES {
                if i > 0 {
                    e = linalg::mul(&e, &step);
                }
                let ve = row_times(&v, &e);
                for c in 0..NA {
                    sup_v[c] = sup_v[c].max(libm::fabs(ve[c]));
                    for r in 0..NA {
                        let f = e[r][c] - if r == c { 1.0 } else { 0.0 };
                        sup_f[r][c] = sup_f[r][c].max(libm::fabs(f));
                    }
                }
            }
            for c in 0..NA {
                let flow: f64 = (0..NA).map(|r| libm::fabs(g[r]) * sup_f[r][c]).sum();
                w[k][c] = 2.0 * sup_v[c] * h4 + ulps * (libm::fabs(g[c]) + flow);
            }
        }
    }
    w
}
