//! Accuracy of the two f32 exponentials over the arguments the Stribeck law uses, exp(-y) for
//! y in [0, 20] (docs/numerics.md, "Transcendentals on the Cortex-M4F"): libm::expf (the
//! model's default) and micromath's `F32Ext::exp` (the feature `micromath`), each against
//! f64 libm::exp of the same f32 argument. `cargo test --release -p stickslip-model --test
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
    println!("exp(-y), y in [0, 20], max relative error against f64 libm::exp:");
    println!("  libm::expf             {libm_err:.3e} (at y = {libm_at})");
    println!("  micromath F32Ext::exp  {mm_err:.3e} (at y = {mm_at})");
    // libm's expf is correctly rounded to within 1 ulp (2^-23 = 1.19e-7 relative)
    assert!(libm_err < 1.2e-7, "libm::expf: {libm_err:e}");
    // micromath's is an approximation: the bound is the measured figure with margin
    assert!(mm_err < 1e-2, "micromath exp: {mm_err:e}");
}
