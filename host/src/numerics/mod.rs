//! The numerics reports and what they measure against: the work-precision report
//! ([`accuracy`]), the stiff and extreme sweeps ([`stability`]), the independent reference
//! simulations of the thesis model and of model 2 ([`reference`]), and the
//! f32 exponentials compared ([`exp_variants`]).

pub mod accuracy;
pub mod exp_variants;
pub mod reference;
pub mod stability;
