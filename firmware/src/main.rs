//! Rig firmware for the brake-groan rig's controller (STM32F407VG).
//!
//! - TIM3 (update event on TRGO) triggers ADC1's regular sequence: the four accelerometers and,
//!   with feature `pressure`, the two pressure transducers, at [`config::SAMPLE_RATE_HZ`] per
//!   channel; DMA2 stream 0 copies each conversion into a circular ring
//!   (embassy-stm32 0.6 `RingBufferedAdc`, timer-triggered, frame-aligned).
//! - The estimator task ([`estimator_task`], below) takes the ring half by half and runs every
//!   frame through `stickslip_rig_core::sample_words` (`rig-core/src/rig_core.rs`, two hops from
//!   here) into the one rig, `stickslip_model::rig::pipeline::Rig` (`shared/src/rig/pipeline.rs`:
//!   calibration, estimator with window statistics and the lockstep model, valve sequencer),
//!   sets the valve outputs of each sample, and
//!   logs over defmt (RTT): sequencer states, button commands, contact events (rate-limited) and
//!   one summary record per window ([`records`]). An overrun of the ring (frames overwritten
//!   before they were read) is counted and logged; no frames at all for 50 ms is a stall: the
//!   valves are vented and the watchdog resets the chip.
//! - The independent watchdog is fed by the estimator task only, after each half-ring read.
//! - E-stop, end-of-stroke (feature `end-of-stroke`) and the start/stop/reset button are EXTI
//!   inputs ([`inputs`]); the e-stop also vents from its own task, before the sequencer's
//!   next tick.
//! - Valves: PD12 (actuator/clamp), PD13 (band drive), high = open; low = vented, the reset
//!   state ([`valves`]); the panic and HardFault handlers vent first ([`panic`]).
//! - Every pin and peripheral is defined once, in [`board`]; `main` is the bring-up
//!   ([`board::bring_up`]), then the tasks.
//!
//! Nothing moves after boot until the button is pressed: the sequencer starts Idle (both valves
//! vented) and only the button's start command begins a clamp / drive / record cycle.

#![no_std]
#![no_main]

mod board;
mod config;
mod inputs;
mod panic;
mod records;
mod valves;

use core::mem::MaybeUninit;

use cortex_m::peripheral::DWT;
use defmt_rtt as _;
use embassy_executor::Spawner;
use embassy_stm32::adc::{Adc, AdcChannel, Exten, RingBufferedAdc};
use embassy_stm32::exti::ExtiInput;
use embassy_stm32::gpio::Pull;
use embassy_stm32::peripherals::{ADC1, IWDG, TIM3};
use embassy_stm32::timer::low_level::{MasterMode, RoundTo, Timer as HwTimer};
use embassy_stm32::wdg::IndependentWatchdog;
use embassy_stm32::{pac, triggers};
use embassy_time::{with_timeout, Duration, Instant, Timer};
use stickslip_model::rig::pipeline::{DigitalInputs, Rig, RigConfig, RigError};
use stickslip_model::rig::sequencer::{button_command, Valves};

use crate::config::{
    ACCEL_FRONT_END_GAIN, ADC_CHANNELS, ADC_SAMPLE_TIME, EVENT_LOGS_PER_WINDOW, FRAMES_PER_HALF, FRAME_WORDS, OVERSAMPLE, RING_WORDS, SAMPLE_RATE_HZ,
    STALL_TIMEOUT_MS, SYSCLK_HZ, WATCHDOG_TIMEOUT_US,
};
use crate::records::{log, read_reset_cause, Boot, Defmt, Logbook, Record};
use crate::valves::ValveOutputs;
use stickslip_rig_core::{sample_words, stack};

// The high-water mark reads the paint cortex-m-rt put on the stack at reset.
const _: () = assert!(stack::PAINT == cortex_m_rt::STACK_PAINT_VALUE);

/// Words of one half of the ring: what one read returns.
const HALF_WORDS: usize = RING_WORDS / 2;

/// What the estimator task owns.
struct Sampler {
    adc: RingBufferedAdc<'static, ADC1>,
    /// Kept alive (dropping it would stop its clock) and started with the sampling.
    timer: HwTimer<'static, TIM3>,
    watchdog: IndependentWatchdog<'static, IWDG>,
    valves: ValveOutputs,
    rig: &'static mut Rig,
    half: &'static mut [u16; HALF_WORDS],
    /// Core cycles in the time of one half-ring.
    batch_budget: u32,
}

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    let reset = read_reset_cause();
    let b = board::bring_up();
    // Valves first: both outputs low (vented) before anything else runs.
    let valves = ValveOutputs::new(b.actuator_valve, b.band_valve);

    // The DWT cycle counter measures each batch's processing time.
    if let Some(mut core) = cortex_m::Peripherals::take() {
        core.DCB.enable_trace();
        core.DWT.enable_cycle_counter();
    }

    // The trigger timer: TIM3 update event -> TRGO -> ADC1 regular sequence. Not started yet.
    let timer = HwTimer::new(b.trigger_timer);
    let f_tim = timer.get_clock_frequency().0;
    // one scan per update, OVERSAMPLE scans per frame
    let scan_hz = SAMPLE_RATE_HZ * OVERSAMPLE as u32;
    let clocks = (f_tim + scan_hz / 2) / scan_hz;
    timer.set_period_clocks(clocks as u64, RoundTo::Faster);
    timer.set_master_mode(MasterMode::UPDATE);
    let fs_hz = f_tim as f64 / (clocks as f64 * OVERSAMPLE as f64);

    let mut cfg = RigConfig::rig(fs_hz, cfg!(feature = "pressure"), cfg!(feature = "end-of-stroke"));
    cfg.calibration.adc.oversample = OVERSAMPLE as u32;
    for (a, g) in cfg.calibration.accel.iter_mut().zip(ACCEL_FRONT_END_GAIN) {
        a.front_end_gain = g;
    }
    log(&Record::Boot(Boot {
        fw: env!("CARGO_PKG_VERSION"),
        reset,
        sysclk_hz: SYSCLK_HZ,
        fs_hz: fs_hz as f32,
        timer_clocks: clocks,
        adc_channels: ADC_CHANNELS as u32,
        window_samples: cfg.estimator.window_samples,
        batch_frames: FRAMES_PER_HALF as u32,
        pressure: cfg.has_pressure,
        end_of_stroke: cfg.has_end_of_stroke,
        oversample: OVERSAMPLE as u32,
    }));

    // The slow part: the estimator, the sequencer and the armed lockstep model (f64 set-up),
    // once, before the watchdog runs and before any sample is taken.
    let t_build = Instant::now();
    let slot = cortex_m::singleton!(: MaybeUninit<Rig> = MaybeUninit::uninit()).expect("one rig");
    let rig = match Rig::init(slot, &cfg) {
        Ok(r) => r,
        Err(RigError::Config(e)) => halt_config(e.field, e.rule, e.value).await,
        Err(RigError::Model(e)) => halt_config(e.field, e.rule, e.value).await,
    };
    let model = rig.model_scene();
    log(&Record::Armed {
        build_us: t_build.elapsed().as_micros() as u32,
        caliper: model.caliper.name(),
        beta_m: model.beta as f32,
        f_n_n: model.f_n as f32,
        v_m_s: model.v as f32,
        n0_n: rig.model_normal_force(),
    });

    // ADC1: regular sequence in frame order, triggered by TIM3_TRGO, into the DMA ring.
    let ring = cortex_m::singleton!(: [u16; RING_WORDS] = [0; RING_WORDS]).expect("one DMA ring");
    let half = cortex_m::singleton!(: [u16; HALF_WORDS] = [0; HALF_WORDS]).expect("one read buffer");
    let st = ADC_SAMPLE_TIME;
    #[cfg(feature = "pressure")]
    let sequence = [
        (AdcChannel::<ADC1>::degrade_adc(b.disc_x), st),
        (AdcChannel::<ADC1>::degrade_adc(b.pad_x), st),
        (AdcChannel::<ADC1>::degrade_adc(b.pad_trail), st),
        (AdcChannel::<ADC1>::degrade_adc(b.pad_lead), st),
        (AdcChannel::<ADC1>::degrade_adc(b.actuator_pressure), st),
        (AdcChannel::<ADC1>::degrade_adc(b.band_pressure), st),
    ];
    #[cfg(not(feature = "pressure"))]
    let sequence = [
        (AdcChannel::<ADC1>::degrade_adc(b.disc_x), st),
        (AdcChannel::<ADC1>::degrade_adc(b.pad_x), st),
        (AdcChannel::<ADC1>::degrade_adc(b.pad_trail), st),
        (AdcChannel::<ADC1>::degrade_adc(b.pad_lead), st),
    ];
    let adc = Adc::new(b.adc).into_ring_buffered(
        b.adc_dma,
        ring,
        board::Irqs,
        sequence.into_iter(),
        triggers::TIM3_TRGO,
        Exten::RISING_EDGE,
    );

    // Digital inputs on EXTI.
    let estop = ExtiInput::new(b.estop, b.estop_exti, Pull::Up, board::Irqs);
    spawner.spawn(inputs::estop_task(estop).expect("e-stop task spawned once"));
    #[cfg(feature = "end-of-stroke")]
    {
        let eos = ExtiInput::new(b.end_of_stroke, b.end_of_stroke_exti, Pull::Up, board::Irqs);
        spawner.spawn(inputs::end_of_stroke_task(eos).expect("end-of-stroke task spawned once"));
    }
    let button = ExtiInput::new(b.button, b.button_exti, Pull::Down, board::Irqs);
    spawner.spawn(inputs::button_task(button).expect("button task spawned once"));

    let mut watchdog = IndependentWatchdog::new(b.watchdog, WATCHDOG_TIMEOUT_US);
    watchdog.unleash();
    let (stack_used, stack_size) = stack::used();
    log(&Record::Start { watchdog_us: WATCHDOG_TIMEOUT_US, stack_used, stack_size });

    let batch_budget = (SYSCLK_HZ as u64 * clocks as u64 * (OVERSAMPLE * FRAMES_PER_HALF) as u64 / f_tim as u64) as u32;
    let sampler = Sampler { adc, timer, watchdog, valves, rig, half, batch_budget };
    spawner.spawn(estimator_task(sampler).expect("estimator task spawned once"));
}

/// A refused configuration: log it and stay idle (valves vented, no watchdog, no sampling).
async fn halt_config(field: &'static str, rule: &'static str, value: f64) -> ! {
    log(&Record::ConfigError { field, rule, value });
    loop {
        Timer::after_secs(3600).await;
    }
}

/// Consumes every frame: the only feeder of the watchdog and the only writer of the valves
/// (besides the vent-only paths: e-stop task, panic, faults).
#[embassy_executor::task]
async fn estimator_task(s: Sampler) {
    let Sampler { mut adc, timer, mut watchdog, mut valves, rig, half, batch_budget } = s;
    // Frames since boot, overruns, the events' rate limit, the window records: the logbook.
    let mut book = Logbook::new(batch_budget, EVENT_LOGS_PER_WINDOW);

    // Arm the DMA ring and the ADC (this also converts one scan at once, by software start),
    // then start the trigger timer: from here on one scan per timer period.
    adc.start();
    timer.start();

    loop {
        match with_timeout(Duration::from_millis(STALL_TIMEOUT_MS), adc.read(&mut half[..])).await {
            Ok(Ok(_)) => {}
            Ok(Err(_overrun)) => {
                // The ring has restarted at the newest whole frame; the lost frames are gone.
                book.overrun(&mut Defmt);
                continue;
            }
            Err(_timeout) => {
                // No samples: vent, say why, and let the watchdog (no longer fed) reset the chip.
                valves.vent();
                log(&Record::Stall {
                    n: book.frames(),
                    ms: STALL_TIMEOUT_MS as u32,
                    adc_ovr: pac::ADC1.sr().read().ovr(),
                });
                loop {
                    valves.vent();
                    Timer::after_millis(10).await;
                }
            }
        }
        watchdog.pet();

        let c0 = DWT::cycle_count();
        let estop_edge = inputs::take_estop_edge();
        let eos_edge = inputs::take_end_of_stroke_edge();
        let mut press = inputs::take_button();
        for words in half.chunks_exact(FRAME_WORDS) {
            let estop = estop_edge || inputs::estop_active();
            let digital = DigitalInputs { estop, end_of_stroke: eos_edge || inputs::end_of_stroke_active() };
            let command = if press {
                press = false;
                Some(button_command(rig.state()))
            } else {
                None
            };
            let out = sample_words(rig, words, &digital, command);
            // The sequencer vents on an e-stop in this very tick; the override is a second line.
            valves.set(if estop { Valves::VENTED } else { out.sequencer.valves });
            book.sample(&mut Defmt, rig, command, &out);
        }
        let cycles = DWT::cycle_count().wrapping_sub(c0);
        // Outside the per-sample loop: the window's divisions and square roots, and its record.
        book.end_batch(&mut Defmt, rig, cycles);
    }
}
