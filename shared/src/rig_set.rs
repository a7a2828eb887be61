//! Model 2's rig set: the six cases with model 2 on (docs/model.md, "The rig set"): the
//! default pad with falling (Stribeck) friction, the band as a mass on its drive, and a few
//! percent of damping on every degree of freedom. Defined here so that the host's built-in
//! scenes (`rig_*`) and a firmware built for the rig set (feature `model2`) run the same pad.
//! Every model-2 value is a guess until it is fitted to the rig's Table 3.1.

use crate::coefficients::Coefficients;
use crate::scene::{Caliper, FrictionLaw, Scene};

/// Rig set, guessed: Stribeck velocity [m/s].
pub const RIG_V_S: f64 = 0.002;
/// Rig set, guessed: band and carriage mass [kg].
pub const RIG_M_B: f64 = 2.0;
/// Rig set, guessed: band drive (cylinder and linkage) stiffness [N/m].
pub const RIG_K_B: f64 = 1e6;
/// Rig set, guessed: damping ratio of the band drive [-].
pub const RIG_ZETA_B: f64 = 0.05;
/// Rig set, guessed: damping ratio of the pad's x and rotation [-].
pub const RIG_ZETA: f64 = 0.02;

/// The rig set's scene for one case.
pub fn rig_scene(caliper: Caliper, beta: f64) -> Scene {
    let mut s = Scene::case(caliper, beta);
    s.friction = FrictionLaw::Stribeck;
    s.v_s = RIG_V_S;
    s.stribeck_exponent = 1.0;
    s.band = true;
    s.m_b = RIG_M_B;
    s.k_b = RIG_K_B;
    s.c_b = 2.0 * RIG_ZETA_B * libm::sqrt(s.k_b * s.m_b);
    s.c_x = 2.0 * RIG_ZETA * libm::sqrt(s.k_g * s.m);
    s.c_phi = 2.0 * RIG_ZETA * libm::sqrt(Coefficients::of(&s).k_rot * s.inertia);
    s
}

/// Rig set, part 2: the pivot's stiffness normal to the band [N/m]: 0, a floating pad (the
/// rig's pad rests on the band, pressed by the actuator; the guide holds it along x only).
pub const RIG_K_PIVOT: f64 = 0.0;

/// The rig set with model 2's part 2 (docs/model.md, "Model 2, part 2"): friction-face
/// kinematics and the floating pad, the bounce damped like the other degrees of freedom
/// (c_y = 2 RIG_ZETA sqrt((k_L + k_T) m)). A set of its own beside [`rig_scene`]: the firmware's
/// `model2` build keeps part 1's composition.
pub fn rig_float_scene(caliper: Caliper, beta: f64) -> Scene {
    let mut s = rig_scene(caliper, beta);
    s.face = true;
    s.k_pivot = RIG_K_PIVOT;
    s.c_y = 2.0 * RIG_ZETA * libm::sqrt((s.k_l + s.k_t) * s.m);
    s
}

/// The quiet rig set: kinetic friction just under the static [-] (mu_s - mu_k = 0.003).
pub const QUIET_MU_K: f64 = 0.447;
/// The quiet rig set: band speed [m/s].
pub const QUIET_V_M_S: f64 = 0.001;

/// The rig set at Table 3.1's signal levels: [`rig_scene`] with mu_k = 0.447 (0.003 under
/// mu_s) and the band at 1 mm/s. Its pad_x peak-to-peak is 2.1 to 3.7 m/s^2 over the six
/// cases (Table 3.1: 1.2 to 4), its stick-slip 93 to 124 Hz with stick fractions of 0.20 to
/// 0.47 (`stickslip sil rig_quiet_CASE --front-end ideal`): a set for the estimator at the
/// rig's real levels, not a fit.
pub fn rig_quiet_scene(caliper: Caliper, beta: f64) -> Scene {
    let mut s = rig_scene(caliper, beta);
    s.mu_k = QUIET_MU_K;
    s.v = QUIET_V_M_S;
    s
}
