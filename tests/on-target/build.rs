//! Puts the repository's memory.x (the STM32F407VG memory map, shared with firmware/)
//! where cortex-m-rt's link.x finds it: this crate's OUT_DIR, added to the link search path.
//!
//! Also makes the frames of `src/bin/rig_count.rs` on the host (OUT_DIR/rig_count_frames.bin,
//! six little-endian u16 counts per frame): the sensor model for the push caliper with the load
//! at the pad centre, 0.5 m/s^2 and 0.005 bar of noise (seed 2024), [`RIG_COUNT_FRAMES`]
//! frames, enough for the first window of a record that starts at the third frame to close.
//! Making them here keeps the sensor model's f64 set-up out of the instruction trace.

use std::env;
use std::fs;
use std::path::PathBuf;

use stickslip_model::harness::sensor_model::{Noise, SensorModel, SensorModelConfig};
use stickslip_model::{Caliper, Scene};

const RIG_COUNT_FRAMES: usize = 2_600;

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let memory_x = manifest.join("..").join("..").join("memory.x");
    fs::copy(&memory_x, out.join("memory.x")).unwrap_or_else(|e| panic!("cannot copy {}: {e}", memory_x.display()));
    println!("cargo:rustc-link-search={}", out.display());
    // defmt's linker script, for the one program that logs with defmt
    println!("cargo:rustc-link-arg-bin=records=-Tdefmt.x");
    println!("cargo:rerun-if-changed={}", memory_x.display());
    println!("cargo:rerun-if-changed=build.rs");

    let mut cfg = SensorModelConfig::RIG;
    cfg.noise = Noise { accel_rms_m_s2: 0.5, pressure_rms_bar: 0.005, seed: 2024, adc_rms_counts: 0.0 };
    let scene = Scene::case(Caliper::Push, 0.040);
    let mut sensor = SensorModel::<f32>::new(&scene, &cfg).expect("the default scene makes frames");
    let mut bytes = Vec::with_capacity(RIG_COUNT_FRAMES * 12);
    for i in 0..RIG_COUNT_FRAMES {
        let frame = sensor.next_frame().unwrap_or_else(|h| panic!("sensor model halted at frame {i}: {h:?}"));
        for c in frame.counts {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    fs::write(out.join("rig_count_frames.bin"), bytes).expect("cannot write the rig_count frames");
}
