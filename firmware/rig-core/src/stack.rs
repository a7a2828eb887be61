//! The stack's high-water mark: painted at boot, measured after the set-up (the firmware logs
//! it in the `start` record; the on-target programs print it after each case). The stack
//! region is [`_stack_end`, `_stack_start`) from the linker: linked by flip-link (the firmware
//! and the on-target programs), that is the bottom of RAM up to the statics, and an overflow
//! faults at the start of RAM (firmware/README.md, "Stack"); with cortex-m-rt's own layout it
//! is the top of RAM down to the end of the statics, unguarded.

/// Stack paint: cortex-m-rt's `STACK_PAINT_VALUE`, with which its feature `paint-stack` paints
/// [`_stack_end`, `_stack_start`) at reset (the firmware enables it and asserts the two equal).
pub const PAINT: u32 = 0xcccc_cccc;

extern "C" {
    /// The lowest address the stack may grow to (cortex-m-rt's link.x: the end of the statics;
    /// flip-link: the start of RAM).
    static mut _stack_end: u32;
    /// Initial stack pointer (cortex-m-rt: the top of RAM; flip-link: just below the statics).
    static _stack_start: u32;
}

/// Fills the free stack below the current stack pointer (less a margin) with [`PAINT`] again:
/// for a high-water mark of what follows (the on-target programs, per case). The firmware needs
/// none: cortex-m-rt painted the whole stack at reset.
pub fn paint() {
    let bottom = core::ptr::addr_of_mut!(_stack_end);
    let sp = cortex_m::register::msp::read() as usize - 512;
    let mut p = bottom;
    while (p as usize) < sp {
        // SAFETY: [_stack_end, sp - 512) is RAM that nothing uses: no heap, and the stack has not
        // grown that far.
        unsafe {
            p.write_volatile(PAINT);
            p = p.add(1);
        }
    }
}

/// Bytes of stack used since [`paint`], and the stack's size (`_stack_start` - `_stack_end`).
pub fn used() -> (u32, u32) {
    let bottom = core::ptr::addr_of_mut!(_stack_end);
    let top = core::ptr::addr_of!(_stack_start) as usize;
    let mut p = bottom;
    // SAFETY: reads of RAM words between the end of the statics and the top of the stack.
    unsafe {
        while (p as usize) < top && p.read_volatile() == PAINT {
            p = p.add(1);
        }
    }
    ((top - p as usize) as u32, (top - bottom as usize) as u32)
}
