//! What keeps the rig safe without the HAL, shared by the firmware and the on-target test that
//! overflows the stack (tests/on-target, bin `stack_overflow`):
//!
//! - [`force_vent`]: both valve pins low (de-energised: closed and vented) with one write of
//!   GPIOD's bit set/reset register, from any context;
//! - [`hard_fault!`]: the `HardFault` entry. It first points the main stack pointer at the top
//!   of the stack region (`_stack_start`) and only then runs Rust code, so it works when the
//!   fault *is* the stack: the firmware links with flip-link (knurling), which puts the stack
//!   at the bottom of RAM, below the statics, so that an overflow runs off the start of RAM
//!   into unmapped memory and faults (a bus fault, escalated to HardFault) instead of
//!   overwriting the statics. The fault's own exception frame cannot be pushed there either,
//!   so the handler is entered with the stack pointer below RAM: any push in a Rust prologue
//!   would fault again, in HardFault, and lock the core up.
//!
//! High = solenoid energised = valve open; low = closed and vented: the safe state, also the
//! state of an undriven pin (after reset every pin is a floating input, held off by the
//! driver's gate pull-down; firmware/README.md, wiring).
#![no_std]

/// The valves' GPIO port, by number (A = 0, ...): port D. The firmware's board module holds its
/// typed valve pins to this and to the pin numbers below (a compile-time assertion).
pub const VALVE_PORT_NUMBER: u32 = 3;
/// GPIO port A's base address; the ports follow every 0x400 bytes (STM32F405/407 reference
/// manual, memory map) [address].
pub const GPIOA_BASE: usize = 0x4002_0000;
/// The valves' port's base address: GPIOD, 0x4002_0C00 [address].
pub const GPIOD_BASE: usize = GPIOA_BASE + 0x400 * VALVE_PORT_NUMBER as usize;
/// Offset of a GPIO port's bit set/reset register, BSRR [bytes].
pub const GPIO_BSRR_OFFSET: usize = 0x18;
/// The actuator (clamp) valve's pin on port D: PD12.
pub const ACTUATOR_VALVE_PIN: u32 = 12;
/// The band-drive valve's pin on port D: PD13.
pub const BAND_VALVE_PIN: u32 = 13;
/// The BSRR word that drives both valve pins low: the reset half (bits 16 + n).
pub const VENT_BSRR_WORD: u32 = (1 << (16 + ACTUATOR_VALVE_PIN)) | (1 << (16 + BAND_VALVE_PIN));

/// Drives both valve pins low (vented) with one write of GPIOD's BSRR: no read-modify-write,
/// nothing to lock, no stack, safe in any context (panic and fault handlers, the e-stop). If
/// GPIOD is not clocked or the pins are not yet outputs, the write changes nothing and the
/// pins are floating inputs, which the drivers' pull-downs hold off: vented as well.
#[inline(always)]
pub fn force_vent() {
    // SAFETY: BSRR is write-only and acts only on the bits written; a write to it from any
    // context sets no other pin and reads nothing.
    unsafe { core::ptr::write_volatile((GPIOD_BASE + GPIO_BSRR_OFFSET) as *mut u32, VENT_BSRR_WORD) }
}

/// Defines the program's `HardFault` entry: it loads the main stack pointer with
/// `_stack_start` (the top of the stack region, from the linker: flip-link's, or
/// cortex-m-rt's), then branches to `$after`, an `extern "C" fn() -> !` that runs on that fresh
/// stack. The firmware's `$after` is [`vent_and_wait`]; the on-target test's vents the same
/// way and then reports over semihosting.
///
/// The entry is a naked function: no prologue runs before the stack pointer is valid again.
/// The fault's exception frame (and with it the faulting address) is abandoned: the handler
/// never returns, and the watchdog, no longer fed, resets the chip.
#[macro_export]
macro_rules! hard_fault {
    ($after:path) => {
        #[unsafe(no_mangle)]
        #[unsafe(naked)]
        pub unsafe extern "C" fn HardFault() -> ! {
            core::arch::naked_asm!(
                "movw r0, :lower16:{stack_start}",
                "movt r0, :upper16:{stack_start}",
                "msr msp, r0",
                "isb",
                "b {after}",
                stack_start = sym $crate::_stack_start,
                after = sym $after,
            )
        }
    };
}

extern "C" {
    /// The top of the stack region (cortex-m-rt's link.x; flip-link redefines it below the
    /// statics). Used by [`hard_fault!`] only as an address.
    #[doc(hidden)]
    pub static _stack_start: u32;
}

/// The firmware's fault path after [`hard_fault!`] has reset the stack: vent, then wait for
/// the watchdog's reset (the valves stay vented through it: floating pins, pulled down).
pub extern "C" fn vent_and_wait() -> ! {
    force_vent();
    loop {
        core::hint::spin_loop();
    }
}
