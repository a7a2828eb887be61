//! Several steps at a time, for runs that need only statistics (a map's cells, f64 on the
//! host): in Stribeck slip one ETDRK4 chunk over m steps where the sampled path takes m, in
//! stick the exact flow over m steps; the samples at the steps between from the exact linear
//! flow (and in slip a cubic forcing).
//!
//! **The slip chunk.** The same Cox-Matthews ETDRK4 as [`super::etd`] with the kinetic operator,
//! over H = m dt (m even, at most [`WIDE_MAX`]; the scene's substep must be its step):
//! z1 = z + (e^(A H) - I) (z, 1) + u0 q0 + wab (q_a + q_b) + wc q_c. Its tables are the powers
//! of one augmented exponential over dt. The stages a = E z + ph q0, b = E z + ph q_a and
//! c = E a + ph (2 q_b - q0) (E the half chunk's flow, ph = (H/2) phi_1(A H/2) b) enter only
//! through their sliding velocity and normal force, and those are affine in z and the stages'
//! forcings: r . a = r . z + (r (E - I)) . (z, 1) + (r . ph) q0, and so on, with the rows
//! r (E - I) and r (e^(A H) - I) and the scalars r . ph, r . E ph, r . u0, r . wab, r . wc fixed
//! at set-up. So a chunk forms no stage vector: four row products of z, then four exponentials
//! in a chain with a few multiply-adds between them, then z1. The exponentials are
//! [`crate::exp64::exp_fast`]'s (within 1e-15 of libm's; the chunk's own error is 1e-6).
//!
//! **The samples between.** By variation of constants,
//! z(tau) = e^(tau A) (z0, 1) + int_0^tau e^((tau - s) A) b q(s) ds, with q(s) the cubic
//! Hermite interpolant of the forcing's values and rates at the chunk's two ends (q0, q0' at z0;
//! q1, q1' at the chunk's end; q' from z' = A z + b q and the shape's derivative). Its monomial
//! terms are m! tau^(m+1) phi_(m+1)(tau A) b / H^m, so each value a sample needs (the sliding
//! velocity, the contact rows, the normal force, the pad's x'' less its Stribeck term) is a
//! row of e^(tau A) times (z0, 1) plus four weights on (q0, H q0', q1, H q1'), fixed at
//! set-up and stored input by input (`lanes`: a sample is six lanes, two-wide vectors on the
//! host). The pad's x'' there adds b_x q at the interpolated v and N (the cubic q itself, tried,
//! was 18 times further from the sampled path's x''). Before the window's samples only the
//! checked lanes (v and the contact rows) are formed.
//!
//! **When a slip chunk is taken** (else the run steps as the sampled path does): in a slip
//! already armed, where the falling slope's rate times H is at most a quarter at both ends (the
//! sampled path then takes the kinetic operator too: no near operator, no split), where the
//! sliding velocity at every sample of the chunk keeps its sign and stays [`CLEAR`] times its
//! largest change from sample to sample (first plus second differences) away from zero (no
//! velocity match and no crest of the guard between samples, where the sampled path would
//! locate one), where every contact row (the floating pad's springs; a hinged pad's phi) keeps
//! its floor at every sample, and where the chunk's end is in range.
//!
//! **The stick chunk** ([`Model2Tables::wide_stick`]) is exact: the flow over m steps and the
//! rows of the flows over 1 .. m - 1 steps, taken where both breakaway guards stay below zero
//! by [`CLEAR`] times their largest change from sample to sample.
//!
//! The statistics are then those of the same continuous motion to the method's error, which
//! the map's tests measure against the sampled path (`map_wide`).

use super::*;

/// Most steps one wide chunk takes.
pub const WIDE_MAX: usize = 8;

/// A sample's sliding velocity must stay this many times its largest change from sample to
/// sample away from zero.
pub const CLEAR: f64 = 4.0;

/// The largest change of |v| / v_s over a slip chunk of at most 4 steps: the falling part
/// exp(-|v| / v_s) then changes by at most a factor e, and the cubic forcing follows it closely
/// (on the hinged rig set's fast slips, 1 brought the chunks' errors from 1.5e-4 to round-off;
/// 0.25 cost the floating set's map 1.6 times the time for no gain there).
pub const DY_MAX: f64 = 1.0;


/// The lanes of a sample between a chunk's ends: the sliding velocity, phi and the two contact
/// springs' compressions (the floating pad), which the checks read at every sample, then the
/// normal force and the pad's x'' less its Stribeck term, which only a sample kept reads: two
/// and one pairs for the host's two-wide vectors.
const LANES: usize = 6;
const L_V: usize = 0;
/// The contact lanes (phi, y + d_L phi, y + d_T phi) and their floors.
const L_CONTACT: usize = 1;
/// The lanes every sample computes; the last two (N, then x'' less its Stribeck term) only a
/// kept sample computes.
const L_CHECKED: usize = 4;
/// A sample's inputs: (z, 1), then the forcing's end values (q0, H q0', q1, H q1').
const INPUTS: usize = NA + 4;

/// The tables of wide chunks of m steps: for both slips (index: slip regime - 1) and for
/// stick.
#[derive(Clone, Debug)]
pub struct WideChunks {
    m: usize,
    /// H = m dt [s].
    h: f64,
    /// The chunk's flow less the identity, by rows over (z, 1): e^(A H) - I.
    flow: [[[f64; NA]; NS]; 2],
    /// The ETDRK4 weights of the whole chunk on q0, q_a + q_b and q_c (see `etd_chunk`).
    u0: [[f64; NS]; 2],
    wab: [[f64; NS]; 2],
    wc: [[f64; NS]; 2],
    /// The sliding velocity's and the normal force's increments over the half chunk's flow and
    /// the whole chunk's, by rows over (z, 1): r (e^(A H/2) - I) and r (e^(A H) - I) ...
    v_inc: [[[f64; NA]; 2]; 2],
    n_inc: [[[f64; NA]; 2]; 2],
    /// ... and their weights on the stages' forcings: r . (H/2) phi_1(A H/2) b,
    /// r . e^(A H/2) (H/2) phi_1(A H/2) b, and r . u0, r . wab, r . wc.
    v_q: [[f64; 5]; 2],
    n_q: [[f64; 5]; 2],
    /// At step k = 1 .. m - 1 of the chunk, each lane's weights on the inputs, input by
    /// input (a lane's row of e^(k dt A) over (z, 1), then its weights on the forcing's end
    /// values from the variation of constants with the cubic forcing).
    lanes: [[[[f64; LANES]; INPUTS]; WIDE_MAX - 1]; 2],
    /// The rates of v and N: (row A) over (z, 1), and row . b.
    dv: [[f64; NA]; 2],
    dn: [[f64; NA]; 2],
    vb: f64,
    nb: f64,
    /// The falling slope's largest rate the chunk takes: 1/4 / H [1/s].
    rate_max: f64,
    /// The largest change of |v| / v_s the chunk takes ([`DY_MAX`] up to 4 steps; a quarter
    /// beyond, where the truncation error grows as the chunk's length to the fifth).
    dy_max: f64,
    /// The contact rows' floors at the samples (the checks' floors; -inf where unchecked).
    floors: [f64; 3],
    /// Stick: the flow over m steps less the identity, by rows over (z, 1) ...
    stick_flow: [[f64; NA]; NS],
    /// ... and at step k = 1 .. m - 1 the rows [`STICK_ROWS`] times e^(k dt A_stick).
    stick_rows: [[[f64; NA]; STICK_ROWS]; WIDE_MAX - 1],
}

/// The rows a stick sample between a chunk's ends reads: the two breakaway guards, the pad's
/// x'', the sliding velocity, the floating pad's two contact compressions.
const STICK_ROWS: usize = 6;

impl WideChunks {
    /// Steps per chunk.
    pub fn steps(&self) -> usize {
        self.m
    }

    /// A sample's first `L` lanes from its table (`lanes` at one step of one slip) and the
    /// inputs `x`: a lane-wide product, input by input.
    #[inline(always)]
    fn lanes_at<const L: usize>(lanes: &[[f64; LANES]; INPUTS], x: &[f64; INPUTS]) -> [f64; L] {
        let mut acc = [0.0f64; L];
        for (col, xc) in lanes.iter().zip(x) {
            for (a, w) in acc.iter_mut().zip(col) {
                *a += w * xc;
            }
        }
        acc
    }
}

/// A wide chunk's samples at its m step ends: the pad's x'' [m/s^2] and the sliding velocity
/// [m/s].
#[derive(Clone, Copy, Debug)]
pub struct WideSamples {
    pub pad_acc: [f64; WIDE_MAX],
    pub v: [f64; WIDE_MAX],
}

impl Default for WideSamples {
    fn default() -> Self {
        WideSamples { pad_acc: [0.0; WIDE_MAX], v: [0.0; WIDE_MAX] }
    }
}

#[inline(always)]
fn dot9(r: &[f64; NA], z: &[f64; NS]) -> f64 {
    row_dot_all(r, z)
}

/// Row `r` of a flow `p` (over (z, 1) in its first NA columns) less the identity: the flow's
/// increment, by rows over (z, 1).
fn less_identity<const N: usize>(p: &MatN<N>, r: usize) -> [f64; NA] {
    core::array::from_fn(|c| p[r][c] - if r == c { 1.0 } else { 0.0 })
}

impl<C: Composition> Model2Tables<f64, C> {
    /// The tables of wide chunks of `m` steps for `scene` (the scene these tables were built
    /// for), in slip and in stick, or `None` where the scene takes none: Coulomb friction, an exponent other than 1,
    /// more than one substep per step, or `m` odd or outside 2 ..= [`WIDE_MAX`].
    #[allow(clippy::needless_range_loop)] // matrix code: indices read as the formulas
    pub fn wide_chunks(&self, scene: &Scene, m: usize) -> Option<WideChunks> {
        if !C::STRIBECK || !self.delta_is_one || self.n_sub != 1 || !(2..=WIDE_MAX).contains(&m) || m % 2 != 0 {
            return None;
        }
        let co = Coefficients::of(scene);
        let sys = if C::FLOAT { System::floating_pad(scene, &co) } else { System::hinged(scene, &co) };
        let dt = self.dt;
        let h = m as f64 * dt;
        const M: usize = NA + 4;
        let mut w = WideChunks {
            m,
            h,
            flow: [[[0.0; NA]; NS]; 2],
            u0: [[0.0; NS]; 2],
            wab: [[0.0; NS]; 2],
            wc: [[0.0; NS]; 2],
            v_inc: [[[0.0; NA]; 2]; 2],
            n_inc: [[[0.0; NA]; 2]; 2],
            v_q: [[0.0; 5]; 2],
            n_q: [[0.0; 5]; 2],
            lanes: [[[[0.0; LANES]; INPUTS]; WIDE_MAX - 1]; 2],
            dv: [[0.0; NA]; 2],
            dn: [[0.0; NA]; 2],
            vb: (0..NA).map(|r| sys.r_v[r] * sys.b[r]).sum(),
            nb: (0..NA).map(|r| sys.r_n[r] * sys.b[r]).sum(),
            rate_max: STRIBECK_RATE_H / h,
            dy_max: if m <= 4 { DY_MAX } else { 0.25 * DY_MAX },
            floors: [f64::NEG_INFINITY; 3],
            stick_flow: [[0.0; NA]; NS],
            stick_rows: [[[0.0; NA]; STICK_ROWS]; WIDE_MAX - 1],
        };
        // the contact rows and their floors, as `check` reads them
        let mut contact = [[0.0f64; NA]; 3];
        if scene.rotation {
            contact[0][2] = 1.0;
            w.floors[0] = self.limits.phi_floor().to_f64();
        }
        if C::FLOAT {
            let [d_l, d_t, floor_l, floor_t, _, _] = self.float_limits;
            contact[1][Y] = 1.0;
            contact[1][2] = d_l;
            contact[2][Y] = 1.0;
            contact[2][2] = d_t;
            w.floors[1] = floor_l;
            w.floors[2] = floor_t;
        }
        for (i, regime) in [Regime::SlipSlower, Regime::SlipFaster].into_iter().enumerate() {
            let a = &sys.a[regime.index()];
            let row_a = |r: &[f64; NA]| -> [f64; NA] { core::array::from_fn(|c| (0..NA).map(|k| r[k] * a[k][c]).sum()) };
            w.dv[i] = row_a(&sys.r_v);
            w.dn[i] = row_a(&sys.r_n);
            let rows: [[f64; NA]; LANES] = [sys.r_v, contact[0], contact[1], contact[2], sys.r_n, a[1]];
            // [[A, b, 0, 0, 0], [0, 0, 1, 0, 0], [0, 0, 0, 1, 0], [0, 0, 0, 0, 1], [0, ...]]: its
            // exponential over tau holds e^(tau A) and, in the columns NA + j, tau^(j+1)
            // phi_(j+1)(tau A) b
            let mut aug: MatN<M> = [[0.0; M]; M];
            for r in 0..NA {
                aug[r][..NA].copy_from_slice(&a[r]);
                aug[r][NA] = sys.b[r];
            }
            for j in 0..3 {
                aug[NA + j][NA + j + 1] = 1.0;
            }
            let mut step = linalg::expm_minus_identity(&linalg::scale(&aug, dt));
            for r in 0..M {
                step[r][r] += 1.0;
            }
            // a row r over (z, 1) times an increment over (z, 1) (rows 0 .. C::ROWS)
            let row_times = |r: &[f64; NA], inc: &[[f64; NA]; NS]| -> [f64; NA] { core::array::from_fn(|c| (0..C::ROWS).map(|k| r[k] * inc[k][c]).sum()) };
            let row_dot = |r: &[f64; NA], u: &[f64; NS]| -> f64 { (0..C::ROWS).map(|k| r[k] * u[k]).sum() };
            let mut p = step;
            let (mut half, mut ph, mut half_term) = ([[0.0f64; NA]; NS], [0.0f64; NS], [0.0f64; NS]);
            for k in 1..=m {
                if k > 1 {
                    p = linalg::mul(&p, &step);
                }
                if k < m {
                    for (q, row) in rows.iter().enumerate() {
                        for c in 0..NA {
                            w.lanes[i][k - 1][c][q] = (0..NA).map(|r| row[r] * p[r][c]).sum();
                        }
                        // m! tau^(m+1) phi_(m+1)(tau A) b / H^m, m = 0 .. 3
                        let g: [f64; 4] = core::array::from_fn(|j| {
                            let fact = [1.0, 1.0, 2.0, 6.0][j];
                            fact * (0..NA).map(|r| row[r] * p[r][NA + j]).sum::<f64>() / libm::pow(h, j as f64)
                        });
                        // the cubic Hermite basis in monomials of s / H
                        let wt = [g[0] - 3.0 * g[2] + 2.0 * g[3], g[1] - 2.0 * g[2] + g[3], 3.0 * g[2] - 2.0 * g[3], g[3] - g[2]];
                        for (j, x) in wt.into_iter().enumerate() {
                            w.lanes[i][k - 1][NA + j][q] = x;
                        }
                    }
                }
                if 2 * k == m {
                    for r in 0..C::ROWS {
                        half[r] = less_identity(&p, r);
                        ph[r] = p[r][NA];
                    }
                    // e^(A H/2) (H/2) phi_1(A H/2) b
                    half_term = core::array::from_fn(|r| if r < C::ROWS { (0..NS).map(|c| p[r][c] * p[c][NA]).sum() } else { 0.0 });
                }
                if k == m {
                    for r in 0..C::ROWS {
                        w.flow[i][r] = less_identity(&p, r);
                        let (c1, c2, c3) = (p[r][NA], p[r][NA + 1] / h, p[r][NA + 2] / (h * h));
                        w.u0[i][r] = c1 - 3.0 * c2 + 4.0 * c3;
                        w.wab[i][r] = 2.0 * c2 - 4.0 * c3;
                        w.wc[i][r] = 4.0 * c3 - c2;
                    }
                }
            }
            let (flow, u0, wab, wc) = (w.flow[i], w.u0[i], w.wab[i], w.wc[i]);
            let inc = |r: &[f64; NA]| [row_times(r, &half), row_times(r, &flow)];
            let q = |r: &[f64; NA]| [row_dot(r, &ph), row_dot(r, &half_term), row_dot(r, &u0), row_dot(r, &wab), row_dot(r, &wc)];
            (w.v_inc[i], w.v_q[i]) = (inc(&sys.r_v), q(&sys.r_v));
            (w.n_inc[i], w.n_q[i]) = (inc(&sys.r_n), q(&sys.r_n));
        }
        // stick: the exact flow's powers
        let a = &sys.a[Regime::Stick.index()];
        let rows: [[f64; NA]; STICK_ROWS] = [self.guards[0], self.guards[1], a[1], sys.r_v, contact[1], contact[2]];
        let mut step = linalg::expm_minus_identity(&linalg::scale(a, dt));
        for r in 0..NA {
            step[r][r] += 1.0;
        }
        let mut p = step;
        for k in 1..=m {
            if k > 1 {
                p = linalg::mul(&p, &step);
            }
            if k < m {
                for (q, row) in rows.iter().enumerate() {
                    w.stick_rows[k - 1][q] = core::array::from_fn(|c| (0..NA).map(|r| row[r] * p[r][c]).sum());
                }
            } else {
                for r in 0..C::ROWS {
                    w.stick_flow[r] = less_identity(&p, r);
                }
            }
        }
        Some(w)
    }

    /// m steps of stick of the run in `s` in one wide chunk, as [`Self::wide_step`]: the exact
    /// flow over m steps, the samples between from the flow's rows, taken where each breakaway
    /// guard stays below zero at every sample by [`CLEAR`] times its largest change from sample
    /// to sample (no breakaway and no crest between samples), the contact rows keep their floors
    /// and the chunk's end is in range. The same motion as the sampled path's to round-off.
    pub fn wide_stick<O: Model2Observer<f64>>(&self, w: &WideChunks, s: &mut Model2State<f64>, obs: &mut O, samples: bool, out: &mut WideSamples) -> bool {
        if O::DERIVATIVES || s.halted.is_some() || s.regime != Regime::Stick {
            return false;
        }
        let m = w.m;
        let z = s.z;
        let mut z1: [f64; NS] = core::array::from_fn(|r| if r < C::ROWS { z[r] + dot9(&w.stick_flow[r], &z) } else { z[r] });
        let (c_lo, c_hi) = if C::FLOAT { (1, 3) } else { (0, 0) };
        let mut clear = true;
        for (g, row) in [(0usize, &self.guards[0]), (1, &self.guards[1])] {
            let (mut prev, mut d_prev) = (dot::<f64, C>(row, &z), f64::NAN);
            let (mut top, mut d1, mut d2) = (prev, 0.0f64, 0.0f64);
            for k in 1..=m {
                let v = if k < m { dot9(&w.stick_rows[k - 1][g], &z) } else { dot::<f64, C>(row, &z1) };
                top = top.max(v);
                let d = v - prev;
                d1 = d1.max(d.abs());
                if d_prev.is_finite() {
                    d2 = d2.max((d - d_prev).abs());
                }
                (prev, d_prev) = (v, d);
            }
            clear &= top < -CLEAR * (d1 + d2);
        }
        if !clear {
            return false;
        }
        for k in 1..m {
            for j in c_lo..c_hi {
                if !(dot9(&w.stick_rows[k - 1][3 + j], &z) >= w.floors[j]) {
                    return false;
                }
            }
        }
        // the stick anchor's x (as `anchor_stick_x` sets it at the end of the chunk's last substep)
        s.subs_done += m as u64 - 1;
        self.anchor_stick_x(s, Regime::Stick, &mut z1, Self::UNITS);
        s.subs_done -= m as u64 - 1;
        if !self.in_range(&z1) {
            return false;
        }
        if samples {
            for k in 1..m {
                out.pad_acc[k - 1] = dot9(&w.stick_rows[k - 1][2], &z);
                out.v[k - 1] = dot9(&w.stick_rows[k - 1][3], &z);
            }
            out.pad_acc[m - 1] = dot::<f64, C>(&self.a[0][1], &z1);
            out.v[m - 1] = self.sliding_velocity(&z1);
        }
        self.take_wide(s, obs, Regime::Stick, m, z, z1, None);
        true
    }

    /// The falling part at `v` [m/s] and `n` [N] with Stribeck exponent 1, its exponential
    /// [`crate::exp64::exp_fast`]'s (within 1e-15 of libm's; the wide chunk's own error is 1e-6).
    #[inline(always)]
    fn falling_part_fast(&self, v: f64, n: f64) -> Excess<f64> {
        let y = v.abs() * self.inv_v_s;
        Excess { v, y, e: crate::exp64::exp_fast(-y), n }
    }

    /// A wide chunk of m steps from `z` to `z1` taken: its one segment to `obs`, and the state
    /// moved on (`head`: the falling part at `z1` in Stribeck slip).
    #[allow(clippy::too_many_arguments)] // a chunk's regime, length, ends and falling part
    fn take_wide<O: Model2Observer<f64>>(&self, s: &mut Model2State<f64>, obs: &mut O, regime: Regime, m: usize, z: [f64; NS], z1: [f64; NS], head: Option<Excess<f64>>) {
        let t0 = s.step as f64 * self.dt;
        let t1 = (s.step + m as u64 - 1) as f64 * self.dt + self.h_sub;
        obs.segment(&Model2Segment { regime, t0, t1, z0: z, z1, zd0: [0.0; NS], zd1: [0.0; NS] });
        s.z = z1;
        s.head = head;
        s.step += m as u64;
        s.subs_done += m as u64;
    }

    /// m steps of the run in `s` in one wide chunk (see the module's documentation), its
    /// samples in `out` (each step end's x'' and v; filled only where `samples`), one segment
    /// to `obs`. Returns false, with `s` untouched, where the chunk is not taken: the run then
    /// steps as the sampled path does.
    pub fn wide_step<O: Model2Observer<f64>>(&self, w: &WideChunks, s: &mut Model2State<f64>, obs: &mut O, samples: bool, out: &mut WideSamples) -> bool {
        let regime = s.regime;
        if O::DERIVATIVES || !C::STRIBECK || s.halted.is_some() || !s.armed || regime == Regime::Stick {
            return false;
        }
        let i = regime.index() - 1;
        let m = w.m;
        let z = s.z;
        let ex0 = match s.head {
            Some(ex) => ex,
            None => self.excess(&z),
        };
        if !(self.rate_coef * (ex0.n * ex0.e).abs() <= w.rate_max) {
            return false;
        }
        let sigma = regime.friction_sign();
        // The stages' v and N are affine in z and the stages' forcings (each stage a flow of z
        // plus phi-weighted forcings): their z parts first, off the chain of exponentials.
        let (vi, ni, vq, nq) = (&w.v_inc[i], &w.n_inc[i], &w.v_q[i], &w.n_q[i]);
        let (v_half, n_half) = (ex0.v + dot9(&vi[0], &z), ex0.n + dot9(&ni[0], &z));
        let (v_full, n_full) = (ex0.v + dot9(&vi[1], &z), ex0.n + dot9(&ni[1], &z));
        // the ETDRK4 stages (as `etd_chunk`): a = E z + ph q0, b = E z + ph q_a,
        // c = E a + ph (2 q_b - q0), with E the half chunk's flow
        let q0 = self.q_of(sigma, &ex0);
        let qa = self.q_of(sigma, &self.falling_part_fast(v_half + vq[0] * q0, n_half + nq[0] * q0));
        let qb = self.q_of(sigma, &self.falling_part_fast(v_half + vq[0] * qa, n_half + nq[0] * qa));
        let qcb = 2.0 * qb - q0;
        let qc = self.q_of(sigma, &self.falling_part_fast(v_full + vq[1] * q0 + vq[0] * qcb, n_full + nq[1] * q0 + nq[0] * qcb));
        let qab = qa + qb;
        let ex1 = self.falling_part_fast(v_full + vq[2] * q0 + vq[3] * qab + vq[4] * qc, n_full + nq[2] * q0 + nq[3] * qab + nq[4] * qc);
        if !(self.rate_coef * (ex1.n * ex1.e).abs() <= w.rate_max) || !(libm::fabs(ex1.v - ex0.v) * self.inv_v_s <= w.dy_max) {
            return false;
        }
        let (flow, u0, wab, wc) = (&w.flow[i], &w.u0[i], &w.wab[i], &w.wc[i]);
        let z1: [f64; NS] = core::array::from_fn(|r| if r < C::ROWS { z[r] + (dot9(&flow[r], &z) + u0[r] * q0 + wab[r] * qab + wc[r] * qc) } else { z[r] });
        // the forcing's rates at the ends: q = sigma d_mu e N, e = exp(-|v| / v_s)
        let q1 = self.q_of(sigma, &ex1);
        let (dv, dn) = (&w.dv[i], &w.dn[i]);
        let rate0 = self.forcing_rate(sigma, &ex0, dot9(dv, &z) + w.vb * q0, dot9(dn, &z) + w.nb * q0);
        let rate1 = self.forcing_rate(sigma, &ex1, dot9(dv, &z1) + w.vb * q1, dot9(dn, &z1) + w.nb * q1);
        let mut x = [0.0f64; INPUTS];
        x[..NS].copy_from_slice(&z);
        x[ONE] = 1.0;
        x[NA..].copy_from_slice(&[q0, w.h * rate0, q1, w.h * rate1]);
        // the contact rows checked at the samples: the floating pad's springs; a hinged pad's phi
        let (c_lo, c_hi) = if C::FLOAT { (1, 3) } else if w.floors[0] > f64::NEG_INFINITY { (0, 1) } else { (0, 0) };
        // the sliding velocity at every sample, its sign kept and clear of zero
        let (mut v_prev, mut d_prev) = (ex0.v, f64::NAN);
        let (mut min_abs, mut d1, mut d2) = (ex0.v.abs(), 0.0f64, 0.0f64);
        let sign = ex0.v.signum();
        let sd = sigma * self.d_mu;
        for k in 1..=m {
            let v = if k < m {
                let lanes = &w.lanes[i][k - 1];
                // all lanes where the sample is kept, else the checked ones only (the rest 0)
                let lane: [f64; LANES] = if samples {
                    WideChunks::lanes_at::<LANES>(lanes, &x)
                } else {
                    let checked = WideChunks::lanes_at::<L_CHECKED>(lanes, &x);
                    core::array::from_fn(|l| if l < L_CHECKED { checked[l] } else { 0.0 })
                };
                for j in c_lo..c_hi {
                    if !(lane[L_CONTACT + j] >= w.floors[j]) {
                        return false;
                    }
                }
                if samples {
                    let (n, acc) = (lane[L_CHECKED], lane[L_CHECKED + 1]);
                    let e = crate::exp64::exp_fast(-(lane[L_V].abs() * self.inv_v_s));
                    out.pad_acc[k - 1] = acc + self.b[1] * (sd * e * n);
                    out.v[k - 1] = lane[L_V];
                }
                lane[L_V]
            } else {
                ex1.v
            };
            if !(v.signum() == sign) {
                return false;
            }
            min_abs = min_abs.min(v.abs());
            let d = v - v_prev;
            d1 = d1.max(d.abs());
            if d_prev.is_finite() {
                d2 = d2.max((d - d_prev).abs());
            }
            (v_prev, d_prev) = (v, d);
        }
        if !(min_abs > CLEAR * (d1 + d2)) {
            return false;
        }
        if !self.in_range(&z1) {
            return false;
        }
        if samples {
            out.pad_acc[m - 1] = dot::<f64, C>(&self.a[regime.index()][1], &z1) + self.b[1] * q1;
            out.v[m - 1] = ex1.v;
        }
        self.take_wide(s, obs, regime, m, z, z1, Some(ex1));
        true
    }
}
