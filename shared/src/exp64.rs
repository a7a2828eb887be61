//! e^x in f64: libm's `exp` (FreeBSD's e_exp.c, as the `libm` crate ports it), the same
//! operations in the same order, with its common path inlined into the caller. Model 2's f64
//! Stribeck slip evaluates e^x four times per ETDRK4 chunk, and the call, its special-case
//! tests and its out-of-line `scalbn` were a third of that exponential's cost.
//!
//! For |x| < 700 the scaling by 2^k (|k| <= 1010, the result a normal number) is one exact
//! multiplication, which is what `scalbn` does there; everything else (|x| >= 700, NaN, inf)
//! goes to `libm::exp` itself. The bits are libm's for every input (test:
//! `cargo test --release -p stickslip-model --test exp_accuracy`, against `libm::exp`).
//!
//! [`exp_fast`] is not libm's bits: a shorter dependency chain to within 1e-15, for the maps'
//! wide chunks only (`model2::stepper::wide`); every other run and the firmware take [`exp`]
//! (f64) or `expf` (f32).

// libm's constants, by their bits (the decimals of e_exp.c round to these)
const LN2HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000); // 6.93147180369123816490e-01
const LN2LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76); // 1.90821492927058770002e-10
const INVLN2: f64 = f64::from_bits(0x3ff7_1547_652b_82fe); // 1.44269504088896338700e+00
const P1: f64 = f64::from_bits(0x3fc5_5555_5555_553e); // 1.66666666666666019037e-01
const P2: f64 = f64::from_bits(0xbf66_c16c_16be_bd93); // -2.77777777770155933842e-03
const P3: f64 = f64::from_bits(0x3f11_566a_af25_de2c); // 6.61375632143793436117e-05
const P4: f64 = f64::from_bits(0xbebb_bd41_c5d2_6bf1); // -1.65339022054652515390e-06
const P5: f64 = f64::from_bits(0x3e66_3769_72be_a4d0); // 4.13813679705723846039e-08

/// e^x, bit for bit `libm::exp(x)`.
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    let hx = (x.to_bits() >> 32) as u32;
    let sign = (hx >> 31) as usize;
    let hx = hx & 0x7fffffff; // high word of |x|
    if hx >= 0x4085e000 {
        // |x| >= 700 (a result near or beyond f64's range), NaN, inf
        return libm::exp(x);
    }
    // argument reduction: x = k ln 2 + r, r = hi - lo
    let (k, hi, lo, r) = if hx > 0x3fd62e42 {
        // |x| > 0.5 ln 2
        let k = if hx >= 0x3ff0a2b2 {
            // |x| >= 1.5 ln 2. libm's HALF[sign], 0.5 with x's sign, is taken from x's bits (two
            // bit operations beside the product), not loaded at an index from them. The sum is
            // below 1011 in magnitude: converted through i64, whose conversion needs no clamp
            // (an i32 one clamps first, two more operations on the exponential's chain); the
            // same k.
            (INVLN2 * x + 0.5f64.copysign(x)) as i64 as i32
        } else {
            1 - 2 * sign as i32
        };
        let hi = x - k as f64 * LN2HI; // k ln2hi is exact here
        let lo = k as f64 * LN2LO;
        (k, hi, lo, hi - lo)
    } else if hx > 0x3e300000 {
        // |x| > 2^-28
        (0, x, 0.0, x)
    } else {
        return 1.0 + x;
    };
    let xx = r * r;
    let c = r - xx * (P1 + xx * (P2 + xx * (P3 + xx * (P4 + xx * P5))));
    let y = 1.0 + (r * c / (2.0 - c) - lo + hi);
    if k == 0 {
        y
    } else {
        // |k| <= 1010 and y in [0.7, 1.5]: 2^k and y 2^k are normal, the product exact
        y * f64::from_bits(((0x3ff + k) as u64) << 52)
    }
}

/// 1.5 * 2^52: added to a number below 2^51 in magnitude, rounds it to an integer held in the
/// sum's low mantissa bits.
const ROUND_SHIFT: f64 = 6_755_399_441_055_744.0;
/// 1 / n!, n = 0 .. 12.
const INV_FACT: [f64; 13] = [
    1.0,
    1.0,
    0.5,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5040.0,
    1.0 / 40_320.0,
    1.0 / 362_880.0,
    1.0 / 3_628_800.0,
    1.0 / 39_916_800.0,
    1.0 / 479_001_600.0,
];

/// e^x to within 1e-15 relative (measured 6.3e-16: a few ulp), not libm's bits: for the map's
/// wide chunks (`model2::stepper::wide`), whose own error is 1e-6 and whose four exponentials in
/// a chain set the chunk's time. The same reduction x = k ln 2 + r, |r| <= ln 2 / 2, as
/// [`exp`], with k rounded by adding 1.5 * 2^52 and e^r as its Taylor polynomial of degree 12
/// (remainder below 2.4e-16 relative) evaluated by Estrin's scheme: no division, a
/// dependency chain of 6 multiplications and additions after r, where `exp`'s is 12 and a
/// division. 21.9 ns a dependent call against `exp`'s 34.3 on this machine (`cargo run
/// --release -p stickslip-model --example exp_chain`). |x| >= 700, NaN and inf go to
/// `libm::exp`. Test: `cargo test --release -p stickslip-model --test exp_accuracy exp_fast`.
#[inline(always)]
pub fn exp_fast(x: f64) -> f64 {
    if !(x.abs() < 700.0) {
        return libm::exp(x);
    }
    let kd = x * INVLN2 + ROUND_SHIFT;
    // k's two's complement in the low bits (|k| <= 1010)
    let k = kd.to_bits() as i32;
    let kd = kd - ROUND_SHIFT;
    // k ln2hi is exact (ln2hi's low 32 bits are zero)
    let r = (x - kd * LN2HI) - kd * LN2LO;
    let c = &INV_FACT;
    let (r2, r4) = (r * r, (r * r) * (r * r));
    let r8 = r4 * r4;
    let p03 = (c[0] + c[1] * r) + r2 * (c[2] + c[3] * r);
    let p47 = (c[4] + c[5] * r) + r2 * (c[6] + c[7] * r);
    let p812 = (c[8] + c[9] * r) + r2 * (c[10] + c[11] * r) + r4 * c[12];
    let p = (p03 + r4 * p47) + r8 * p812;
    p * f64::from_bits(((k + 0x3ff) as u64) << 52)
}
