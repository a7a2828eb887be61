//! A run with the pneumatic band drive (model 3, option 1; docs/model.md, "Model 3, part 3"):
//! model 2's pad and band ([`System`]) with the band pushed by the cylinder of
//! [`super::cylinder`] instead of a drive point at V, and the cylinder seal's own stick and slip.
//!
//! State w = [z, p, x_b]: model 2's z = [x, x', phi, phi', u, u', y, y'] (u = x_b - V t, V the
//! scene's reference speed), the chamber pressure p [Pa] and the band's position x_b [m]. The
//! regimes are the pad's (stick, slip slower, slip faster) times the band's (sliding forward,
//! sliding back, stuck at its seal):
//!
//! - **band sliding**: z' = A_r z + g_r G + b q (model 2's equations with k_b = 0, c_b the
//!   guides' damping; the cylinder's net force G = A (p - p_atm) - F_seal - c_b V enters along
//!   [`System::band_force_response`]), p' and x_b' from the cylinder;
//! - **band stuck** (x_b' = 0): the pad against a band at rest (model 2's equations without the
//!   band, V = 0), u' = -V held, p' with x_b' = 0; the band breaks away once the net force on
//!   it, A (p - p_atm) less the pad's friction, reaches the seal's static friction.
//!
//! Every regime is stepped by the Dormand-Prince 5(4) pair under error control (each
//! component's local error at most `rtol` times the largest magnitude it has reached, max norm;
//! the air column is not linear in p and x_b), steps end at every grid time k dt, where the
//! sink gets the state (no interpolation). Guards (the pad's breakaway and velocity match, the
//! band's stop and breakaway) are located by the Illinois method on the step's own solution from
//! its start. A guard that rises through zero and falls back inside one step is not seen: steps
//! are at most one grid interval and the error control's, and a run states its step count.
//!
//! f64 only, on the host (the crate's feature `model3`).

use crate::coefficients::Coefficients;
use crate::halt::{Halt, Limits};
use crate::model2::stepper::{Model2Observer, Model2Segment};
use crate::model2::system::{System, NA, NS, ONE, Y};
use crate::scene::{Scene, SceneError};
use crate::stickslip::Regime;

use super::cylinder::Cylinder;

mod equations;
mod events;

/// State size: model 2's z, then p and x_b.
pub const NP: usize = NS + 2;
/// Index of the chamber pressure p [Pa] and of the band position x_b [m] in the state.
pub const P: usize = NS;
pub const XB: usize = NS + 1;
/// Smallest magnitude a component's error is taken relative to, per component of w: a
/// nanometre, a nanoradian, a micrometre (or microradian) per second, a pascal; x_b's is the
/// column's length (set in `new`). Not smaller: the cylinder's force A (p - p_atm) carries p's
/// round-off (an ulp of 1e5 Pa times A), which tolerances far below these would chase.
const SCALE_FLOOR: [f64; NP] = [1e-9, 1e-6, 1e-9, 1e-6, 1e-9, 1e-6, 1e-9, 1e-6, 1.0, 0.0];
/// The event runner's range limits of the band and the floating pad (|u| [m], |u'| [m/s],
/// |y| [m], |y'| [m/s]).
const U_LIMIT: f64 = 1.0;
const UDOT_LIMIT: f64 = 1e3;
const Y_LIMIT: f64 = 0.1;
const YDOT_LIMIT: f64 = 1e3;
/// Steps a run may take per grid interval (plus a million) before it stops as stalled: every
/// run is bounded.
pub const STEP_BUDGET_PER_SAMPLE: f64 = 1000.0;
/// A guard is located to this fraction of the step.
const GUARD_TOL: f64 = 1e-14;

/// The band at its seal: sliding forward (+1), back (-1), or stuck (0).
pub type BandMotion = i8;

/// What a pneumatic run measured of its drive over the statistics window.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DriveStats {
    /// Window length [s] and the time the band spent stuck at its seal in it [s].
    pub window_s: f64,
    pub stuck_s: f64,
    /// Seal breakaways in the window (stuck to sliding).
    pub breakaways: u64,
    /// The band's travel over the window [m] (its mean speed: travel / window).
    pub travel: f64,
    /// Chamber pressure over the window: time mean, least, greatest [Pa] (absolute).
    pub p_mean: f64,
    pub p_min: f64,
    pub p_max: f64,
    /// The throttle's conductance [m^3/(s Pa)] and whether it was solved from V.
    pub conductance: f64,
    pub conductance_solved: bool,
    /// The air column's small-signal stiffness at the mean pressure and mean position [N/m].
    pub column_stiffness: f64,
}

impl DriveStats {
    /// The band's mean speed over the window [m/s].
    pub fn mean_speed(&self) -> f64 {
        if self.window_s > 0.0 {
            self.travel / self.window_s
        } else {
            0.0
        }
    }

    /// The fraction of the window the band spent stuck.
    pub fn stuck_fraction(&self) -> f64 {
        if self.window_s > 0.0 {
            self.stuck_s / self.window_s
        } else {
            0.0
        }
    }
}

/// A sample on the grid: time [s], the pad's regime, the band's motion, the state and its rate,
/// the normal force N [N], the friction force on the pad [N] and the sliding velocity [m/s].
#[derive(Clone, Copy, Debug)]
pub struct PneumaticSample {
    pub t: f64,
    pub regime: Regime,
    pub band: BandMotion,
    pub w: [f64; NP],
    pub d: [f64; NP],
    pub n: f64,
    pub f_f: f64,
    pub v_slide: f64,
}

/// Counts of a run's work.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PneumaticCounts {
    pub steps: u64,
    pub rejected: u64,
    pub transitions: u64,
    pub band_changes: u64,
}

/// A run of a scene with the pneumatic drive (f64).
#[derive(Clone, Debug)]
pub struct PneumaticRunner {
    /// The pad and the sliding band (k_b = 0), and the pad against the band at rest.
    sliding: System,
    stuck: System,
    /// A band force's direction in each regime (sliding band) and its share in F_req.
    g: [[f64; NS]; 3],
    f_g: f64,
    cyl: Cylinder,
    v: f64,
    /// The pad's friction in steady sliding at V [N] (the throttle's solve, the sliding start).
    pad_friction: f64,
    /// No pad friction (F_N = 0 or mu_s = 0): the pad's regime is slip for good.
    frictionless: bool,
    limits: Limits<f64>,
    float_limits: [f64; 4],
    h_max: f64,
    rtol: f64,
    scale: [f64; NP],
    w: [f64; NP],
    regime: Regime,
    band: BandMotion,
    t: f64,
    h: f64,
    counts: PneumaticCounts,
    stats: DriveStats,
    p_integral: f64,
    xb_mean_integral: f64,
}

/// Why a pneumatic run stopped short.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PneumaticStop {
    /// The stepper's halt (out of range, contact loss, not finite).
    Halt(Halt),
    /// The error control asked for a step below round-off, transitions without time
    /// advancing, or the run used up its step budget ([`STEP_BUDGET_PER_SAMPLE`] steps per grid
    /// interval), at `t` [s].
    Stalled { t: f64 },
}

impl PneumaticRunner {
    /// Validates `scene` (which must have `drive = "pneumatic"`), builds its equations and the
    /// cylinder (the throttle solved from V when not given), and starts at rest as the band
    /// breaks away: the pad in stick on the band, the band at rest and sliding forward, the
    /// chamber at p_atm + F_ss / A (the seal's static friction just reached: the rig's run
    /// starts when the band starts to move, at 0.6 to 0.7 bar gauge in the thesis).
    pub fn new(scene: &Scene, rtol: f64) -> Result<Self, SceneError> {
        scene.validate()?;
        if !scene.pneumatic() {
            return Err(SceneError { field: "drive", rule: "the pneumatic runner needs drive = \"pneumatic\"", value: 0.0 });
        }
        let base = scene.linearised_contact();
        let mut free_band = base;
        free_band.k_b = 0.0;
        let co = Coefficients::of(&free_band);
        let sliding = System::of(&free_band, &co);
        let (g, f_g) = System::band_force_response(&free_band, &co);
        let mut fixed_band = base;
        fixed_band.band = false;
        fixed_band.v = 0.0;
        let stuck = System::of(&fixed_band, &Coefficients::of(&fixed_band));
        // the pad's friction at V in steady sliding: the load the throttle is solved for
        let pad_friction = super::cylinder::steady_pad_friction(&free_band);
        let cyl = Cylinder::of(scene, pad_friction)?;
        // the fastest linear mode with the column at its stiffest (supply pressure, start volume)
        let mut stiff = base;
        stiff.k_b = cyl.column_stiffness(cyl.p_s, 0.0);
        let stiff_co = Coefficients::of(&stiff);
        let rate = System::of(&stiff, &stiff_co).linear_rate(&stiff, &stiff_co);
        let h_max = if rate > 0.0 { 1.0 / rate } else { scene.duration };
        let floor = |d: f64| -(1e-6 * libm::fabs(sliding.y0 + d * sliding.phi0) + 1e-12);
        let mut w = [0.0; NP];
        w[2] = sliding.phi0;
        w[5] = -scene.v;
        w[Y] = sliding.y0;
        // the run starts as the band breaks away: the chamber at the seal's static friction
        w[P] = crate::scene::ATMOSPHERE_PA + cyl.f_ss / cyl.area;
        let mut scale = SCALE_FLOOR;
        for i in 0..NP {
            scale[i] = scale[i].max(libm::fabs(w[i]));
        }
        // x_b acts through the chamber's volume A (L_0 + x_b): its error is relative to L_0
        scale[XB] = cyl.l0;
        let frictionless = !(sliding.n0 * scene.mu_s > 0.0);
        Ok(PneumaticRunner {
            sliding,
            stuck,
            g,
            f_g,
            cyl,
            v: scene.v,
            pad_friction,
            frictionless,
            limits: Limits::new(scene, &co),
            float_limits: [sliding.d_l, sliding.d_t, floor(sliding.d_l), floor(sliding.d_t)],
            h_max,
            rtol,
            scale,
            w,
            regime: if frictionless { Regime::SlipSlower } else { Regime::Stick },
            band: 1,
            t: 0.0,
            h: 0.0,
            counts: PneumaticCounts::default(),
            stats: DriveStats { conductance: cyl.conductance, conductance_solved: cyl.solved, ..DriveStats::default() },
            p_integral: 0.0,
            xb_mean_integral: 0.0,
        })
    }

    /// The cylinder (its conductance as given or solved).
    pub fn cylinder(&self) -> &Cylinder {
        &self.cyl
    }

    pub fn state(&self) -> [f64; NP] {
        self.w
    }

    pub fn regime(&self) -> Regime {
        self.regime
    }

    pub fn band(&self) -> BandMotion {
        self.band
    }

    pub fn time(&self) -> f64 {
        self.t
    }

    pub fn counts(&self) -> PneumaticCounts {
        self.counts
    }

    /// The longest step [s]: one radian of the fastest linear mode (the column at its stiffest).
    pub fn max_step(&self) -> f64 {
        self.h_max
    }

    /// Starts from `w` with the pad in `regime` and the band in `band` instead of at rest
    /// (e.g. steady sliding, for a stability test).
    pub fn set_state(&mut self, w: [f64; NP], regime: Regime, band: BandMotion) {
        self.w = w;
        self.regime = if self.frictionless { Regime::SlipSlower } else { regime };
        self.band = band;
        for i in 0..NP {
            self.scale[i] = self.scale[i].max(libm::fabs(w[i]));
        }
    }

    /// Starts from model 2's state `z` in slip slower with the band sliding forward and the
    /// chamber at the steady pressure of sliding at V ([`Cylinder::steady_pressure`]): the
    /// maps' start from perturbed sliding.
    pub fn set_sliding(&mut self, z: [f64; NS]) {
        let mut w = [0.0; NP];
        w[..NS].copy_from_slice(&z);
        w[P] = self.cyl.steady_pressure(self.v, self.pad_friction);
        self.set_state(w, Regime::SlipSlower, 1);
    }

    /// The drive's statistics over the window so far.
    pub fn drive_stats(&self) -> DriveStats {
        let mut s = self.stats;
        if s.window_s > 0.0 {
            s.p_mean = self.p_integral / s.window_s;
            s.column_stiffness = self.cyl.column_stiffness(s.p_mean, self.xb_mean_integral / s.window_s);
        }
        s
    }

    fn sample(&self, w: &[f64; NP], d: &[f64; NP]) -> PneumaticSample {
        PneumaticSample {
            t: self.t,
            regime: self.regime,
            band: self.band,
            w: *w,
            d: *d,
            n: self.normal_force(w),
            f_f: self.friction_force(self.regime, self.band, w),
            v_slide: self.sliding_velocity(w),
        }
    }

    /// Runs to `t_end` [s] with samples at every grid time k dt: `obs` gets every step's
    /// segment and the pad's transitions, `on_sample` the state at each grid time (returning
    /// false stops the run there). The drive's statistics count from `t_from` [s].
    pub fn run_sampled<O: Model2Observer<f64>>(
        &mut self,
        t_from: f64,
        t_end: f64,
        dt: f64,
        obs: &mut O,
        on_sample: &mut dyn FnMut(&PneumaticSample) -> bool,
    ) -> Result<(), PneumaticStop> {
        let mut w0 = self.w;
        let mut d0 = self.derivative(self.regime, self.band, &w0);
        if self.h == 0.0 {
            self.h = self.h_max * 1e-3;
        }
        let mut k_next = libm::floor(self.t / dt) as u64 + 1;
        let mut stalls = 0u32;
        let used0 = self.counts.steps + self.counts.rejected;
        let budget = used0 + 1e6 as u64 + (STEP_BUDGET_PER_SAMPLE * ((t_end - self.t) / dt).max(0.0)) as u64;
        let t0 = self.t;
        let mut window_started = self.t >= t_from;
        if window_started && self.stats.window_s == 0.0 {
            self.stats.p_min = w0[P];
            self.stats.p_max = w0[P];
        }
        while self.t < t_end {
            let mut stop = t_end;
            if self.t < t_from && t_from < stop {
                stop = t_from;
            }
            let tg = k_next as f64 * dt;
            let at_grid = tg <= stop;
            if at_grid {
                stop = tg;
            }
            let limit = stop - self.t;
            if limit <= 1e-13 * (libm::fabs(self.t) + 1e-3) {
                // a stop within round-off of the present (a grid time's product k dt): reached
                self.t = stop;
                if at_grid {
                    k_next += 1;
                    let sample = self.sample(&w0, &d0);
                    if !on_sample(&sample) {
                        break;
                    }
                }
                continue;
            }
            let used = self.counts.steps + self.counts.rejected;
            if used > budget || crate::model2::event_run::behind_pace(used - used0, budget - used0, t0, self.t, t_end) {
                return Err(PneumaticStop::Stalled { t: self.t });
            }
            let (h, w1, d1) = self.step(&w0, &d0, limit)?;
            let event = self.first_guard(&w0, &d0, h, &w1);
            let (theta, we, guard) = match event {
                Some((th, we, k)) => (th, we, Some(k)),
                None => (1.0, w1, None),
            };
            let reached = guard.is_none() && h == limit;
            let t1 = if reached { stop } else { self.t + theta * h };
            let de = if guard.is_some() { self.derivative(self.regime, self.band, &we) } else { d1 };
            self.check(&we, t1).map_err(PneumaticStop::Halt)?;
            obs.segment(&Model2Segment { regime: self.regime, t0: self.t, t1, z0: Self::z(&w0), z1: Self::z(&we), zd0: Self::z(&d0), zd1: Self::z(&de) });
            if self.t >= t_from && t1 > self.t {
                // steps end at t_from: none straddles the window's start
                if !window_started {
                    window_started = true;
                    self.stats.p_min = w0[P];
                    self.stats.p_max = w0[P];
                }
                let span = t1 - self.t;
                self.stats.window_s += span;
                if self.band == 0 {
                    self.stats.stuck_s += span;
                }
                // trapezoids: steps are short against the pressure's swings
                self.p_integral += 0.5 * (w0[P] + we[P]) * span;
                self.xb_mean_integral += 0.5 * (w0[XB] + we[XB]) * span;
                self.stats.travel += we[XB] - w0[XB];
                self.stats.p_min = self.stats.p_min.min(we[P]);
                self.stats.p_max = self.stats.p_max.max(we[P]);
            }
            if t1 > self.t {
                stalls = 0;
            } else {
                stalls += 1;
                if stalls > 64 {
                    return Err(PneumaticStop::Stalled { t: self.t });
                }
            }
            self.t = t1;
            for i in 0..NP {
                self.scale[i] = self.scale[i].max(libm::fabs(we[i]));
            }
            w0 = match guard {
                Some(k) => self.fire(k, we, t1, t_from, obs),
                None => we,
            };
            d0 = self.derivative(self.regime, self.band, &w0);
            self.w = w0;
            if reached && at_grid {
                k_next += 1;
                let sample = self.sample(&w0, &d0);
                if !on_sample(&sample) {
                    break;
                }
            }
        }
        Ok(())
    }
}

/// (z, 1) . row.
#[inline(always)]
fn dot(r: &[f64; NA], z: &[f64; NS]) -> f64 {
    let mut s = r[ONE];
    for i in 0..NS {
        s += r[i] * z[i];
    }
    s
}
