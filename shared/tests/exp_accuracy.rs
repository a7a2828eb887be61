//! Accuracy of the three f32 exponentials over the arguments the Stribeck law uses, exp(-y) for
//! y in [0, 20] (docs/numerics.md, "Transcendentals on the Cortex-M4F"): the model's own
//! `expf::expf` (the default), libm::expf (the feature `libm-exp`) and micromath's
//! `F32Ext::exp` (the feature `micromath`), each against f64 libm::exp of the same f32
//! argument; and the model's over f32's whole range, with its edges. In f64, the maps'
//! `exp64::exp_fast` against libm::exp. `cargo test --release -p stickslip-model --test
//! exp_accuracy -- --nocapture` prints the figures.

/// Max relative error and where, over `n + 1` evenly spaced y in [0, 20] and every f32 in
/// [0, 2^-10] at a stride (the small arguments where a polynomial is most exposed).
fn max_rel(f: impl Fn(f32) -> f32) -> (f64, f32) {
    let mut worst = (0.0f64, 0.0f32);
    let mut take = |y: f32| {
        let x = -y;
        let exact = libm::exp(x as f64);
        let e = ((f(x) as f64 - exact) / exact).abs();
        if e > worst.0 {
            worst = (e, y);
        }
    };
    let n = 2_000_000u32;
    for i in 0..=n {
        take((20.0 * i as f64 / n as f64) as f32);
    }
    let mut bits = 0u32;
    while f32::from_bits(bits) <= 1.0 / 1024.0 {
        take(f32::from_bits(bits));
        bits += 997;
    }
    worst
}

#[test]
fn exp_f32_accuracy_on_the_stribeck_range() {
    let (libm_err, libm_at) = max_rel(libm::expf);
    let (mm_err, mm_at) = max_rel(micromath::F32Ext::exp);
    let (own_err, own_at) = max_rel(stickslip_model::expf::expf);
    println!("exp(-y), y in [0, 20], max relative error against f64 libm::exp:");
    println!("  stickslip_model::expf  {own_err:.3e} (at y = {own_at})");
    println!("  libm::expf             {libm_err:.3e} (at y = {libm_at})");
    println!("  micromath F32Ext::exp  {mm_err:.3e} (at y = {mm_at})");
    // libm's expf is correctly rounded to within 1 ulp (2^-23 = 1.19e-7 relative)
    assert!(libm_err < 1.2e-7, "libm::expf: {libm_err:e}");
    // micromath's is an approximation: the bound is the measured figure with margin
    assert!(mm_err < 1e-2, "micromath exp: {mm_err:e}");
    // the model's: within 1 ulp (Cephes' polynomial, Cody-Waite reduction)
    assert!(own_err < 1.2e-7, "expf::expf: {own_err:e}");
}

/// The model's expf over f32's whole range: every 61st f32 in [-87.3, 88.7] within 1 ulp
/// of f64 libm::exp (relative, or absolute at f32's smallest normal where the result is
/// subnormal), and the edges: overflow to +inf, flush to 0 below the smallest normal, NaN.
#[test]
fn model_expf_over_the_whole_range() {
    use stickslip_model::expf::expf;
    let mut worst = (0.0f64, 0.0f32);
    let mut check = |x: f32| {
        let exact = libm::exp(x as f64);
        let got = expf(x) as f64;
        let err = (got - exact).abs() / exact.max(f32::MIN_POSITIVE as f64);
        if err > worst.0 {
            worst = (err, x);
        }
    };
    for sign in [1u32 << 31, 0] {
        let mut bits = 0u32;
        loop {
            let x = f32::from_bits(sign | bits);
            if !(-87.3..=88.7).contains(&x) {
                break;
            }
            check(x);
            bits += 61;
        }
    }
    println!("expf::expf over [-87.3, 88.7]: max relative error {:.3e} (at x = {})", worst.0, worst.1);
    assert!(worst.0 < 1.2e-7, "expf::expf: {:e} at x = {}", worst.0, worst.1);
    // e^88.72 = 3.39e38 is finite (2^k with k = 128 built in two factors); e^88.73 overflows
    let near_max = expf(88.72);
    assert!(near_max.is_finite() && ((near_max as f64 - libm::exp(88.72f32 as f64)) / libm::exp(88.72f32 as f64)).abs() < 1.2e-7);
    assert_eq!(expf(88.73), f32::INFINITY);
    assert_eq!(expf(f32::INFINITY), f32::INFINITY);
    // below -87.3366 the result would be subnormal: flushed to 0 (absolute error < 1.2e-38)
    assert_eq!(expf(-87.34), 0.0);
    assert_eq!(expf(-1e30), 0.0);
    assert_eq!(expf(f32::NEG_INFINITY), 0.0);
    assert!(expf(f32::NAN).is_nan());
    assert_eq!(expf(0.0), 1.0);
    assert_eq!(expf(-0.0), 1.0);
}

/// The model's f64 exp (`exp64::exp`, libm's algorithm with its common path inlined) gives
/// `libm::exp`'s bits: over every sign and exponent (a stride through the bit patterns), the
/// Stribeck law's arguments densely, and the edges where it hands over to libm.
#[test]
fn the_f64_exp_is_libms_bit_for_bit() {
    use stickslip_model::exp64::exp;
    let check = |x: f64| {
        let (a, b) = (exp(x), libm::exp(x));
        assert!(a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()), "exp({x:e}) = {a:e}, libm {b:e}");
    };
    let mut bits = 0u64;
    while bits < 0x7ff0_0000_0000_0000 {
        check(f64::from_bits(bits));
        check(-f64::from_bits(bits));
        bits += 0x0000_0123_4567_89ab;
    }
    let n = 4_000_000;
    for i in 0..=n {
        check(-50.0 * i as f64 / n as f64);
        check(2.0 * i as f64 / n as f64 - 1.0);
    }
    for edge in [700.0f64, 708.0, 708.3964185322641, 709.782712893384, 745.1332191019411, 0.5 * core::f64::consts::LN_2, 1.5 * core::f64::consts::LN_2, 2f64.powi(-28)] {
        let mut x = edge;
        for _ in 0..1000 {
            check(x);
            check(-x);
            x = f64::from_bits(x.to_bits() - 1);
        }
        let mut x = edge;
        for _ in 0..1000 {
            check(x);
            check(-x);
            x = f64::from_bits(x.to_bits() + 1);
        }
    }
    for x in [0.0, -0.0, f64::INFINITY, f64::NEG_INFINITY, f64::NAN, f64::MIN_POSITIVE, 5e-324, f64::MAX, f64::MIN] {
        check(x);
    }
}

/// The map's fast f64 exponential (`exp64::exp_fast`) against libm's: within 1e-15 relative
/// over the Stribeck law's arguments (every 1e-6 of [-40, 0]), at a stride over [-700, 700],
/// and at the edges (±700 and beyond, NaN, inf: libm's own values).
#[test]
fn exp_fast_within_1e_15() {
    use stickslip_model::exp64::exp_fast;
    let mut worst = (0.0f64, 0.0f64);
    let mut check = |x: f64| {
        let (got, exact) = (exp_fast(x), libm::exp(x));
        let err = ((got - exact) / exact).abs();
        if err > worst.0 {
            worst = (err, x);
        }
    };
    for i in 0..=40_000_000u32 {
        check(-40.0 * i as f64 / 40_000_000.0);
    }
    for i in 0..=1_400_000u32 {
        check(-700.0 + 1e-3 * i as f64 + 1.234e-7);
    }
    for x in [-1e-300, 0.0, 1e-300, 1e-20, -1e-20, 0.5 * core::f64::consts::LN_2, -0.5 * core::f64::consts::LN_2, 699.999, -699.999] {
        check(x);
    }
    println!("exp_fast: max relative error {:.3e} (at x = {})", worst.0, worst.1);
    assert!(worst.0 < 1e-15, "exp_fast: {:.3e} at {}", worst.0, worst.1);
    for x in [700.0, -700.0, 710.0, -745.0, -800.0, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(exp_fast(x).to_bits(), libm::exp(x).to_bits(), "exp_fast({x})");
    }
    assert!(exp_fast(f64::NAN).is_nan());
}
