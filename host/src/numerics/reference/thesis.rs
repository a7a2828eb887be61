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
use super::common::{Pad, WindowStats};
use stickslip_model::Scene;

type Y = State<4>;

/// The contact's regime.
pub use super::common::Regime;

/// The pad's constants (docs/model.md) and its static rotation under the load.
#[derive(Clone, Copy, Debug)]
struct Phys {
    pad: Pad,
    phi0: f64,
}

impl Phys {
    fn of(sc: &Scene) -> Phys {
        let pad = Pad::of(sc);
        Phys { pad, phi0: pad.moment_load / pad.k_rot }
    }
    fn normal(&self, y: &Y) -> f64 {
        self.pad.c_n * if self.pad.rotation { y[2] } else { self.phi0 }
    }
    fn f_req(&self, y: &Y) -> f64 {
        self.pad.kg * y[0] + self.pad.cx * self.pad.v
    }
    /// Friction force on the pad in `regime`.
    fn friction(&self, regime: Regime, y: &Y) -> f64 {
        match regime {
            Regime::Stick => self.f_req(y),
            Regime::Slower => self.pad.mu_k * self.normal(y),
            Regime::Faster => -self.pad.mu_k * self.normal(y),
        }
    }
}

impl Hybrid<4> for Phys {
    type Regime = Regime;
    const NAME: &'static str = "thesis reference";

    fn rhs(&self, regime: Regime, y: &Y) -> Y {
        let ff = self.friction(regime, y);
        let xdd = match regime {
            Regime::Stick => 0.0,
            _ => (-self.pad.kg * y[0] - self.pad.cx * y[1] + ff) / self.pad.m,
        };
        let (phid, phidd) = if self.pad.rotation {
            (y[3], (-self.pad.k_rot * y[2] - self.pad.cphi * y[3] + self.pad.moment_load + self.pad.s * self.pad.w * ff) / self.pad.i)
        } else {
            (0.0, 0.0)
        };
        Y::new(y[1], xdd, phid, phidd)
    }
    /// Guard value: the regime holds while negative.
    fn guard(&self, regime: Regime, y: &Y) -> f64 {
        match regime {
            Regime::Stick => self.f_req(y).abs() - self.pad.mu_s * self.normal(y),
            Regime::Slower => y[1] - self.pad.v,
            Regime::Faster => self.pad.v - y[1],
        }
    }
    /// The table of docs/model.md; entering stick sets x' = V.
    fn transition(&self, regime: Regime, y: &mut Y) -> Regime {
        let next = regime.after(self.f_req(y), self.pad.mu_s * self.normal(y));
        if next == Regime::Stick {
            y[1] = self.pad.v;
        }
        next
    }
    /// The fastest mode's angular frequency: it bounds the step so no guard or extremum is
    /// stepped over.
    fn fastest_rate(&self) -> f64 {
        (self.pad.kg / self.pad.m).sqrt().max(if self.pad.rotation {
            ((self.pad.k_rot + self.pad.mu_s * self.pad.w * self.pad.c_n) / self.pad.i).sqrt()
        } else {
            0.0
        })
    }
}

/// Statistics of the window, as in the product's contract: [x, x', phi, phi'].
pub type RefStats = WindowStats<4>;

/// A reference run: the transitions (time, from, to), the window statistics (when asked for),
/// the final state and the work done.
pub struct RefRun {
    pub transitions: Vec<(f64, Regime, Regime)>,
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
    let y0 = Y::new(0.0, p.pad.v, p.phi0, 0.0);
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
    let path = driver::run(&p, y0, Regime::Stick, t_end, plan, &tol, |piece| {
        let (regime, t, y, ts, ys) = (piece.regime, piece.t0, piece.y0, piece.ts, piece.ys);
        let (seg_end, y_end) = (piece.t1, piece.y1);
        // statistics over the part of this run inside the window
        if t >= t_win {
            if regime == Regime::Stick {
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
                let da = p.rhs(regime, &y_a);
                let db = p.rhs(regime, &y_b);
                for c in 0..4 {
                    if da[c] * db[c] < 0.0 {
                        // an interior extremum of component c: bisect on the sign of its rate
                        let sign_a = da[c] > 0.0;
                        let step = Bracket { t_a: ts[k - 1], y_a, lo: ts[k - 1], hi: hi_t, y_hi: y_b };
                        let found =
                            driver::bisect(&p, regime, step, piece.h_max, &tol, |ym| (p.rhs(regime, ym)[c] > 0.0) != sign_a)?;
                        include(&mut ext, &found.last.unwrap_or(y_a));
                    }
                }
            }
        }
        Ok(())
    })?;
    let transitions: Vec<(f64, Regime, Regime)> =
        path.transitions.iter().filter(|tr| tr.to != tr.from).map(|tr| (tr.t, tr.from, tr.to)).collect();
    let onsets: Vec<f64> = transitions.iter().filter(|tr| tr.1 == Regime::Stick && tr.0 >= t_win).map(|tr| tr.0).collect();
    let (min, max) = ext.unwrap_or(([0.0; 4], [0.0; 4]));
    let y = path.final_state;
    Ok(RefRun {
        final_state: [y[0], y[1], y[2], y[3]],
        accepted_steps: path.accepted_steps,
        transitions,
        stats: WindowStats::of(min, max, stick_time, t_end - t_win, &onsets),
    })
}
