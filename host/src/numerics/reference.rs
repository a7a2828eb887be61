//! An event-driven reference simulation of the model, independent of `stickslip_model`'s
//! stepper: its own right-hand side (written from docs/model.md, not from the crate's
//! matrices), the adaptive DOP853 integrator of the `ode_solvers` crate (Hairer-Wanner,
//! order 8 with step-size control; default rtol 1e-12, atol 1e-16), and event location by
//! bisection on re-integrated sub-intervals (default to 1e-13 s). It takes only the scene's
//! data from the crate.
//!
//! It is slow (tens of milliseconds per simulated second) and allocates; it is the yardstick
//! of the tests and the adaptive baseline of `stickslip accuracy`, not the product.

use ode_solvers::dop853::Dop853;
use ode_solvers::{OutputType, System, Vector4};
use stickslip_model::{Caliper, Scene};

type Y = Vector4<f64>;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Stick,
    Slower,
    Faster,
}

/// Physical constants written out from docs/model.md (pivot at the supported edge).
#[derive(Clone, Copy, Debug)]
struct Phys {
    m: f64,
    i: f64,
    kg: f64,
    cx: f64,
    cphi: f64,
    k_rot: f64,
    c_n: f64,
    moment_load: f64,
    s: f64,
    w: f64,
    v: f64,
    mu_s: f64,
    mu_k: f64,
    rotation: bool,
    phi0: f64,
}

impl Phys {
    fn of(sc: &Scene) -> Phys {
        let (dl, dt, arm, s) = match sc.caliper {
            Caliper::Push => (sc.l + sc.l_cl, sc.l - sc.l_ct, sc.beta, 1.0),
            Caliper::Pull => (sc.l - sc.l_cl, sc.l + sc.l_ct, 2.0 * sc.l - sc.beta, -1.0),
        };
        let k_rot = sc.k_l * dl * dl + sc.k_t * dt * dt;
        Phys {
            m: sc.m,
            i: sc.inertia,
            kg: sc.k_g,
            cx: sc.c_x,
            cphi: sc.c_phi,
            k_rot,
            c_n: sc.k_l * dl + sc.k_t * dt,
            moment_load: sc.f_n * arm,
            s,
            w: sc.w,
            v: sc.v,
            mu_s: sc.mu_s,
            mu_k: sc.mu_k,
            rotation: sc.rotation,
            phi0: sc.f_n * arm / k_rot,
        }
    }
    fn normal(&self, y: &Y) -> f64 {
        self.c_n * if self.rotation { y[2] } else { self.phi0 }
    }
    fn f_req(&self, y: &Y) -> f64 {
        self.kg * y[0] + self.cx * self.v
    }
    /// Friction force on the pad in `mode`.
    fn friction(&self, mode: Mode, y: &Y) -> f64 {
        match mode {
            Mode::Stick => self.f_req(y),
            Mode::Slower => self.mu_k * self.normal(y),
            Mode::Faster => -self.mu_k * self.normal(y),
        }
    }
    fn rhs(&self, mode: Mode, y: &Y) -> Y {
        let ff = self.friction(mode, y);
        let xdd = match mode {
            Mode::Stick => 0.0,
            _ => (-self.kg * y[0] - self.cx * y[1] + ff) / self.m,
        };
        let (phid, phidd) = if self.rotation {
            (y[3], (-self.k_rot * y[2] - self.cphi * y[3] + self.moment_load + self.s * self.w * ff) / self.i)
        } else {
            (0.0, 0.0)
        };
        Y::new(y[1], xdd, phid, phidd)
    }
    /// Guard value: the regime holds while negative.
    fn guard(&self, mode: Mode, y: &Y) -> f64 {
        match mode {
            Mode::Stick => self.f_req(y).abs() - self.mu_s * self.normal(y),
            Mode::Slower => y[1] - self.v,
            Mode::Faster => self.v - y[1],
        }
    }
}

struct Rhs {
    p: Phys,
    mode: Mode,
}

impl System<f64, Y> for Rhs {
    fn system(&self, _t: f64, y: &Y, dy: &mut Y) {
        *dy = self.p.rhs(self.mode, y);
    }
}

/// Tolerances of a reference run.
#[derive(Clone, Copy, Debug)]
pub struct Tolerances {
    /// Relative tolerance of DOP853's step-size control.
    pub rtol: f64,
    /// Absolute tolerance [state units: m, m/s, rad, rad/s].
    pub atol: f64,
    /// Width to which transitions and extrema are bisected [s].
    pub t_tol: f64,
    /// Largest step, as a fraction of 1 / omega_max (the fastest mode's period over 2 pi).
    pub h_max_factor: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances { rtol: 1e-12, atol: 1e-16, t_tol: 1e-13, h_max_factor: 0.05 }
    }
}

impl Tolerances {
    /// A looser run for the work-precision baseline: atol scaled with rtol, transitions to
    /// max(1e-13 s, rtol x 1e-3 s), steps up to 1/12 of the fastest period (the step-size
    /// control, not a cap, sets them).
    pub fn loose(rtol: f64) -> Self {
        Tolerances { rtol, atol: rtol * 1e-4, t_tol: (rtol * 1e-3).max(1e-13), h_max_factor: 0.5 }
    }
}

/// Step-end states of one DOP853 run in `mode` from (t0, y0) to t1, and the accepted steps.
fn integrate(p: Phys, mode: Mode, t0: f64, y0: Y, t1: f64, h_max: f64, tol: Tolerances) -> Result<(Vec<f64>, Vec<Y>, u64), String> {
    if t1 <= t0 {
        return Ok((vec![t0], vec![y0], 0));
    }
    let mut solver = Dop853::from_param(
        Rhs { p, mode },
        t0,
        t1,
        t1 - t0,
        y0,
        tol.rtol,
        tol.atol,
        0.9,
        0.0,
        0.333,
        6.0,
        h_max.min(t1 - t0),
        0.0,
        10_000_000,
        1000,
        OutputType::Sparse,
    );
    let stats = solver
        .integrate()
        .map_err(|e| format!("reference DOP853 failed from t = {t0} s in {mode:?}: {e:?}"))?;
    let (xs, ys) = (solver.x_out().clone(), solver.y_out().clone());
    if ys.iter().any(|y| !y.iter().all(|v| v.is_finite())) {
        return Err(format!("reference DOP853 produced a non-finite state after t = {t0} s in {mode:?}"));
    }
    Ok((xs, ys, stats.accepted_steps as u64))
}

fn state_at(p: Phys, mode: Mode, t0: f64, y0: Y, t: f64, h_max: f64, tol: Tolerances) -> Result<Y, String> {
    let (_, ys, _) = integrate(p, mode, t0, y0, t, h_max, tol)?;
    Ok(*ys.last().unwrap())
}

/// Statistics of the window, as in the product's contract.
#[derive(Clone, Copy, Debug, Default)]
pub struct RefStats {
    pub min: [f64; 4],
    pub max: [f64; 4],
    pub stick_fraction: f64,
    pub stick_slip_hz: f64,
    pub slip_onsets: usize,
}

impl RefStats {
    pub fn pp(&self, i: usize) -> f64 {
        self.max[i] - self.min[i]
    }
}

/// A reference run: the transitions (time, from, to), the window statistics (when asked for),
/// the final state and the work done.
pub struct RefRun {
    pub transitions: Vec<(f64, Mode, Mode)>,
    pub stats: RefStats,
    /// [x, x', phi, phi'] at `scene.duration`.
    pub final_state: [f64; 4],
    /// DOP853 steps accepted on the main path (not counting the bisections' re-integrations).
    pub accepted_steps: u64,
}

/// Simulates `scene` from the default initial state to `scene.duration` at the default (tight)
/// tolerances, window statistics over [scene.stats_from, scene.duration].
pub fn simulate(scene: &Scene) -> RefRun {
    simulate_with(scene, Tolerances::default(), true).expect("the reference run failed")
}

/// As [`simulate`], with given tolerances; `with_stats = false` skips the extremum search
/// (the window's extrema stay zero) for timing the trajectory alone.
pub fn simulate_with(scene: &Scene, tol: Tolerances, with_stats: bool) -> Result<RefRun, String> {
    let p = Phys::of(scene);
    // the fastest period bounds the step so no guard or extremum is stepped over
    let omega_max = (p.kg / p.m).sqrt().max(if p.rotation {
        ((p.k_rot + p.mu_s * p.w * p.c_n) / p.i).sqrt()
    } else {
        0.0
    });
    let h_max = tol.h_max_factor / omega_max;
    let mut t = 0.0;
    let mut y = Y::new(0.0, p.v, p.phi0, 0.0);
    if !p.rotation {
        y[2] = p.phi0;
    }
    let mut mode = Mode::Stick;
    let mut transitions = Vec::new();
    let t_win = scene.stats_from;
    let t_end = scene.duration;
    let mut ext: Option<([f64; 4], [f64; 4])> = None;
    let mut stick_time = 0.0;
    let mut onsets: Vec<f64> = Vec::new();
    let mut accepted = 0u64;
    let include = |ext: &mut Option<([f64; 4], [f64; 4])>, y: &Y| {
        let v = [y[0], y[1], y[2], y[3]];
        match ext {
            None => *ext = Some((v, v)),
            Some((lo, hi)) => {
                for i in 0..4 {
                    lo[i] = lo[i].min(v[i]);
                    hi[i] = hi[i].max(v[i]);
                }
            }
        }
    };
    while t < t_end {
        // next stop: the window start (if ahead) or the end
        let stop = if t < t_win { t_win } else { t_end };
        let (ts, ys, acc) = integrate(p, mode, t, y, stop, h_max, tol)?;
        accepted += acc;
        // first step end where the guard fired (never at the segment's own start)
        let fired = (1..ts.len()).find(|&k| p.guard(mode, &ys[k]) >= 0.0);
        let (seg_end, y_end, event) = match fired {
            None => (stop, *ys.last().unwrap(), false),
            Some(k) => {
                // bisection on (ts[k-1], ts[k]]: the guard is negative at lo, >= 0 at hi
                let (mut lo, mut hi) = (ts[k - 1], ts[k]);
                let y_lo0 = ys[k - 1];
                let mut y_hi = ys[k];
                while hi - lo > tol.t_tol {
                    let mid = 0.5 * (lo + hi);
                    let ym = state_at(p, mode, ts[k - 1], y_lo0, mid, h_max, tol)?;
                    if p.guard(mode, &ym) >= 0.0 {
                        hi = mid;
                        y_hi = ym;
                    } else {
                        lo = mid;
                    }
                }
                (hi, y_hi, true)
            }
        };
        // statistics over the part of this segment inside the window
        if t >= t_win {
            if mode == Mode::Stick {
                stick_time += seg_end - t;
            }
            let last = if with_stats { fired.unwrap_or(ts.len() - 1) } else { 0 };
            include(&mut ext, &y);
            include(&mut ext, &y_end);
            for k in 1..=last {
                let hi_t = if k == last { seg_end } else { ts[k] };
                let y_a = ys[k - 1];
                let y_b = if k == last { y_end } else { ys[k] };
                include(&mut ext, &y_b);
                let da = p.rhs(mode, &y_a);
                let db = p.rhs(mode, &y_b);
                for c in 0..4 {
                    if da[c] * db[c] < 0.0 {
                        // an interior extremum of component c: bisect on the sign of its rate
                        let (mut lo, mut hi) = (ts[k - 1], hi_t);
                        let sign_a = da[c] > 0.0;
                        let mut best = y_a;
                        while hi - lo > tol.t_tol {
                            let mid = 0.5 * (lo + hi);
                            let ym = state_at(p, mode, ts[k - 1], y_a, mid, h_max, tol)?;
                            if (p.rhs(mode, &ym)[c] > 0.0) == sign_a {
                                lo = mid;
                            } else {
                                hi = mid;
                            }
                            best = ym;
                        }
                        include(&mut ext, &best);
                    }
                }
            }
        }
        t = seg_end;
        y = y_end;
        if event {
            let next = match mode {
                Mode::Stick => {
                    if p.f_req(&y) > 0.0 {
                        Mode::Slower
                    } else {
                        Mode::Faster
                    }
                }
                _ => {
                    let f = p.f_req(&y);
                    let lim = p.mu_s * p.normal(&y);
                    if f.abs() <= lim {
                        Mode::Stick
                    } else if f > 0.0 {
                        Mode::Slower
                    } else {
                        Mode::Faster
                    }
                }
            };
            if next == Mode::Stick {
                y[1] = p.v;
            }
            if next != mode {
                transitions.push((t, mode, next));
                if mode == Mode::Stick && t >= t_win {
                    onsets.push(t);
                }
            }
            mode = next;
        }
    }
    let (min, max) = ext.unwrap_or(([0.0; 4], [0.0; 4]));
    let hz = if onsets.len() >= 2 {
        (onsets.len() - 1) as f64 / (onsets[onsets.len() - 1] - onsets[0])
    } else {
        0.0
    };
    Ok(RefRun {
        final_state: [y[0], y[1], y[2], y[3]],
        accepted_steps: accepted,
        transitions,
        stats: RefStats {
            min,
            max,
            stick_fraction: stick_time / (t_end - t_win),
            stick_slip_hz: hz,
            slip_onsets: onsets.len(),
        },
    })
}
