//! The translating friction element: a 2-DOF brake pad (translation x, rotation phi) pressed
//! on a band moving at constant speed, with stick and two slip regimes (docs/model.md).
//!
//! `no_std`, no allocation, no panics on a validated scene: the same code runs on the rig's
//! Cortex-M4F and in the desktop tool.
//!
//! - [`design`]: the rig's design constants (sample rate, window, range): a leaf every layer reads.
//! - [`scene`]: parameters (plain data) and their validation.
//! - [`catalogue`]: the built-in scenes: the default pad, the six cases, the oracle, model 2's
//!   rig set ([`rig_set`]).
//! - [`coefficients`]: lever arms, rotational stiffness, normal-force gain.
//! - [`friction`]: the Coulomb law.
//! - [`stickslip`]: the regimes and their transitions (the state machine).
//! - [`propagator`]: exact flows of each regime on a dyadic grid.
//! - [`exact`]: the fixed-step exact stepper.
//! - [`expf`]: the f32 exponential of Stribeck slip (small and exact on the Cortex-M4F).
//! - [`model2`]: model 2 (Stribeck friction, the band, damping), stepper per composition.
//! - [`rig`]: the per-sample chain the firmware runs (calibration, estimator, sequencer).
//! - [`harness`]: the rig's simulation harness (sensor model, replay digests, random numbers).
//! - [`stats`]: run statistics with exact extremes (peak-to-peak, stick fraction, frequency).
#![no_std]
#![forbid(unsafe_code)]
// `!(a < b)` is deliberate throughout: it is true for NaN, which must count as a fired guard.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Units are written in brackets in doc comments (`[kg]`, `[N/m]`), not links.
#![allow(rustdoc::broken_intra_doc_links)]

pub mod catalogue;
pub mod coefficients;
pub mod design;
pub mod digest;
pub mod exact;
pub mod exp64;
pub mod expf;
pub mod friction;
pub mod halt;
pub mod harness;
pub mod linalg;
pub mod methods;
pub mod model2;
#[cfg(feature = "model3")]
pub mod model3;
pub mod propagator;
pub mod real;
pub mod rig;
pub mod scene;
pub mod stats;
pub mod stickslip;

pub use coefficients::Coefficients;
pub use exact::{ExactState, ExactStepper, ExactTables, Halt, Observer, Segment, State, StickJump, Transition};
pub use real::Real;
pub use catalogue::{rig_set, DEFAULT_SCENE};
pub use scene::{BandDrive, Caliper, ContactLaw, FrictionLaw, Scene, SceneError};
pub use stickslip::Regime;
