//! Runs every cross-check scene ([`stickslip_on_target::scenes::CASES`]) with the f32 and the
//! f64 exact stepper on the Cortex-M4F and prints one line per run over semihosting:
//!
//!     digest pull_center f32 0123456789abcdef steps=25600 transitions=N
//!
//! (all scenes in f32 first, then in f64), the stack's high-water mark after each half
//! (`stack f32 used=<bytes> of <bytes>`, painted stack), then each model-2 composition in f32
//! on the rig set's push_center (`scenes::model2_scene`):
//!
//!     digest2 stribeck+band f32 0123456789abcdef steps=12800 transitions=N
//!
//! and `done runs=<n> model2_runs=<m>`, and exits with success (QEMU's exit status). A scene the model rejects exits with failure.
//! The host test `tests/tests/on_target.rs` recomputes every digest line on x86-64.
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use panic_semihosting as _;
use stickslip_on_target::stack;
use stickslip_model::digest::DigestBits;
use stickslip_model::model2::{Band, Composition, Stribeck, StribeckBand};
use stickslip_model::Real;
use stickslip_on_target::scenes::{self, Report, Report2, CASES};

/// One model-2 composition in f32 (never inlined: its stepper lives in this frame).
#[inline(never)]
fn report2<C: Composition>() -> bool {
    match scenes::run_model2::<f32, C>(&scenes::model2_scene::<C>()) {
        Ok(run) => {
            hprintln!("{}", Report2 { composition: C::NAME, real: "f32", run: &run });
            true
        }
        Err(e) => {
            hprintln!("error {} f32: scene rejected: {}", C::NAME, e);
            false
        }
    }
}

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
    stack::paint();
    ok &= report2::<Band>();
    ok &= report2::<Stribeck>();
    ok &= report2::<StribeckBand>();
    let (used, size) = stack::used();
    hprintln!("stack model2 used={} of {}", used, size);
    hprintln!("done runs={} model2_runs=3", runs);
    debug::exit(if ok { debug::EXIT_SUCCESS } else { debug::EXIT_FAILURE });
    #[allow(clippy::empty_loop)]
    loop {}
}
