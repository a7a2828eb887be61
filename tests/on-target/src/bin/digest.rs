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
use stickslip_model::digest::DigestBits;
use stickslip_model::Real;
use stickslip_on_target::scenes::{self, Report, CASES};

/// Stack paint for the high-water mark.
const PAINT: u32 = 0xdead_beef;

extern "C" {
    /// End of .bss/.uninit: the lowest address the stack may grow to (cortex-m-rt).
    static mut __sheap: u32;
    /// Initial stack pointer, the top of RAM (cortex-m-rt).
    static _stack_start: u32;
}

/// Fills the free stack below the current stack pointer (less a margin) with [`PAINT`].
fn paint_stack() {
    let bottom = core::ptr::addr_of_mut!(__sheap);
    let sp = cortex_m::register::msp::read() as usize - 256;
    let mut p = bottom;
    while (p as usize) < sp {
        // SAFETY: [__sheap, sp - 256) is RAM that nothing uses yet: cortex-m-rt puts no data
        // there and the stack has not grown that far.
        unsafe {
            p.write_volatile(PAINT);
            p = p.add(1);
        }
    }
}

/// Bytes of stack used so far: from the top of RAM to the lowest overwritten paint word.
fn stack_used() -> (usize, usize) {
    let bottom = core::ptr::addr_of_mut!(__sheap);
    let top = core::ptr::addr_of!(_stack_start) as usize;
    let mut p = bottom;
    // SAFETY: reads of RAM words between the end of .bss and the top of the stack.
    unsafe {
        while (p as usize) < top && p.read_volatile() == PAINT {
            p = p.add(1);
        }
    }
    (top - p as usize, top - bottom as usize)
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
    paint_stack();
    let mut ok = true;
    let mut runs = 0;
    for case in CASES {
        ok &= report::<f32>(case.name, &(case.scene)());
        runs += 1;
    }
    let (used, size) = stack_used();
    hprintln!("stack f32 used={} of {}", used, size);
    for case in CASES {
        ok &= report::<f64>(case.name, &(case.scene)());
        runs += 1;
    }
    let (used, size) = stack_used();
    hprintln!("stack f32+f64 used={} of {}", used, size);
    hprintln!("done runs={}", runs);
    debug::exit(if ok { debug::EXIT_SUCCESS } else { debug::EXIT_FAILURE });
    #[allow(clippy::empty_loop)]
    loop {}
}
