//! e^x in f32 for the Cortex-M4F, small and exact to about one ulp: the model's f32 `Real::exp`
//! (Stribeck slip evaluates it four times per ETDRK4 chunk).
//!
//! Cody-Waite range reduction and the minimax polynomial of Cephes' `expf` (S. L. Moshier):
//!
//! - k = x log2(e) rounded to the nearest integer (ties to even), r = x - k ln 2 with
//!   ln 2 split into C1 + C2 (C1 = 0.693359375 has 9 significant bits, so k C1 is exact for
//!   |k| <= 128): |r| <= ln(2) / 2 up to round-off;
//! - e^r = 1 + r + r^2 P(r), P of degree 5 (Cephes' coefficients);
//! - e^x = 2^k e^r, 2^k built from its exponent bits.
//!
//! Only `+ - *` in f32 and one f32 -> i32 conversion (truncating, as `vcvt.s32.f32`): the same
//! bits on x86-64 and on the Cortex-M4F (rustc forms no fused multiply-add). About 30
//! instructions on the M4F against libm's 62 (`scripts/count-model2.sh`, class `expf_model`);
//! max relative error 1.3e-7 over the Stribeck law's range (`cargo test --release -p
//! stickslip-model --test exp_accuracy -- --nocapture`), docs/numerics.md "Transcendentals on
//! the Cortex-M4F".
//!
//! Range: x > 88.72 gives +inf; x < -87.33 (e^x below f32's smallest normal, 1.18e-38) gives 0
//! (no subnormal results: an absolute error under 1.2e-38); NaN gives NaN; -inf gives 0.

/// log2(e).
const LOG2_E: f32 = core::f32::consts::LOG2_E;
/// 1.5 2^23: adding it rounds an f32 of magnitude below 2^22 to an integer.
const ROUND: f32 = 12_582_912.0;
/// ln 2 = C1 + C2: C1 with 9 significant bits (k C1 exact for |k| <= 128), C2 the rest.
const LN2_C1: f32 = f32::from_bits(0x3F31_8000); // 0.693359375 = 355 / 512
const LN2_C2: f32 = -2.121_944_4e-4;
/// Cephes expf's polynomial: e^r ~ 1 + r + r^2 (P0 r^5 + P1 r^4 + ... + P5), its decimal
/// coefficients rounded to f32 (P5 = 0.50000001201 is 0.5 in f32).
const P0: f32 = 1.987_569_1e-4;
const P1: f32 = 1.398_199_9e-3;
const P2: f32 = 8.333_452e-3;
const P3: f32 = 4.166_579_6e-2;
const P4: f32 = 1.666_666_5e-1;
const P5: f32 = 0.5;
/// Above: e^x overflows f32.
const X_MAX: f32 = 88.722_84;
/// Below: e^x is under f32's smallest normal number (flushed to 0).
const X_MIN: f32 = -87.336_55;

/// e^x in f32 (see the module documentation for the method, the range and the error).
#[inline]
pub fn expf(x: f32) -> f32 {
    if x > X_MAX {
        return f32::INFINITY;
    }
    if x < X_MIN {
        return 0.0;
    }
    // kf: x log2(e) rounded to the nearest integer (ties to even) by adding and taking away
    // 1.5 2^23, where f32's spacing is 1 (|x log2(e)| <= 128.0 here); NaN stays NaN below
    let kf = (x * LOG2_E + ROUND) - ROUND;
    let k = kf as i32;
    let r = (x - kf * LN2_C1) - kf * LN2_C2;
    let r2 = r * r;
    let p = (((((P0 * r + P1) * r + P2) * r + P3) * r + P4) * r + P5) * r2 + r + 1.0;
    // 2^k from its exponent bits: x >= X_MIN gives x log2(e) >= -126.0, so k >= -126 (a
    // normal 2^k); x <= X_MAX gives k <= 128, and 2^128 is out of f32's range: two factors
    if k <= 127 {
        p * f32::from_bits(((k + 127) as u32) << 23)
    } else {
        (p * f32::from_bits(254u32 << 23)) * 2.0
    }
}
