//! The reference simulation of model 2, part 1 (docs/model.md, "Model 2, part 1: falling
//! friction, a band that moves, damping"), independent of `stickslip_model`'s matrices and
//! steppers, and of the thesis reference's right-hand side ([`super::thesis`]): its own
//! right-hand side written from the equations of docs/model.md (it takes only the scene's data
//! and computes the lever arms itself), run by the event-driven DOP853 driver
//! ([`super::driver`]) in chunks of 400 largest steps.
//!
//! The state is `z = [x, x', phi, phi', u, u']` with `u = x_b - V t` the band's offset from its
//! drive point (`u = u' = 0` for good without the band; `phi = phi_0`, `phi' = 0` for good
//! without rotation). The sliding velocity is `v = x' - V - u'`, with friction-face kinematics
//! (`face`) `v = x' + s w phi' - V - u'`; stick then holds the face, and its friction is solved
//! from the three equations of motion and the constraint `v' = 0` as written (not from the
//! model crate's scaled form).
//!
//! Event location (the driver's, with what this model gives it):
//! - a regime's guard `g(z)` is negative while the regime holds (stick:
//!   `|F_req| - mu_s N`; slip with the pad slower: `v`; faster: `-v`);
//! - its rate is written analytically, so that the driver locates crests of `g` inside a step
//!   (a graze is not missed); the step is capped at a fraction of the fastest time scale;
//! - **Arming of slip phases.** With Stribeck friction a slip phase starts at `v = 0` with
//!   `v' = 0` (the friction is continuous at breakaway), so its guard is 0 (or round-off above
//!   it) at the start. A slip phase's guard is therefore *armed* only once it has been below
//!   `-ARM * V` (`ARM = 1e-9`) at a step end; before that the phase cannot end. A slip phase
//!   whose `|v|` never exceeds `1e-9 V` would be missed (it cannot occur with Coulomb friction,
//!   where `v'` jumps away from 0 at breakaway).
//!
//! Transitions follow the table of docs/model.md. Entering stick sets `v = 0`: without the band
//! `x' = V`; with the band both velocities to the momentum velocity
//! `(m x' + m_b x_b') / (m + m_b)`; with the face, the friction impulse
//! `P = -v / (1/m + w^2/I + 1/m_b)` changes x', phi', u' by `P/m`, `s w P / I`, `-P/m_b`.
//!
//! Slow and allocating: a yardstick for tests, not the product.

use super::driver::{self, arr, Bracket, Hybrid, Plan, State};
pub use super::driver::Tolerances;
use super::common::{Pad, WindowStats};
use stickslip_model::{FrictionLaw, Scene};

mod hybrid;
pub(crate) mod physics;
mod unilateral;
use physics::*;
pub use unilateral::{simulate_unilateral, Contact, UnilateralRun};

/// [x, x', phi, phi', u, u', y, y'] (y: the floating pad's pivot normal to the band).
type Z = State<8>;

/// Guards of slip phases are armed once `v` has been beyond `ARM * V` (see the module doc).
const ARM: f64 = 1e-9;
/// Integration is done in chunks of this many largest steps, so an early event does not pay for
/// integrating to the end of the run.
const CHUNK_STEPS: f64 = 400.0;

/// The regime of the contact.
pub use super::common::Regime;

/// One transition: at `t` the regime changed from `from` to `to`; `state` is the state the new
/// regime starts from (after the stick projection `v = 0` when `to` is stick).
pub type Transition = driver::Transition<Regime, 8>;

/// Window statistics of a run. Quantities are indexed [x, x', phi, phi', x_b', u''] (x_b' =
/// V + u' the band's velocity, u'' its acceleration; V and 0 without the band).
pub type Stats = WindowStats<6>;

/// Where a run starts: the state `[x, x', phi, phi', u, u', y, y']` at t = 0 and its regime.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Start {
    pub state: [f64; 8],
    pub regime: Regime,
}

impl Start {
    /// The default initial state of docs/model.md: stick, x = 0, x' = V, phi = F_N a_N / K,
    /// phi' = 0, u = u' = 0 (the floating pad: (y, phi) static under the load, y' = 0).
    pub fn default_of(scene: &Scene) -> Start {
        let p = Phys::of(scene);
        Start { state: [0.0, p.pad.v, p.phi0, 0.0, 0.0, 0.0, p.y0, 0.0], regime: Regime::Stick }
    }
}

/// A reference run of model 2, part 1, from t = 0 to `duration`.
#[derive(Clone, Debug)]
pub struct Run {
    /// The start state and regime (after normalisation: phi held without rotation, u = u' = 0
    /// without the band).
    pub start: Start,
    pub transitions: Vec<Transition>,
    /// The state at `duration`, and its regime.
    pub final_state: [f64; 8],
    pub final_regime: Regime,
    pub duration: f64,
    /// DOP853 steps accepted on the main path (not counting bisections).
    pub accepted_steps: u64,
    p: Phys,
    tol: Tolerances,
    h_max: f64,
}

/// Runs `scene` from the default initial state to `scene.duration` at the default (tight)
/// tolerances (rtol 1e-12, atol 1e-16, transitions to 1e-13 s, steps up to 0.05 / the fastest
/// rate).
pub fn simulate(scene: &Scene) -> Result<Run, String> {
    simulate_from(scene, Start::default_of(scene), Tolerances::default())
}

/// Runs `scene` from `start` (at t = 0) to `scene.duration` with the given tolerances.
pub fn simulate_from(scene: &Scene, start: Start, tol: Tolerances) -> Result<Run, String> {
    scene.validate().map_err(|e| format!("invalid scene: {e}"))?;
    let p = Phys::of(scene);
    let mut z = Z::from_row_slice(&start.state);
    if !p.pad.rotation {
        z[2] = p.phi0;
        z[3] = 0.0;
    }
    if !p.band {
        z[4] = 0.0;
        z[5] = 0.0;
    }
    if !p.floating {
        z[6] = 0.0;
        z[7] = 0.0;
    }
    if start.regime == Regime::Stick {
        p.project_stick(&mut z);
    }
    let plan = Plan { stop_at: None, chunk_steps: Some(CHUNK_STEPS) };
    let path = driver::run(&p, z, start.regime, scene.duration, plan, &tol, |_| Ok(()))?;
    Ok(Run {
        start: Start { state: path.start.0, regime: path.start.1 },
        transitions: path.transitions,
        final_state: arr(&path.final_state),
        final_regime: path.final_regime,
        duration: scene.duration,
        accepted_steps: path.accepted_steps,
        p,
        tol,
        h_max: path.h_max,
    })
}

impl Run {
    /// The regime segments: (start time, start state, regime, end time).
    fn segments(&self) -> Vec<(f64, Z, Regime, f64)> {
        let mut out = Vec::with_capacity(self.transitions.len() + 1);
        let mut t0 = 0.0;
        let mut z0 = Z::from_row_slice(&self.start.state);
        let mut r0 = self.start.regime;
        for tr in &self.transitions {
            out.push((t0, z0, r0, tr.t));
            t0 = tr.t;
            z0 = Z::from_row_slice(&tr.state);
            r0 = tr.to;
        }
        out.push((t0, z0, r0, self.duration));
        out
    }

    /// Integrates a segment from its start to `t1` in chunks; the step ends of every chunk at
    /// and after `from` are handed to `f` (times, states).
    fn walk<F: FnMut(&[f64], &[Z]) -> Result<(), String>>(
        &self,
        seg: (f64, Z, Regime),
        from: f64,
        t1: f64,
        mut f: F,
    ) -> Result<Z, String> {
        let (mut t, mut z, regime) = seg;
        let chunk = CHUNK_STEPS * self.h_max;
        if from > t {
            // to the window's start without output
            while t < from {
                let stop = if from - t > 1.5 * chunk { t + chunk } else { from };
                z = driver::state_at(&self.p, regime, t, z, stop, self.h_max, &self.tol)?;
                t = stop;
            }
        }
        while t < t1 {
            let stop = if t1 - t > 1.5 * chunk { t + chunk } else { t1 };
            let (ts, zs, _) = driver::integrate(&self.p, regime, t, z, stop, self.h_max, &self.tol)?;
            f(&ts, &zs)?;
            t = stop;
            z = *zs.last().expect("DOP853 output holds the start");
        }
        Ok(z)
    }

    /// Statistics over [from, to] (0 <= from < to <= duration): the true extremes of the
    /// continuous motion (extrema inside a step are bisected on the sign of the quantity's rate;
    /// both one-sided values at a transition count), the stick fraction and the stick-slip
    /// frequency.
    pub fn window_stats(&self, from: f64, to: f64) -> Result<Stats, String> {
        if !(from >= 0.0 && from < to && to <= self.duration) {
            return Err(format!("model-2 reference: window [{from}, {to}] s not inside [0, {}] s", self.duration));
        }
        let p = self.p;
        let mut lo = [f64::INFINITY; 6];
        let mut hi = [f64::NEG_INFINITY; 6];
        let mut stick_time = 0.0;
        for (t0, z0, regime, t1) in self.segments() {
            if t0 > to || (t1 <= from && t0 < from) {
                continue;
            }
            let (a, b) = (t0.max(from), t1.min(to));
            if regime == Regime::Stick {
                stick_time += b - a;
            }
            let mut include = |q: [f64; 6]| {
                for c in 0..6 {
                    lo[c] = lo[c].min(q[c]);
                    hi[c] = hi[c].max(q[c]);
                }
            };
            if t0 >= from {
                include(p.quantities(regime, &z0));
            }
            if b <= a {
                continue;
            }
            let tol = self.tol;
            let h_max = self.h_max;
            let z_end = self.walk((t0, z0, regime), a, b, |ts, zs| {
                include(p.quantities(regime, &zs[0]));
                for k in 1..zs.len() {
                    include(p.quantities(regime, &zs[k]));
                    let ra = p.quantity_rates(regime, &zs[k - 1]);
                    let rb = p.quantity_rates(regime, &zs[k]);
                    for c in 0..6 {
                        if ra[c] * rb[c] < 0.0 {
                            let up = ra[c] > 0.0;
                            let step = Bracket { t_a: ts[k - 1], y_a: zs[k - 1], lo: ts[k - 1], hi: ts[k], y_hi: zs[k] };
                            let found = driver::bisect(&p, regime, step, h_max, &tol, |y| {
                                (p.quantity_rates(regime, y)[c] > 0.0) != up
                            })?;
                            include(p.quantities(regime, &found.state));
                        }
                    }
                }
                Ok(())
            })?;
            include(p.quantities(regime, &z_end));
        }
        let onsets: Vec<f64> = self
            .transitions
            .iter()
            .filter(|tr| tr.from == Regime::Stick && tr.t >= from && tr.t <= to)
            .map(|tr| tr.t)
            .collect();
        Ok(Stats::of(lo, hi, stick_time, to - from, &onsets))
    }

    /// The regime at time t (the regime a transition at exactly t enters).
    pub fn regime_at(&self, t: f64) -> Regime {
        self.transitions.iter().take_while(|tr| tr.t <= t).last().map_or(self.start.regime, |tr| tr.to)
    }

    /// The states `[x, x', phi, phi', u, u', y, y']` at the given times (each in [0, duration]; any
    /// order). At a transition's time the state is the one the new regime starts from. Each
    /// state is integrated from the previous requested time in the same segment (or the
    /// segment's start), at the run's tolerances.
    pub fn sample(&self, times: &[f64]) -> Result<Vec<[f64; 8]>, String> {
        if let Some(t) = times.iter().find(|t| !(**t >= 0.0 && **t <= self.duration)) {
            return Err(format!("model-2 reference: sample time {t} s not inside [0, {}] s", self.duration));
        }
        let mut order: Vec<usize> = (0..times.len()).collect();
        order.sort_by(|a, b| times[*a].total_cmp(&times[*b]));
        let segs = self.segments();
        let mut out = vec![[0.0; 8]; times.len()];
        let mut si = 0;
        let (mut t, mut z) = (segs[0].0, segs[0].1);
        for idx in order {
            let tq = times[idx];
            // the segment holding tq: the last one starting at or before it
            while si + 1 < segs.len() && segs[si + 1].0 <= tq {
                si += 1;
                t = segs[si].0;
                z = segs[si].1;
            }
            let regime = segs[si].2;
            z = self.walk((t, z, regime), t, tq, |_, _| Ok(()))?;
            t = tq;
            out[idx] = arr(&z);
        }
        Ok(out)
    }

    /// Window statistics over the scene's window [stats_from, duration].
    pub fn stats(&self, scene: &Scene) -> Result<Stats, String> {
        self.window_stats(scene.stats_from, self.duration)
    }
}
