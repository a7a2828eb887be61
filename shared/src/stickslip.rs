//! The stick-slip state machine: the three regimes, the guard that ends each one, and the
//! decision taken when a guard fires (the thesis's four conditions, completed).
//!
//! - **Stick** (x' = V): the contact transmits the required force F_req = k_g x + c_x V.
//!   It ends when F_req >= +mu_s N (the pad falls behind: slip, pad slower) or when
//!   F_req <= -mu_s N (the pad runs ahead: slip, pad faster).
//! - **Slip, pad slower** (V_r < 0, F_f = +mu_k N) and **slip, pad faster** (V_r > 0,
//!   F_f = -mu_k N): they end when V_r returns to 0. There the pad sticks if
//!   |F_req| <= mu_s N; otherwise it keeps sliding, in the direction F_req dictates
//!   (a reversal when it differs from the one it came from).
//!
//! Every guard is written as a linear function g(z) of the augmented state
//! z = [x, x', phi, phi', 1] that is negative while the regime holds and fires at g >= 0.
//! A guard that has just fired is exactly 0 at the start of the next regime; the transition
//! search in [`crate::exact`] never evaluates a guard at the instant it starts from, so a
//! guard starting at zero is not taken for a new crossing (and cannot loop), while one that
//! truly departs in the firing direction fires one search unit later.

use crate::real::Real;
use crate::scene::Scene;
use crate::coefficients::Coefficients;

/// The contact regime.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Regime {
    /// Pad moves with the band: x' = V.
    Stick = 0,
    /// Pad slides slower than the band (V_r < 0): friction +mu_k N drags it forward.
    SlipSlower = 1,
    /// Pad slides faster than the band (V_r > 0): friction -mu_k N holds it back.
    SlipFaster = 2,
}

impl Regime {
    pub const ALL: [Regime; 3] = [Regime::Stick, Regime::SlipSlower, Regime::SlipFaster];

    pub const fn name(self) -> &'static str {
        match self {
            Regime::Stick => "stick",
            Regime::SlipSlower => "slip_slower",
            Regime::SlipFaster => "slip_faster",
        }
    }

    pub const fn index(self) -> usize {
        self as usize
    }

    /// Sign of the kinetic friction force in this slip regime (+1 slower, -1 faster); 0 in stick.
    pub const fn friction_sign(self) -> f64 {
        match self {
            Regime::Stick => 0.0,
            Regime::SlipSlower => 1.0,
            Regime::SlipFaster => -1.0,
        }
    }
}

/// A linear guard g(z) = c . [x, x', phi, phi', 1] that ends its regime when it reaches >= 0.
#[derive(Clone, Copy, Debug)]
pub struct Guard<T> {
    pub c: [T; 5],
}

impl<T: Real> Guard<T> {
    #[inline(always)]
    pub fn value(&self, z: &[T; 4]) -> T {
        self.c[0] * z[0] + self.c[1] * z[1] + self.c[2] * z[2] + self.c[3] * z[3] + self.c[4]
    }
    #[inline(always)]
    pub fn fired(&self, z: &[T; 4]) -> bool {
        !(self.value(z) < T::zero())
    }
}

/// The guards of each regime and the constants of the transition decisions, in the stepper's
/// precision.
#[derive(Clone, Copy, Debug)]
pub struct Guards<T> {
    /// Stick, first: F_req - mu_s N (fires into slip, pad slower).
    pub stick_behind: Guard<T>,
    /// Stick, second: -F_req - mu_s N (fires into slip, pad faster).
    pub stick_ahead: Guard<T>,
    /// Slip, pad slower: x' - V (fires when the pad catches up with the band).
    pub slower_caught_up: Guard<T>,
    /// Slip, pad faster: V - x' (fires when the band catches up with the pad).
    pub faster_caught_up: Guard<T>,
    k_g: T,
    c_x_v: T,
    mu_s_c_n: T,
    phi_fixed: Option<T>,
}

impl<T: Real> Guards<T> {
    /// `phi_fixed` is Some(phi_0) for a scene without rotation (N constant).
    pub fn new(scene: &Scene, co: &Coefficients) -> Self {
        let t = T::from_f64;
        let mus_cn = scene.mu_s * co.c_n;
        // With the rotation left out, phi is the constant phi_0: fold N into the constant term.
        let (phi_coef, phi_const) = if scene.rotation { (mus_cn, 0.0) } else { (0.0, mus_cn * co.phi0) };
        let c_x_v = scene.c_x * scene.v;
        Guards {
            stick_behind: Guard { c: [t(scene.k_g), t(0.0), t(-phi_coef), t(0.0), t(c_x_v - phi_const)] },
            stick_ahead: Guard { c: [t(-scene.k_g), t(0.0), t(-phi_coef), t(0.0), t(-c_x_v - phi_const)] },
            slower_caught_up: Guard { c: [t(0.0), t(1.0), t(0.0), t(0.0), t(-scene.v)] },
            faster_caught_up: Guard { c: [t(0.0), t(-1.0), t(0.0), t(0.0), t(scene.v)] },
            k_g: t(scene.k_g),
            c_x_v: t(c_x_v),
            mu_s_c_n: t(mus_cn),
            phi_fixed: if scene.rotation { None } else { Some(t(co.phi0)) },
        }
    }

    /// The guards that can end `regime`, with the regime each leads to (`None`: decided by
    /// [`Guards::after_velocity_match`]).
    #[inline(always)]
    pub fn of(&self, regime: Regime) -> ([&Guard<T>; 2], usize) {
        match regime {
            Regime::Stick => ([&self.stick_behind, &self.stick_ahead], 2),
            Regime::SlipSlower => ([&self.slower_caught_up, &self.slower_caught_up], 1),
            Regime::SlipFaster => ([&self.faster_caught_up, &self.faster_caught_up], 1),
        }
    }

    /// Required friction force to hold the pad on the band, F_req = k_g x + c_x V [N].
    #[inline(always)]
    pub fn required_force(&self, z: &[T; 4]) -> T {
        self.k_g * z[0] + self.c_x_v
    }

    /// The static friction limit mu_s N [N].
    #[inline(always)]
    pub fn static_limit(&self, z: &[T; 4]) -> T {
        match self.phi_fixed {
            Some(p) => self.mu_s_c_n * p,
            None => self.mu_s_c_n * z[2],
        }
    }

    /// The regime entered when guard `which` of `regime` fires at state `z`.
    #[inline]
    pub fn next_regime(&self, regime: Regime, which: usize, z: &[T; 4]) -> Regime {
        match regime {
            Regime::Stick => {
                if which == 0 {
                    Regime::SlipSlower
                } else {
                    Regime::SlipFaster
                }
            }
            Regime::SlipSlower | Regime::SlipFaster => self.after_velocity_match(z),
        }
    }

    /// Slip reached V_r = 0: stick if |F_req| <= mu_s N, else slide on in the direction the
    /// required force dictates (F_req > 0 means the guard pulls the pad back: pad slower).
    #[inline]
    pub fn after_velocity_match(&self, z: &[T; 4]) -> Regime {
        let f_req = self.required_force(z);
        let limit = self.static_limit(z);
        if f_req > limit {
            Regime::SlipSlower
        } else if -f_req > limit {
            Regime::SlipFaster
        } else {
            Regime::Stick
        }
    }
}
