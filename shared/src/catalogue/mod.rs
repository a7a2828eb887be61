//! The catalogue of built-in scenes: the thesis-sized default pad, the six cases (caliper x
//! load position), the closed-form oracle, and model 2's rig set ([`rig_set`]). Scenes as
//! values, built on the plain data and validation of [`crate::scene`] (which imports nothing
//! from here) and on [`crate::coefficients`] (the oracle's load is set from its coefficients).

pub mod rig_set;

use crate::coefficients::Coefficients;
use crate::design::SAMPLE_RATE_HZ;
#[cfg(feature = "model3")]
use crate::scene::{BandDrive, ContactLaw};
use crate::scene::{Caliper, FrictionLaw, Scene};

/// The thesis-sized pad of docs/model.md (80 mm pad, 5 bar actuator, slow band).
pub const DEFAULT_SCENE: Scene = Scene {
    caliper: Caliper::Push,
    m: 0.3,
    inertia: 6.8e-4,
    l: 0.04,
    w: 0.01,
    l_cl: 0.03,
    l_ct: 0.025,
    k_l: 1e6,
    k_t: 1e6,
    k_g: 2e5,
    f_n: 150.0,
    beta: 0.040,
    v: 0.005,
    mu_s: 0.45,
    mu_k: 0.35,
    c_x: 0.0,
    c_phi: 0.0,
    rotation: true,
    friction: FrictionLaw::Coulomb,
    v_s: 0.005,
    stribeck_exponent: 1.0,
    band: false,
    m_b: 2.0,
    k_b: 1e6,
    c_b: 0.0,
    face: false,
    k_pivot: f64::INFINITY,
    c_y: 0.0,
    #[cfg(feature = "model3")]
    contact: ContactLaw::Bilateral,
    #[cfg(feature = "model3")]
    contact_exponent: 1.0,
    #[cfg(feature = "model3")]
    contact_ref_load: 75.0,
    #[cfg(feature = "model3")]
    drive: BandDrive::Velocity,
    #[cfg(feature = "model3")]
    bore: 0.040,
    #[cfg(feature = "model3")]
    supply_pressure: 6.0e5,
    #[cfg(feature = "model3")]
    throttle_conductance: 0.0,
    #[cfg(feature = "model3")]
    throttle_critical_ratio: 0.5,
    #[cfg(feature = "model3")]
    column_length: 0.05,
    #[cfg(feature = "model3")]
    polytropic_exponent: 1.2,
    #[cfg(feature = "model3")]
    seal_static: 80.0,
    #[cfg(feature = "model3")]
    seal_kinetic: 60.0,
    #[cfg(feature = "model3")]
    seal_v_s: 0.005,
    dt: 1.0 / SAMPLE_RATE_HZ,
    duration: 1.0,
    stats_from: 0.5,
};

/// Load positions of the six cases [m from the trailing edge]: trailing, centre, leading.
pub const CASE_BETAS: [(&str, f64); 3] = [("trail", 0.025), ("center", 0.040), ("lead", 0.055)];

impl Default for Scene {
    /// [`DEFAULT_SCENE`].
    fn default() -> Self {
        DEFAULT_SCENE
    }
}

impl Scene {
    /// One of the six cases: the default pad with the given caliper and load position.
    pub const fn case(caliper: Caliper, beta: f64) -> Scene {
        let mut s = DEFAULT_SCENE;
        s.caliper = caliper;
        s.beta = beta;
        s
    }

    /// Normal force of [`Scene::oracle_1dof`], N0 = c_N F_N a_N / K [N].
    pub const ORACLE_N0: f64 = 10.0;

    /// The closed-form check of docs/model.md: the 1-DOF mass on a moving belt (rotation held,
    /// so N is constant): m = 1 kg, k_g = 100 N/m, V = 0.05 m/s, mu_s = 0.6, mu_k = 0.4, and F_N
    /// chosen so that N0 = 10 N; a 6 s run (first breakaway at 1.2 s, then four cycles), the
    /// statistics over [1.3, 6] s.
    pub fn oracle_1dof() -> Scene {
        let mut s = Scene::case(Caliper::Push, 0.040);
        s.rotation = false;
        s.m = 1.0;
        s.k_g = 100.0;
        s.v = 0.05;
        s.mu_s = 0.6;
        s.mu_k = 0.4;
        s.duration = 6.0;
        s.stats_from = 1.3;
        let co = Coefficients::of(&s);
        s.f_n = Self::ORACLE_N0 * co.k_rot / (co.c_n * co.a_n);
        s
    }
}
