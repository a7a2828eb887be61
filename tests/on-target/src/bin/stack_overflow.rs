//! A stack overflow on the Cortex-M4F ends in the firmware's HardFault entry with both valves
//! vented. Linked like the firmware (flip-link: the stack at the bottom of RAM, below the
//! statics), `main` recurses without bound; the overflow runs off the start of RAM and faults,
//! and the fault's entry is the firmware's own ([`stickslip_safety::hard_fault!`]: the stack
//! pointer reset to the top of the stack region before any Rust code). From there this program
//! vents with the firmware's [`stickslip_safety::force_vent`] (the firmware's
//! [`stickslip_safety::vent_and_wait`] vents, then waits for the watchdog) and prints over
//! semihosting
//!
//!     layout stack_end=0x20000000 stack_start=0x2001.... statics_from=0x2001....
//!     hardfault vent_bsrr=0x30000000 cfsr=0x........ hfsr=0x........ deepest_sp=0x........ depth=N
//!
//! then exits with success. The host test `tests/tests/on_target.rs` runs it with QEMU's log of
//! unimplemented-device writes (`-d unimp`), where the vent is GPIOD's BSRR written with
//! 0x30000000, and checks the fault status: a bus fault on the stack (STKERR, or a precise
//! data bus fault below RAM), escalated to HardFault (FORCED).
#![no_std]
#![no_main]

use core::sync::atomic::{AtomicU32, Ordering};
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use panic_semihosting as _;
use stickslip_safety::{force_vent, VENT_BSRR_WORD};

stickslip_safety::hard_fault!(after_fault);

extern "C" {
    /// Top of the stack region (flip-link: just below the statics).
    static _stack_start: u32;
    /// Bottom of the stack region (flip-link: the start of RAM).
    static _stack_end: u32;
    /// Start of .data, the lowest static (cortex-m-rt).
    static __sdata: u32;
}

/// Lowest stack pointer the recursion reached [address].
static DEEPEST_SP: AtomicU32 = AtomicU32::new(u32::MAX);
/// Recursion depth reached.
static DEPTH: AtomicU32 = AtomicU32::new(0);

/// Configurable Fault Status Register, HardFault Status Register (ARMv7-M System Control
/// Block) [addresses].
const CFSR: *const u32 = 0xE000_ED28 as *const u32;
const HFSR: *const u32 = 0xE000_ED2C as *const u32;

#[entry]
fn main() -> ! {
    let (start, end, sdata) = (
        core::ptr::addr_of!(_stack_start) as u32,
        core::ptr::addr_of!(_stack_end) as u32,
        core::ptr::addr_of!(__sdata) as u32,
    );
    hprintln!("layout stack_end={:#010x} stack_start={:#010x} statics_from={:#010x}", end, start, sdata);
    let r = recurse(0);
    hprintln!("error the recursion returned {}", r);
    debug::exit(debug::EXIT_FAILURE);
    loop {}
}

/// 256 bytes of frame per call, kept live across the call so that it is neither a loop nor a
/// tail call. It never returns: the overflow is the point.
#[inline(never)]
#[allow(unconditional_recursion)]
fn recurse(n: u32) -> u32 {
    let mut frame = [n; 64];
    let sp = cortex_m::register::msp::read();
    DEEPEST_SP.fetch_min(sp, Ordering::Relaxed);
    DEPTH.store(n, Ordering::Relaxed);
    core::hint::black_box(&mut frame);
    recurse(n + 1).wrapping_add(frame[(n % 64) as usize])
}

/// After the firmware's fault entry (stack pointer reset): vent as the firmware does, report.
extern "C" fn after_fault() -> ! {
    force_vent();
    // SAFETY: reads of the System Control Block's fault status registers.
    let (cfsr, hfsr) = unsafe { (core::ptr::read_volatile(CFSR), core::ptr::read_volatile(HFSR)) };
    hprintln!(
        "hardfault vent_bsrr={:#010x} cfsr={:#010x} hfsr={:#010x} deepest_sp={:#010x} depth={}",
        VENT_BSRR_WORD,
        cfsr,
        hfsr,
        DEEPEST_SP.load(Ordering::Relaxed),
        DEPTH.load(Ordering::Relaxed)
    );
    debug::exit(debug::EXIT_SUCCESS);
    loop {}
}
