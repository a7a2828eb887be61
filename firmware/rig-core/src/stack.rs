//! The stack's high-water mark: painted at boot, measured after the set-up (the firmware logs
//! it in the `start` record; the on-target programs print it after each case). cortex-m-rt puts the stack at the top of RAM, growing down toward the end
//! of the statics (`__sheap`); nothing guards that end, so the figure is worth watching.

/// Stack paint.
const PAINT: u32 = 0xdead_beef;

extern "C" {
    /// End of .bss/.uninit: the lowest address the stack may grow to (cortex-m-rt).
    static mut __sheap: u32;
    /// Initial stack pointer, the top of RAM (cortex-m-rt).
    static _stack_start: u32;
}

/// Fills the free stack below the current stack pointer (less a margin) with [`PAINT`]. Call
/// once, first thing in `main`.
pub fn paint() {
    let bottom = core::ptr::addr_of_mut!(__sheap);
    let sp = cortex_m::register::msp::read() as usize - 512;
    let mut p = bottom;
    while (p as usize) < sp {
        // SAFETY: [__sheap, sp - 512) is RAM that nothing uses: no heap, and the stack has not
        // grown that far.
        unsafe {
            p.write_volatile(PAINT);
            p = p.add(1);
        }
    }
}

/// Bytes of stack used since [`paint`], and the stack's size (top of RAM to `__sheap`).
pub fn used() -> (u32, u32) {
    let bottom = core::ptr::addr_of_mut!(__sheap);
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
