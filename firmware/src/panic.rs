//! Panic and HardFault: vent the valves first, then report.
//!
//! The panic handler drives both valve pins low ([`valves::force_vent`], one register write),
//! then logs a `panic` record over defmt (file, line, and the message when it is a plain
//! string: formatting arguments would pull `core::fmt` into the image, about 4 KB), and ends
//! in a HardFault (`udf`), where `probe-rs run` prints a backtrace. The HardFault entry
//! ([`stickslip_safety::hard_fault!`]) resets the stack pointer to the top of the stack region,
//! vents again and spins ([`stickslip_safety::vent_and_wait`]): the watchdog, no longer fed,
//! resets the chip within its timeout, and the valves stay vented through the reset (floating
//! pins, pulled down by the drivers) and after it (the firmware starts with both outputs low,
//! the sequencer Idle).
//!
//! A stack overflow is such a fault: linked by flip-link, the stack sits at the bottom of RAM,
//! and an overflow runs off the start of RAM into a bus fault instead of into the statics. The
//! fault's frame cannot be pushed either, which is why the entry resets the stack pointer
//! before any Rust code runs (the on-target program `stack_overflow` shows it on the emulated
//! core: tests/tests/on_target.rs).
//!
//! With a debug probe attached, `probe-rs` halts the core on entry to the HardFault handler
//! (vector catch), i.e. before that handler runs: a panic has vented already; any other fault
//! (a bus fault, ...) is then vented by the watchdog reset, which keeps running while the core
//! is halted (DBGMCU does not freeze the IWDG unless told to).

use core::panic::PanicInfo;
use core::sync::atomic::{AtomicBool, Ordering};

use crate::records::{log, Record};
use crate::valves;

/// Set by the first panic: a panic inside the handler (e.g. in the logger) skips the log.
static PANICKED: AtomicBool = AtomicBool::new(false);

#[panic_handler]
fn panic(info: &PanicInfo) -> ! {
    valves::force_vent();
    cortex_m::interrupt::disable();
    if !PANICKED.swap(true, Ordering::AcqRel) {
        let (file, line) = info.location().map_or(("?", 0), |l| (l.file(), l.line()));
        let msg = info.message().as_str().unwrap_or("(formatted message, not shown)");
        log(&Record::Panic { file, line, msg });
    }
    cortex_m::asm::udf()
}

stickslip_safety::hard_fault!(stickslip_safety::vent_and_wait);
