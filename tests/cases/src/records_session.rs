//! A rig session played without the hardware, for the log: the records the firmware writes,
//! in the order and with the values it would write them, from the firmware's own code
//! (the rig, `stickslip_model::rig::pipeline::Rig`, through `stickslip_rig_core::sample_words`
//! for every frame, `Logbook` for what is logged, the estimator task's batch loop
//! of firmware/src/main.rs), on frames of the sensor model instead of the ADC.
//!
//! Run by the Cortex-M4F program `tests/on-target/src/bin/records.rs`, which writes the records
//! with defmt over semihosting (`stickslip_records`, the firmware's formatting), and by the host
//! test `tests/tests/records_on_target.rs`, which collects them as values and compares them
//! with what `stickslip decode` reads from the program's stream. Uses `core`,
//! `stickslip_model` and `stickslip_rig_core` (firmware/rig-core), nothing else.
//!
//! The session (push caliper, load at the pad centre, sensor noise 0.5 m/s^2 and 0.005 bar):
//! 1. a boot whose configuration is refused (the model's load position beyond the pad):
//!    `boot`, `config_error`;
//! 2. the rig's boot: `boot`, `armed`, `start`;
//! 3. [`BATCHES`] batches of [`BATCH_FRAMES`] frames (half a DMA ring each, as the firmware
//!    reads them): the button in batch 0 (start: clamp), [`CLAMP_BATCHES`] batches of the
//!    clamped, band-still phase while the actuator line fills (quiet frames, the actuator's
//!    pressure channel at 0 bar: the noise floor, a `floor` record), then the run (drive,
//!    record) with the trailing-edge accelerometer dead ([`DEAD_CHANNEL`] reads a constant
//!    count: a `health` record after each window of the record), the half-ring of batch
//!    [`OVERRUN_BATCH`] lost to an overrun (its frames are drawn and never processed, as when
//!    the ring is overwritten), the e-stop pressed over batches [`ESTOP_BATCHES`] (a fault that
//!    vents), the button again in batch [`RESET_BATCH`] (reset). States, commands, contact
//!    events (at most [`EVENT_LOGS_PER_WINDOW`] per window) and a `window` record per closed
//!    window, as the firmware logs them.
//!
//! What only a chip has is given, not measured: the build time of the armed model and the batch
//! cycle counts are 0 (QEMU has no cycle counter); the stack figures of `start` come from the
//! caller (the program paints the stack; the host test passes zeros and does not compare them).
//! The timestamps are the uptime the rig would have, from the frames converted so far at the
//! firmware's sampling rate ([`uptime_us`]), with the set-up taking no time.

use stickslip_model::rig::pipeline::DigitalInputs;
use stickslip_model::rig::CHANNELS;
use stickslip_model::harness::sensor_model::{Noise, SensorModel, SensorModelConfig};
use stickslip_model::{Caliper, Scene};

use crate::logbook::{Boot, Logbook, Record, RecordSink, ResetCause};
use stickslip_model::rig::pipeline::{Rig, RigConfig, RigError};
use stickslip_model::rig::sequencer::button_command;
use stickslip_rig_core::sample_words;

/// The trigger timer's clock [Hz] (TIM3 on APB1 x 2 at 168 MHz SYSCLK: firmware/src/config.rs).
pub const TIMER_HZ: u32 = 84_000_000;
/// Timer clocks per scan: 84 MHz / (4 x 25.6 kHz), rounded, as the firmware sets it.
pub const TIMER_CLOCKS: u32 = 820;
/// Scans per frame, as the firmware takes them (`config::OVERSAMPLE`).
pub const OVERSAMPLE: u32 = 4;
/// SYSCLK [Hz], as the `boot` record reports it.
pub const SYSCLK_HZ: u32 = 168_000_000;
/// Frames per batch: half of the firmware's DMA ring (`FRAMES_PER_HALF`).
pub const BATCH_FRAMES: u32 = 64;
/// Batches in the session: 200 x 64 frames = 12 800 frames, 0.5 s.
pub const BATCHES: u32 = 200;
/// Batches of the clamped phase (the floor: 6 x 64 = 384 samples, at least the 256 a design
/// needs).
pub const CLAMP_BATCHES: u32 = 6;
/// The accelerometer that is dead in the run (pad_trail): a constant count.
pub const DEAD_CHANNEL: usize = stickslip_model::rig::PAD_TRAIL;
/// The batch whose half-ring is lost to an overrun.
pub const OVERRUN_BATCH: u32 = 100;
/// The batches over which the e-stop is held.
pub const ESTOP_BATCHES: core::ops::Range<u32> = 140..156;
/// The batch in which the button is pressed again (reset from the e-stop fault).
pub const RESET_BATCH: u32 = 172;
/// The firmware's event rate limit (`config::EVENT_LOGS_PER_WINDOW`).
pub const EVENT_LOGS_PER_WINDOW: u32 = 32;
/// The firmware's watchdog timeout [us] (`config::WATCHDOG_TIMEOUT_US`).
pub const WATCHDOG_US: u32 = 100_000;
/// The firmware's version string in the `boot` record.
pub const FW: &str = "0.1.0";

/// Where the session's records go, and the clock of their timestamps.
pub trait SessionOut: RecordSink {
    /// `frames` frames have been converted since the rig's boot: the uptime of what follows.
    fn at_frame(&mut self, frames: u64);
}

/// The uptime [us] after `frames` frames at the firmware's rate (`TIMER_CLOCKS` clocks of
/// `TIMER_HZ` each), rounded down.
pub const fn uptime_us(frames: u64) -> u64 {
    frames * (TIMER_CLOCKS * OVERSAMPLE) as u64 * 1_000_000 / TIMER_HZ as u64
}

/// The sampling rate the firmware gets [Hz].
pub fn fs_hz() -> f64 {
    TIMER_HZ as f64 / (TIMER_CLOCKS as f64 * OVERSAMPLE as f64)
}

/// The rig's configuration as the firmware makes it: oversampled.
fn rig_config() -> RigConfig {
    let mut cfg = RigConfig::rig(fs_hz(), true, true);
    cfg.calibration.adc.oversample = OVERSAMPLE;
    cfg
}

/// What the session did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SessionSummary {
    /// Frames processed (the lost half-ring not counted).
    pub frames: u64,
    /// Records written.
    pub records: u32,
}

/// Counts the records on their way.
struct Counting<'a, S: SessionOut> {
    out: &'a mut S,
    records: u32,
}

impl<S: SessionOut> RecordSink for Counting<'_, S> {
    fn record(&mut self, r: &Record<'_>) {
        self.records += 1;
        self.out.record(r);
    }
}

fn boot_record(cfg: &RigConfig) -> Record<'static> {
    Record::Boot(Boot {
        fw: FW,
        reset: ResetCause::PowerOn,
        sysclk_hz: SYSCLK_HZ,
        fs_hz: cfg.estimator.fs_hz as f32,
        timer_clocks: TIMER_CLOCKS,
        adc_channels: cfg.adc_channels() as u32,
        window_samples: cfg.estimator.window_samples,
        batch_frames: BATCH_FRAMES,
        pressure: cfg.has_pressure,
        end_of_stroke: cfg.has_end_of_stroke,
        oversample: cfg.calibration.adc.oversample,
    })
}

fn config_error(e: RigError) -> Record<'static> {
    match e {
        RigError::Config(e) => Record::ConfigError { field: e.field, rule: e.rule, value: e.value },
        RigError::Model(e) => Record::ConfigError { field: e.field, rule: e.rule, value: e.value },
    }
}

/// Plays the session (see the module documentation) into `out`; `stack` gives the stack's
/// high-water mark and size [bytes] for the `start` record. An error is a short reason: the
/// rig's own configuration refused, or the sensor model halted.
#[inline(never)]
pub fn run<S: SessionOut>(out: &mut S, stack: fn() -> (u32, u32)) -> Result<SessionSummary, &'static str> {
    let mut log = Counting { out, records: 0 };
    log.out.at_frame(0);

    // Boot 1: a configuration with the load beyond the pad's leading edge.
    let mut bad = rig_config();
    bad.model_template.beta = 0.095;
    log.record(&boot_record(&bad));
    match build(&bad) {
        Ok(_) => return Err("the configuration with beta off the pad was accepted"),
        Err(e) => log.record(&config_error(e)),
    }

    // Boot 2: the rig's configuration, both features.
    let cfg = rig_config();
    log.record(&boot_record(&cfg));
    let mut slot = core::mem::MaybeUninit::uninit();
    let rig = Rig::init(&mut slot, &cfg).map_err(|_| "the rig's configuration was refused")?;
    let model = *rig.model_scene();
    log.record(&Record::Armed {
        build_us: 0,
        caliper: model.caliper.name(),
        beta_m: model.beta as f32,
        f_n_n: model.f_n as f32,
        v_m_s: model.v as f32,
        n0_n: rig.model_normal_force(),
    });
    let (stack_used, stack_size) = stack();
    log.record(&Record::Start { watchdog_us: WATCHDOG_US, stack_used, stack_size });

    let mut sensor_cfg = SensorModelConfig::RIG;
    sensor_cfg.calibration = cfg.calibration;
    sensor_cfg.noise = Noise { accel_rms_m_s2: 0.5, pressure_rms_bar: 0.005, seed: 2024, adc_rms_counts: 0.0 };
    let scene = Scene::case(Caliper::Push, 0.040);
    let mut sensor = SensorModel::<f32>::new(&scene, &sensor_cfg).map_err(|_| "the sensor model was refused")?;

    // the count of 0 bar on the actuator line: the line still filling
    let cal = &cfg.calibration;
    let filling = cal.adc.frame_count(cal.pressure[stickslip_model::rig::ACTUATOR].count_for(&cal.adc, 0.0));
    // a dead sensor: the front end's mid-scale, 0 m/s^2 for ever
    let dead = cal.adc.frame_count(2048);
    let mut book = Logbook::new(0, EVENT_LOGS_PER_WINDOW);
    let mut converted: u64 = 0;
    for b in 0..BATCHES {
        converted += BATCH_FRAMES as u64;
        log.out.at_frame(converted);
        if b == OVERRUN_BATCH {
            for _ in 0..BATCH_FRAMES {
                sensor.next_frame().map_err(|_| "the sensor model halted")?;
            }
            book.overrun(&mut log);
            continue;
        }
        // the e-stop task's records come before the batch that sees the input
        if b == ESTOP_BATCHES.start {
            log.record(&Record::Input { name: "estop", active: true });
        }
        if b == ESTOP_BATCHES.end {
            log.record(&Record::Input { name: "estop", active: false });
        }
        let digital = DigitalInputs { estop: ESTOP_BATCHES.contains(&b), end_of_stroke: false };
        let mut press = b == 0 || b == RESET_BATCH;
        for _ in 0..BATCH_FRAMES {
            let frame = if b < CLAMP_BATCHES {
                let mut f = sensor.quiet_frame();
                f.counts[stickslip_model::rig::ACTUATOR + stickslip_model::rig::ACCEL_CHANNELS] = filling;
                f
            } else {
                let mut f = sensor.next_frame().map_err(|_| "the sensor model halted")?;
                f.counts[DEAD_CHANNEL] = dead;
                f
            };
            let command = if press {
                press = false;
                Some(button_command(rig.state()))
            } else {
                None
            };
            // the sensor model gives the frame's sum of the four conversions: the first scan
            // carries it, the other three read 0 (the same sum through the decimation)
            let mut words = [0u16; OVERSAMPLE as usize * CHANNELS];
            words[..CHANNELS].copy_from_slice(&frame.counts);
            let o = sample_words(rig, &words, &digital, command);
            book.sample(&mut log, rig, command, &o);
        }
        book.end_batch(&mut log, rig, 0);
    }
    Ok(SessionSummary { frames: book.frames(), records: log.records })
}

/// Builds a rig in a slot of its own frame (dropped on return): for the refused boot.
#[inline(never)]
fn build(cfg: &RigConfig) -> Result<(), RigError> {
    let mut slot = core::mem::MaybeUninit::uninit();
    Rig::init(&mut slot, cfg).map(|_| ())
}
