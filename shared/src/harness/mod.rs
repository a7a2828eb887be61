//! The rig's simulation harness: what the tests, the virtual rig and the host == Cortex-M4F
//! cross-checks run around the per-sample chain ([`crate::rig`]), apart from that chain (the
//! firmware runs the chain, not this).
//!
//! - [`prng`]: a seeded xorshift generator for deterministic noise.
//! - [`sensor_model`]: model motion to frames (accelerometer geometry, noise, clipping, ADC).
//! - [`replay`]: a synthetic run digested with FNV-1a, for bit-identity checks.

pub mod prng;
pub mod replay;
pub mod sensor_model;
