//! The fixed-step methods side by side, behind one interface: the exact per-regime
//! propagator ([`crate::exact`]) and the classical alternatives it is measured against.
//! All are `no_std`, allocation-free and generic over f32 and f64.
//!
//! | method | order | stability on an undamped oscillator | transitions |
//! |---|---|---|---|
//! | exact | exact in each regime | unconditional | located in the step to 2^-L |
//! | explicit Euler | 1 | never (growth sqrt(1 + (omega h)^2) per step) | at step ends |
//! | symplectic Euler | 1 | omega h < 2 | at step ends |
//! | RK4 + Karnopp band | 4 between transitions, 1 overall | omega h < 2.83 | band |V_r| < eta |
//! | Moreau-Jean (theta = 1/2) | 2 between transitions, 1 overall | unconditional | set-valued law per step |

pub mod core;
pub mod moreau_jean;
pub mod plant;
pub mod rk4_karnopp;
pub mod switched;

use crate::exact::{ExactStepper, State, Transition};
use crate::halt::Halt;
use crate::real::Real;
use crate::scene::{Scene, SceneError};
use crate::stickslip::Regime;

/// What every fixed-step method offers.
pub trait Method<T: Real> {
    /// Advances by one step of the scene's dt; returns the number of transitions in it.
    fn step(&mut self) -> Result<usize, Halt>;
    fn state(&self) -> State<T>;
    fn regime(&self) -> Regime;
    fn steps(&self) -> u64;
    /// The transitions of the last step.
    fn transitions(&self) -> &[Transition<T>];
}

impl<T: Real> Method<T> for ExactStepper<T> {
    #[inline]
    fn step(&mut self) -> Result<usize, Halt> {
        ExactStepper::step(self)
    }
    fn state(&self) -> State<T> {
        ExactStepper::state(self)
    }
    fn regime(&self) -> Regime {
        ExactStepper::regime(self)
    }
    fn steps(&self) -> u64 {
        ExactStepper::steps(self)
    }
    fn transitions(&self) -> &[Transition<T>] {
        ExactStepper::transitions(self)
    }
}

/// The methods by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum MethodKind {
    Exact,
    ExplicitEuler,
    SymplecticEuler,
    Rk4Karnopp,
    MoreauJean,
}

impl MethodKind {
    pub const ALL: [MethodKind; 5] = [
        MethodKind::Exact,
        MethodKind::ExplicitEuler,
        MethodKind::SymplecticEuler,
        MethodKind::Rk4Karnopp,
        MethodKind::MoreauJean,
    ];

    pub const fn name(self) -> &'static str {
        match self {
            MethodKind::Exact => "exact",
            MethodKind::ExplicitEuler => "explicit_euler",
            MethodKind::SymplecticEuler => "symplectic_euler",
            MethodKind::Rk4Karnopp => "rk4_karnopp",
            MethodKind::MoreauJean => "moreau_jean",
        }
    }

    pub fn from_name(name: &str) -> Option<MethodKind> {
        MethodKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Largest omega h for which the method is stable on an undamped linear oscillator;
    /// `None`: unconditionally stable; `Some(0.0)`: unstable at any step.
    pub const fn omega_dt_limit(self) -> Option<f64> {
        match self {
            MethodKind::Exact | MethodKind::MoreauJean => None,
            MethodKind::ExplicitEuler => Some(0.0),
            MethodKind::SymplecticEuler => Some(2.0),
            MethodKind::Rk4Karnopp => Some(2.828_427_124_746_19),
        }
    }
}

/// Any method, chosen at run time, without allocation.
#[derive(Clone, Debug)]
pub enum AnyMethod<T: Real> {
    Exact(ExactStepper<T>),
    Euler(switched::Euler<T>),
    Rk4Karnopp(rk4_karnopp::Rk4Karnopp<T>),
    MoreauJean(moreau_jean::MoreauJean<T>),
}

impl<T: Real> AnyMethod<T> {
    pub fn new(kind: MethodKind, scene: &Scene) -> Result<Self, SceneError> {
        Ok(match kind {
            MethodKind::Exact => AnyMethod::Exact(ExactStepper::new(scene)?),
            MethodKind::ExplicitEuler => AnyMethod::Euler(switched::Euler::new(switched::EulerKind::Explicit, scene)?),
            MethodKind::SymplecticEuler => AnyMethod::Euler(switched::Euler::new(switched::EulerKind::Symplectic, scene)?),
            MethodKind::Rk4Karnopp => AnyMethod::Rk4Karnopp(rk4_karnopp::Rk4Karnopp::new(scene)?),
            MethodKind::MoreauJean => AnyMethod::MoreauJean(moreau_jean::MoreauJean::new(scene)?),
        })
    }
}

macro_rules! dispatch {
    ($self:ident, $m:ident => $e:expr) => {
        match $self {
            AnyMethod::Exact($m) => $e,
            AnyMethod::Euler($m) => $e,
            AnyMethod::Rk4Karnopp($m) => $e,
            AnyMethod::MoreauJean($m) => $e,
        }
    };
}

impl<T: Real> Method<T> for AnyMethod<T> {
    fn step(&mut self) -> Result<usize, Halt> {
        dispatch!(self, m => Method::step(m))
    }
    fn state(&self) -> State<T> {
        dispatch!(self, m => Method::state(m))
    }
    fn regime(&self) -> Regime {
        dispatch!(self, m => Method::regime(m))
    }
    fn steps(&self) -> u64 {
        dispatch!(self, m => Method::steps(m))
    }
    fn transitions(&self) -> &[Transition<T>] {
        dispatch!(self, m => Method::transitions(m))
    }
}
