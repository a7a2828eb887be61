//! Statistics of a run over a time window, taken from the continuous motion.
//!
//! Peak-to-peak values are the true extremes of the exact solution, not of the samples: at
//! each segment the derivative of every quantity is tested at both ends, and a sign change is
//! resolved by binary lifting on the segment's dyadic grid (2^-L of a substep). So the result
//! does not depend on the step size, beyond the step's resolution of the transitions.
//!
//! - stick fraction: time in stick / window length (from the exact transition times);
//! - stick-slip frequency: 1 / mean interval between successive stick-to-slip transitions in
//!   the window (0 with fewer than two).

use crate::exact::{Observer, Segment, Transition};
use crate::propagator::{apply, Propagator};
use crate::real::Real;
use crate::stickslip::Regime;

/// Window statistics of one run (SI units).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RunStats {
    /// [min, max] of x [m], x' [m/s], phi [rad], phi' [rad/s].
    pub min: [f64; 4],
    pub max: [f64; 4],
    pub stick_fraction: f64,
    pub stick_slip_hz: f64,
    /// Stick-to-slip transitions in the window.
    pub slip_onsets: u64,
    /// All transitions in the window.
    pub transitions: u64,
    /// Window length actually covered [s]; 0 when the run ended before the window (then
    /// every other field is 0 too and means nothing).
    pub window_s: f64,
}

impl RunStats {
    /// Peak-to-peak of quantity `i` (0 x, 1 x', 2 phi, 3 phi').
    pub fn pp(&self, i: usize) -> f64 {
        self.max[i] - self.min[i]
    }
}

/// The slip onsets of a window and the stick-slip frequency they give, (n - 1) / (last -
/// first) [Hz]: the one definition the model's statistics (thesis and model 2), the virtual
/// rig's truth and the recorded-data analysis all use.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OnsetRate {
    count: u64,
    first_s: f64,
    last_s: f64,
}

impl OnsetRate {
    pub const fn new() -> Self {
        OnsetRate { count: 0, first_s: 0.0, last_s: 0.0 }
    }

    /// A slip onset at `t_s` [s] (onsets in time order).
    #[inline]
    pub fn add(&mut self, t_s: f64) {
        if self.count == 0 {
            self.first_s = t_s;
        }
        self.last_s = t_s;
        self.count += 1;
    }

    /// Onsets counted.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// The first onset's time [s], if any.
    pub fn first_s(&self) -> Option<f64> {
        (self.count > 0).then_some(self.first_s)
    }

    /// The stick-slip frequency [Hz]: `None` with fewer than two onsets or none of the window's
    /// time between them.
    pub fn hz(&self) -> Option<f64> {
        (self.count >= 2 && self.last_s > self.first_s).then(|| (self.count - 1) as f64 / (self.last_s - self.first_s))
    }
}

/// Collects [`RunStats`] from the segments of steps `from_step` onward.
#[derive(Clone, Debug)]
pub struct StatsObserver<T: Real> {
    from_step: u64,
    t_from: f64,
    min: [T; 4],
    max: [T; 4],
    seen: bool,
    stick_s: f64,
    window_s: f64,
    onsets: OnsetRate,
    transitions: u64,
}

impl<T: Real> StatsObserver<T> {
    /// Window from the step boundary nearest `t_from` [s] (steps of `dt`) to the end of the run.
    pub fn new(t_from: f64, dt: f64) -> Self {
        let from_step = libm::round(t_from / dt) as u64;
        StatsObserver {
            from_step,
            t_from: from_step as f64 * dt,
            min: [T::zero(); 4],
            max: [T::zero(); 4],
            seen: false,
            stick_s: 0.0,
            window_s: 0.0,
            onsets: OnsetRate::new(),
            transitions: 0,
        }
    }

    /// Start of the window actually used [s].
    pub fn window_start(&self) -> f64 {
        self.t_from
    }

    #[allow(clippy::needless_range_loop)] // min and max of the same component
    fn include(&mut self, z: &[T; 4]) {
        // the segments of a step that halts may hold a non-finite state: never let it in
        if !(z[0].is_finite() && z[1].is_finite() && z[2].is_finite() && z[3].is_finite()) {
            return;
        }
        if !self.seen {
            self.min = *z;
            self.max = *z;
            self.seen = true;
            return;
        }
        for i in 0..4 {
            self.min[i] = self.min[i].min(z[i]);
            self.max[i] = self.max[i].max(z[i]);
        }
    }

    pub fn finish(&self) -> RunStats {
        let f = |a: [T; 4]| [a[0].to_f64(), a[1].to_f64(), a[2].to_f64(), a[3].to_f64()];
        let hz = self.onsets.hz().unwrap_or(0.0);
        RunStats {
            min: f(self.min),
            max: f(self.max),
            stick_fraction: if self.window_s > 0.0 { self.stick_s / self.window_s } else { 0.0 },
            stick_slip_hz: hz,
            slip_onsets: self.onsets.count(),
            transitions: self.transitions,
            window_s: self.window_s,
        }
    }
}

/// The derivative of quantity `i` at `z`: x' for x, x'' for x', phi' for phi, phi'' for phi'.
#[inline]
fn derivative<T: Real>(prop: &Propagator<T>, regime: Regime, z: &[T; 4], i: usize) -> T {
    match i {
        0 => z[1],
        1 => prop.accelerations(regime, z).0,
        2 => z[3],
        _ => prop.accelerations(regime, z).1,
    }
}

impl<T: Real> Observer<T> for StatsObserver<T> {
    fn segment(&mut self, seg: &Segment<T>, prop: &Propagator<T>) {
        if seg.step < self.from_step {
            return;
        }
        let len = (seg.p1 - seg.p0) as f64 / Propagator::<T>::UNITS as f64 * prop.h_sub;
        self.window_s += len;
        if seg.regime == Regime::Stick {
            self.stick_s += len;
        }
        self.include(&seg.z0);
        self.include(&seg.z1);
        for i in 0..4 {
            let d0 = derivative(prop, seg.regime, &seg.z0, i);
            let d1 = derivative(prop, seg.regime, &seg.z1, i);
            let zero = T::zero();
            let rising = d0 > zero && d1 < zero;
            let falling = d0 < zero && d1 > zero;
            if !(rising || falling) || seg.p1 - seg.p0 < 2 {
                continue;
            }
            let positive = d0 > zero;
            let (_, zp) = prop.lift(seg.regime, &seg.z0, seg.p0, seg.p1, |c| {
                let d = derivative(prop, seg.regime, c, i);
                if positive {
                    d > zero
                } else {
                    d < zero
                }
            });
            let zq = apply(prop.flow(seg.regime, 0), &zp);
            self.include(&zp);
            self.include(&zq);
        }
    }

    fn transition(&mut self, tr: &Transition<T>) {
        if tr.t < self.t_from {
            return;
        }
        self.transitions += 1;
        if tr.from == Regime::Stick {
            self.onsets.add(tr.t);
        }
    }
}

/// The window statistics that the transitions alone give (stick fraction, stick-slip
/// frequency, transition counts), for a run stepped without an observer: the stepper's fast
/// path ([`crate::ExactStepper::step`]) reports each step's transitions, and the time in stick
/// is the sum of the stick intervals between them, clipped to the window. The same quantities
/// as [`StatsObserver`] (which sums the stick segments instead: equal to round-off).
#[derive(Clone, Copy, Debug)]
pub struct EventWindow {
    t_from: f64,
    stick: bool,
    /// Start of the current regime [s].
    since: f64,
    stick_s: f64,
    onsets: OnsetRate,
    transitions: u64,
}

impl EventWindow {
    /// A window from `t_from` [s] of a run that starts at t = 0 in stick (`stick`) or slip.
    pub fn new(t_from: f64, stick: bool) -> Self {
        EventWindow { t_from, stick, since: 0.0, stick_s: 0.0, onsets: OnsetRate::new(), transitions: 0 }
    }

    /// A transition at `t` [s] out of stick (`from_stick`) or into it (`to_stick`).
    pub fn transition(&mut self, t: f64, from_stick: bool, to_stick: bool) {
        if self.stick && from_stick {
            self.stick_s += (t - self.since.max(self.t_from)).max(0.0);
        }
        self.stick = to_stick;
        self.since = t;
        if t < self.t_from {
            return;
        }
        self.transitions += 1;
        if from_stick {
            self.onsets.add(t);
        }
    }

    /// The statistics of the window [t_from, `t_end`] (min and max 0: not kept).
    pub fn finish(&self, t_end: f64) -> RunStats {
        let window_s = (t_end - self.t_from).max(0.0);
        let mut stick_s = self.stick_s;
        if self.stick {
            stick_s += (t_end - self.since.max(self.t_from)).max(0.0);
        }
        let hz = self.onsets.hz().unwrap_or(0.0);
        RunStats {
            min: [0.0; 4],
            max: [0.0; 4],
            stick_fraction: if window_s > 0.0 { stick_s / window_s } else { 0.0 },
            stick_slip_hz: hz,
            slip_onsets: self.onsets.count(),
            transitions: self.transitions,
            window_s,
        }
    }
}

#[cfg(test)]
mod onset_rate_tests {
    use super::OnsetRate;

    /// Onsets at 0.10, 0.20 and 0.35 s: two cycles in 0.25 s, 8 Hz; fewer than two onsets, or
    /// two at one time, give none.
    #[test]
    fn the_rate_is_cycles_over_the_time_they_span() {
        let mut r = OnsetRate::new();
        assert_eq!((r.count(), r.first_s(), r.hz()), (0, None, None));
        r.add(0.10);
        assert_eq!((r.count(), r.first_s(), r.hz()), (1, Some(0.10), None));
        r.add(0.20);
        r.add(0.35);
        assert_eq!(r.count(), 3);
        assert!((r.hz().unwrap() - 8.0).abs() < 1e-12, "{:?}", r.hz());
        let mut same = OnsetRate::new();
        same.add(0.5);
        same.add(0.5);
        assert_eq!(same.hz(), None);
    }
}
