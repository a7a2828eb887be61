//! A defmt stream with known content for the host's `decode` tests: one record of every kind of
//! the rig firmware's log (`stickslip_rig_core::logbook::Record`), written by the firmware's
//! own formatting (`stickslip_records::log`, firmware/records) with fixed values, then one line
//! that is no record, over defmt-semihosting, under a timestamp that counts 1000 us per frame.
//! The host test (host/tests/recorded_decode.rs) checks the decoded records against the values
//! below, which it writes out on its own: change both together. Floating-point values are
//! exactly representable (binary fractions) so that the test compares them exactly.
#![no_std]
#![no_main]

use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m_rt::entry;
use cortex_m_semihosting::debug;
use defmt_semihosting as _;
use stickslip_model::rig::contact::{ContactEvent, ContactEventKind};
use stickslip_model::rig::sequencer::{Command, CommandResult, FaultCause, SeqState, Valves};
use stickslip_model::rig::window::{ModelWindow, WindowReport};
use stickslip_model::Halt;
use stickslip_records::log;
use stickslip_rig_core::logbook::{Boot, Record, ResetCause, WindowExtras};
use stickslip_model::rig::pipeline::{ClosedWindow, PressureWindow};

static FRAMES: AtomicU32 = AtomicU32::new(0);

// like embassy-time's defmt-timestamp-uptime: microseconds, here 1000 per log frame
defmt::timestamp!("{=u64:us}", FRAMES.fetch_add(1, Ordering::Relaxed) as u64 * 1000);

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    debug::exit(debug::EXIT_FAILURE);
    loop {}
}

#[entry]
fn main() -> ! {
    // frame 0
    log(&Record::Boot(Boot {
        fw: "0.1.0-fixture",
        reset: ResetCause::PowerOn,
        sysclk_hz: 168_000_000,
        fs_hz: 25_599.5,
        timer_clocks: 3281,
        adc_channels: 8,
        window_samples: 2560,
        batch_frames: 128,
        pressure: true,
        end_of_stroke: false,
    }));
    // frame 1
    log(&Record::ConfigError { field: "beta_m", rule: "inside the pad", value: -0.015625 });
    // frame 2
    log(&Record::Armed {
        build_us: 1234,
        caliper: "push",
        beta_m: 0.03125,
        f_n_n: 1500.5,
        v_m_s: 0.375,
        n0_n: 1498.25,
    });
    // frame 3
    log(&Record::Start { watchdog_us: 250_000, stack_used: 3412, stack_size: 16_384 });
    // frame 4: a fault, with the band valve still open
    log(&Record::State {
        n: 51_199,
        record: 1,
        from: SeqState::Record,
        to: SeqState::Fault(FaultCause::AccelSaturation),
        valves: Valves { actuator_open: false, band_open: true },
    });
    // frames 5 and 6: a command accepted, one refused
    log(&Record::Command {
        n: 12_800,
        state: SeqState::Idle,
        command: Command::Start,
        result: CommandResult::Accepted,
    });
    log(&Record::Command {
        n: 51_300,
        state: SeqState::Fault(FaultCause::EStop),
        command: Command::Reset,
        result: CommandResult::Refused(FaultCause::EStop),
    });
    // frame 7
    log(&Record::Event {
        n: 51_200,
        record: 1,
        event: ContactEvent { kind: ContactEventKind::StickToSlip, sample: 25_600 },
        v_r_m_s: -0.0078125,
        a_rel_m_s2: -24.5,
    });
    // frame 8
    let window = ClosedWindow {
        record: 1,
        report: WindowReport {
            index: 20,
            first_sample: 51_200,
            samples: 2560,
            valid_samples: 2558,
            pp_m_s2: [3.25, 80.5, 12.0, 150.75],
            rms_m_s2: [0.5, 10.25, 2.5, 30.0],
            groan_rms_m_s2: [0.125, 8.5, 2.0, 25.5],
            stick_fraction: 0.8125,
            stick_slip_hz: 48.5,
            slip_onsets: 5,
            saturated_samples: 3,
            faulted_samples: 2,
            model: Some(ModelWindow {
                samples: 2304,
                stick_fraction: 0.8046875,
                stick_slip_hz: 48.75,
                slip_onsets: 4,
                residual_rms_m_s2: 1.5,
                halt: Some(Halt::ContactLoss { t: 0.75, n: -1.25 }),
            }),
            non_finite: false,
        },
        pressure: PressureWindow { mean_bar: [5.0, 0.625], min_bar: [4.875, 0.5625], max_bar: [5.125, 0.6875] },
    };
    log(&Record::Window {
        window: &window,
        extras: WindowExtras {
            n: 53_760,
            state: SeqState::Record,
            overruns: 1,
            events_dropped: 7,
            windows_dropped: 2,
            batch_cycles_max: 41_000,
            batch_cycles_budget: 65_625,
        },
    });
    // frames 9 to 12
    log(&Record::Overrun { n: 60_000, count: 2 });
    log(&Record::Stall { n: 60_128, ms: 12, adc_ovr: true });
    log(&Record::Input { name: "estop", active: true });
    log(&Record::Panic { file: "src/main.rs", line: 42, msg: "explicit panic" });
    // frame 13: a line that is no record (like embassy-stm32's own defmt lines): kind `log`
    defmt::warn!("DMA: error on channel {=u8} (flags {=u32:#x})", 3, 0x28);
    debug::exit(debug::EXIT_SUCCESS);
    loop {}
}
