//! Exact flows of the three regimes, tabulated on a dyadic grid of the (sub)step.
//!
//! Within a regime the equations of motion are linear with constant coefficients. With the
//! augmented state z = [x, x', phi, phi', 1]:
//!
//! ```text
//! stick:  x'' = 0 (x' = V)      I phi'' = -K phi - c_phi phi' + F_N a_N + s w (k_g x + c_x x')
//! slip:   m x'' = -k_g x - c_x x' + sigma mu_k c_N phi
//!         I phi'' = -(K - s sigma mu_k w c_N) phi - c_phi phi' + F_N a_N
//! ```
//!
//! with sigma = +1 (pad slower) or -1 (pad faster). Without rotation phi is held at phi_0 and
//! phi' = 0. The flow over tau is expm(A tau), computed once in f64 and rounded to `T`.
//!
//! A substep of length h is split into U = 2^L units (L = `T::DYADIC_LEVELS`); the table holds
//! expm(A h 2^(j-L)) for j = 0..=L. Any whole number of units is reached by at most L products,
//! and a guard crossing is found by binary lifting (one product per level): that is how the
//! exact stepper locates a transition inside a step to 2^-L of the step.

use crate::coefficients::Coefficients;
use crate::linalg::{self, Mat};
use crate::real::Real;
use crate::scene::Scene;
use crate::stickslip::Regime;

/// A flow in increment form, E = expm(A tau) - I restricted to 4 x 5, row-major: rows x, x',
/// phi, phi'; columns x, x', phi, phi', 1. The new state is z + E [z; 1]: storing the
/// increment, not the flow, keeps the short-step flows' (1 - cos) terms at full relative
/// precision in f32.
pub type Flow<T> = [T; 20];

/// Applies a flow (increment form) to a state.
#[inline(always)]
pub fn apply<T: Real>(f: &Flow<T>, z: &[T; 4]) -> [T; 4] {
    let mut out = [T::zero(); 4];
    for (r, o) in out.iter_mut().enumerate() {
        let row = &f[r * 5..r * 5 + 5];
        *o = z[r] + (row[0] * z[0] + row[1] * z[1] + row[2] * z[2] + row[3] * z[3] + row[4]);
    }
    out
}

/// The continuous-time system matrix of a regime (augmented, 5 x 5, f64).
pub fn system_matrix(scene: &Scene, co: &Coefficients, regime: Regime) -> Mat {
    let mut a = [[0.0; 5]; 5];
    a[0][1] = 1.0;
    if scene.rotation {
        a[2][3] = 1.0;
    }
    match regime {
        Regime::Stick => {
            // x'' = 0; phi driven by the friction moment of the required force.
            if scene.rotation {
                a[3][0] = co.s * scene.w * scene.k_g / scene.inertia;
                a[3][1] = co.s * scene.w * scene.c_x / scene.inertia;
                a[3][2] = -co.k_rot / scene.inertia;
                a[3][3] = -scene.c_phi / scene.inertia;
                a[3][4] = scene.f_n * co.a_n / scene.inertia;
            }
        }
        Regime::SlipSlower | Regime::SlipFaster => {
            let sigma = regime.friction_sign();
            let fric = sigma * scene.mu_k * co.c_n; // F_f = fric * phi
            a[1][0] = -scene.k_g / scene.m;
            a[1][1] = -scene.c_x / scene.m;
            if scene.rotation {
                a[1][2] = fric / scene.m;
                let k_eff = co.k_rot - co.s * scene.w * fric;
                a[3][2] = -k_eff / scene.inertia;
                a[3][3] = -scene.c_phi / scene.inertia;
                a[3][4] = scene.f_n * co.a_n / scene.inertia;
            } else {
                a[1][4] = fric * co.phi0 / scene.m;
            }
        }
    }
    a
}

/// Largest |eigenvalue| over the regimes [1/s]: sets how finely a step must be subdivided for
/// every guard and every extremum to be bracketed (one sign change per substep at most).
pub fn fastest_rate(scene: &Scene, co: &Coefficients) -> f64 {
    fn quad_max_root(a: f64, b: f64, c: f64) -> f64 {
        // |roots| of a s^2 + b s + c
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            libm::sqrt(c / a)
        } else {
            let r = libm::sqrt(disc);
            libm::fabs((-b - r) / (2.0 * a)).max(libm::fabs((-b + r) / (2.0 * a)))
        }
    }
    let mut rate = quad_max_root(scene.m, scene.c_x, scene.k_g);
    if scene.rotation {
        for regime in Regime::ALL {
            let k = co.k_rot - co.s * scene.w * regime.friction_sign() * scene.mu_k * co.c_n;
            rate = rate.max(quad_max_root(scene.inertia, scene.c_phi, k));
        }
    }
    rate
}

/// Everything [`Propagator::new`] reads, as bit patterns: the step, the fastest rate (which
/// sets the substeps) and the three regimes' system matrices. Scenes with equal keys have
/// bit-identical propagators (e.g. a map's cells that differ only in mu_s, V, the duration
/// or the window), so a caller may build one and share it ([`Propagator::key`]).
pub type PropagatorKey = [u64; 2 + 3 * 25];

/// Tabulated exact flows of the three regimes for one substep length.
#[derive(Clone, Copy, Debug)]
pub struct Propagator<T: Real> {
    /// tables[regime][j] = flow over 2^j units.
    tables: [T::DyadicTable; 3],
    /// Rows 1 and 3 of A (x'' and phi'' as functions of z) per regime, for extremum search.
    accel: [[[T; 5]; 2]; 3],
    /// Substep length [s] (f64: times are kept in f64 outside the dynamics).
    pub h_sub: f64,
    /// Substeps per step.
    pub n_sub: u32,
}

impl<T: Real> Propagator<T> {
    pub const LEVELS: usize = T::DYADIC_LEVELS;
    /// Units per substep, 2^LEVELS.
    pub const UNITS: u64 = 1u64 << T::DYADIC_LEVELS;

    /// Substeps per step of `dt`: at most a quarter radian of the fastest mode per substep
    /// (1 to 1e6).
    pub fn substeps(scene: &Scene, co: &Coefficients, dt: f64) -> u32 {
        let rate = fastest_rate(scene, co);
        let mut n_sub = libm::ceil(dt * rate / 0.25);
        if !(n_sub >= 1.0) {
            n_sub = 1.0;
        }
        if n_sub > 1e6 {
            n_sub = 1e6;
        }
        n_sub as u32
    }

    /// Builds the tables for a validated scene and step `dt`.
    pub fn new(scene: &Scene, co: &Coefficients, dt: f64) -> Self {
        let n_sub = Self::substeps(scene, co, dt);
        let h_sub = dt / n_sub as f64;
        let mut tables = [T::empty_table(), T::empty_table(), T::empty_table()];
        let mut accel = [[[T::zero(); 5]; 2]; 3];
        for regime in Regime::ALL {
            let a = system_matrix(scene, co, regime);
            let table = tables[regime.index()].as_mut();
            for (j, flow) in table.iter_mut().enumerate() {
                let tau = h_sub * libm::ldexp(1.0, j as i32 - T::DYADIC_LEVELS as i32);
                let e = linalg::expm_minus_identity(&linalg::scale(&a, tau));
                for r in 0..4 {
                    for c in 0..5 {
                        flow[r * 5 + c] = T::from_f64(e[r][c]);
                    }
                }
            }
            for c in 0..5 {
                accel[regime.index()][0][c] = T::from_f64(a[1][c]);
                accel[regime.index()][1][c] = T::from_f64(a[3][c]);
            }
        }
        Propagator { tables, accel, h_sub, n_sub }
    }

    /// The key of the propagator [`Self::new`] builds for `scene` and `dt`: equal keys, equal
    /// tables, bit for bit (the tables are a function of the key's values alone).
    pub fn key(scene: &Scene, co: &Coefficients, dt: f64) -> PropagatorKey {
        let mut k = [0u64; 2 + 3 * 25];
        k[0] = dt.to_bits();
        k[1] = fastest_rate(scene, co).to_bits();
        for regime in Regime::ALL {
            let a = system_matrix(scene, co, regime);
            for r in 0..5 {
                for c in 0..5 {
                    k[2 + regime.index() * 25 + r * 5 + c] = a[r][c].to_bits();
                }
            }
        }
        k
    }

    /// Flow over 2^level units of `regime`.
    #[inline(always)]
    pub fn flow(&self, regime: Regime, level: usize) -> &Flow<T> {
        &self.tables[regime.index()].as_ref()[level]
    }

    /// Flow over one whole substep.
    #[inline(always)]
    pub fn substep_flow(&self, regime: Regime) -> &Flow<T> {
        self.flow(regime, T::DYADIC_LEVELS)
    }

    /// Propagates `z` by `units` units (0 < units <= UNITS) in `regime`.
    pub fn advance(&self, regime: Regime, z: &[T; 4], units: u64) -> [T; 4] {
        let mut out = *z;
        let mut j = T::DYADIC_LEVELS;
        loop {
            if units & (1u64 << j) != 0 {
                out = apply(self.flow(regime, j), &out);
            }
            if j == 0 {
                break;
            }
            j -= 1;
        }
        out
    }

    /// Binary lifting: starting from `z` at unit `from`, the last unit p in [from, to) such
    /// that `holds` is true at every probed point up to p, assuming `holds` is true on a
    /// prefix of (from, to] and false after. Returns p and the state at p. `holds` is never
    /// evaluated at `from` itself.
    pub fn lift(
        &self,
        regime: Regime,
        z: &[T; 4],
        from: u64,
        to: u64,
        mut holds: impl FnMut(&[T; 4]) -> bool,
    ) -> (u64, [T; 4]) {
        let mut pos = from;
        let mut cur = *z;
        let mut j = T::DYADIC_LEVELS;
        loop {
            let step = 1u64 << j;
            if pos + step < to {
                let cand = apply(self.flow(regime, j), &cur);
                if holds(&cand) {
                    pos += step;
                    cur = cand;
                }
            }
            if j == 0 {
                break;
            }
            j -= 1;
        }
        (pos, cur)
    }

    /// The row of x'' in `regime`: x'' = r . [z; 1] ([`Self::accelerations`]'s first value).
    #[inline(always)]
    pub fn accel_row(&self, regime: Regime) -> [T; 5] {
        self.accel[regime.index()][0]
    }

    /// x'' and phi'' at state `z` in `regime`.
    #[inline(always)]
    pub fn accelerations(&self, regime: Regime, z: &[T; 4]) -> (T, T) {
        let r = &self.accel[regime.index()];
        let d = |c: &[T; 5]| c[0] * z[0] + c[1] * z[1] + c[2] * z[2] + c[3] * z[3] + c[4];
        (d(&r[0]), d(&r[1]))
    }
}
