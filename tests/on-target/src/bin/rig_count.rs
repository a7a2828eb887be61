//! Instruction counts of the rig's per-sample path on the Cortex-M4F, for
//! `scripts/count-instructions.sh`.
//!
//! Two paths, measured on every frame of a fixed sequence (see below):
//! - **A**, the decimation of the frame's four scans (the firmware's oversampling,
//!   `Rig::frame`), calibration of the six channels + `Estimator::update` (contact
//!   estimate, groan band-pass, window statistics; no lockstep model):
//!   `stickslip_rig_core::calibrate_estimate` with a calibrator and an estimator of its own;
//! - **B**, the firmware's whole per-sample call, `stickslip_rig_core::sample_words`
//!   (`firmware/rig-core`, the crate the firmware links) on the one rig,
//!   `stickslip_model::rig::pipeline::Rig`: frame, calibration, estimator with the lockstep model during
//!   the record, sequencer, and the firmware's glue. The button's start at frame 0 takes the
//!   sequencer through clamp and drive to record within three frames.
//!
//! Build it with the `firmware` profile (`--profile firmware`, the firmware's code generation
//! settings: both measured functions are compiled in `stickslip-rig-core` at opt-level 3, the
//! rest for size), as scripts/count-instructions.sh does.
//!
//! Each call sits between a call of `stickslip_mark_begin` and one of `stickslip_mark_end`
//! (never inlined, opaque); right after the end marker a class marker `rig_class_<class>` names
//! what the sample was, so that the script (which counts the trace lines between the two
//! markers, `qemu-system-arm -d exec,nochain`, one instruction per line) can report each class:
//!
//! - `a_stick`, `a_slip`: estimated stick or slip, no event, no window closed;
//! - `a_event`: a contact event (stick-to-slip, slip-to-stick, reversal) was decided;
//! - `a_window`: the sample closed a window (its sums set aside, the next window started);
//! - `b_stick`, `b_slip`, `b_event`, `b_window`: the same for path B during the record (with
//!   the lockstep model stepping);
//! - `b_model_transition`: the lockstep model's step had a transition (its in-step search);
//! - `b_record_start`: the sample entered Record (the armed estimator is copied in);
//! - `b_setup`: idle, clamp and drive, before the record.
//!
//! Window 0 is empty (class `baseline`): the markers' calling glue, subtracted by the script.
//!
//! The configuration is the firmware's: the rig's, with [`OVERSAMPLE`] scans per frame. Each
//! frame's counts are taken as the four conversions of its scans (sum: four times the count).
//! The frames are made on the host by this crate's build script (push caliper, load at the
//! pad centre, 0.5 m/s^2 and 0.005 bar of noise, seed 2024): running the sensor model here
//! would add its own f64 set-up (some 13 million instructions) to the trace. The program prints
//! `frames <n>` and `done rig_count`, and exits with success.
#![no_std]
#![no_main]

use core::hint::black_box;
use core::mem::MaybeUninit;
use core::ptr::addr_of_mut;

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use panic_semihosting as _;
use stickslip_model::rig::calibration::Calibrator;
use stickslip_model::rig::estimator::Estimator;
use stickslip_model::rig::pipeline::{DigitalInputs, Rig, RigConfig};
use stickslip_model::rig::sequencer::{Command, SeqState};
use stickslip_model::rig::CHANNELS;
use stickslip_model::Regime;
use stickslip_on_target::rig_core::{calibrate_estimate, sample_words};

/// Scans per frame, as the firmware takes them (firmware/src/config.rs, `OVERSAMPLE`).
const OVERSAMPLE: usize = 4;

/// Six little-endian u16 counts per frame, made by build.rs.
static FRAMES: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/rig_count_frames.bin"));

/// Start of a measured window.
#[inline(never)]
#[no_mangle]
pub extern "C" fn stickslip_mark_begin() {
    cortex_m::asm::nop();
}

/// End of a measured window (a body unlike the begin marker's, so that they stay two
/// functions).
#[inline(never)]
#[no_mangle]
pub extern "C" fn stickslip_mark_end() {
    cortex_m::asm::nop();
    cortex_m::asm::nop();
}

/// Written by the class markers (each with its own value, so that no two markers have the same
/// body and are merged into one function).
static mut CLASS: u32 = 0;

macro_rules! class_markers {
    ($($name:ident = $k:expr),* $(,)?) => {
        $(
            #[inline(never)]
            #[no_mangle]
            pub extern "C" fn $name() {
                // SAFETY: single-threaded program; a plain volatile store.
                unsafe { addr_of_mut!(CLASS).write_volatile($k) }
            }
        )*
    };
}

class_markers!(
    rig_class_baseline = 1,
    rig_class_a_stick = 2,
    rig_class_a_slip = 3,
    rig_class_a_event = 4,
    rig_class_a_window = 5,
    rig_class_b_stick = 6,
    rig_class_b_slip = 7,
    rig_class_b_event = 8,
    rig_class_b_window = 9,
    rig_class_b_model_transition = 10,
    rig_class_b_record_start = 11,
    rig_class_b_setup = 12,
);

/// Everything the measured calls touch, reached through a pointer the optimiser must assume
/// the markers can see: no part of a measured call moves out of its window.
struct Bench {
    words: [u16; OVERSAMPLE * CHANNELS],
    calibrator: Calibrator,
    estimator: Estimator,
    rig: &'static mut Rig,
    digital: DigitalInputs,
    command: Option<Command>,
}

fn fail(msg: &str) -> ! {
    hprintln!("error {}", msg);
    debug::exit(debug::EXIT_FAILURE);
    #[allow(clippy::empty_loop)]
    loop {}
}

/// The static home of the firmware's per-sample state, as in the firmware.
static mut SLOT: MaybeUninit<Rig> = MaybeUninit::uninit();

#[entry]
fn main() -> ! {
    let mut cfg = RigConfig::rig(25_600.0, true, true);
    cfg.calibration.adc.oversample = OVERSAMPLE as u32;
    let calibrator = match Calibrator::new(&cfg.calibration) {
        Ok(c) => c,
        Err(_) => fail("calibration refused"),
    };
    let estimator = match Estimator::new(&cfg.estimator) {
        Ok(e) => e,
        Err(_) => fail("estimator refused"),
    };
    // SAFETY: the only reference ever made to SLOT; single-threaded program.
    let slot = unsafe { &mut *addr_of_mut!(SLOT) };
    let rig = match Rig::init(slot, &cfg) {
        Ok(r) => r,
        Err(_) => fail("rig refused"),
    };
    let mut bench = Bench {
        words: [0; OVERSAMPLE * CHANNELS],
        calibrator,
        estimator,
        rig,
        digital: DigitalInputs::default(),
        command: None,
    };
    let b: &mut Bench = black_box(&mut bench);

    // Window 0: nothing between the markers.
    stickslip_mark_begin();
    stickslip_mark_end();
    rig_class_baseline();

    let n = FRAMES.len() / (2 * CHANNELS);
    for (i, bytes) in FRAMES.chunks_exact(2 * CHANNELS).enumerate() {
        for (j, c) in b.words.iter_mut().enumerate() {
            let k = j % CHANNELS;
            *c = u16::from_le_bytes([bytes[2 * k], bytes[2 * k + 1]]);
        }

        // Path A: decimate + calibrate + estimator (window statistics included). The result is handed to
        // black_box by reference before the end marker: it is complete in memory there, and
        // nothing is copied for the harness.
        stickslip_mark_begin();
        let (cal, a) = calibrate_estimate(b.rig, &b.calibrator, &mut b.estimator, &b.words);
        black_box(&cal);
        black_box(&a);
        stickslip_mark_end();
        match () {
            _ if a.window_ready => rig_class_a_window(),
            _ if a.contact.event.is_some() => rig_class_a_event(),
            _ if a.contact.regime == Regime::Stick => rig_class_a_stick(),
            _ => rig_class_a_slip(),
        }
        if a.window_ready && b.estimator.take_window().is_none() {
            fail("a closed window had no report");
        }

        // Path B: the firmware's per-sample call.
        b.command = if i == 0 { Some(Command::Start) } else { None };
        stickslip_mark_begin();
        let o = sample_words(b.rig, &b.words, &b.digital, b.command);
        black_box(&o);
        stickslip_mark_end();
        let model_transition = b.rig.estimator().model().and_then(|m| m.stepper()).is_some_and(|s| !s.transitions().is_empty());
        match () {
            _ if o.record_started => rig_class_b_record_start(),
            _ if o.before != SeqState::Record => rig_class_b_setup(),
            _ if o.estimate.window_ready => rig_class_b_window(),
            _ if model_transition => rig_class_b_model_transition(),
            _ if o.estimate.contact.event.is_some() => rig_class_b_event(),
            _ if o.estimate.contact.regime == Regime::Stick => rig_class_b_stick(),
            _ => rig_class_b_slip(),
        }
        while b.rig.take_window().is_some() {}
        if i > 10 && b.rig.state() != SeqState::Record {
            fail("path B left Record");
        }
    }
    hprintln!("frames {}", n);
    hprintln!("done rig_count");
    debug::exit(debug::EXIT_SUCCESS);
    #[allow(clippy::empty_loop)]
    loop {}
}
