//! Runs every cross-check scene ([`stickslip_on_target::scenes::CASES`]) with the f32 and the
//! f64 exact stepper on the Cortex-M4F and prints one line per run over semihosting:
//!
//!     digest pull_center f32 0123456789abcdef steps=25600 transitions=N
//!
//! (all scenes in f32 first, then in f64), the stack's high-water mark after each half
//! (`stack f32 used=<bytes> of <bytes>`, painted stack) and `done runs=<n>`, and exits
//! with success (QEMU's exit status). A scene the model rejects exits with failure.
//! The host test `tests/tests/on_target.rs` recomputes every digest line on x86-64.
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use panic_semihosting as _;
use stickslip_on_target::stack;
use stickslip_model::digest::DigestBits;
use stickslip_model::Real;
use stickslip_on_target::scenes::{self, Report, CASES};

/// Never inlined, so that the f32 and f64 runs have their own stack frames (and the
/// high-water marks tell them apart).
#[inline(never)]
fn report<T: Real + DigestBits>(name: &str, scene: &stickslip_model::Scene) -> bool {
    match scenes::run::<T>(scene) {
        Ok(run) => {
            hprintln!("{}", Report { scene: name, real: T::NAME, run: &run });
            true
        }
        Err(e) => {
            hprintln!("error {} {}: scene rejected: {}", name, T::NAME, e);
            false
        }
    }
}

#[entry]
fn main() -> ! {
    stack::paint();
    let mut ok = true;
    let mut runs = 0;
    for case in CASES {
        ok &= report::<f32>(case.name, &(case.scene)());
        runs += 1;
    }
    let (used, size) = stack::used();
    hprintln!("stack f32 used={} of {}", used, size);
    for case in CASES {
        ok &= report::<f64>(case.name, &(case.scene)());
        runs += 1;
    }
    let (used, size) = stack::used();
    hprintln!("stack f32+f64 used={} of {}", used, size);
    hprintln!("done runs={}", runs);
    debug::exit(if ok { debug::EXIT_SUCCESS } else { debug::EXIT_FAILURE });
    #[allow(clippy::empty_loop)]
    loop {}
}
