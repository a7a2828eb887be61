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
use crate::model2::system::{System, NA, NS, ONE, Y};
use crate::scene::{Scene, SceneError};
use crate::stickslip::Regime;

pub mod flow;
pub mod rk;

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

/// Why the event run stopped short: the caller runs the sampled path instead.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fallback {
    /// The state left the stepper's range (or is not finite) at `t` [s].
    Range { t: f64 },
    /// A guard holds at the start (a regime that ends at once).
    StartOnGuard,
    /// The error control asked for a step below round-off at `t` [s].
    StepUnderflow { t: f64 },
    /// Many events without time advancing at `t` [s].
    Stalled { t: f64 },
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
    sys: System,
    /// Guard rows ([stick behind, stick ahead, slip slower, slip faster]; fire at row . z >= 0).
    guards: [[f64; NA]; 4],
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
}

impl EventRunner {
    /// Validates `scene` (model 2) and starts at rest in stick, as the stepper does.
    pub fn new(scene: &Scene, rtol: f64) -> Result<Self, SceneError> {
        scene.validate()?;
        let co = Coefficients::of(scene);
        let sys = System::of(scene, &co);
        let rate = sys.linear_rate(scene, &co);
        let g = |sign: f64, mu: f64| -> [f64; NA] { core::array::from_fn(|c| sign * sys.r_freq[c] - mu * sys.r_n[c]) };
        let guards = [g(1.0, scene.mu_s), g(-1.0, scene.mu_s), sys.r_v, core::array::from_fn(|c| -sys.r_v[c])];
        let floor = |d: f64| -(1e-6 * libm::fabs(sys.y0 + d * sys.phi0) + 1e-12);
        let z = [0.0, scene.v, sys.phi0, 0.0, 0.0, 0.0, sys.y0, 0.0];
        let mut scale = [SCALE_FLOOR; NS];
        for i in 0..NS {
            scale[i] = scale[i].max(libm::fabs(z[i]));
        }
        Ok(EventRunner {
            sys,
            guards,
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

    fn stribeck_slip(&self, regime: Regime) -> bool {
        self.sys.stribeck && regime != Regime::Stick
    }

    /// Stribeck forcing q = sigma (mu(|v|) - mu_k) N and the shape's parts (e, N, v).
    fn excess(&self, regime: Regime, z: &[f64; NS]) -> (f64, f64, f64, f64) {
        let sys = &self.sys;
        let v = dot(&sys.r_v, z);
        let n = dot(&sys.r_n, z);
        let y = libm::fabs(v) / sys.v_s;
        let e = if sys.delta == 1.0 {
            libm::exp(-y)
        } else if y > 0.0 {
            libm::exp(-libm::pow(y, sys.delta))
        } else {
            1.0
        };
        (regime.friction_sign() * sys.d_mu * e * n, e, n, v)
    }

    /// z' in `regime` at `z`.
    fn derivative(&self, regime: Regime, z: &[f64; NS]) -> [f64; NS] {
        let a = &self.sys.a[regime.index()];
        let mut d: [f64; NS] = core::array::from_fn(|r| dot(&a[r], z));
        if self.stribeck_slip(regime) {
            let q = self.excess(regime, z).0;
            for (r, v) in d.iter_mut().enumerate() {
                *v += self.sys.b[r] * q;
            }
        }
        d
    }

    /// z'' in `regime` at `z` with z' = `d`.
    fn second(&self, regime: Regime, z: &[f64; NS], d: &[f64; NS]) -> [f64; NS] {
        let sys = &self.sys;
        let a = &sys.a[regime.index()];
        let mut s: [f64; NS] = core::array::from_fn(|r| rate(&a[r], d));
        if self.stribeck_slip(regime) {
            let (_, e, n, v) = self.excess(regime, z);
            let vd = rate(&sys.r_v, d);
            let nd = rate(&sys.r_n, d);
            let y = libm::fabs(v) / sys.v_s;
            let dy = if v >= 0.0 { vd / sys.v_s } else { -vd / sys.v_s };
            let de = if sys.delta == 1.0 {
                -e * dy
            } else if y > 0.0 {
                -sys.delta * libm::pow(y, sys.delta - 1.0) * e * dy
            } else {
                0.0
            };
            let qd = regime.friction_sign() * sys.d_mu * (de * n + e * nd);
            for (r, v) in s.iter_mut().enumerate() {
                *v += sys.b[r] * qd;
            }
        }
        s
    }

    fn point(&self, regime: Regime, z: [f64; NS]) -> Point {
        let d = self.derivative(regime, &z);
        let s = self.second(regime, &z, &d);
        Point { z, d, s }
    }

    /// The guards of `regime`: (first slot, count).
    fn guard_slots(regime: Regime) -> (usize, usize) {
        match regime {
            Regime::Stick => (0, 2),
            Regime::SlipSlower => (2, 1),
            Regime::SlipFaster => (3, 1),
        }
    }

    /// The rate of extreme `k`'s quantity (its zero is the extreme): x', x'', phi', phi'', u''
    /// (the band velocity's rate), x''' and u''' (the accelerations' rates).
    fn extreme_rate(p: &Point, k: usize) -> f64 {
        match k {
            0 => p.d[0],
            1 => p.d[1],
            2 => p.d[2],
            3 => p.d[3],
            4 => p.d[5],
            5 => p.s[1],
            _ => p.s[5],
        }
    }

    /// Sets the sliding velocity to zero on entry to stick: the friction impulse p that stops
    /// the face, -v / (r_v . b), moves the state by b p, and x' then takes the constraint's
    /// value exactly (as the stepper's `enter_stick`).
    fn enter_stick(&self, z: &mut [f64; NS]) {
        let sys = &self.sys;
        let p = -dot(&sys.r_v, z) / sys.inv_mass_v;
        for (r, v) in z.iter_mut().enumerate() {
            *v += sys.b[r] * p;
        }
        // r_v[1] = 1: x' = -(the rest of the row)
        z[1] = -(sys.r_v[3] * z[3] + sys.r_v[5] * z[5] + sys.r_v[ONE]);
    }

    /// The regime after a slip reached v = 0 at `z`.
    fn after_velocity_match(&self, z: &[f64; NS]) -> Regime {
        let mut zs = *z;
        self.enter_stick(&mut zs);
        let f_req = dot(&self.sys.r_freq, &zs);
        let limit = self.sys.mu_s * dot(&self.sys.r_n, &zs);
        if f_req > limit {
            Regime::SlipSlower
        } else if -f_req > limit {
            Regime::SlipFaster
        } else {
            Regime::Stick
        }
    }

    /// In the stepper's range (every halt it reports falls outside).
    fn in_range(&self, z: &[f64; NS]) -> bool {
        let pad = [z[0], z[1], z[2], z[3]];
        let band = libm::fabs(z[4]) <= U_LIMIT && libm::fabs(z[5]) <= UDOT_LIMIT;
        let float = !self.sys.floating || {
            let [d_l, d_t, floor_l, floor_t] = self.float_limits;
            z[Y] + d_l * z[2] >= floor_l
                && z[Y] + d_t * z[2] >= floor_t
                && libm::fabs(z[Y]) <= Y_LIMIT
                && libm::fabs(z[Y + 1]) <= YDOT_LIMIT
        };
        self.limits.in_range(&pad) && band && float
    }

    /// The error of a Stribeck step relative to the tolerance (max norm; <= 1 accepts).
    fn error_ratio(&self, err: &[f64; NS], z0: &[f64; NS], z1: &[f64; NS]) -> f64 {
        let mut worst: f64 = 0.0;
        for i in 0..NS {
            let sc = self.rtol * self.scale[i].max(libm::fabs(z0[i])).max(libm::fabs(z1[i]));
            worst = worst.max(libm::fabs(err[i]) / sc);
        }
        if worst.is_finite() {
            worst
        } else {
            f64::INFINITY
        }
    }

    /// One Stribeck step from `p0` of at most `limit` [s]: its length and end point.
    fn slip_step(&mut self, regime: Regime, p0: &Point, limit: f64) -> Result<(f64, Point), Fallback> {
        loop {
            let h = self.h_slip.min(limit).min(self.h_max);
            if !(h > 1e-15 * (libm::fabs(self.t) + 1e-3)) {
                return Err(Fallback::StepUnderflow { t: self.t });
            }
            let mut f = |z: &[f64; NS]| self.derivative(regime, z);
            let (z1, d1, err) = rk::step(&mut f, &p0.z, &p0.d, h);
            self.counts.evaluations += 6;
            let ratio = self.error_ratio(&err, &p0.z, &z1);
            let factor = if ratio > 0.0 { 0.9 * libm::pow(ratio, -0.2) } else { 5.0 };
            if ratio <= 1.0 {
                let next = h * factor.clamp(0.2, 5.0);
                self.h_slip = if h < self.h_slip { self.h_slip.max(next) } else { next };
                let s1 = self.second(regime, &z1, &d1);
                return Ok((h, Point { z: z1, d: d1, s: s1 }));
            }
            self.counts.rejected += 1;
            self.h_slip = h * factor.clamp(0.1, 0.9);
        }
    }

    /// The point at fraction `theta` of a step of length `h` from `p0` in `regime` (the exact
    /// flow `taylor`, or a Dormand-Prince step of theta h).
    fn at(&mut self, regime: Regime, p0: &Point, h: f64, taylor: Option<&flow::Taylor>, theta: f64) -> Point {
        match taylor {
            Some(tf) => {
                let (z, d, s) = tf.at(theta * h);
                Point { z, d, s }
            }
            None => {
                let mut f = |z: &[f64; NS]| self.derivative(regime, z);
                let (z, d, _) = rk::step(&mut f, &p0.z, &p0.d, theta * h);
                self.counts.evaluations += 6;
                let s = self.second(regime, &z, &d);
                Point { z, d, s }
            }
        }
    }

    /// The value of watched function `k` (guards of `regime` first, then the extremes' rates).
    fn watched(&self, regime: Regime, k: usize, p: &Point) -> f64 {
        let (slot, n) = Self::guard_slots(regime);
        if k < n {
            dot(&self.guards[slot + k], &p.z)
        } else {
            Self::extreme_rate(p, k - n)
        }
    }

    /// Illinois search for the sign change of `f` on [lo, hi] (f(lo) = flo, f(hi) = fhi of
    /// opposite signs, or fhi = 0 for a guard): the smallest fraction past it and its point.
    #[allow(clippy::too_many_arguments)]
    fn locate(
        &mut self,
        regime: Regime,
        p0: &Point,
        h: f64,
        taylor: Option<&flow::Taylor>,
        f: &dyn Fn(&Self, &Point) -> f64,
        (mut lo, mut flo): (f64, f64),
        (mut hi, mut fhi, mut phi): (f64, f64, Point),
        tol: f64,
    ) -> (f64, Point) {
        let neg = flo < 0.0;
        let mut side = 0i32;
        for _ in 0..100 {
            if hi - lo <= tol {
                break;
            }
            let mut x = if fhi != flo { (lo * fhi - hi * flo) / (fhi - flo) } else { 0.5 * (lo + hi) };
            if !(x > lo && x < hi) {
                x = 0.5 * (lo + hi);
            }
            let p = self.at(regime, p0, h, taylor, x);
            let fx = f(self, &p);
            // the lo side keeps f(lo)'s sign; a zero belongs to the hi side (a guard fires at 0)
            if if neg { fx < 0.0 } else { fx > 0.0 } {
                lo = x;
                flo = fx;
                if side == -1 {
                    fhi *= 0.5;
                }
                side = -1;
            } else {
                hi = x;
                fhi = fx;
                phi = p;
                if side == 1 {
                    flo *= 0.5;
                }
                side = 1;
            }
        }
        (hi, phi)
    }

    /// The first event inside the step from `p0` to `p1` (length `h`): its fraction, point
    /// and whether it is a guard (its index) or an extreme (None).
    fn first_event(&mut self, regime: Regime, p0: &Point, p1: &Point, h: f64, taylor: Option<&flow::Taylor>) -> Option<(f64, Point, Option<usize>)> {
        let (slot, n) = Self::guard_slots(regime);
        let mut best: Option<(f64, Point, Option<usize>)> = None;
        for k in 0..n + EXTREMES {
            let f0 = self.watched(regime, k, p0);
            let f1 = self.watched(regime, k, p1);
            let guard = k < n;
            if guard {
                let row = self.guards[slot + k];
                let g = move |_: &Self, p: &Point| dot(&row, &p.z);
                let gr = move |_: &Self, p: &Point| rate(&row, &p.d);
                if !(f0 < 0.0) {
                    continue;
                }
                let mut end = None;
                if !(f1 < 0.0) {
                    end = Some((1.0, f1, *p1));
                } else {
                    // a crest: the rate falls through zero inside the step with the guard above
                    let (r0, r1) = (gr(self, p0), gr(self, p1));
                    if r0 > 0.0 && r1 < 0.0 {
                        let (tc, pc) = self.locate(regime, p0, h, taylor, &gr, (0.0, r0), (1.0, r1, *p1), EXTREME_TOL);
                        let gc = g(self, &pc);
                        if !(gc < 0.0) {
                            end = Some((tc, gc, pc));
                        }
                    }
                }
                if let Some((th, fh, ph)) = end {
                    let (t, p) = self.locate(regime, p0, h, taylor, &g, (0.0, f0), (th, fh, ph), GUARD_TOL);
                    if best.as_ref().is_none_or(|b| t < b.0) {
                        best = Some((t, p, Some(k)));
                    }
                }
            } else if f0 * f1 < 0.0 {
                let e = k - n;
                let fe = move |_: &Self, p: &Point| Self::extreme_rate(p, e);
                let (t, p) = self.locate(regime, p0, h, taylor, &fe, (0.0, f0), (1.0, f1, *p1), EXTREME_TOL);
                if best.as_ref().is_none_or(|b| t < b.0) {
                    best = Some((t, p, None));
                }
            }
        }
        best
    }

    /// Runs to `t_end` [s], handing every segment and transition to `obs`; a segment ends at
    /// `t_from` [s] (the statistics window's start), at every event and at every step's end.
    pub fn run<O: Model2Observer<f64>>(&mut self, t_from: f64, t_end: f64, obs: &mut O) -> Result<(), Fallback> {
        let mut regime = self.regime;
        let mut p0 = self.point(regime, self.z);
        let (slot, n) = Self::guard_slots(regime);
        if (0..n).any(|k| !(dot(&self.guards[slot + k], &p0.z) < 0.0)) && regime == Regime::Stick {
            return Err(Fallback::StartOnGuard);
        }
        if self.stribeck_slip(regime) && self.h_slip == 0.0 {
            self.h_slip = self.h_max * 1e-3;
        }
        let mut stalls = 0u32;
        while self.t < t_end {
            let stop = if self.t < t_from && t_from < t_end { t_from } else { t_end };
            let limit = stop - self.t;
            let (h, p1, taylor) = if self.stribeck_slip(regime) {
                let (h, p1) = self.slip_step(regime, &p0, limit)?;
                (h, p1, None)
            } else {
                let tf = flow::Taylor::new(&self.sys.a[regime.index()], &p0.z);
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
            let t1 = if theta == 1.0 && h == limit { stop } else { self.t + theta * h };
            if !pe.z.iter().all(|v| v.is_finite()) || !self.in_range(&pe.z) {
                return Err(Fallback::Range { t: t1 });
            }
            obs.segment(&Model2Segment { regime, t0: self.t, t1, z0: p0.z, z1: pe.z, zd0: p0.d, zd1: pe.d });
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
            if event.is_some() {
                self.counts.events += 1;
            }
            let Some(which) = guard else {
                p0 = pe;
                continue;
            };
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
                obs.transition(&Model2Transition { t: t1, from: regime, to: next, z: zn });
                self.counts.transitions += 1;
            }
            if self.stribeck_slip(next) && !self.stribeck_slip(regime) {
                // a slip starts where the friction's slope is steepest: start small
                self.h_slip = self.h_max * 1e-3;
            }
            regime = next;
            p0 = self.point(regime, zn);
        }
        self.z = p0.z;
        self.regime = regime;
        Ok(())
    }
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
