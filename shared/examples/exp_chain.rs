//! The latency of f64 exponentials, as a wide slip chunk meets them (each one's argument
//! depends on the one before): 2e7 dependent calls of `libm::exp`, `exp64::exp` (libm's bits,
//! inlined) and `exp64::exp_fast` (the maps' wide chunks), the best of three rounds, in ns a
//! call (the chain's multiply-add included). A benchmark, not a test: it asserts nothing.
//!
//! `cargo run --release -p stickslip-model --example exp_chain`

use std::hint::black_box;
use std::time::Instant;

fn chain(name: &str, f: impl Fn(f64) -> f64) {
    const N: u32 = 20_000_000;
    let mut best = f64::INFINITY;
    let mut x = 0.0;
    for _ in 0..3 {
        let t = Instant::now();
        x = black_box(-0.3f64);
        for _ in 0..N {
            x = -0.2 - 0.5 * f(x);
        }
        best = best.min(t.elapsed().as_secs_f64() * 1e9 / N as f64);
    }
    println!("{name:<16} {best:6.2} ns a dependent call (x = {x})");
}

fn main() {
    chain("libm::exp", libm::exp);
    chain("exp64::exp", stickslip_model::exp64::exp);
    chain("exp64::exp_fast", stickslip_model::exp64::exp_fast);
}
