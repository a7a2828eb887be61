//! Panic and HardFault: vent the valves first, then report.
//!
//! The panic handler drives both valve pins low ([`valves::force_vent`], one register write),
//! then logs a `panic` record over defmt (file, line, and the message when it is a plain
//! string: formatting arguments would pull `core::fmt` into the image, about 4 KB), and ends
//! in a HardFault (`udf`), where `probe-rs run` prints a backtrace. The HardFault handler
//! vents again and spins: the watchdog, no longer fed, resets the chip within its timeout, and
//! the valves stay vented through the reset (floating pins, pulled down by the drivers) and
//! after it (the firmware starts with both outputs low, the sequencer Idle).
//!
//! With a debug probe attached, `probe-rs` halts the core on entry to the HardFault handler
//! (vector catch), i.e. before that handler runs: a panic has vented already; any other fault
//! (a bus fault, ...) is then vented by the watchdog reset, which keeps running while the core
//! is halted (DBGMCU does not freeze the IWDG unless told to).

use core::panic::PanicInfo;
use core::sync::atomic::{AtomicBool, Ordering};

use cortex_m_rt::{exception, ExceptionFrame};

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

#[exception]
unsafe fn HardFault(_frame: &ExceptionFrame) -> ! {
    valves::force_vent();
    loop {
        cortex_m::asm::nop();
    }
}
