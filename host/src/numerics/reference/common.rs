//! What the thesis model and model 2 share, written out from docs/model.md, not from
//! `stickslip_model`'s code: the hinged pad's constants (pivot at the supported edge; only the
//! scene's data is taken), the contact's regimes and transition table, and the window
//! statistics.

use stickslip_model::{Caliper, Scene};

/// The hinged pad's constants.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pad {
    pub m: f64,
    pub i: f64,
    pub kg: f64,
    pub cx: f64,
    pub cphi: f64,
    /// Rotational stiffness of the two contact springs about the pivot, K.
    pub k_rot: f64,
    /// N per radian: N = c_n phi (hinged).
    pub c_n: f64,
    /// The load's moment about the pivot, F_N a_N.
    pub moment_load: f64,
    /// +1 push, -1 pull.
    pub s: f64,
    pub w: f64,
    pub v: f64,
    pub mu_s: f64,
    pub mu_k: f64,
    pub rotation: bool,
    /// Lever arms of the leading and trailing springs and of the load.
    pub d_l: f64,
    pub d_t: f64,
    pub a_n: f64,
}

impl Pad {
    pub fn of(sc: &Scene) -> Pad {
        // lever arms: push d_L = l + l_cL, d_T = l - l_cT, a_N = beta, s = +1;
        //             pull d_L = l - l_cL, d_T = l + l_cT, a_N = 2 l - beta, s = -1
        let (d_l, d_t, a_n, s) = match sc.caliper {
            Caliper::Push => (sc.l + sc.l_cl, sc.l - sc.l_ct, sc.beta, 1.0),
            Caliper::Pull => (sc.l - sc.l_cl, sc.l + sc.l_ct, 2.0 * sc.l - sc.beta, -1.0),
        };
        Pad {
            m: sc.m,
            i: sc.inertia,
            kg: sc.k_g,
            cx: sc.c_x,
            cphi: sc.c_phi,
            k_rot: sc.contact_stiffnesses()[0] * d_l * d_l + sc.contact_stiffnesses()[1] * d_t * d_t,
            c_n: sc.contact_stiffnesses()[0] * d_l + sc.contact_stiffnesses()[1] * d_t,
            moment_load: sc.f_n * a_n,
            s,
            w: sc.w,
            v: sc.v,
            mu_s: sc.mu_s,
            mu_k: sc.mu_k,
            rotation: sc.rotation,
            d_l,
            d_t,
            a_n,
        }
    }
}

/// The regime of the contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Regime {
    Stick,
    /// Slip with the pad slower than the band (`v < 0`, sigma = +1).
    Slower,
    /// Slip with the pad faster than the band (`v > 0`, sigma = -1).
    Faster,
}

impl Regime {
    /// The regime after the guard of `self` fired, from the stick's required friction `f_req`
    /// and the static limit `mu_s N` there (the table of docs/model.md).
    pub(super) fn after(self, f_req: f64, limit: f64) -> Regime {
        match self {
            Regime::Stick => {
                if f_req > 0.0 {
                    Regime::Slower
                } else {
                    Regime::Faster
                }
            }
            _ => {
                if f_req.abs() <= limit {
                    Regime::Stick
                } else if f_req > 0.0 {
                    Regime::Slower
                } else {
                    Regime::Faster
                }
            }
        }
    }
}

/// Window statistics of a run, over Q quantities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WindowStats<const Q: usize> {
    pub min: [f64; Q],
    pub max: [f64; Q],
    /// Share of the window spent in stick.
    pub stick_fraction: f64,
    /// 1 / (mean interval between stick -> slip transitions in the window); 0 with fewer than
    /// two.
    pub stick_slip_hz: f64,
    /// Number of stick -> slip transitions in the window.
    pub slip_onsets: usize,
}

impl<const Q: usize> Default for WindowStats<Q> {
    fn default() -> Self {
        WindowStats { min: [0.0; Q], max: [0.0; Q], stick_fraction: 0.0, stick_slip_hz: 0.0, slip_onsets: 0 }
    }
}

impl<const Q: usize> WindowStats<Q> {
    /// Peak-to-peak of quantity i.
    pub fn pp(&self, i: usize) -> f64 {
        self.max[i] - self.min[i]
    }

    /// The statistics of extremes, time in stick over the window's length, and the slip onsets
    /// in the window (in time order).
    pub(super) fn of(min: [f64; Q], max: [f64; Q], stick_time: f64, window: f64, onsets: &[f64]) -> Self {
        let hz = if onsets.len() >= 2 {
            (onsets.len() - 1) as f64 / (onsets[onsets.len() - 1] - onsets[0])
        } else {
            0.0
        };
        WindowStats { min, max, stick_fraction: stick_time / window, stick_slip_hz: hz, slip_onsets: onsets.len() }
    }
}
