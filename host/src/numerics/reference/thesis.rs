//! The reference simulation of the thesis model, independent of `stickslip_model`'s stepper:
//! its own right-hand side (written from docs/model.md, not from the crate's matrices), run by
//! the event-driven DOP853 driver ([`super::driver`]; default rtol 1e-12, atol 1e-16,
//! transitions to 1e-13 s). It takes only the scene's data from the crate.
//!
//! The window's statistics are taken on the main path as it is integrated: the step ends, both
//! sides of every transition, and every extremum inside a step (bisected on the sign of the
//! quantity's rate).
//!
//! It is slow and allocates; it is the yardstick of the tests and the adaptive baseline of
//! `stickslip accuracy`, not the product.

use super::driver::{self, Bracket, Hybrid, Plan, State};
pub use super::driver::Tolerances;
use stickslip_model::{Caliper, Scene};

type Y = State<4>;

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
}

impl Hybrid<4> for Phys {
    type Regime = Mode;
    const NAME: &'static str = "thesis reference";

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
    /// The table of docs/model.md; entering stick sets x' = V.
    fn transition(&self, mode: Mode, y: &mut Y) -> Mode {
        let f = self.f_req(y);
        let next = match mode {
            Mode::Stick => {
                if f > 0.0 {
                    Mode::Slower
                } else {
                    Mode::Faster
                }
            }
            _ => {
                let lim = self.mu_s * self.normal(y);
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
            y[1] = self.v;
        }
        next
    }
    /// The fastest mode's angular frequency: it bounds the step so no guard or extremum is
    /// stepped over.
    fn fastest_rate(&self) -> f64 {
        (self.kg / self.m).sqrt().max(if self.rotation {
            ((self.k_rot + self.mu_s * self.w * self.c_n) / self.i).sqrt()
        } else {
            0.0
        })
    }
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
    let y0 = Y::new(0.0, p.v, p.phi0, 0.0);
    let t_win = scene.stats_from;
    let t_end = scene.duration;
    let mut ext: Option<([f64; 4], [f64; 4])> = None;
    let mut stick_time = 0.0;
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
    // one DOP853 run to the window's start, one from there to the end, each cut at events
    let plan = Plan { stop_at: Some(t_win), chunk_steps: None };
    let path = driver::run(&p, y0, Mode::Stick, t_end, plan, &tol, |piece| {
        let (mode, t, y, ts, ys) = (piece.regime, piece.t0, piece.y0, piece.ts, piece.ys);
        let (seg_end, y_end) = (piece.t1, piece.y1);
        // statistics over the part of this run inside the window
        if t >= t_win {
            if mode == Mode::Stick {
                stick_time += seg_end - t;
            }
            let last = if with_stats { piece.fired.unwrap_or(ts.len() - 1) } else { 0 };
            include(&mut ext, y);
            include(&mut ext, y_end);
            for k in 1..=last {
                let hi_t = if k == last { seg_end } else { ts[k] };
                let y_a = ys[k - 1];
                let y_b = if k == last { *y_end } else { ys[k] };
                include(&mut ext, &y_b);
                let da = p.rhs(mode, &y_a);
                let db = p.rhs(mode, &y_b);
                for c in 0..4 {
                    if da[c] * db[c] < 0.0 {
                        // an interior extremum of component c: bisect on the sign of its rate
                        let sign_a = da[c] > 0.0;
                        let step = Bracket { t_a: ts[k - 1], y_a, lo: ts[k - 1], hi: hi_t, y_hi: y_b };
                        let found =
                            driver::bisect(&p, mode, step, piece.h_max, &tol, |ym| (p.rhs(mode, ym)[c] > 0.0) != sign_a)?;
                        include(&mut ext, &found.last.unwrap_or(y_a));
                    }
                }
            }
        }
        Ok(())
    })?;
    let transitions: Vec<(f64, Mode, Mode)> =
        path.transitions.iter().filter(|tr| tr.to != tr.from).map(|tr| (tr.t, tr.from, tr.to)).collect();
    let onsets: Vec<f64> = transitions.iter().filter(|tr| tr.1 == Mode::Stick && tr.0 >= t_win).map(|tr| tr.0).collect();
    let (min, max) = ext.unwrap_or(([0.0; 4], [0.0; 4]));
    let hz = if onsets.len() >= 2 {
        (onsets.len() - 1) as f64 / (onsets[onsets.len() - 1] - onsets[0])
    } else {
        0.0
    };
    let y = path.final_state;
    Ok(RefRun {
        final_state: [y[0], y[1], y[2], y[3]],
        accepted_steps: path.accepted_steps,
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
