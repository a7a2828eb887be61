//! The firmware's log on the Cortex-M4F: plays [`records_session`] (a boot refused, the rig's
//! boot, 0.5 s of a record with an overrun, an e-stop and a reset, through the firmware's
//! the rig through `sample_words`, and `Logbook`) and writes every record with the firmware's own defmt formatting
//! (`stickslip_records`) over semihosting: standard output gets the raw defmt stream (rzCOBS
//! frames), nothing else. Exits with success, or with failure after an `error` log line
//! `session_error reason={=str}` when the session could not run.
//!
//! The timestamp is the rig's uptime [us] ([`records_session::uptime_us`]). The host test
//! `tests/tests/records_on_target.rs` decodes the stream with this ELF (`stickslip decode`'s
//! code) and compares every record with the session played on x86-64.
#![no_std]
#![no_main]

use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m_rt::entry;
use cortex_m_semihosting::debug;
use defmt_semihosting as _;
use panic_semihosting as _;
use stickslip_on_target::logbook::{Record, RecordSink};
use stickslip_on_target::records_session::{self, uptime_us, SessionOut};
use stickslip_on_target::stack;

/// The uptime [us] of the records being written (0.5 s fits a u32 many times over; the M4 has
/// no 64-bit atomics).
static UPTIME_US: AtomicU32 = AtomicU32::new(0);

defmt::timestamp!("{=u64:us}", UPTIME_US.load(Ordering::Relaxed) as u64);

/// Writes the records with the firmware's formatting.
struct Semihosting;

impl RecordSink for Semihosting {
    fn record(&mut self, r: &Record<'_>) {
        stickslip_records::log(r);
    }
}

impl SessionOut for Semihosting {
    fn at_frame(&mut self, frames: u64) {
        UPTIME_US.store(uptime_us(frames) as u32, Ordering::Relaxed);
    }
}

#[entry]
fn main() -> ! {
    stack::paint();
    let ok = match records_session::run(&mut Semihosting, stack::used) {
        Ok(_) => true,
        Err(reason) => {
            defmt::error!("session_error reason={=str}", reason);
            false
        }
    };
    debug::exit(if ok { debug::EXIT_SUCCESS } else { debug::EXIT_FAILURE });
    #[allow(clippy::empty_loop)]
    loop {}
}
