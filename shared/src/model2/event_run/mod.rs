//! Statistics at event speed (issue 35, item 3): a model-2 run that goes from event to event
//! instead of stepping at the sample rate, for runs that need only the statistics of the
//! continuous motion (no samples on the grid).
//!
//! - **Linear regimes** (stick, Coulomb slip): the exact flow ([`flow::Taylor`], the series of
//!   expm(A s) (z, 1) summed to round-off) over steps of up to one radian of the fastest mode
//!   (`System::linear_rate`), so that a guard or an extremum changes sign at most once per step.
//! - **Stribeck slip**: the Dormand-Prince 5(4) pair ([`rk`]) with error control: every
//!   component's local error at most `rtol` times the largest magnitude that component has
//!   reached in the run (floor 1e-12 in SI units), max norm. The tolerance against the
//!   statistics' error is measured by `cargo run --release -p stickslip --example event_speed`.
//! - **Events**, inside each step: the regime's guards (the stepper's rows: stick's breakaway
//!   F_req -+ mu_s N, slip's sliding velocity), and crests of a guard (a rise and fall inside
//!   the step, found from its rate's sign change), end the regime; the zeros of x', x'', phi',
//!   phi'', u'', and of the accelerations' rates x''' and u''' split the motion into segments at
//!   the extremes of x, x', phi, phi', the band velocity and the accelerations, so the
//!   statistics observer needs no interpolation
//!   ([`crate::model2::Model2StatsObserver::without_interpolation`]). Each is located by the
//!   Illinois method on the step's own solution from its start (the exact flow; in Stribeck
//!   slip a fresh Dormand-Prince step of the shorter length), to the time's round-off for a
//!   guard and to 1e-9 of the step for an extremum (the extreme's value error is quadratic in
//!   it).
//! - **Transitions**: as the stepper's (entry to stick by the friction impulse that stops the
//!   face; after a slip reaches v = 0, stick or a reversal as the static limit says).
//!
//! What it does not do, and returns as a [`Fallback`] for the caller to run the sampled path
//! instead: a state out of the stepper's range (whatever halt the stepper would report), a
//! start on a guard, a step size underflow, or many transitions without time advancing.
//!
//! In f64 only, and not used by the firmware (nothing of it is linked there).

use crate::coefficients::Coefficients;
use crate::halt::Limits;
use crate::model2::stepper::{Model2Observer, Model2Segment, Model2Transition};
use crate::model2::system::{System, NA, NS, ONE};
use crate::scene::{Scene, SceneError};
use crate::stickslip::Regime;

mod dynamics;
pub mod edges;
mod events;
pub mod flow;
pub mod illinois;
pub mod rk;

use edges::EdgeStats;

/// The default tolerance of Stribeck slip (see the module comment).
pub const DEFAULT_RTOL: f64 = 1e-10;
/// Smallest magnitude a component's error is taken relative to [SI units].
const SCALE_FLOOR: f64 = 1e-12;
/// A guard is located to this fraction of the step (then to the time's round-off); an extremum
/// to `EXTREME_TOL`.
const GUARD_TOL: f64 = 1e-15;
const EXTREME_TOL: f64 = 1e-9;
/// The stepper's range limits of the band and the floating pad (stepper/mod.rs): |u| [m],
/// |u'| [m/s], |y| [m], |y'| [m/s].
const U_LIMIT: f64 = 1.0;
const UDOT_LIMIT: f64 = 1e3;
const Y_LIMIT: f64 = 0.1;
const YDOT_LIMIT: f64 = 1e3;
/// Watched functions: up to two guards, then the extremes' rates.
const EXTREMES: usize = 7;
/// An extreme's rate that changes sign inside a step is an event only if it reaches this
/// fraction of the largest magnitude that rate has had in the run: below it the sign change is
/// round-off (phi'' alternating at 1e-13 rad/s^2 in steady Stribeck sliding made events 1e-14 s
/// apart, a run that never ended).
const EXTREME_NOISE: f64 = 1e-9;
/// Steps (accepted and rejected) a run may take per grid interval or per longest step, plus a
/// million, before it stops as [`Fallback::Stalled`]: every run is bounded.
const STEP_BUDGET: f64 = 1000.0;

/// Steps (accepted and rejected) of a run's budget after which its pace is checked
/// ([`behind_pace`]).
const PACE_SLACK: u64 = 1 << 20;

/// Whether a run that has taken `used` of its `budget` steps (both counted from its start at
/// `t0`) and reached `t` of `t0..t_end` [s] would use the budget up before `t_end` at the
/// pace it has kept: checked at every step once `PACE_SLACK` steps are used (the budget's own
/// slack is a million; a step's rejections can move the count by more than one, so no step is
/// skipped), a division against a step's six right-hand sides, so a stiff run stops after about
/// a second of work rather than
/// after the whole budget (a 1 s run of a throttle 1e8 times too wide took 22 s to use it up,
/// a 100 s run would have taken 40 minutes).
pub(crate) fn behind_pace(used: u64, budget: u64, t0: f64, t: f64, t_end: f64) -> bool {
    if used < PACE_SLACK || !(t_end > t0) {
        return false;
    }
    let done = ((t - t0) / (t_end - t0)).clamp(0.0, 1.0);
    used as f64 > done * budget as f64
}

/// Why the event run stopped short: the caller runs the sampled path instead.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fallback {
    /// The state left the stepper's range (or is not finite) at `t` [s].
    Range { t: f64 },
    /// A guard holds at the start (a regime that ends at once).
    StartOnGuard,
    /// The error control asked for a step below round-off at `t` [s].
    StepUnderflow { t: f64 },
    /// Many events without time advancing, or the run's step budget used up
    /// (`STEP_BUDGET` steps per grid interval or per longest step, plus a million), at `t` [s].
    Stalled { t: f64 },
    /// Unilateral contact: both edges open at `t` [s] (the pad in the air; no sampled path
    /// carries this either: the run halts with `contact_loss`).
    BothEdgesOpen { t: f64 },
}

/// The work an event run did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EventCounts {
    /// Accepted steps (linear and Stribeck), rejected Stribeck steps.
    pub steps: u64,
    pub rejected: u64,
    /// Right-hand side evaluations of Stribeck slip (steps and root searches).
    pub evaluations: u64,
    /// Located events (extremes, crests and transitions) and transitions among them.
    pub events: u64,
    pub transitions: u64,
    /// Unilateral contact: changes of an edge's state (openings and closings).
    pub contact_changes: u64,
}

/// The state at one instant and its first two derivatives.
#[derive(Clone, Copy, Debug)]
struct Point {
    z: [f64; NS],
    d: [f64; NS],
    s: [f64; NS],
}

/// An event run of one scene (f64).
#[derive(Clone, Debug)]
pub struct EventRunner {
    /// The system of each contact state ([`edges::systems`]; a bilateral scene uses only the
    /// first) and the current one's index.
    systems: [System; 3],
    contact: usize,
    /// Guard rows of each contact state ([stick behind, stick ahead, slip slower, slip
    /// faster]; fire at row . z >= 0).
    guard_sets: [[[f64; NA]; 4]; 3],
    /// Unilateral contact: the edges' compression rows, which edges are open ([lead, trail]),
    /// and their statistics.
    unilateral: bool,
    compression: [[f64; NA]; 2],
    open: [bool; 2],
    edge_stats: EdgeStats,
    limits: Limits<f64>,
    /// The floating pad's spring lever arms d_L, d_T [m] and their round-off floors [m].
    float_limits: [f64; 4],
    h_max: f64,
    rtol: f64,
    /// The largest |z_i| of the run so far (the error's scale).
    scale: [f64; NS],
    z: [f64; NS],
    regime: Regime,
    t: f64,
    /// The Stribeck step size to try next [s].
    h_slip: f64,
    counts: EventCounts,
    /// The largest |rate| each extreme's watched rate has had (its noise floor's scale).
    rate_scale: [f64; EXTREMES],
}

impl EventRunner {
    /// Validates `scene` (model 2) and starts at rest in stick, as the stepper does.
    pub fn new(scene: &Scene, rtol: f64) -> Result<Self, SceneError> {
        scene.validate()?;
        let co = Coefficients::of(scene);
        let sys = System::of(scene, &co);
        let unilateral = scene.unilateral();
        let systems = if unilateral { edges::systems(scene) } else { [sys; 3] };
        let mut rate = sys.linear_rate(scene, &co);
        if unilateral {
            // the open states' modes too (one spring: a softer, but other, pair of modes)
            for lead_open in [true, false] {
                let mut s = scene.linearised_contact();
                if lead_open {
                    s.k_l = 0.0;
                } else {
                    s.k_t = 0.0;
                }
                rate = rate.max(systems[0].linear_rate(&s, &Coefficients::of(&s)));
            }
        }
        let guards_of = |sys: &System| {
            let g = |sign: f64, mu: f64| -> [f64; NA] { core::array::from_fn(|c| sign * sys.r_freq[c] - mu * sys.r_n[c]) };
            [g(1.0, scene.mu_s), g(-1.0, scene.mu_s), sys.r_v, core::array::from_fn(|c| -sys.r_v[c])]
        };
        let guard_sets = [guards_of(&systems[0]), guards_of(&systems[1]), guards_of(&systems[2])];
        let floor = |d: f64| -(1e-6 * libm::fabs(sys.y0 + d * sys.phi0) + 1e-12);
        let z = [0.0, scene.v, sys.phi0, 0.0, 0.0, 0.0, sys.y0, 0.0];
        let mut scale = [SCALE_FLOOR; NS];
        for i in 0..NS {
            scale[i] = scale[i].max(libm::fabs(z[i]));
        }
        Ok(EventRunner {
            systems,
            contact: 0,
            guard_sets,
            unilateral,
            compression: edges::compression_rows(&sys),
            open: [false; 2],
            edge_stats: EdgeStats::default(),
            limits: Limits::new(scene, &co),
            float_limits: [sys.d_l, sys.d_t, floor(sys.d_l), floor(sys.d_t)],
            h_max: if rate > 0.0 { 1.0 / rate } else { scene.duration.max(1e-3) },
            rtol,
            scale,
            z,
            regime: Regime::Stick,
            t: 0.0,
            h_slip: 0.0,
            counts: EventCounts::default(),
            rate_scale: [0.0; EXTREMES],
        })
    }

    pub fn state(&self) -> [f64; NS] {
        self.z
    }

    pub fn regime(&self) -> Regime {
        self.regime
    }

    pub fn time(&self) -> f64 {
        self.t
    }

    pub fn counts(&self) -> EventCounts {
        self.counts
    }

    /// The longest step [s]: one radian of the fastest linear mode.
    pub fn max_step(&self) -> f64 {
        self.h_max
    }

    /// The system of the current contact state.
    #[inline(always)]
    fn sys(&self) -> &System {
        &self.systems[self.contact]
    }

    /// Unilateral contact: each edge's time open and openings over the window (None for
    /// bilateral springs).
    pub fn edges(&self) -> Option<EdgeStats> {
        self.unilateral.then_some(self.edge_stats)
    }

    /// Which edges are open now ([lead, trail]).
    pub fn open_edges(&self) -> [bool; 2] {
        self.open
    }

    /// Starts from `z` in `regime` (both edges closed) instead of the rest start: the maps'
    /// start from perturbed sliding.
    pub fn set_state(&mut self, z: [f64; NS], regime: Regime) {
        self.z = z;
        self.regime = regime;
        for i in 0..NS {
            self.scale[i] = self.scale[i].max(libm::fabs(z[i]));
        }
    }

    /// The normal force N at `z` in the current contact state [N].
    pub fn normal_force(&self, z: &[f64; NS]) -> f64 {
        dot(&self.sys().r_n, z)
    }

    /// The sliding velocity at `z` [m/s].
    pub fn sliding_velocity(&self, z: &[f64; NS]) -> f64 {
        dot(&self.sys().r_v, z)
    }

    /// Runs to `t_end` [s], handing every segment and transition to `obs`; a segment ends at
    /// `t_from` [s] (the statistics window's start), at every event and at every step's end.
    pub fn run<O: Model2Observer<f64>>(
        &mut self,
        t_from: f64,
        t_end: f64,
        obs: &mut O,
    ) -> Result<(), Fallback> {
        self.run_grid(t_from, t_end, None, obs)
    }

    /// [`Self::run`] with samples on the grid k dt (k = 1, 2, ... up to `t_end`): every step
    /// also ends at each grid time, where `on_sample` gets the state (the exact flow's, or a
    /// Dormand-Prince step's, not an interpolation). `on_sample` returning false stops the run
    /// there (Ok: the caller knows why).
    pub fn run_sampled<O: Model2Observer<f64>>(
        &mut self,
        t_from: f64,
        t_end: f64,
        dt: f64,
        obs: &mut O,
        on_sample: &mut dyn FnMut(&GridSample) -> bool,
    ) -> Result<(), Fallback> {
        self.run_grid(t_from, t_end, Some((dt, on_sample)), obs)
    }

    fn run_grid<O: Model2Observer<f64>>(
        &mut self,
        t_from: f64,
        t_end: f64,
        mut grid: Option<(f64, &mut dyn FnMut(&GridSample) -> bool)>,
        obs: &mut O,
    ) -> Result<(), Fallback> {
        let mut regime = self.regime;
        if self.unilateral && self.t == 0.0 && self.counts.steps == 0 {
            // an edge in tension at the start opens at once
            for e in 0..2 {
                self.open[e] = edges::compression(&self.compression[e], &self.z) < 0.0;
            }
            self.contact =
                edges::state_index(self.open).ok_or(Fallback::BothEdgesOpen { t: 0.0 })?;
        }
        let mut p0 = self.point(regime, self.z);
        let (slot, n) = Self::guard_slots(regime);
        if (0..n).any(|k| !(dot(&self.guard_sets[self.contact][slot + k], &p0.z) < 0.0))
            && regime == Regime::Stick
        {
            return Err(Fallback::StartOnGuard);
        }
        if self.stribeck_slip(regime) && self.h_slip == 0.0 {
            self.h_slip = self.h_max * 1e-3;
        }
        let mut k_next: u64 = match &grid {
            Some((dt, _)) => libm::floor(self.t / dt) as u64 + 1,
            None => 0,
        };
        let mut stalls = 0u32;
        let unit = match &grid {
            Some((dt, _)) => *dt,
            None => self.h_max,
        };
        let used0 = self.counts.steps + self.counts.rejected;
        let budget = used0 + 1_000_000 + (STEP_BUDGET * ((t_end - self.t) / unit).max(0.0)).min(1e15) as u64;
        let t0 = self.t;
        let mut in_window = self.t >= t_from;
        while self.t < t_end {
            let mut stop = if self.t < t_from && t_from < t_end {
                t_from
            } else {
                t_end
            };
            let mut at_grid = false;
            if let Some((dt, _)) = &grid {
                let tg = k_next as f64 * *dt;
                if tg <= stop {
                    stop = tg;
                    at_grid = true;
                }
            }
            let limit = stop - self.t;
            let used = self.counts.steps + self.counts.rejected;
            if used > budget || behind_pace(used - used0, budget - used0, t0, self.t, t_end) {
                return Err(Fallback::Stalled { t: self.t });
            }
            let (h, p1, taylor) = if self.stribeck_slip(regime) {
                let (h, p1) = self.slip_step(regime, &p0, limit)?;
                (h, p1, None)
            } else {
                let tf = flow::Taylor::new(&self.sys().a[regime.index()], &p0.z);
                let mut h = self.h_max.min(limit);
                while !tf.converged(h) {
                    h *= 0.5;
                    if h < 1e-12 * self.h_max {
                        return Err(Fallback::StepUnderflow { t: self.t });
                    }
                }
                let (z, d, s) = tf.at(h);
                (h, Point { z, d, s }, Some(tf))
            };
            self.counts.steps += 1;
            let event = self.first_event(regime, &p0, &p1, h, taylor.as_ref());
            let (theta, pe, guard) = match event {
                Some(e) => e,
                None => (1.0, p1, None),
            };
            let reached = theta == 1.0 && h == limit;
            let t1 = if reached { stop } else { self.t + theta * h };
            if !pe.z.iter().all(|v| v.is_finite()) || !self.in_range(&pe.z) {
                return Err(Fallback::Range { t: t1 });
            }
            obs.segment(&Model2Segment {
                regime,
                t0: self.t,
                t1,
                z0: p0.z,
                z1: pe.z,
                zd0: p0.d,
                zd1: pe.d,
            });
            if self.unilateral && t1 > t_from {
                if !in_window {
                    // an edge open as the window starts counts one opening
                    in_window = true;
                    for e in 0..2 {
                        self.edge_stats.openings[e] += self.open[e] as u64;
                    }
                }
                let span = t1 - self.t.max(t_from);
                self.edge_stats.window_s += span;
                for e in 0..2 {
                    if self.open[e] {
                        self.edge_stats.open_s[e] += span;
                    }
                }
            }
            if t1 > self.t {
                stalls = 0;
            } else {
                stalls += 1;
                if stalls > 64 {
                    return Err(Fallback::Stalled { t: self.t });
                }
            }
            self.t = t1;
            for i in 0..NS {
                self.scale[i] = self.scale[i].max(libm::fabs(pe.z[i]));
            }
            for e in 0..EXTREMES {
                self.rate_scale[e] = self.rate_scale[e].max(libm::fabs(Self::extreme_rate(&pe, e)));
            }
            if event.is_some() {
                self.counts.events += 1;
            }
            let sample_now = reached && at_grid;
            if sample_now {
                k_next += 1;
            }
            match guard {
                None => p0 = pe,
                Some(which) => {
                    regime = self.after_guard(regime, which, t_from, t1, &pe, obs, &mut p0)?
                }
            }
            if sample_now {
                if let Some((_, on_sample)) = &mut grid {
                    let sample = GridSample {
                        t: t1,
                        regime,
                        z: p0.z,
                        d: p0.d,
                        n: self.normal_force(&p0.z),
                        f_f: self.friction_force(regime, &p0.z),
                        v_slide: self.sliding_velocity(&p0.z),
                    };
                    if !on_sample(&sample) {
                        break;
                    }
                }
            }
        }
        self.z = p0.z;
        self.regime = regime;
        Ok(())
    }

    /// After guard `which` of `regime` fired at `t1` in point `pe`: the regime that follows,
    /// and its start point in `p0` (an edge's contact guard changes the contact state and
    /// keeps the regime; a friction guard changes the regime).
    #[allow(clippy::too_many_arguments)]
    fn after_guard<O: Model2Observer<f64>>(
        &mut self,
        regime: Regime,
        which: usize,
        t_from: f64,
        t1: f64,
        pe: &Point,
        obs: &mut O,
        p0: &mut Point,
    ) -> Result<Regime, Fallback> {
        {
            let n_friction = Self::guard_slots(regime).1;
            if which >= n_friction {
                // an edge's contact guard: the compression's rate (its curvature on a graze)
                // decides whether the edge's state changes
                let e = which - n_friction;
                let r = self.compression[e];
                let (dr, ddr) = (rate(&r, &pe.d), rate(&r, &pe.s));
                let was_open = self.open[e];
                let now_open = if was_open {
                    !(dr > 0.0 || (dr == 0.0 && ddr > 0.0))
                } else {
                    dr < 0.0 || (dr == 0.0 && ddr < 0.0)
                };
                if now_open != was_open {
                    self.open[e] = now_open;
                    self.contact =
                        edges::state_index(self.open).ok_or(Fallback::BothEdgesOpen { t: t1 })?;
                    if now_open {
                        self.edge_stats.openings_run[e] += 1;
                        if t1 > t_from {
                            self.edge_stats.openings[e] += 1;
                        }
                    }
                    self.counts.contact_changes += 1;
                }
                *p0 = self.point(regime, pe.z);
                return Ok(regime);
            }
        }
        let next = match regime {
            Regime::Stick => {
                if which == 0 {
                    Regime::SlipSlower
                } else {
                    Regime::SlipFaster
                }
            }
            _ => self.after_velocity_match(&pe.z),
        };
        let mut zn = pe.z;
        if next == Regime::Stick {
            self.enter_stick(&mut zn);
        }
        if next != regime {
            obs.transition(&Model2Transition {
                t: t1,
                from: regime,
                to: next,
                z: zn,
            });
            self.counts.transitions += 1;
        }
        if self.stribeck_slip(next) && !self.stribeck_slip(regime) {
            // a slip starts where the friction's slope is steepest: start small
            self.h_slip = self.h_max * 1e-3;
        }
        *p0 = self.point(next, zn);
        Ok(next)
    }
}

/// A sample on the grid: time [s], regime, state z and its rate z', and in the contact state
/// of that instant the normal force N [N], the friction force on the pad [N] and the sliding
/// velocity [m/s].
#[derive(Clone, Copy, Debug)]
pub struct GridSample {
    pub t: f64,
    pub regime: Regime,
    pub z: [f64; NS],
    pub d: [f64; NS],
    pub n: f64,
    pub f_f: f64,
    pub v_slide: f64,
}

/// (z, 1) . row over every entry.
#[inline(always)]
fn dot(r: &[f64; NA], z: &[f64; NS]) -> f64 {
    let mut s = r[ONE];
    for i in 0..NS {
        s += r[i] * z[i];
    }
    s
}

/// The rate of a row, row . z' (the constant does not move).
#[inline(always)]
fn rate(r: &[f64; NA], d: &[f64; NS]) -> f64 {
    let mut s = 0.0;
    for i in 0..NS {
        s += r[i] * d[i];
    }
    s
}
