//! The actuator line's pressure and the normal load it puts on the pad.
//!
//! The pneumatic actuator is a single-acting piston: F_N = p A, with p the line's gauge
//! pressure [Pa] and A the piston area [m^2]. The default area makes the thesis's 5 bar give the
//! default scene's 150 N (docs/model.md): A = 150 N / 5e5 Pa = 3.0e-4 m^2 (a 19.5 mm bore).
//! Seal friction and the return spring (if any) are ignored.

/// Pascals per bar.
pub const PA_PER_BAR: f64 = 1e5;

/// The rig actuator's piston area [m^2]: 5 bar gives 150 N.
pub const RIG_PISTON_AREA_M2: f64 = 3.0e-4;

/// Normal load F_N = p A [N] from the actuator line pressure [bar] and the piston area [m^2].
pub fn normal_load_n(actuator_bar: f64, piston_area_m2: f64) -> f64 {
    actuator_bar * PA_PER_BAR * piston_area_m2
}

/// Actuator line pressure [bar] that gives the normal load `f_n` [N] on a piston of area
/// `piston_area_m2` [m^2].
pub fn actuator_bar_for(f_n: f64, piston_area_m2: f64) -> f64 {
    f_n / (piston_area_m2 * PA_PER_BAR)
}
