//! The pneumatic band drive's parts (model 3, option 1; docs/model.md, "Model 3, part 3"): the
//! air column, the throttle that feeds it, and the cylinder seal's friction. SI units, absolute
//! pressures.
//!
//! ```text
//! A = pi D^2 / 4,   V_c = A (L_0 + x_b)                          chamber volume
//! p' = n / V_c (R T m' - p A x_b')                               polytropic, inflow at T_0
//! R T m' = p_ref C p_s phi(p / p_s)                              ISO 6358 throttle
//! phi(r) = 1 for r <= b, sqrt(1 - ((r - b) / (1 - b))^2) for b < r < 1, 0 for r >= 1
//! m_b x_b'' = A (p - p_atm) - F_seal - c_b x_b' - F             the band (F: the pad's friction)
//! F_seal = sign(x_b') (F_sk + (F_ss - F_sk) exp(-|x_b'| / v_ss)) sliding; |net| <= F_ss stuck
//! ```
//!
//! p_ref = 1e5 Pa is ISO 8778's reference atmosphere (R T_0 rho_0 = p_ref at 20 C), so that
//! C is the standard's sonic conductance [m^3/(s Pa)] with the supply at T_0.

use crate::coefficients::Coefficients;
use crate::scene::{BandDrive, FrictionLaw, Scene, SceneError, ATMOSPHERE_PA};

/// ISO 8778's reference pressure [Pa]: R T_0 rho_0 for the ANR atmosphere.
pub const P_REF: f64 = 1e5;

/// The cylinder's constants, from a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cylinder {
    /// Piston area A [m^2].
    pub area: f64,
    /// Supply pressure p_s (absolute) [Pa].
    pub p_s: f64,
    /// Sonic conductance C [m^3/(s Pa)] (given, or solved from V).
    pub conductance: f64,
    /// Whether `conductance` was solved from V ([`Cylinder::of`]).
    pub solved: bool,
    /// Critical pressure ratio b [-].
    pub b: f64,
    /// Air column length at the start L_0 [m].
    pub l0: f64,
    /// Polytropic exponent n [-].
    pub n: f64,
    /// Seal: static F_ss, kinetic F_sk [N], Stribeck velocity v_ss [m/s].
    pub f_ss: f64,
    pub f_sk: f64,
    pub v_ss: f64,
    /// The band's damping on its guides c_b [N s/m].
    pub c_b: f64,
}

impl Cylinder {
    /// The cylinder of `scene` (validated); with `throttle_conductance` = 0 the conductance is
    /// solved so that steady sliding at V draws the air it needs: at the steady pressure
    /// p_0 = p_atm + (F_seal(V) + F_pad + c_b V) / A, with `pad_friction` F_pad [N] the pad's
    /// friction at V, the throttle passes p_0 A V. Error (field `supply_pressure`): the supply
    /// cannot hold p_0.
    pub fn of(scene: &Scene, pad_friction: f64) -> Result<Cylinder, SceneError> {
        let area = core::f64::consts::PI * scene.bore * scene.bore / 4.0;
        let mut c = Cylinder {
            area,
            p_s: scene.supply_pressure,
            conductance: scene.throttle_conductance,
            solved: false,
            b: scene.throttle_critical_ratio,
            l0: scene.column_length,
            n: scene.polytropic_exponent,
            f_ss: scene.seal_static,
            f_sk: scene.seal_kinetic,
            v_ss: scene.seal_v_s,
            c_b: scene.c_b,
        };
        if c.conductance == 0.0 {
            let p0 = c.steady_pressure(scene.v, pad_friction);
            let phi = c.flow_fraction(p0);
            if !(p0 < c.p_s && phi > 0.0) {
                return Err(SceneError {
                    field: "supply_pressure",
                    rule: "the supply cannot push the band's load at v: steady sliding needs more than the supply pressure (raise supply_pressure or the bore, or lower the seal friction)",
                    value: c.p_s,
                });
            }
            c.conductance = p0 * area * scene.v / (P_REF * c.p_s * phi);
            c.solved = true;
        }
        Ok(c)
    }

    /// The chamber pressure at which the cylinder holds steady sliding at `v` [m/s] against
    /// `pad_friction` [N]: p_atm + (F_seal(v) + F_pad + c_b v) / A [Pa].
    pub fn steady_pressure(&self, v: f64, pad_friction: f64) -> f64 {
        ATMOSPHERE_PA + (self.seal_friction(v) + pad_friction + self.c_b * v) / self.area
    }

    /// The fraction of the choked flow the throttle passes at chamber pressure `p` [Pa]
    /// (ISO 6358's elliptic law; 0 once p reaches the supply: a meter-in throttle with a check
    /// valve, no backflow).
    pub fn flow_fraction(&self, p: f64) -> f64 {
        let r = p / self.p_s;
        if r <= self.b {
            1.0
        } else if r < 1.0 {
            let x = (r - self.b) / (1.0 - self.b);
            libm::sqrt(1.0 - x * x)
        } else {
            0.0
        }
    }

    /// R T m', the throttle's inflow as p V-power [Pa m^3/s], at chamber pressure `p` [Pa].
    pub fn inflow(&self, p: f64) -> f64 {
        P_REF * self.conductance * self.p_s * self.flow_fraction(p)
    }

    /// Chamber volume [m^3] with the band at `x_b` [m] from its start.
    pub fn volume(&self, x_b: f64) -> f64 {
        self.area * (self.l0 + x_b)
    }

    /// p' [Pa/s] at pressure `p`, band position `x_b` and velocity `w` = x_b'.
    pub fn pressure_rate(&self, p: f64, x_b: f64, w: f64) -> f64 {
        self.n / self.volume(x_b) * (self.inflow(p) - p * self.area * w)
    }

    /// The air's force on the piston less the atmosphere's, A (p - p_atm) [N].
    pub fn force(&self, p: f64) -> f64 {
        self.area * (p - ATMOSPHERE_PA)
    }

    /// The seal's friction magnitude sliding at speed `w` [m/s] [N].
    pub fn seal_friction(&self, w: f64) -> f64 {
        self.f_sk + (self.f_ss - self.f_sk) * libm::exp(-libm::fabs(w) / self.v_ss)
    }

    /// The air column's small-signal stiffness n p A^2 / V_c [N/m] at pressure `p`, band at
    /// `x_b`: today's band spring k_b in the small-signal limit.
    pub fn column_stiffness(&self, p: f64, x_b: f64) -> f64 {
        self.n * p * self.area * self.area / self.volume(x_b)
    }
}

/// The pad's friction force in steady sliding at the scene's V [N]: mu(V) N_0 (the load the
/// throttle is solved for), N_0 the static normal force under the load: c_N phi_0 on the
/// hinged pad, (k_L + k_T) y_0 + c_N phi_0 on the floating one (F_N itself with k_pivot = 0).
pub fn steady_pad_friction(scene: &Scene) -> f64 {
    let mu_v = match scene.friction {
        FrictionLaw::Coulomb => scene.mu_k,
        FrictionLaw::Stribeck => scene.mu_k + (scene.mu_s - scene.mu_k) * libm::exp(-libm::pow(scene.v / scene.v_s, scene.stribeck_exponent)),
    };
    let linear = scene.linearised_contact();
    let co = Coefficients::of(&linear);
    let n0 = if linear.floating() {
        let (y0, phi0) = co.floating_rest(&linear);
        (linear.k_l + linear.k_t) * y0 + co.c_n * phi0
    } else {
        co.n0
    };
    mu_v * n0
}

/// The pneumatic scene's small-signal equivalent (docs/model.md, "Model 3, part 3"): the band
/// driven at V through the air column's stiffness at the steady pressure, k_b = n p_0 A / L_0,
/// with the guides' damping less the seal friction's slope at V, c_b + dF_seal/dw (negative
/// where the seal's friction falls faster than the guides damp). The column's relaxation
/// (rate n V / L_0) is left out. What the linear stability of steady sliding is taken of.
/// `scene` itself if its band is driven at V.
pub fn small_signal_scene(scene: &Scene) -> Result<Scene, SceneError> {
    if !scene.pneumatic() {
        return Ok(*scene);
    }
    let pad_friction = steady_pad_friction(scene);
    let cyl = Cylinder::of(scene, pad_friction)?;
    let p0 = cyl.steady_pressure(scene.v, pad_friction);
    let mut s = *scene;
    s.drive = BandDrive::Velocity;
    s.k_b = cyl.column_stiffness(p0, 0.0);
    s.c_b = cyl.c_b - (cyl.f_ss - cyl.f_sk) / cyl.v_ss * libm::exp(-scene.v / cyl.v_ss);
    Ok(s)
}
