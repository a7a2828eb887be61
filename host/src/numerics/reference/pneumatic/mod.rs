//! The reference simulation of model 3's pneumatic band drive (docs/model.md, "Model 3, part 3:
//! the pneumatic band drive"), independent of `stickslip_model`'s matrices, cylinder and
//! runners (`model3::pneumatic_run`, `model3::cylinder`): its own right-hand side written from
//! the equations of docs/model.md, taking only the scene's data, run by the event-driven DOP853
//! driver ([`super::driver`]) in chunks of 400 largest steps. The pad's constants and forces
//! (lever arms, normal force, friction law, the floating pad's mass matrix) are the model-2
//! reference's ([`super::model2`]); the band, the air column, the throttle and the seal are
//! this module's ([`physics`]).
//!
//! The state is `y = [x, x', phi, phi', x_b, x_b', y, y', p, P]`: the pad as in the model-2
//! reference, the band in absolute terms (position and velocity), the chamber's absolute
//! pressure p [Pa] and its time integral P [Pa s] (the window's mean pressure, exactly). The
//! pad slides at `v = x' (+ s w phi') - x_b'`; the band obeys
//! `m_b x_b'' = A (p - p_atm) - F_seal - c_b x_b' - F` while it slides and `x_b' = 0` while it is
//! stuck at its seal (`|A (p - p_atm) - F| <= F_ss`), and `p' = n / V_c (p_ref C p_s phi(p / p_s)
//! - p A x_b')`.
//!
//! Regimes: the pad's (stick, slip slower, slip faster) times the band's (sliding forward,
//! back, stuck), the slips each with an arming flag. The driver watches two guards in every
//! regime (`Hybrid::guard_count`), each located with its crests and the earliest made (each
//! normalised: a force over max(mu_s N_0, F_ss), a speed over V):
//! - pad: stick `|F_req| - mu_s N`; slip slower `v`, faster `-v`;
//! - band: stuck `|A (p - p_atm) - F| - F_ss`; sliding forward `-x_b'`, back `x_b'`;
//! - **arming**: a slip of the pad or of the band that starts at zero speed (every one with
//!   Stribeck friction, and the seal's friction is Stribeck's) has its velocity guard at zero;
//!   until armed its guard is `|v| - ARM V` (`ARM = 1e-9`), whose firing arms it (in the slip's
//!   direction: not reported as a transition) or, the other way, is the velocity match.
//!
//! Transitions: the pad's follow the table of docs/model.md, with the stick's friction solved
//! from `v' = 0` against a sliding band (its `x_b''` from the band's equation) or a band at
//! rest; entering stick applies the friction impulse `P = -v / (1/m (+ w^2/I) (+ 1/m_b if the
//! band slides))`. The band's: after a stop (`x_b' = 0` set, the stuck pad's face projected
//! onto the band at rest) it sticks if the net force is within F_ss, else slides on either
//! way; it breaks away in the direction of the net force once that reaches F_ss. After every
//! change a stuck pad past mu_s N slips and a stuck band past F_ss breaks away at once.
//!
//! Slow and allocating: a yardstick for tests, not the product.

use super::common::{Regime as Pad, WindowStats};
use super::driver::{self, arr, Bracket, Hybrid, Plan, State};
pub use super::driver::Tolerances;
use super::model2::physics::Phys;
use std::cell::RefCell;
use stickslip_model::scene::ATMOSPHERE_PA;
use stickslip_model::Scene;

mod hybrid;
mod physics;
use physics::*;

/// [x, x', phi, phi', x_b, x_b', y, y', p, P].
pub type Y = State<10>;
/// Indices of x_b (x_b' follows), p and its integral.
pub const XB: usize = 4;
pub const P: usize = 8;
pub const P_INT: usize = 9;

/// A slip's guard arms once its speed has left zero by `ARM * V`.
const ARM: f64 = 1e-9;
const CHUNK_STEPS: f64 = 400.0;

/// The pad's regime (model 2's).
pub use super::common::Regime as PadRegime;

/// The band at its seal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Band {
    Forward,
    Back,
    Stuck,
}

impl Band {
    /// +1 forward, -1 back, 0 stuck.
    pub fn dir(self) -> f64 {
        match self {
            Band::Forward => 1.0,
            Band::Back => -1.0,
            Band::Stuck => 0.0,
        }
    }
}

/// The combined regime: the pad's and the band's, and whether each slip's guard is armed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Regime {
    pub pad: Pad,
    pub band: Band,
    pub pad_armed: bool,
    pub band_armed: bool,
}

/// One elementary change: the pad's regime, or the band's (a band stop that slides on in the
/// same direction is `Band { from, to }` with `from == to`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Change {
    Pad { from: Pad, to: Pad },
    Band { from: Band, to: Band },
}

/// A change at time t [s].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Event {
    pub t: f64,
    pub change: Change,
}

/// The drive's and the pad's statistics over the window [stats_from, duration].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// The pad: extremes of [x, x', phi, phi'] (true extremes of the continuous motion), stick
    /// fraction, stick-slip frequency and slip onsets.
    pub pad: WindowStats<4>,
    /// The band: travel over the window / its length [m/s], the fraction of the window stuck,
    /// breakaways (stuck to sliding), its greatest and least speed [m/s].
    pub band_mean_speed: f64,
    pub band_stuck_fraction: f64,
    pub band_breakaways: usize,
    pub band_speed_min: f64,
    pub band_speed_max: f64,
    /// The chamber pressure [Pa]: least, greatest (true extremes), time mean.
    pub p_min: f64,
    pub p_max: f64,
    pub p_mean: f64,
}

/// A reference run of a pneumatic scene from its start to `scene.duration`.
#[derive(Clone, Debug)]
pub struct Run {
    pub start: [f64; 10],
    /// Every change of the pad's or the band's regime, in order (arming not counted).
    pub transitions: Vec<Event>,
    pub final_state: [f64; 10],
    pub final_regime: Regime,
    /// DOP853 steps accepted on the main path (not counting bisections).
    pub accepted_steps: u64,
    /// The throttle's conductance [m^3/(s Pa)] (given, or solved from V).
    pub conductance: f64,
    pub stats: Stats,
}

impl Run {
    /// The pad's changes: (t, from, to).
    pub fn pad_transitions(&self) -> Vec<(f64, Pad, Pad)> {
        self.transitions.iter().filter_map(|e| if let Change::Pad { from, to } = e.change { Some((e.t, from, to)) } else { None }).collect()
    }

    /// The band's changes: (t, from, to).
    pub fn band_transitions(&self) -> Vec<(f64, Band, Band)> {
        self.transitions.iter().filter_map(|e| if let Change::Band { from, to } = e.change { Some((e.t, from, to)) } else { None }).collect()
    }
}

/// The quantities whose extremes are taken: x, x', phi, phi', x_b', p (indices in y).
const Q: [usize; 6] = [0, 1, 2, 3, 5, 8];

/// Runs `scene` (which must have `drive = "pneumatic"`) from the drive's start (the band at
/// rest as it breaks away, the chamber at p_atm + F_ss / A, the pad at rest, static under its
/// load, stuck on the band) to `scene.duration`.
pub fn simulate(scene: &Scene, tol: Tolerances) -> Result<Run, String> {
    scene.validate().map_err(|e| format!("invalid scene: {e}"))?;
    if !scene.pneumatic() {
        return Err("pneumatic reference: the scene's drive is not pneumatic".into());
    }
    let sys = Pneu::of(scene)?;
    let y0 = sys.start_state();
    let pad0 = if sys.frictionless { Pad::Slower } else { Pad::Stick };
    let r0 = Regime { pad: pad0, band: Band::Forward, pad_armed: pad0 == Pad::Stick, band_armed: false };
    let from = scene.stats_from.clamp(0.0, scene.duration);
    let (mut lo, mut hi) = ([f64::INFINITY; 6], [f64::NEG_INFINITY; 6]);
    let (mut stick_time, mut stuck_time) = (0.0, 0.0);
    let mut y_from: Option<Y> = None;
    let plan = Plan { stop_at: Some(from), chunk_steps: Some(CHUNK_STEPS) };
    let path = driver::run(&sys, y0, r0, scene.duration, plan, &tol, |pc| {
        if pc.t0 < from {
            return Ok(());
        }
        if y_from.is_none() {
            y_from = Some(*pc.y0);
        }
        let r = pc.regime;
        if r.pad == Pad::Stick {
            stick_time += pc.t1 - pc.t0;
        }
        if r.band == Band::Stuck {
            stuck_time += pc.t1 - pc.t0;
        }
        // the step ends up to the event, then the event's state
        let n = pc.fired.unwrap_or(pc.ys.len());
        let mut pts: Vec<(f64, Y)> = (0..n).map(|k| (pc.ts[k], pc.ys[k])).collect();
        if pc.fired.is_some() || pts.last().is_none_or(|p| p.0 < pc.t1) {
            pts.push((pc.t1, *pc.y1));
        }
        let mut include = |y: &Y| {
            for (c, &i) in Q.iter().enumerate() {
                lo[c] = lo[c].min(y[i]);
                hi[c] = hi[c].max(y[i]);
            }
        };
        include(&pts[0].1);
        for k in 1..pts.len() {
            include(&pts[k].1);
            let (ra, rb) = (sys.deriv(r, &pts[k - 1].1), sys.deriv(r, &pts[k].1));
            for &i in &Q {
                if ra[i] * rb[i] < 0.0 {
                    let up = ra[i] > 0.0;
                    let step = Bracket { t_a: pts[k - 1].0, y_a: pts[k - 1].1, lo: pts[k - 1].0, hi: pts[k].0, y_hi: pts[k].1 };
                    let found = driver::bisect(&sys, r, step, pc.h_max, &tol, |y| (sys.deriv(r, y)[i] > 0.0) != up)?;
                    include(&found.state);
                }
            }
        }
        Ok(())
    })?;
    // the changes each transition made, at its time
    let log = sys.log.borrow();
    let mut transitions = Vec::new();
    for (tr, changes) in path.transitions.iter().zip(log.iter()) {
        transitions.extend(changes.iter().map(|&change| Event { t: tr.t, change }));
    }
    let window = scene.duration - from;
    let yf = y_from.unwrap_or(path.final_state);
    let onsets: Vec<f64> = transitions
        .iter()
        .filter(|e| matches!(e.change, Change::Pad { from: Pad::Stick, .. }) && e.t >= from)
        .map(|e| e.t)
        .collect();
    let band_breakaways =
        transitions.iter().filter(|e| matches!(e.change, Change::Band { from: Band::Stuck, .. }) && e.t >= from).count();
    let stats = Stats {
        pad: WindowStats::of([lo[0], lo[1], lo[2], lo[3]], [hi[0], hi[1], hi[2], hi[3]], stick_time, window, &onsets),
        band_mean_speed: (path.final_state[XB] - yf[XB]) / window,
        band_stuck_fraction: stuck_time / window,
        band_breakaways,
        band_speed_min: lo[4],
        band_speed_max: hi[4],
        p_min: lo[5],
        p_max: hi[5],
        p_mean: (path.final_state[P_INT] - yf[P_INT]) / window,
    };
    Ok(Run {
        start: arr(&y0),
        transitions,
        final_state: arr(&path.final_state),
        final_regime: path.final_regime,
        accepted_steps: path.accepted_steps,
        conductance: sys.conductance,
        stats,
    })
}

/// The right-hand side of `scene`'s pneumatic system in `regime` at `y` (for checks).
pub fn rhs(scene: &Scene, regime: Regime, y: &[f64; 10]) -> Result<[f64; 10], String> {
    let sys = Pneu::of(scene)?;
    Ok(arr(&sys.deriv(regime, &Y::from_row_slice(y))))
}
