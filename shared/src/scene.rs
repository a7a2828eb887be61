//! Scene parameters: one rig configuration plus the run settings, and their validation.
//!
//! All values are SI (kg, m, N, s, rad). A scene is plain data in `f64`; the steppers round the
//! derived coefficients to their own precision. [`Scene::validate`] names the offending field
//! and the rule it breaks, so a user's edited scene file gets a precise message.
//!
//! Scenes as data only: the built-in scenes (the default pad, the six cases, the oracles,
//! model 2's rig set) are in [`crate::catalogue`], beside this module.

/// Where the pad's frictional guide (and so the rotation pivot) sits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Caliper {
    /// Guide at the trailing edge: the band pushes the pad against it.
    Push,
    /// Guide at the leading edge: the band pulls the pad away from the load side.
    Pull,
}

impl Caliper {
    pub const fn name(self) -> &'static str {
        match self {
            Caliper::Push => "push",
            Caliper::Pull => "pull",
        }
    }
}

/// The friction law in slip (docs/model.md, "Model 2", option 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrictionLaw {
    /// The thesis's law: mu_s holds in stick, mu_k in slip.
    Coulomb,
    /// Falling friction: mu(v) = mu_k + (mu_s - mu_k) exp(-(|v| / v_s)^delta), continuous at
    /// breakaway (mu(0+) = mu_s).
    Stribeck,
}

impl FrictionLaw {
    pub const fn name(self) -> &'static str {
        match self {
            FrictionLaw::Coulomb => "coulomb",
            FrictionLaw::Stribeck => "stribeck",
        }
    }
}

/// How the edge contact springs of a pad that is not hinged act (model 3, option 2; issue 34).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactLaw {
    /// Each spring pushes and pulls (model 2): a spring that would pull halts the run with
    /// `contact_loss`.
    Bilateral,
    /// Each spring pushes and never pulls, F_i = k_i max(0, d_i): an edge opens (a regime with
    /// its own linear flow) and closes again. Runs on the host's event-driven path in f64 only.
    Unilateral,
}

/// How the band is driven (model 3, option 1; issue 34).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BandDrive {
    /// The band's drive point moves at exactly V (models 1 and 2; with `band`, through k_b and
    /// c_b).
    Velocity,
    /// A throttled pneumatic cylinder pushes the band (a mass m_b) through its air column
    /// against the cylinder's seal friction; the band's speed emerges (docs/model.md, "Model 3,
    /// part 3"). Needs `band`; runs event-driven in f64 on the host.
    Pneumatic,
}

impl BandDrive {
    pub const fn name(self) -> &'static str {
        match self {
            BandDrive::Velocity => "velocity",
            BandDrive::Pneumatic => "pneumatic",
        }
    }
}

impl ContactLaw {
    pub const fn name(self) -> &'static str {
        match self {
            ContactLaw::Bilateral => "bilateral",
            ContactLaw::Unilateral => "unilateral",
        }
    }
}

/// One scene: the pad, the contact, the load, the band and the run settings.
///
/// Symbols follow docs/model.md. Pad length is `2 l`, thickness `2 w`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scene {
    pub caliper: Caliper,
    /// Pad mass m [kg].
    pub m: f64,
    /// Moment of inertia about the pivot (supported edge, mid-thickness) I [kg m^2].
    pub inertia: f64,
    /// Pad half-length l [m].
    pub l: f64,
    /// Pad half-thickness w [m] (friction face to pivot line).
    pub w: f64,
    /// Distance from the centre of gravity to the leading contact spring l_cL [m].
    pub l_cl: f64,
    /// Distance from the centre of gravity to the trailing contact spring l_cT [m].
    pub l_ct: f64,
    /// Leading contact spring stiffness k_L [N/m].
    pub k_l: f64,
    /// Trailing contact spring stiffness k_T [N/m].
    pub k_t: f64,
    /// Guide (abutment) stiffness along x, k_g [N/m].
    pub k_g: f64,
    /// Normal load F_N [N].
    pub f_n: f64,
    /// Load position, distance from the trailing edge, beta [m], in [0, 2 l].
    pub beta: f64,
    /// Band speed V [m/s], > 0.
    pub v: f64,
    /// Static friction coefficient mu_s [-].
    pub mu_s: f64,
    /// Kinetic friction coefficient mu_k [-], 0 <= mu_k <= mu_s.
    pub mu_k: f64,
    /// Viscous damping on x, c_x [N s/m].
    pub c_x: f64,
    /// Viscous damping on phi, c_phi [N m s/rad].
    pub c_phi: f64,
    /// `false` holds phi at its static value F_N a_N / K (the 1-DOF mass on a moving belt,
    /// N constant): the rotation is left out of the step entirely.
    pub rotation: bool,
    /// Friction law in slip ([`FrictionLaw::Coulomb`]: the thesis model).
    pub friction: FrictionLaw,
    /// Stribeck velocity v_s [m/s], > 0 (read only with [`FrictionLaw::Stribeck`]).
    pub v_s: f64,
    /// Stribeck exponent delta [-], > 0 (read only with [`FrictionLaw::Stribeck`]).
    pub stribeck_exponent: f64,
    /// `true`: the band is a mass m_b driven at V through the cylinder's k_b, c_b
    /// (docs/model.md, "Model 2", option 3); `false`: the band moves at exactly V.
    pub band: bool,
    /// Band mass m_b [kg] (read only with `band`).
    pub m_b: f64,
    /// Band drive stiffness k_b [N/m] (read only with `band`).
    pub k_b: f64,
    /// Band drive damping c_b [N s/m] (read only with `band`).
    pub c_b: f64,
    /// `true`: friction-face kinematics (docs/model.md, "Model 2", option 4): the face slides
    /// at x' + s w phi' less the band's velocity, and stick holds that sliding velocity at zero
    /// (x and phi coupled); `false`: the thesis's pivot kinematics, x' less the band's velocity.
    pub face: bool,
    /// Stiffness of the pivot normal to the band, k_pivot [N/m] (docs/model.md, "Model 2",
    /// option 5): infinite (the default) is the thesis's hinge; finite, the pad also translates
    /// normal to the band (y), carried by the contact springs and held at the pivot through
    /// k_pivot; 0 is a floating pad. A finite k_pivot needs `face` and the rotation.
    pub k_pivot: f64,
    /// Viscous damping on the pad's normal translation y, c_y [N s/m] (read only with a finite
    /// `k_pivot`).
    pub c_y: f64,
    /// The edge springs' law ([`ContactLaw::Bilateral`], the default: model 2). Unilateral
    /// contact needs a pad that is not hinged (finite `k_pivot`).
    #[cfg(feature = "model3")]
    pub contact: ContactLaw,
    /// Exponent p of the edge springs' load law F = k0 d^p (model 3, option 3; 1, the default:
    /// linear springs, the option off). With p > 1 each spring's stiffness is the law's tangent
    /// at the static load it carries, k_i (F_i / F_ref)^((p - 1) / p) with k_i = `k_l`, `k_t`
    /// the tangent at the reference load F_ref = `contact_ref_load`
    /// ([`Scene::contact_stiffnesses`]): a contact that stiffens with load, linearised about
    /// the static state.
    #[cfg(feature = "model3")]
    pub contact_exponent: f64,
    /// The reference load F_ref [N] at which `k_l` and `k_t` are the springs' tangent
    /// stiffness (read only with `contact_exponent` > 1).
    #[cfg(feature = "model3")]
    pub contact_ref_load: f64,
    /// How the band is driven ([`BandDrive::Velocity`], the default). With
    /// [`BandDrive::Pneumatic`] the cylinder's keys below act, `k_b` does not (the air column
    /// is the drive's spring) and `c_b` is the band's viscous damping on its guides (to the
    /// frame, -c_b x_b').
    #[cfg(feature = "model3")]
    pub drive: BandDrive,
    /// Cylinder bore D [m]: piston area A = pi D^2 / 4.
    #[cfg(feature = "model3")]
    pub bore: f64,
    /// Supply pressure p_s, absolute [Pa].
    #[cfg(feature = "model3")]
    pub supply_pressure: f64,
    /// The throttle's sonic conductance C [m^3/(s Pa)] (ISO 6358: mass flow C p_s rho_0 when
    /// choked); 0: solved from V, the band speed steady sliding should have.
    #[cfg(feature = "model3")]
    pub throttle_conductance: f64,
    /// The throttle's critical pressure ratio b [-] (ISO 6358), 0 <= b < 1.
    #[cfg(feature = "model3")]
    pub throttle_critical_ratio: f64,
    /// The air column's length at the start L_0 [m] (dead volume included: V_0 = A L_0).
    #[cfg(feature = "model3")]
    pub column_length: f64,
    /// Polytropic exponent n [-] of the air column: 1 (isothermal) to 1.4 (adiabatic).
    #[cfg(feature = "model3")]
    pub polytropic_exponent: f64,
    /// The cylinder seal's static friction F_ss [N] (the band sticks while the net force on it
    /// stays within it).
    #[cfg(feature = "model3")]
    pub seal_static: f64,
    /// The seal's kinetic friction F_sk [N], <= `seal_static`: sliding at speed w, the seal's
    /// friction is F_sk + (F_ss - F_sk) exp(-|w| / `seal_v_s`).
    #[cfg(feature = "model3")]
    pub seal_kinetic: f64,
    /// The seal's Stribeck velocity v_ss [m/s], > 0.
    #[cfg(feature = "model3")]
    pub seal_v_s: f64,
    /// Fixed step dt [s].
    pub dt: f64,
    /// Run length [s].
    pub duration: f64,
    /// Start of the statistics window [s]; the window runs to `duration`.
    pub stats_from: f64,
}

/// The atmosphere's pressure [Pa] (on the cylinder's rod side, and where the throttle's
/// conductance is referred).
pub const ATMOSPHERE_PA: f64 = 101_325.0;

/// A scene value that breaks a rule: which field, which rule, what value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneError {
    pub field: &'static str,
    pub rule: &'static str,
    pub value: f64,
}

/// The scene's fields whose values are words or switches, not numbers: an error about one
/// names the field and the rule only (its `value` is a code, or another field's number).
const WORD_FIELDS: [&str; 7] = ["caliper", "friction", "band", "face", "rotation", "contact", "drive"];

impl core::fmt::Display for SceneError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if WORD_FIELDS.contains(&self.field) {
            write!(f, "field `{}`: {}", self.field, self.rule)
        } else {
            write!(f, "field `{}` = {}: {}", self.field, self.value, self.rule)
        }
    }
}

fn check(ok: bool, field: &'static str, rule: &'static str, value: f64) -> Result<(), SceneError> {
    if ok {
        Ok(())
    } else {
        Err(SceneError { field, rule, value })
    }
}

impl Scene {
    /// Whether the scene uses any option of model 2 that the thesis stepper
    /// ([`crate::ExactStepper`]) does not carry: Stribeck friction, the band degree of
    /// freedom, friction-face kinematics or the floating pad. Damping is part of both steppers' exact flows.
    pub const fn uses_model2(&self) -> bool {
        matches!(self.friction, FrictionLaw::Stribeck) || self.band || self.face || self.floating()
    }

    /// Whether the edge springs push and never pull ([`ContactLaw::Unilateral`]).
    /// (Always false without the crate's feature `model3`.)
    pub const fn unilateral(&self) -> bool {
        #[cfg(feature = "model3")]
        return matches!(self.contact, ContactLaw::Unilateral);
        #[cfg(not(feature = "model3"))]
        false
    }

    /// Whether a pneumatic cylinder drives the band ([`BandDrive::Pneumatic`]).
    /// (Always false without the crate's feature `model3`.)
    pub const fn pneumatic(&self) -> bool {
        #[cfg(feature = "model3")]
        return matches!(self.drive, BandDrive::Pneumatic);
        #[cfg(not(feature = "model3"))]
        false
    }

    /// The edge springs' stiffnesses [k_L, k_T] [N/m] the equations use: `k_l`, `k_t` as given
    /// with linear springs (`contact_exponent` = 1: exactly those values); with a load law
    /// F = k0 d^p (p > 1), each spring's tangent stiffness at the static load it carries,
    /// k_i (F_i / F_ref)^((p - 1) / p), the loads F_i those of the pad at rest under F_N with
    /// these stiffnesses (a fixed point: the floating pad with k_pivot = 0 carries statically
    /// determinate loads, found in one pass; otherwise iterated to round-off). A static load
    /// below 1e-6 F_ref is taken as 1e-6 F_ref (a spring that carries nothing has a nearly
    /// vanishing tangent). docs/model.md, "Model 3, part 2".
    pub fn contact_stiffnesses(&self) -> [f64; 2] {
        #[cfg(not(feature = "model3"))]
        return [self.k_l, self.k_t];
        #[cfg(feature = "model3")]
        self.load_law_stiffnesses()
    }

    #[cfg(feature = "model3")]
    fn load_law_stiffnesses(&self) -> [f64; 2] {
        let p = self.contact_exponent;
        if p == 1.0 {
            return [self.k_l, self.k_t];
        }
        let q = (p - 1.0) / p;
        let f_ref = self.contact_ref_load;
        let (d_l, d_t, a_n) = match self.caliper {
            Caliper::Push => (self.l + self.l_cl, self.l - self.l_ct, self.beta),
            Caliper::Pull => (self.l - self.l_cl, self.l + self.l_ct, 2.0 * self.l - self.beta),
        };
        let mut k = [self.k_l, self.k_t];
        for _ in 0..200 {
            let k_rot = k[0] * d_l * d_l + k[1] * d_t * d_t;
            let c_n = k[0] * d_l + k[1] * d_t;
            let (y, phi) = if self.floating() {
                let k_y = k[0] + k[1] + self.k_pivot;
                let det = k_y * k_rot - c_n * c_n;
                ((self.f_n * k_rot - c_n * self.f_n * a_n) / det, (k_y * self.f_n * a_n - c_n * self.f_n) / det)
            } else {
                (0.0, self.f_n * a_n / k_rot)
            };
            let load = |i: usize, d: f64| (k[i] * (y + d * phi)).max(1e-6 * f_ref);
            let next = [self.k_l * libm::pow(load(0, d_l) / f_ref, q), self.k_t * libm::pow(load(1, d_t) / f_ref, q)];
            let done = (next[0] - k[0]).abs() <= 1e-15 * next[0] && (next[1] - k[1]).abs() <= 1e-15 * next[1];
            k = next;
            if done {
                break;
            }
        }
        k
    }

    /// The scene with [`Self::contact_stiffnesses`] as its `k_l`, `k_t` and linear springs
    /// (itself when `contact_exponent` = 1).
    pub fn linearised_contact(&self) -> Scene {
        #[cfg(not(feature = "model3"))]
        return *self;
        #[cfg(feature = "model3")]
        {
            let [k_l, k_t] = self.contact_stiffnesses();
            Scene { k_l, k_t, contact_exponent: 1.0, ..*self }
        }
    }

    /// Whether the pad is not hinged: a finite pivot stiffness k_pivot (the floating pad).
    pub const fn floating(&self) -> bool {
        self.k_pivot.is_finite()
    }

    /// Checks every field; the first violation is returned. A scene that passes can be
    /// stepped without panics (all derived quantities are finite and non-degenerate).
    pub fn validate(&self) -> Result<(), SceneError> {
        let finite: [(&'static str, f64); 24] = [
            ("m", self.m),
            ("inertia", self.inertia),
            ("l", self.l),
            ("w", self.w),
            ("l_cl", self.l_cl),
            ("l_ct", self.l_ct),
            ("k_l", self.k_l),
            ("k_t", self.k_t),
            ("k_g", self.k_g),
            ("f_n", self.f_n),
            ("beta", self.beta),
            ("v", self.v),
            ("mu_s", self.mu_s),
            ("mu_k", self.mu_k),
            ("c_x", self.c_x),
            ("c_phi", self.c_phi),
            ("v_s", self.v_s),
            ("stribeck_exponent", self.stribeck_exponent),
            ("m_b", self.m_b),
            ("k_b", self.k_b),
            ("c_b", self.c_b),
            ("dt", self.dt),
            ("duration", self.duration),
            ("stats_from", self.stats_from),
        ];
        for (field, value) in finite {
            check(value.is_finite(), field, "must be a finite number", value)?;
        }
        check(self.m > 0.0, "m", "mass must be > 0 kg", self.m)?;
        check(self.inertia > 0.0, "inertia", "moment of inertia must be > 0 kg m^2", self.inertia)?;
        check(self.l > 0.0, "l", "pad half-length must be > 0 m", self.l)?;
        check(self.w >= 0.0, "w", "pad half-thickness must be >= 0 m", self.w)?;
        check(self.l_cl >= 0.0, "l_cl", "must be >= 0 m", self.l_cl)?;
        check(self.l_cl < self.l, "l_cl", "leading spring must lie on the pad: l_cl < l", self.l_cl)?;
        check(self.l_ct >= 0.0, "l_ct", "must be >= 0 m", self.l_ct)?;
        check(self.l_ct < self.l, "l_ct", "trailing spring must lie on the pad: l_ct < l", self.l_ct)?;
        check(self.k_l >= 0.0, "k_l", "contact stiffness must be >= 0 N/m", self.k_l)?;
        check(self.k_t >= 0.0, "k_t", "contact stiffness must be >= 0 N/m", self.k_t)?;
        check(self.k_l + self.k_t > 0.0, "k_l", "k_l + k_t must be > 0 (the pad needs a contact)", self.k_l)?;
        check(self.k_g > 0.0, "k_g", "guide stiffness must be > 0 N/m", self.k_g)?;
        check(self.f_n >= 0.0, "f_n", "normal load must be >= 0 N", self.f_n)?;
        check(
            self.beta >= 0.0 && self.beta <= 2.0 * self.l,
            "beta",
            "load position must lie on the pad: 0 <= beta <= 2 l",
            self.beta,
        )?;
        check(self.v > 0.0, "v", "band speed must be > 0 m/s", self.v)?;
        check(self.mu_s >= 0.0, "mu_s", "static friction coefficient must be >= 0", self.mu_s)?;
        check(self.mu_k >= 0.0, "mu_k", "kinetic friction coefficient must be >= 0", self.mu_k)?;
        check(self.mu_k <= self.mu_s, "mu_k", "kinetic friction must not exceed static: mu_k <= mu_s", self.mu_k)?;
        check(self.c_x >= 0.0, "c_x", "damping must be >= 0 N s/m", self.c_x)?;
        check(self.c_phi >= 0.0, "c_phi", "damping must be >= 0 N m s/rad", self.c_phi)?;
        if self.friction == FrictionLaw::Stribeck {
            check(self.v_s > 0.0, "v_s", "Stribeck velocity must be > 0 m/s", self.v_s)?;
            check(
                self.stribeck_exponent > 0.0 && self.stribeck_exponent <= 8.0,
                "stribeck_exponent",
                "Stribeck exponent must satisfy 0 < delta <= 8",
                self.stribeck_exponent,
            )?;
        }
        check(!self.k_pivot.is_nan() && self.k_pivot >= 0.0, "k_pivot", "pivot stiffness must be >= 0 N/m (inf: the hinge)", self.k_pivot)?;
        if self.floating() {
            check(self.c_y.is_finite() && self.c_y >= 0.0, "c_y", "damping must be a finite number >= 0 N s/m", self.c_y)?;
            check(self.rotation, "k_pivot", "a pad that is not hinged needs the rotation (rotation = true)", self.k_pivot)?;
            check(
                self.face,
                "k_pivot",
                "a pad that is not hinged needs friction-face kinematics (face = true): with the pivot's, the friction moment does work nothing dissipates",
                self.k_pivot,
            )?;
            check(self.k_l > 0.0 && self.k_t > 0.0, "k_l", "a pad that is not hinged needs both contact springs > 0 N/m", self.k_l)?;
            check(
                self.inertia > self.m * self.l * self.l,
                "inertia",
                "a pad that is not hinged needs I (about the pivot) > m l^2: its inertia about the centre of gravity, l from the pivot, must be > 0",
                self.inertia,
            )?;
        }
        #[cfg(feature = "model3")]
        self.validate_model3()?;
        if self.band {
            check(self.m_b > 0.0, "m_b", "band mass must be > 0 kg", self.m_b)?;
            check(self.k_b > 0.0, "k_b", "band drive stiffness must be > 0 N/m", self.k_b)?;
            check(self.c_b >= 0.0, "c_b", "band drive damping must be >= 0 N s/m", self.c_b)?;
        }
        check(self.dt > 0.0, "dt", "time step must be > 0 s", self.dt)?;
        check(self.duration > 0.0, "duration", "run length must be > 0 s", self.duration)?;
        check(self.dt <= self.duration, "dt", "time step must not exceed the run length", self.dt)?;
        check(
            self.duration / self.dt <= 1e10,
            "dt",
            "run needs more than 1e10 steps: raise dt or shorten the run",
            self.dt,
        )?;
        check(
            self.stats_from >= 0.0 && self.stats_from < self.duration,
            "stats_from",
            "statistics window start must satisfy 0 <= stats_from < duration",
            self.stats_from,
        )?;
        Ok(())
    }

    /// Model 3's keys (the crate's feature `model3`).
    #[cfg(feature = "model3")]
    fn validate_model3(&self) -> Result<(), SceneError> {
        check(
            self.contact_exponent.is_finite() && self.contact_exponent >= 1.0 && self.contact_exponent <= 5.0,
            "contact_exponent",
            "the contact law's exponent must satisfy 1 <= p <= 5 (1: linear springs; 1.5: Hertz-like)",
            self.contact_exponent,
        )?;
        if self.contact_exponent != 1.0 {
            check(
                self.contact_ref_load.is_finite() && self.contact_ref_load > 0.0,
                "contact_ref_load",
                "the reference load of the contact law must be a finite number > 0 N",
                self.contact_ref_load,
            )?;
        }
        check(
            !self.unilateral() || self.floating(),
            "contact",
            "unilateral contact needs a pad that is not hinged (a finite k_pivot): the hinge holds both edges",
            self.k_pivot,
        )?;
        check(
            !self.unilateral() || self.f_n > 0.0,
            "f_n",
            "unilateral contact needs a normal load f_n > 0 N: with none the edges carry nothing, and open and close at once",
            self.f_n,
        )?;
        if self.pneumatic() {
            self.validate_cylinder()?;
        }
        Ok(())
    }

    /// The pneumatic drive's keys (model 3, option 1).
    #[cfg(feature = "model3")]
    fn validate_cylinder(&self) -> Result<(), SceneError> {
        check(self.band, "drive", "a pneumatic drive pushes the band: it needs band = true", 0.0)?;
        check(
            !self.unilateral(),
            "drive",
            "a pneumatic drive with unilateral contact is not built yet: give one of the two",
            0.0,
        )?;
        let finite = [
            ("bore", self.bore),
            ("supply_pressure", self.supply_pressure),
            ("throttle_conductance", self.throttle_conductance),
            ("throttle_critical_ratio", self.throttle_critical_ratio),
            ("column_length", self.column_length),
            ("polytropic_exponent", self.polytropic_exponent),
            ("seal_static", self.seal_static),
            ("seal_kinetic", self.seal_kinetic),
            ("seal_v_s", self.seal_v_s),
        ];
        for (field, value) in finite {
            check(value.is_finite(), field, "must be a finite number", value)?;
        }
        check(self.bore > 0.0, "bore", "cylinder bore must be > 0 m", self.bore)?;
        check(
            self.supply_pressure > ATMOSPHERE_PA,
            "supply_pressure",
            "supply pressure (absolute) must exceed the atmosphere's 101325 Pa",
            self.supply_pressure,
        )?;
        check(self.throttle_conductance >= 0.0, "throttle_conductance", "must be >= 0 m^3/(s Pa) (0: solved from v)", self.throttle_conductance)?;
        check(
            self.throttle_critical_ratio >= 0.0 && self.throttle_critical_ratio < 1.0,
            "throttle_critical_ratio",
            "the throttle's critical pressure ratio must satisfy 0 <= b < 1",
            self.throttle_critical_ratio,
        )?;
        check(self.column_length > 0.0, "column_length", "the air column's length must be > 0 m", self.column_length)?;
        check(
            self.polytropic_exponent >= 1.0 && self.polytropic_exponent <= 1.4,
            "polytropic_exponent",
            "the polytropic exponent must lie between 1 (isothermal) and 1.4 (adiabatic)",
            self.polytropic_exponent,
        )?;
        check(self.seal_kinetic >= 0.0, "seal_kinetic", "seal friction must be >= 0 N", self.seal_kinetic)?;
        check(
            self.seal_static >= self.seal_kinetic,
            "seal_static",
            "the seal's static friction must be >= its kinetic friction",
            self.seal_static,
        )?;
        check(self.seal_v_s > 0.0, "seal_v_s", "the seal's Stribeck velocity must be > 0 m/s", self.seal_v_s)?;
        Ok(())
    }

}
