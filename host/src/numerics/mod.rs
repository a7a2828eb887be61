//! The numerics reports and what they measure against: the work-precision report
//! ([`accuracy`]), the stiff and extreme sweeps ([`stability`]), the independent reference
//! simulations of the thesis model ([`reference`]) and of model 2 ([`reference2`]), and the
//! f32 exponentials compared ([`exp_variants`]).

pub mod accuracy;
pub mod exp_variants;
pub mod reference;
pub mod reference2;
pub mod stability;
