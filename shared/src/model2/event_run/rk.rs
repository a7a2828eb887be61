//! The Dormand-Prince 5(4) pair (Dormand and Prince 1980; Hairer, Norsett and Wanner,
//! "Solving ODEs I", II.5): seven stages, the fifth-order solution advanced (local
//! extrapolation), the fourth-order one for the error estimate, the last stage the next step's
//! first (FSAL). Written here from the published tableau, apart from the host's DOP853
//! reference (host/src/numerics/reference/), which stays independent of the code under test.


const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;

const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
/// The fifth-order weights (also the seventh stage's row).
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
/// Fifth- less fourth-order weights.
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;

/// The abscissae c_2..c_5 (c_6 = c_7 = 1), for the tests.
pub const NODES: [f64; 4] = [C2, C3, C4, C5];

/// One step of length `h` [s] from `z` with slope `k1` = f(z): the fifth-order state, its
/// slope f(z1) (the next step's first stage) and the error estimate (fifth less fourth order).
/// Any state size N (model 2's NS; the pneumatic drive's runner, model 3, adds its own).
#[inline]
pub fn step<const N: usize>(f: &mut impl FnMut(&[f64; N]) -> [f64; N], z: &[f64; N], k1: &[f64; N], h: f64) -> ([f64; N], [f64; N], [f64; N]) {
    let comb = |w: &[(f64, &[f64; N])]| -> [f64; N] {
        core::array::from_fn(|i| {
            let mut s = 0.0;
            for (a, k) in w {
                s += a * k[i];
            }
            z[i] + h * s
        })
    };
    let k2 = f(&comb(&[(A21, k1)]));
    let k3 = f(&comb(&[(A31, k1), (A32, &k2)]));
    let k4 = f(&comb(&[(A41, k1), (A42, &k2), (A43, &k3)]));
    let k5 = f(&comb(&[(A51, k1), (A52, &k2), (A53, &k3), (A54, &k4)]));
    let k6 = f(&comb(&[(A61, k1), (A62, &k2), (A63, &k3), (A64, &k4), (A65, &k5)]));
    let z1 = comb(&[(B1, k1), (B3, &k3), (B4, &k4), (B5, &k5), (B6, &k6)]);
    let k7 = f(&z1);
    let err: [f64; N] =
        core::array::from_fn(|i| h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]));
    (z1, k7, err)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model2::system::NS;

    #[test]
    fn the_tableau_is_consistent() {
        let rows: [&[f64]; 5] = [&[A21], &[A31, A32], &[A41, A42, A43], &[A51, A52, A53, A54], &[A61, A62, A63, A64, A65]];
        let c = [C2, C3, C4, C5, 1.0];
        for (r, ci) in rows.iter().zip(c) {
            assert!((r.iter().sum::<f64>() - ci).abs() < 1e-14);
        }
        assert!((B1 + B3 + B4 + B5 + B6 - 1.0).abs() < 1e-14);
        assert!((E1 + E3 + E4 + E5 + E6 + E7).abs() < 1e-15);
    }

    /// x'' = -x from (1, 0): the global error at t = 1 falls as h^5.
    #[test]
    fn the_pair_is_fifth_order() {
        let err_at = |n: usize| {
            let h = 1.0 / n as f64;
            let mut f = |z: &[f64; NS]| -> [f64; NS] { core::array::from_fn(|i| match i { 0 => z[1], 1 => -z[0], _ => 0.0 }) };
            let mut z = [0.0; NS];
            z[0] = 1.0;
            let mut k = f(&z);
            for _ in 0..n {
                let (z1, k1, _) = step(&mut f, &z, &k, h);
                z = z1;
                k = k1;
            }
            (z[0] - 1f64.cos()).abs()
        };
        let ratio = err_at(8) / err_at(16);
        assert!(ratio > 25.0 && ratio < 45.0, "ratio {ratio}");
    }
}
