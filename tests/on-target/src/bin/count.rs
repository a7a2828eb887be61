//! Instruction counts of single `ExactStepper<f32>::step()` calls on the Cortex-M4F, for
//! `scripts/count-instructions.sh`.
//!
//! Run under `qemu-system-arm -singlestep -d exec,nochain`, every executed instruction is one
//! `Trace` line naming its function. Each measured call sits between a call of
//! [`stickslip_mark_begin`] and one of [`stickslip_mark_end`] (never inlined, opaque to the
//! optimiser); the script counts the trace lines between the two, window by window, in the
//! order the windows ran. Window 0 is empty (the cost of the markers' calling glue, which
//! the script subtracts from the others).
//!
//! The scene is the default (push caliper, beta = 0.040 m, dt = 1/25 600 s). A first pass on a
//! clone of the fresh stepper finds the steps to measure; the second pass replays the same
//! run and measures them:
//! - `stick_no_transition`: the last stick step before the first breakaway;
//! - `stick_to_slip`: the step with the first breakaway;
//! - `slip_no_transition`: the first slip step after it without a transition;
//! - `slip_transition`: the first step that ends that slip (re-stick or reversal).
//!
//! After the run it prints one `window <i> <label> step=<k> <from>-><to> transitions=<n>` line
//! per window (semihosting) and exits with success; with failure if the run does not reach
//! those events within [`MAX_STEPS`].
#![no_std]
#![no_main]

use core::hint::black_box;

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use panic_semihosting as _;
use stickslip_model::{ExactStepper, Regime};
use stickslip_on_target::scenes;

/// The first events of the default scene come well within this many steps (0.1 s).
const MAX_STEPS: u64 = 2_560;

/// Start of a measured window (see the module documentation).
#[inline(never)]
#[no_mangle]
pub extern "C" fn stickslip_mark_begin() {
    cortex_m::asm::nop();
}

/// End of a measured window. Its body differs from [`stickslip_mark_begin`]'s so that the
/// linker cannot fold the two into one address (the trace would then name only one).
#[inline(never)]
#[no_mangle]
pub extern "C" fn stickslip_mark_end() {
    cortex_m::asm::nop();
    cortex_m::asm::nop();
}

#[derive(Clone, Copy)]
struct Probe {
    label: &'static str,
    step: u64,
}

#[derive(Clone, Copy)]
struct Seen {
    from: Regime,
    to: Regime,
    transitions: usize,
}

fn fail(msg: &str) -> ! {
    hprintln!("error {}", msg);
    debug::exit(debug::EXIT_FAILURE);
    #[allow(clippy::empty_loop)]
    loop {}
}

/// Pass 1: the step indices of the four windows, found on a clone.
fn find_probes(mut st: ExactStepper<f32>) -> [Probe; 4] {
    let mut stick_to_slip = None;
    let mut slip_quiet = None;
    let mut slip_end = None;
    for k in 0..MAX_STEPS {
        let from = st.regime();
        let n = match st.step() {
            Ok(n) => n,
            Err(_) => fail("the default scene halted while looking for events"),
        };
        match (from, n) {
            (Regime::Stick, 1..) if stick_to_slip.is_none() => stick_to_slip = Some(k),
            (Regime::SlipSlower | Regime::SlipFaster, 0) if stick_to_slip.is_some() && slip_quiet.is_none() => {
                slip_quiet = Some(k)
            }
            (Regime::SlipSlower | Regime::SlipFaster, 1..) if stick_to_slip.is_some() && slip_end.is_none() => {
                slip_end = Some(k)
            }
            _ => {}
        }
        if slip_end.is_some() && slip_quiet.is_some() {
            break;
        }
    }
    let (Some(a), Some(b), Some(c)) = (stick_to_slip, slip_quiet, slip_end) else {
        fail("the default scene did not breakaway and re-stick within MAX_STEPS");
    };
    if a == 0 {
        fail("breakaway in the very first step: no stick step before it to measure");
    }
    [
        Probe { label: "stick_no_transition", step: a - 1 },
        Probe { label: "stick_to_slip", step: a },
        Probe { label: "slip_no_transition", step: b },
        Probe { label: "slip_transition", step: c },
    ]
}

#[entry]
fn main() -> ! {
    let scene = scenes::push_center();
    let mut stepper = match ExactStepper::<f32>::new(&scene) {
        Ok(s) => s,
        Err(_) => fail("the default scene was rejected"),
    };
    let probes = find_probes(stepper.clone());

    // Window 0: nothing between the markers.
    stickslip_mark_begin();
    stickslip_mark_end();

    // Pass 2. The stepper is reached through a pointer the optimiser must assume the markers
    // can see, so no part of a measured step moves out of its window.
    let st: &mut ExactStepper<f32> = black_box(&mut stepper);
    let mut seen = [Seen { from: Regime::Stick, to: Regime::Stick, transitions: 0 }; 4];
    let last = probes[3].step;
    for k in 0..=last {
        let from = st.regime();
        let result;
        match probes.iter().position(|p| p.step == k) {
            Some(i) => {
                stickslip_mark_begin();
                result = st.step();
                stickslip_mark_end();
                let n = match black_box(result) {
                    Ok(n) => n,
                    Err(_) => fail("halted in a measured step"),
                };
                seen[i] = Seen { from, to: st.regime(), transitions: n };
            }
            None => {
                if st.step().is_err() {
                    fail("halted between measured steps");
                }
            }
        }
    }

    hprintln!("window 0 baseline step=- none->none transitions=0");
    for (i, (p, s)) in probes.iter().zip(seen.iter()).enumerate() {
        hprintln!(
            "window {} {} step={} {}->{} transitions={}",
            i + 1,
            p.label,
            p.step,
            s.from.name(),
            s.to.name(),
            s.transitions
        );
    }
    debug::exit(debug::EXIT_SUCCESS);
    #[allow(clippy::empty_loop)]
    loop {}
}
