//! Rig firmware, first stage: the exact stick-slip model running in real time on the
//! STM32F407VG, with nothing attached yet.
//!
//! - brings the chip up at 168 MHz (PLL from the internal 16 MHz HSI, so any F407 board boots);
//! - builds `ExactStepper<f32>` for the default scene (push caliper, load at the pad centre);
//! - steps it once per tick of an embassy `Ticker` at the model's rate (dt = 1/25 600 s; see
//!   [`STEP_HZ`] for the rate the 1 MHz time base actually gives);
//! - logs each transition with defmt (at most [`TRANSITION_LOGS_PER_MODEL_SECOND`] per model
//!   second, the others are counted) and, once per model second, a summary with the cost of a
//!   step in core cycles (DWT cycle counter) and how late the ticks came.
//!
//! Sampling, valves and the host link come with the rig firmware proper.

#![no_std]
#![no_main]

use cortex_m::peripheral::DWT;
use defmt::{error, info, warn};
use embassy_executor::Spawner;
use embassy_stm32::Config;
use embassy_time::{Duration, Instant, Ticker, TICK_HZ};
use stickslip_model::{Caliper, ExactStepper, Halt, Scene};
use {defmt_rtt as _, panic_probe as _};

/// The model's step rate [Hz] (the default scene's dt is 1/25 600 s). The embassy time base
/// ticks at 1 MHz, so `Duration::from_hz(STEP_HZ)` is 39 ticks: the ticker runs at 25 641 Hz,
/// 0.16 % fast in wall-clock terms (the model itself always advances by exactly dt per step).
/// The rig firmware will pace sampling from a hardware timer, not from the executor.
const STEP_HZ: u64 = 25_600;
/// Core clock set by [`clock_config`] [Hz].
const SYSCLK_HZ: u64 = 168_000_000;
/// Transitions logged per model second; the rest are only counted.
const TRANSITION_LOGS_PER_MODEL_SECOND: u32 = 8;

/// 168 MHz from the HSI: 16 MHz / 16 * 336 / 2; 48 MHz on PLL Q for USB later.
/// APB1 42 MHz (its timers 84 MHz), APB2 84 MHz (its timers 168 MHz).
fn clock_config() -> Config {
    use embassy_stm32::rcc::{AHBPrescaler, APBPrescaler, Pll, PllMul, PllPDiv, PllPreDiv, PllQDiv, PllSource, Sysclk};
    let mut config = Config::default();
    config.rcc.hsi = true;
    config.rcc.pll_src = PllSource::HSI;
    config.rcc.pll = Some(Pll {
        prediv: PllPreDiv::DIV16,
        mul: PllMul::MUL336,
        divp: Some(PllPDiv::DIV2),
        divq: Some(PllQDiv::DIV7),
        divr: None,
    });
    config.rcc.ahb_pre = AHBPrescaler::DIV1;
    config.rcc.apb1_pre = APBPrescaler::DIV4;
    config.rcc.apb2_pre = APBPrescaler::DIV2;
    config.rcc.sys = Sysclk::PLL1_P;
    config
}

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    let _p = embassy_stm32::init(clock_config());
    info!("stickslip firmware {=str}: STM32F407VG at {=u64} Hz", env!("CARGO_PKG_VERSION"), SYSCLK_HZ);

    // The DWT cycle counter measures each step's cost in core cycles.
    match cortex_m::Peripherals::take() {
        Some(mut core) => {
            core.DCB.enable_trace();
            core.DWT.enable_cycle_counter();
        }
        None => warn!("core peripherals already taken: step cycle counts will read 0"),
    }

    spawner.spawn(model_task().expect("model task spawned once"));
}

/// What happened during one model second, for the summary line.
#[derive(Default)]
struct Window {
    steps: u32,
    transitions: u32,
    logged: u32,
    not_logged: u32,
    cycles_sum: u64,
    cycles_max: u32,
    late_max_ticks: u64,
    /// Ticks that came a whole period or more late (the ticker then catches up in a burst).
    overruns: u32,
}

#[embassy_executor::task]
async fn model_task() {
    let scene = Scene::case(Caliper::Push, 0.040);
    let t_build = Instant::now();
    let mut stepper = match ExactStepper::<f32>::new(&scene) {
        Ok(s) => s,
        Err(e) => {
            error!("scene rejected: field {=str} = {=f64}: {=str}", e.field, e.value, e.rule);
            return;
        }
    };
    info!(
        "ExactStepper<f32> built in {=u64} us: {=str} caliper, beta {=f64} m, {=u32} substep(s) per step",
        t_build.elapsed().as_micros(),
        scene.caliper.name(),
        scene.beta,
        stepper.propagator().n_sub
    );

    let period = Duration::from_hz(STEP_HZ);
    let period_ticks = period.as_ticks();
    info!(
        "stepping every {=u64} ticks of {=u64} Hz: {=u64} Hz (model dt 1/{=u64} s)",
        period_ticks,
        TICK_HZ,
        TICK_HZ / period_ticks,
        STEP_HZ
    );
    let cycles_per_period = SYSCLK_HZ / (TICK_HZ / period_ticks);

    let start = Instant::now();
    let mut ticker = Ticker::every(period);
    let mut tick: u64 = 0;
    let mut window = Window::default();
    let mut window_start = start;
    loop {
        ticker.next().await;
        tick += 1;
        // The ticker's k-th deadline is (at or just after) start + k periods.
        let now = Instant::now().as_ticks();
        let due = start.as_ticks() + tick * period_ticks;
        let late = now.saturating_sub(due);
        window.late_max_ticks = window.late_max_ticks.max(late);
        if late >= period_ticks {
            window.overruns += 1;
        }

        let c0 = DWT::cycle_count();
        let result = stepper.step();
        let cycles = DWT::cycle_count().wrapping_sub(c0);
        window.steps += 1;
        window.cycles_sum += cycles as u64;
        window.cycles_max = window.cycles_max.max(cycles);

        match result {
            Ok(n) => {
                window.transitions += n as u32;
                for tr in stepper.transitions() {
                    if window.logged < TRANSITION_LOGS_PER_MODEL_SECOND {
                        info!(
                            "t={=f64} s {=str} -> {=str}: x={=f32} m x'={=f32} m/s phi={=f32} rad",
                            tr.t,
                            tr.from.name(),
                            tr.to.name(),
                            tr.state.x,
                            tr.state.xdot,
                            tr.state.phi
                        );
                        window.logged += 1;
                    } else {
                        window.not_logged += 1;
                    }
                }
            }
            Err(halt) => {
                log_halt(&halt);
                // The stepper refuses further steps; keep the chip alive for the probe.
                loop {
                    ticker.next().await;
                }
            }
        }

        if window.steps as u64 == STEP_HZ {
            let wall = Instant::now().as_ticks() - window_start.as_ticks();
            let state = stepper.state();
            info!(
                "model t={=f64} s (wall {=u64} us): {=u32} transitions ({=u32} logged), regime {=str}, x={=f32} m, phi={=f32} rad",
                stepper.time(),
                wall * 1_000_000 / TICK_HZ,
                window.transitions,
                window.logged,
                stepper.regime().name(),
                state.x,
                state.phi
            );
            info!(
                "step cost: mean {=u64} max {=u32} cycles of {=u64} per tick; latest tick {=u64} ticks late, {=u32} overruns",
                window.cycles_sum / window.steps as u64,
                window.cycles_max,
                cycles_per_period,
                window.late_max_ticks,
                window.overruns
            );
            window = Window::default();
            window_start = Instant::now();
        }
    }
}

fn log_halt(halt: &Halt) {
    match *halt {
        Halt::NonFinite { t } => error!("model halted at t={=f64} s: non-finite state", t),
        Halt::Diverged { t, regime, stiffness_margin } => error!(
            "model halted at t={=f64} s: diverged in {=str} (rotational stiffness margin {=f64} N m/rad)",
            t,
            regime.name(),
            stiffness_margin
        ),
        Halt::ContactLoss { t, n } => error!("model halted at t={=f64} s: contact lost (N = {=f64} N)", t, n),
        Halt::TransitionStorm { t } => error!("model halted at t={=f64} s: transition storm", t),
    }
}
