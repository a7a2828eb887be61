//! Why a run stops early, and the checks that stop it: a finite state, a plausible range, and
//! a closed contact. No NaN or infinity ever leaves a stepper: the step that would produce one
//! stops the run with a classified [`Halt`] instead.

use crate::coefficients::Coefficients;
use crate::real::Real;
use crate::scene::Scene;
use crate::stickslip::Regime;

/// |phi| beyond this is taken as divergence [rad].
pub const PHI_LIMIT: f64 = 0.5;
/// |x| beyond this is taken as divergence [m].
pub const X_LIMIT: f64 = 1.0;
/// |x'| beyond this is taken as divergence [m/s].
pub const XDOT_LIMIT: f64 = 1e3;
/// |phi'| beyond this is taken as divergence [rad/s].
pub const PHIDOT_LIMIT: f64 = 1e7;

/// Why a run stopped early. Never a NaN in the output: the step that would produce one stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Halt {
    /// A state value became NaN or infinite at time `t` [s].
    NonFinite { t: f64 },
    /// x, phi or their rates left the plausible range at time `t`, in `regime`, whose rotational stiffness
    /// margin K_eff [N m/rad] is given: <= 0 is the model's own divergence (sprag).
    Diverged { t: f64, regime: Regime, stiffness_margin: f64 },
    /// The normal force N = c_N phi [N] went negative at time `t`: the pad lifts off and the
    /// model is outside its validity.
    ContactLoss { t: f64, n: f64 },
    /// More than [`MAX_TRANSITIONS_PER_SUBSTEP`] transitions inside one substep at time `t`.
    TransitionStorm { t: f64 },
}

impl Halt {
    pub fn time(&self) -> f64 {
        match *self {
            Halt::NonFinite { t }
            | Halt::Diverged { t, .. }
            | Halt::ContactLoss { t, .. }
            | Halt::TransitionStorm { t } => t,
        }
    }
}

/// The end-of-step checks of every stepper, with the scene's constants in `T`.
#[derive(Clone, Copy, Debug)]
pub struct Limits<T> {
    /// Rotational stiffness margin of each regime, K_eff [N m/rad] (index: `Regime::index`).
    /// Stick: K - s mu_s w c_N, the stiffness at the static limit (<= 0: the pad self-locks
    /// and is carried along for good); slip: K - s sigma mu_k w c_N.
    pub margins: [f64; 3],
    rotation: bool,
    phi_floor: T,
    x_limit: T,
    xdot_limit: T,
    phi_limit: T,
    phidot_limit: T,
    c_n: f64,
}

impl<T: Real> Limits<T> {
    pub fn new(scene: &Scene, co: &Coefficients) -> Self {
        Limits {
            margins: [
                co.effective_rotational_stiffness(scene, 1.0, scene.mu_s),
                co.effective_rotational_stiffness(scene, 1.0, scene.mu_k),
                co.effective_rotational_stiffness(scene, -1.0, scene.mu_k),
            ],
            rotation: scene.rotation,
            // a rounding-level negative phi with no load is not a lift-off
            // (the floating pad's phi may go negative in contact: its steppers check each
            // contact spring's compression instead)
            phi_floor: T::from_f64(if scene.floating() { -PHI_LIMIT } else { -(1e-6 * libm::fabs(co.phi0) + 1e-12) }),
            x_limit: T::from_f64(X_LIMIT),
            xdot_limit: T::from_f64(XDOT_LIMIT),
            phi_limit: T::from_f64(PHI_LIMIT),
            phidot_limit: T::from_f64(PHIDOT_LIMIT),
            c_n: co.c_n,
        }
    }

    /// Checks state `z` = [x, x', phi, phi'] reached in `regime`; `t` gives the time if a
    /// halt must be reported. The common case (all in range) is one branch: the comparisons are
    /// combined without short-circuit, and a NaN fails every one of them.
    #[inline(always)]
    pub fn check(&self, z: &[T; 4], regime: Regime, t: impl Fn() -> f64) -> Result<(), Halt> {
        if self.in_range(z) {
            return Ok(());
        }
        self.classify(z, regime, t())
    }

    /// The floor of phi below which the pad has lost contact [rad].
    pub(crate) fn phi_floor(&self) -> T {
        self.phi_floor
    }

    /// Whether `z` passes every check (false for any NaN).
    #[inline(always)]
    pub fn in_range(&self, z: &[T; 4]) -> bool {
        (z[0].abs() <= self.x_limit)
            & (z[1].abs() <= self.xdot_limit)
            & (z[2] >= self.phi_floor)
            & (z[2] <= self.phi_limit)
            & (z[3].abs() <= self.phidot_limit)
    }

    #[cold]
    fn classify(&self, z: &[T; 4], regime: Regime, t: f64) -> Result<(), Halt> {
        let finite = z[0].is_finite() && z[1].is_finite() && z[2].is_finite() && z[3].is_finite();
        if !finite {
            return Err(Halt::NonFinite { t });
        }
        if self.rotation && z[2] < self.phi_floor {
            return Err(Halt::ContactLoss { t, n: self.c_n * z[2].to_f64() });
        }
        Err(Halt::Diverged { t, regime, stiffness_margin: self.margins[regime.index()] })
    }
}
