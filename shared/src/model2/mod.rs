//! Model 2 (docs/model.md, "Model 2"): Stribeck friction, the band as a degree of freedom,
//! damping on every degree of freedom, friction-face kinematics, on top of the thesis model.
//!
//! - [`system`]: the equations as matrices and rows (state x, x', phi, phi', u, u').
//! - [`composition`]: which options a stepper is compiled for (band; Stribeck or Coulomb; face).
//! - [`stepper`]: the fixed-step stepper (exact flows for the linear regimes, ETDRK4 for
//!   Stribeck slip, in-step transitions and crests), generic over its composition.
//! - [`event_run`]: statistics at event speed (exact flows and an error-controlled Runge-Kutta
//!   pair from event to event, no samples on the grid; host runs that need only statistics).
//! - [`any`]: the stepper of the composition a scene asks for, chosen at run time (host).
//! - [`stats`]: window statistics of a model-2 run (extremes inside segments by cubic Hermite
//!   interpolation of the state and its derivative).
//!
//! The stick-slip state machine is the thesis's ([`crate::stickslip::Regime`] and its
//! transition table, with the sliding velocity and the required force of model 2).
pub mod any;
pub mod composition;
pub mod event_run;
pub mod stats;
pub mod stepper;
pub mod system;

pub use any::{AnyModel2Stepper, Owned, Shared, TableStore};
pub use composition::{
    Band, BandFace, Composition, Coulomb, CoulombFace, FloatFace, Stribeck, StribeckBand, StribeckBandFace, StribeckFace,
    StribeckFloatFace,
};
pub use stats::{Model2Stats, Model2StatsObserver};
pub use stepper::{Model2Observer, Model2Segment, Model2State, Model2Stepper, Model2Tables, Model2Transition, WideSamples, WideChunks, WIDE_MAX};
pub use system::{System, NA, NS, Y};
