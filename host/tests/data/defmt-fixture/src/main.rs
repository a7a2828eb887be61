//! A defmt stream with known content for the host's `decode` tests: the log lines of the rig
//! firmware (firmware/src/main.rs, format strings copied verbatim) with fixed values, over
//! defmt-semihosting, under a timestamp that counts 1000 us per frame. The host test
//! (host/tests/recorded_decode.rs) checks the decoded records against the values below.
#![no_std]
#![no_main]

use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m_rt::entry;
use cortex_m_semihosting::debug;
use defmt::{error, info, warn};
use defmt_semihosting as _;

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
    info!("stickslip firmware {=str}: STM32F407VG at {=u64} Hz", "0.1.0", 168_000_000u64);
    info!(
        "ExactStepper<f32> built in {=u64} us: {=str} caliper, beta {=f64} m, {=u32} substep(s) per step",
        1234u64,
        "push",
        0.04f64,
        1u32
    );
    info!(
        "stepping every {=u64} ticks of {=u64} Hz: {=u64} Hz (model dt 1/{=u64} s)",
        39u64,
        1_000_000u64,
        25_641u64,
        25_600u64
    );
    for k in 0..3u32 {
        let t = 0.125 * (k + 1) as f64;
        let (from, to) = if k % 2 == 0 { ("stick", "slip_slower") } else { ("slip_slower", "stick") };
        info!(
            "t={=f64} s {=str} -> {=str}: x={=f32} m x'={=f32} m/s phi={=f32} rad",
            t,
            from,
            to,
            0.000_25 * (k + 1) as f32,
            -0.5 * k as f32,
            0.002_75f32
        );
    }
    info!(
        "model t={=f64} s (wall {=u64} us): {=u32} transitions ({=u32} logged), regime {=str}, x={=f32} m, phi={=f32} rad",
        1.0f64,
        1_000_123u64,
        48u32,
        8u32,
        "stick",
        0.000_5f32,
        0.002_75f32
    );
    info!(
        "step cost: mean {=u64} max {=u32} cycles of {=u64} per tick; latest tick {=u64} ticks late, {=u32} overruns",
        812u64,
        2301u32,
        6552u64,
        3u64,
        0u32
    );
    warn!("core peripherals already taken: step cycle counts will read 0");
    // records in the layout of firmware/src/records.rs (format strings copied verbatim)
    info!(
        "event n={=u64} rec={=u32} sample={=u64} kind={=str} v_r={=f32} a_rel={=f32}",
        51_200u64,
        1u32,
        25_600u64,
        "stick_to_slip",
        -0.001_5f32,
        -24.5f32
    );
    let pp: [f32; 4] = [3.25, 80.5, 12.0, 150.75];
    let rms: [f32; 4] = [0.5, 10.25, 2.5, 30.0];
    let groan: [f32; 4] = [0.125, 8.5, 2.0, 25.5];
    let p_mean: [f32; 2] = [5.0, 0.65];
    let p_min: [f32; 2] = [4.875, 0.625];
    let p_max: [f32; 2] = [5.125, 0.6875];
    info!(
        "window n={=u64} rec={=u32} idx={=u32} first={=u64} samples={=u32} valid={=u32} pp={} rms={} groan_rms={} stick={=f32} ss_hz={=f32} onsets={=u32} saturated={=u32} faulted={=u32} nonfinite={=bool} model={=bool} model_samples={=u32} model_stick={=f32} model_ss_hz={=f32} model_onsets={=u32} residual_rms={=f32} model_halt={=str} p_mean={} p_min={} p_max={} state={=str} overruns={=u32} events_dropped={=u32} windows_dropped={=u32} batch_cyc_max={=u32} batch_cyc_budget={=u32}",
        53_760u64,
        1u32,
        20u32,
        51_200u64,
        2560u32,
        2560u32,
        pp,
        rms,
        groan,
        0.8125f32,
        48.5f32,
        5u32,
        0u32,
        0u32,
        false,
        true,
        2560u32,
        0.8046875f32,
        48.75f32,
        5u32,
        1.5f32,
        "none",
        p_mean,
        p_min,
        p_max,
        "record",
        0u32,
        0u32,
        0u32,
        41_000u32,
        65_625u32
    );
    error!("model halted at t={=f64} s: contact lost (N = {=f64} N)", 0.75f64, -1.25f64);
    debug::exit(debug::EXIT_SUCCESS);
    loop {}
}
