//! Build-time settings of the rig firmware: clocks, sampling, buffers, watchdog, log limits.
//! The pins are in `board.rs` (and in README.md's pin map).

use embassy_stm32::adc::SampleTime;
use embassy_stm32::Config;
#[cfg(not(feature = "pressure"))]
use stickslip_model::rig::ACCEL_CHANNELS;
#[cfg(feature = "pressure")]
use stickslip_model::rig::CHANNELS;

/// Core clock set by [`clock_config`] [Hz].
pub const SYSCLK_HZ: u32 = 168_000_000;

/// Sampling rate per channel [Hz], the model crate's design value
/// (`stickslip_model::design::SAMPLE_RATE_HZ`): one frame of all channels per [`OVERSAMPLE`] TIM3 updates.
/// TIM3 counts the 84 MHz APB1 timer clock and triggers one scan per update, so the scan period
/// is the nearest whole number of clocks: 102 400 Hz asks for 820.3 clocks and gets 820, i.e.
/// a frame rate of 25 609.76 Hz (+381 ppm). The firmware runs the estimator and the lockstep
/// model at the rate it really gets (logged at boot); the HSI oscillator's own tolerance (1 %)
/// is larger than that rounding.
pub const SAMPLE_RATE_HZ: u32 = stickslip_model::design::SAMPLE_RATE_HZ as u32;

/// Scans per frame (the calibration's `adc.oversample`): each channel is converted this many
/// times per frame and the frame's count is their sum (`Rig::frame`, shared/src/rig/pipeline.rs: a boxcar of 4 at
/// 102.4 kHz, then one sample in 4; stickslip_model::rig::calibration states the filter). The
/// anti-alias ahead of it: the accelerometers' 8 kHz bandwidth and the front end's low-pass.
/// The sum has 14 bits; it resolves finer than one 12-bit count where the converter's own
/// noise dithers the four conversions (`sil --oversample 4 --adc-noise C` measures it).
pub const OVERSAMPLE: usize = 4;

/// Front-end gain of each accelerometer channel [V/V] (disc_x, pad_x, pad_trail, pad_lead):
/// 0.2 spans +-809 m/s^2 at 0.395 m/s^2 per count (the nominal front end); the amplifier
/// option for Table 3.1's levels is 10 (+-16 m/s^2 at 7.9 mm/s^2 per count, README.md,
/// "Wiring notes"). The calibration divides it out.
pub const ACCEL_FRONT_END_GAIN: [f64; 4] = [0.2; 4];

/// Channels in the ADC's regular sequence: the four accelerometers, then the two pressures.
#[cfg(feature = "pressure")]
pub const ADC_CHANNELS: usize = CHANNELS;
/// Channels in the ADC's regular sequence: the four accelerometers (no pressure transducers).
#[cfg(not(feature = "pressure"))]
pub const ADC_CHANNELS: usize = ACCEL_CHANNELS;

/// Sampling time of every channel: 15 ADC clocks (+ 12 for the conversion) at 21 MHz
/// (PCLK2 84 MHz / 4) = 1.29 us per channel, 7.7 us for six, within the 9.76 us scan period
/// (the next longer sampling time, 28 clocks, would take 11.4 us). 15 clocks of sampling
/// (0.71 us) need a low source impedance: the front end's op-amp driver (RM0090 / the
/// datasheet's R_AIN table: below about 1.5 kOhm for 12 bits at 15 cycles).
pub const ADC_SAMPLE_TIME: SampleTime = SampleTime::CYCLES15;
/// ADC clocks per conversion with [`ADC_SAMPLE_TIME`], and the ADC clock [Hz].
const ADC_CLOCKS_PER_CONVERSION: u32 = 15 + 12;
const ADC_CLOCK_HZ: u32 = 21_000_000;
const _: () = assert!(
    (ADC_CHANNELS as u32) * ADC_CLOCKS_PER_CONVERSION * SAMPLE_RATE_HZ * (OVERSAMPLE as u32) < ADC_CLOCK_HZ,
    "the regular sequence does not fit in one scan period: shorten ADC_SAMPLE_TIME or OVERSAMPLE"
);

/// Frames per half of the DMA ring: the estimator task wakes once per half (2.5 ms at
/// 25.6 kHz) and processes this many frames; a frame is [`OVERSAMPLE`] scans of
/// [`ADC_CHANNELS`] u16 words.
pub const FRAMES_PER_HALF: usize = 64;
/// Words of one frame.
pub const FRAME_WORDS: usize = OVERSAMPLE * ADC_CHANNELS;
/// Words in the DMA ring (two halves).
pub const RING_WORDS: usize = 2 * FRAMES_PER_HALF * FRAME_WORDS;

/// Independent watchdog timeout [us] (LSI 32 kHz nominal, 17 to 47 kHz: 68 to 188 ms real).
/// The estimator task feeds it after every half-ring of frames it received, so it runs out
/// only when no samples arrive (or the task is stuck): then the chip resets and the valves
/// drop to their reset (vented) state.
pub const WATCHDOG_TIMEOUT_US: u32 = 100_000;
/// No half-ring within this [ms] is a sampling stall: logged, valves vented, and the watchdog
/// left to reset the chip.
pub const STALL_TIMEOUT_MS: u64 = 50;

/// Contact event records logged between two window records; the others are counted and
/// reported in the next window record (`events_dropped`). 32 per 100 ms window: 320 per
/// second at most.
pub const EVENT_LOGS_PER_WINDOW: u32 = 32;

/// The start/stop/reset button must stay pressed this long to count [ms].
pub const BUTTON_DEBOUNCE_MS: u64 = 30;

/// 168 MHz from the HSI: 16 MHz / 16 * 336 / 2; 48 MHz on PLL Q for USB later.
/// APB1 42 MHz (its timers 84 MHz), APB2 84 MHz (its timers 168 MHz, the ADC 84 / 4 = 21 MHz).
pub fn clock_config() -> Config {
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
