//! The exact flow of a linear regime (stick, Coulomb slip), z' = A (z, 1), as its Taylor
//! series about the step's start: the vectors w_k = A^k (z, 1) are formed once per step, and
//! z, z' and z'' anywhere in the step are polynomials in the time offset s (Horner). The series
//! is summed until its terms are below round-off: the same flow as expm(A s) (z, 1) to
//! rounding, and cheap to evaluate at the many instants a root search asks for.

use crate::model2::system::{Mat9, NA, NS, ONE};

/// Terms kept: w_0 .. w_{TERMS-1} (z'' needs two more than z).
const TERMS: usize = 26;
/// The highest power of s the state's polynomial uses.
const ORDER: usize = TERMS - 3;

/// The Taylor vectors of one step.
pub struct Taylor {
    w: [[f64; NA]; TERMS],
}

impl Taylor {
    pub fn new(a: &Mat9, z: &[f64; NS]) -> Taylor {
        let mut w = [[0.0; NA]; TERMS];
        w[0][..NS].copy_from_slice(z);
        w[0][ONE] = 1.0;
        for k in 1..TERMS {
            let prev = w[k - 1];
            for r in 0..NS {
                let row = &a[r];
                let mut acc = 0.0;
                for c in 0..NA {
                    acc += row[c] * prev[c];
                }
                w[k][r] = acc;
            }
        }
        Taylor { w }
    }

    /// Whether the series has converged to round-off at offsets up to `s` [s]: each entry's
    /// last two terms (of z, z' and z'') below 1e-17 of its largest term.
    pub fn converged(&self, s: f64) -> bool {
        let mut c = [1.0; ORDER + 1];
        for k in 1..=ORDER {
            c[k] = c[k - 1] * s / k as f64;
        }
        for shift in 0..3 {
            for i in 0..NS {
                let mut big: f64 = 0.0;
                for k in 0..=ORDER {
                    big = big.max(libm::fabs(c[k] * self.w[k + shift][i]));
                }
                let tail = libm::fabs(c[ORDER - 1] * self.w[ORDER - 1 + shift][i]) + libm::fabs(c[ORDER] * self.w[ORDER + shift][i]);
                if !(tail <= 1e-17 * big) && tail > 0.0 {
                    return false;
                }
            }
        }
        true
    }

    /// z, z' and z'' at offset `s` [s] from the start.
    pub fn at(&self, s: f64) -> ([f64; NS], [f64; NS], [f64; NS]) {
        let sum = |shift: usize| -> [f64; NS] {
            let mut p = [0.0; NS];
            p.copy_from_slice(&self.w[ORDER + shift][..NS]);
            for k in (0..ORDER).rev() {
                let f = s / (k + 1) as f64;
                for i in 0..NS {
                    p[i] = self.w[k + shift][i] + f * p[i];
                }
            }
            p
        };
        (sum(0), sum(1), sum(2))
    }
}
