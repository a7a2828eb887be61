//! The exponential time differencing of Stribeck slip: ETDRK4 (Cox-Matthews) chunks about
//! the kinetic operator or a near operator A + b g_k, the choice of that operator, and the
//! level of each chunk from the falling slope's rate (see the module documentation of
//! [`super`]).

use super::*;

impl<T: Real, C: Composition> Model2Tables<T, C> {
    /// The flow over 2^j units in `regime` from `z` (exact in linear regimes; ETDRK4 in
    /// Stribeck slip, which needs j >= 1).
    pub(super) fn chunk(&self, regime: Regime, j: usize, z: &[T; NS]) -> [T; NS] {
        if Self::is_stribeck_slip(regime) {
            self.chunk_from(regime, j, z, &self.excess(z))
        } else {
            self.linear_chunk(regime, j, z)
        }
    }

    /// [`Self::chunk`] in a linear regime (stick; Coulomb slip): the exact flow. Inlined where
    /// the regime is known to be linear (the short path), so that the chunk's state stays in
    /// registers rather than going out and back through memory.
    #[inline(always)]
    pub(super) fn linear_chunk(&self, regime: Regime, j: usize, z: &[T; NS]) -> [T; NS] {
        let d = self.flow_increment(regime, j, z);
        core::array::from_fn(|r| z[r] + d[r])
    }

    /// The lowest level a chunk can take a near operator at (it reads levels j - 1 and j).
    pub(super) const NEAR_MIN_LEVEL: usize = T::DYADIC_LEVELS + 2 - NEAR_LEVELS;

    /// The operator a Stribeck slip chunk of 2^j units starting at the falling part `ex`
    /// takes: k = 0, the kinetic one, where the falling slope's rate fits the chunk
    /// (rate x chunk <= 1/4, see `chunk_level`) or no near operator exists; otherwise a near
    /// one, k = 1 .. NEAR_OPS, the one whose slope c_k N_0 / v_s is nearest the friction's,
    /// N e / v_s (delta = 1), so that the forcing's residual slope |N e - c_k N_0| / v_s is at
    /// most N_0 / (2 NEAR_OPS v_s) (for N e <= (1 + 1 / (2 NEAR_OPS)) N_0). The kinetic one is
    /// preferred because its flows are block-sparse in slip (cheaper on the M4F). Near operators
    /// exist on the top levels only; below, a chunk is short enough for the kinetic one.
    #[inline(always)]
    pub(super) fn near_op(&self, ex: &Excess<T>, j: usize) -> usize {
        let mut k = 0;
        if self.near_on && j >= Self::NEAR_MIN_LEVEL {
            let ne = ex.n * ex.e;
            if self.rate_coef * ne.abs() > self.rate_limit.as_ref()[j] {
                while k < NEAR_OPS && ne > self.near_thr[k] {
                    k += 1;
                }
            }
        }
        k
    }

    /// The forcing of near operator k's split: q - g_k (z, 1)
    /// = sigma (mu_s - mu_k) N (e - c_k) - c_k (mu_s - mu_k) N_0 v / v_s (the sign on the
    /// constant, exactly, as in `q_of`).
    #[inline(always)]
    pub(super) fn q_near(&self, sigma: T, ex: &Excess<T>, k: usize) -> T {
        (sigma * self.d_mu) * (ex.e - self.near_c[k]) * ex.n - self.near_ckv[k] * ex.v
    }

    /// ETDRK4 (Cox-Matthews) over 2^j units of Stribeck slip from `z`, with the falling part
    /// `ex0` at `z`: about the kinetic operator A with forcing q, or near v = 0
    /// ([`Self::near_op`]) about A + b g_k with forcing q - g_k (z, 1). Both are z' = A z + b q;
    /// the split decides how much of the falling slope the exponential carries exactly.
    #[inline(always)]
    pub(super) fn chunk_from(&self, regime: Regime, j: usize, z: &[T; NS], ex0: &Excess<T>) -> [T; NS] {
        self.chunk_with(regime, j, z, ex0, self.near_op(ex0, j))
    }

    /// [`Self::chunk_from`] with its operator k (0 kinetic, else near) already chosen.
    pub(super) fn chunk_with(&self, regime: Regime, j: usize, z: &[T; NS], ex0: &Excess<T>, k: usize) -> [T; NS] {
        if k > 0 {
            self.etd_chunk::<true>(regime, j, z, ex0, k)
        } else {
            self.etd_chunk::<false>(regime, j, z, ex0, 0)
        }
    }

    /// The forcing of an ETDRK4 chunk: q, or with near operator k its residual.
    #[inline(always)]
    pub(super) fn etd_q<const NEAR: bool>(&self, sigma: T, ex: &Excess<T>, k: usize) -> T {
        if NEAR {
            self.q_near(sigma, ex, k)
        } else {
            self.q_of(sigma, ex)
        }
    }

    /// The flow increment over 2^j units of a chunk's operator (a near operator's flows are on
    /// levels L - NEAR_LEVELS + 1 ..= L - 1).
    #[inline(always)]
    pub(super) fn etd_inc<const NEAR: bool>(&self, regime: Regime, j: usize, z: &[T; NS], near_index: usize) -> [T; NS] {
        if NEAR {
            let top = T::DYADIC_LEVELS + 1 - NEAR_LEVELS;
            increment::<T, C>(&self.near_flows.as_ref()[near_index * NEAR_FLOW_LEVELS + j - top], z)
        } else {
            self.flow_increment(regime, j, z)
        }
    }

    #[inline(always)]
    pub(super) fn etd_chunk<const NEAR: bool>(&self, regime: Regime, j: usize, z: &[T; NS], ex0: &Excess<T>, k: usize) -> [T; NS] {
        let rows = C::ROWS;
        let sigma = T::from_f64(regime.friction_sign());
        let near_index = (k.max(1) - 1) * 2 + regime.index() - 1;
        let top = T::DYADIC_LEVELS + 1 - NEAR_LEVELS;
        let (ph, w) = if NEAR {
            let etd = &self.near_etd.as_ref()[near_index * NEAR_LEVELS..(near_index + 1) * NEAR_LEVELS];
            (&etd[j - 1 - top].phi1, &etd[j - top])
        } else {
            let etd = self.etd.as_ref()[regime.index() - 1].as_ref();
            (&etd[j - 1].phi1, &etd[j])
        };
        // (methods, not closures: a closure here was compiled out of line on the M4F, three calls
        // per chunk)
        let q0 = self.etd_q::<NEAR>(sigma, ex0, k);
        let eh = self.etd_inc::<NEAR>(regime, j - 1, z, near_index);
        let da: [T; NS] = core::array::from_fn(|r| if r < rows { eh[r] + ph[r] * q0 } else { T::zero() });
        let a: [T; NS] = core::array::from_fn(|r| z[r] + da[r]);
        let qa = self.etd_q::<NEAR>(sigma, &self.excess(&a), k);
        let bb: [T; NS] = core::array::from_fn(|r| if r < rows { z[r] + (eh[r] + ph[r] * qa) } else { z[r] });
        let qb = self.etd_q::<NEAR>(sigma, &self.excess(&bb), k);
        let ea = self.etd_inc::<NEAR>(regime, j - 1, &a, near_index);
        let two = T::one() + T::one();
        let qcb = two * qb - q0;
        let c: [T; NS] = core::array::from_fn(|r| if r < rows { a[r] + (ea[r] + ph[r] * qcb) } else { z[r] });
        let qc = self.etd_q::<NEAR>(sigma, &self.excess(&c), k);
        let qab = qa + qb;
        // the chunk's linear flow from z, e^(hA) z (affine), is the half flow from a less
        // e^(hA/2) ph q0: w0 carries that term (see `fill_tables`), which saves one flow
        // application. Summed from z, not from a, so that a's rounding stays out of z1.
        core::array::from_fn(|r| {
            if r < rows {
                z[r] + (da[r] + ea[r] + w.w0[r] * q0 + w.wab[r] * qab + w.wc[r] * qc)
            } else {
                z[r]
            }
        })
    }

    /// The smallest level a transition is located to in `regime`.
    pub(super) fn min_level(regime: Regime) -> usize {
        if Self::is_stribeck_slip(regime) {
            1
        } else {
            0
        }
    }

    /// The level of the next chunk with `remaining` units left in the substep: the largest
    /// power of two that fits, limited in Stribeck slip by the friction slope's rate at the
    /// chunk's start (from its falling part `ex`); and the chunk's operator there
    /// ([`Self::near_op`]; 0 outside Stribeck slip).
    pub(super) fn chunk_level(&self, ex: Option<&Excess<T>>, remaining: u64) -> (usize, usize) {
        let mut j = 63 - remaining.leading_zeros() as usize; // largest 2^j <= remaining
        let mut k = 0;
        if let Some(ex) = ex {
            // the falling slope's rate, |dq/dv| (1/m + 1/m_b), in T (no f64 on the M4F's path)
            let y = ex.y;
            let shape = if self.delta_is_one {
                ex.e
            } else if y > T::zero() {
                y.powf(self.delta - T::one()) * ex.e
            } else if self.delta > T::one() {
                T::zero()
            } else {
                let r0 = self.rate_limit.as_ref()[0];
                r0 * r0 // delta < 1: infinite slope at v = 0
            };
            let far = self.rate_coef * shape * ex.n.abs();
            let floor = (Self::LEVELS.saturating_sub(STRIBECK_REFINE)).max(1);
            let limits = self.rate_limit.as_ref();
            loop {
                // with a near operator, the residual slope of its split (delta = 1: shape = e)
                k = self.near_op(ex, j);
                let rate = if k > 0 { self.rate_coef * (ex.n * ex.e - self.near_cn0[k]).abs() } else { far };
                if j > floor && rate > limits[j] {
                    j -= 1;
                } else {
                    break;
                }
            }
            // (j >= floor >= 1 unless fewer than 2 units remain, where k = 0 on either level)
            j = j.max(1);
        }
        (j, k)
    }
}
