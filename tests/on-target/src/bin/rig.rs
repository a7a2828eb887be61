//! Runs every rig case ([`stickslip_on_target::rig_scenes::RIG_CASES`]) on the Cortex-M4F and
//! prints one line per case over semihosting:
//!
//!     rig_digest replay_push_center_noisy 0123456789abcdef frames=12800 windows=4 onsets=N final=3
//!
//! each followed by its stack high-water mark (`stack <case> used=<bytes> of <bytes>`, painted
//! stack), then the stack that building the rig (`stickslip_model::rig::pipeline::Rig`) in a
//! static slot takes, as the firmware does (`stack rig_init used=...`), and
//! `done rig_cases=<n>`, and exits with success (QEMU's exit status). A case whose
//! configuration is refused prints `error <case> <reason>` and the program exits with failure.
//! The host test `tests/tests/on_target.rs` recomputes every line on x86-64.
#![no_std]
#![no_main]

use core::mem::MaybeUninit;
use core::ptr::addr_of_mut;
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use panic_semihosting as _;
use stickslip_on_target::stack;

use stickslip_model::rig::pipeline::{Rig, RigConfig};
use stickslip_on_target::rig_scenes::{self, RigReport, RIG_CASES};

/// The static home of the rig, as in the firmware.
static mut SLOT: MaybeUninit<Rig> = MaybeUninit::uninit();

#[entry]
fn main() -> ! {
    let mut ok = true;
    // Built with `model2` the replay cases do not apply (their digests are the thesis model's)
    // and would hold model-2 rigs on the stack: only the set-up's stack is measured.
    let cases: &[_] = if cfg!(feature = "model2") { &[] } else { &RIG_CASES };
    for case in cases {
        stack::paint();
        match rig_scenes::run(case) {
            Ok(run) => hprintln!("{}", RigReport { case: case.name, run: &run }),
            Err(e) => {
                hprintln!("error {} {}", case.name, e.0);
                ok = false;
            }
        }
        let (used, size) = stack::used();
        hprintln!("stack {} used={} of {}", case.name, used, size);
    }
    // The firmware's set-up: Rig::init into a static slot, as the firmware does.
    stack::paint();
    // SAFETY: the only reference ever made to SLOT; single-threaded program.
    let slot = unsafe { &mut *addr_of_mut!(SLOT) };
    let built = Rig::init(slot, &RigConfig::rig(25_600.0, true, true)).is_ok();
    let (used, size) = stack::used();
    hprintln!(
        "stack rig_init used={} of {} (Rig {} bytes, built={})",
        used,
        size,
        core::mem::size_of::<Rig>(),
        built
    );
    ok &= built;
    hprintln!("done rig_cases={}", cases.len());
    debug::exit(if ok { debug::EXIT_SUCCESS } else { debug::EXIT_FAILURE });
    #[allow(clippy::empty_loop)]
    loop {}
}
