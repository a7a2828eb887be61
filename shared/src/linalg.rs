//! 5 x 5 matrices in f64 and their exponential, for the set-up of the exact propagators.
//!
//! The state is augmented with a constant 1, so each regime's affine ODE z' = A z is linear and
//! its exact flow over a time tau is expm(A tau). The exponential uses diagonal balancing by
//! powers of two (exact in floating point), scaling and squaring, and a degree-18 Taylor
//! polynomial on a matrix of 1-norm <= 1/2 (truncation below 1e-22). Only set-up code calls
//! this; the per-step path multiplies by precomputed matrices.

pub const N: usize = 5;
pub type Mat = [[f64; N]; N];
/// An n x n matrix (model 2's augmented systems are 7 x 7, their phi-function blocks 10 x 10).
pub type MatN<const M: usize> = [[f64; M]; M];

pub const IDENTITY: Mat = identity::<N>();

pub const fn identity<const N: usize>() -> MatN<N> {
    let mut m = [[0.0; N]; N];
    let mut i = 0;
    while i < N {
        m[i][i] = 1.0;
        i += 1;
    }
    m
}

pub fn mul<const N: usize>(a: &MatN<N>, b: &MatN<N>) -> MatN<N> {
    let mut c = [[0.0; N]; N];
    for i in 0..N {
        for k in 0..N {
            let aik = a[i][k];
            if aik == 0.0 {
                continue;
            }
            for j in 0..N {
                c[i][j] += aik * b[k][j];
            }
        }
    }
    c
}

pub fn scale<const N: usize>(a: &MatN<N>, s: f64) -> MatN<N> {
    let mut c = *a;
    for row in c.iter_mut() {
        for v in row.iter_mut() {
            *v *= s;
        }
    }
    c
}

fn norm1<const N: usize>(a: &MatN<N>) -> f64 {
    let mut best = 0.0;
    for j in 0..N {
        let mut s = 0.0;
        for row in a.iter() {
            s += libm::fabs(row[j]);
        }
        if s > best {
            best = s;
        }
    }
    best
}

/// Diagonal similarity D^-1 A D with power-of-two entries that evens out row and column norms
/// (Parlett and Reinsch). Returns the balanced matrix and D's diagonal.
#[allow(clippy::needless_range_loop)] // matrix code: indices read as the formulas
fn balance<const N: usize>(a: &MatN<N>) -> (MatN<N>, [f64; N]) {
    let mut b = *a;
    let mut d = [1.0; N];
    for _ in 0..64 {
        let mut changed = false;
        for i in 0..N {
            let mut c = 0.0;
            let mut r = 0.0;
            for j in 0..N {
                if j != i {
                    c += libm::fabs(b[j][i]);
                    r += libm::fabs(b[i][j]);
                }
            }
            // (a row or column that sums to inf or NaN is left as it is: halving inf never ends)
            if c == 0.0 || r == 0.0 || !(c + r).is_finite() {
                continue;
            }
            let mut f = 1.0;
            let s = c + r;
            let (mut cc, mut rr) = (c, r);
            while cc < rr / 2.0 {
                cc *= 2.0;
                rr /= 2.0;
                f *= 2.0;
            }
            while cc >= rr * 2.0 {
                cc /= 2.0;
                rr *= 2.0;
                f /= 2.0;
            }
            if (cc + rr) < 0.95 * s {
                changed = true;
                d[i] *= f;
                for j in 0..N {
                    b[i][j] /= f;
                    b[j][i] *= f;
                }
            }
        }
        if !changed {
            break;
        }
    }
    (b, d)
}

/// expm(A) - I, computed without forming I + (small): every entry keeps its full relative
/// precision even when the flow is close to the identity (a short step). Balancing by powers
/// of two (exact), scaling so the 1-norm is <= 1/2, a degree-18 Taylor polynomial of
/// (expm(B) - I) = B (I + B/2 (I + B/3 (...))), then squaring in the form E <- 2 E + E E.
pub fn expm_minus_identity<const N: usize>(a: &MatN<N>) -> MatN<N> {
    let (b, d) = balance(a);
    let nrm = norm1(&b);
    let mut squarings = 0u32;
    let mut s = 1.0;
    while nrm * s > 0.5 && squarings < 1100 {
        s *= 0.5;
        squarings += 1;
    }
    let bs = scale(&b, s);
    let mut p = identity::<N>();
    for k in (2..=18).rev() {
        p = scale(&mul(&bs, &p), 1.0 / k as f64);
        for (i, row) in p.iter_mut().enumerate() {
            row[i] += 1.0;
        }
    }
    let mut e = mul(&bs, &p);
    for _ in 0..squarings {
        let ee = mul(&e, &e);
        for i in 0..N {
            for j in 0..N {
                e[i][j] = 2.0 * e[i][j] + ee[i][j];
            }
        }
    }
    // undo the balancing: expm(A) - I = D (expm(B) - I) D^-1
    for i in 0..N {
        for j in 0..N {
            e[i][j] *= d[i] / d[j];
        }
    }
    e
}

/// expm(A).
pub fn expm<const N: usize>(a: &MatN<N>) -> MatN<N> {
    let mut e = expm_minus_identity(a);
    for (i, row) in e.iter_mut().enumerate() {
        row[i] += 1.0;
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expm_of_harmonic_oscillator_matches_cos_sin() {
        // x'' = -w^2 x, state [x, v, 0, 0, 1]
        let w: f64 = 2745.0;
        let t: f64 = 3.3e-3;
        let mut a = [[0.0; N]; N];
        a[0][1] = 1.0;
        a[1][0] = -w * w;
        let e = expm(&scale(&a, t));
        let (c, s) = ((w * t).cos(), (w * t).sin());
        let expect = [[c, s / w], [-w * s, c]];
        for i in 0..2 {
            for j in 0..2 {
                let scale = if i == 1 && j == 0 { w } else if i == 0 && j == 1 { 1.0 / w } else { 1.0 };
                assert!((e[i][j] - expect[i][j]).abs() <= 1e-12 * scale, "{i}{j}: {} vs {}", e[i][j], expect[i][j]);
            }
        }
        assert_eq!(e[4][4], 1.0);
    }

    #[test]
    fn expm_of_constant_forcing_is_exact_parabola() {
        // x'' = g, state [x, v, 0, 0, 1]
        let g = 9.81;
        let t = 0.37;
        let mut a = [[0.0; N]; N];
        a[0][1] = 1.0;
        a[1][4] = g;
        let e = expm(&scale(&a, t));
        assert!((e[0][4] - 0.5 * g * t * t).abs() < 1e-15);
        assert!((e[1][4] - g * t).abs() < 1e-15);
        assert!((e[0][1] - t).abs() < 1e-16);
    }
}
