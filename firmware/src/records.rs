//! The firmware's log: the records of `stickslip_rig_core::logbook` (what each holds) written
//! with defmt over RTT by `stickslip_records` (their text: the contract with the
//! host's `decode` command, listed in README.md, "Log records"). The same code writes them in
//! the on-target program `tests/on-target/src/bin/records.rs`, whose stream CI decodes.
//!
//! Here: what only the chip has, the reset cause from RCC_CSR.

pub use stickslip_rig_core::logbook::{Boot, Logbook, Record, ResetCause};
pub use stickslip_records::{log, Defmt};

/// Reads the reset flags and clears them (RMVF), most specific first: a watchdog reset also
/// sets the pin flag (the reset drives NRST).
pub fn read_reset_cause() -> ResetCause {
    let rcc = embassy_stm32::pac::RCC;
    let csr = rcc.csr().read();
    let cause = if csr.wdgrstf() {
        ResetCause::Watchdog
    } else if csr.wwdgrstf() {
        ResetCause::WindowWatchdog
    } else if csr.lpwrrstf() {
        ResetCause::LowPower
    } else if csr.sftrstf() {
        ResetCause::Software
    } else if csr.porrstf() {
        ResetCause::PowerOn
    } else if csr.borrstf() {
        ResetCause::BrownOut
    } else if csr.padrstf() {
        ResetCause::Pin
    } else {
        ResetCause::Unknown
    };
    rcc.csr().modify(|w| w.set_rmvf(true));
    cause
}
