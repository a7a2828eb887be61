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

/// The slip onsets of a stretch and the stick-slip frequency they give, (n - 1) / (last -
/// first): the one definition the model's statistics (thesis and model 2), the virtual rig's
/// truth, the recorded-data analysis and the rig's window statistics all use. The onsets' time
/// `T` is seconds (`f64`, the default) or, on the rig's per-sample path, a sample index (`u32`,
/// the frequency then scaled by the sampling rate in f32: no f64 per sample on the
/// microcontroller).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OnsetRate<T = f64> {
    count: u32,
    first: T,
    last: T,
}

impl<T: Copy + PartialOrd + Default> OnsetRate<T> {
    pub fn new() -> Self {
        OnsetRate { count: 0, first: T::default(), last: T::default() }
    }

    /// A slip onset at `t` (onsets in time order).
    #[inline(always)]
    pub fn add(&mut self, t: T) {
        if self.count == 0 {
            self.first = t;
        }
        self.last = t;
        self.count = self.count.saturating_add(1);
    }

    /// Onsets counted (saturating at `u32::MAX`).
    pub fn count(&self) -> u32 {
        self.count
    }

    /// The first onset's time, if any.
    pub fn first(&self) -> Option<T> {
        (self.count > 0).then_some(self.first)
    }

    /// Two onsets or more with time between them: (n - 1, first, last).
    #[inline(always)]
    fn span(&self) -> Option<(u32, T, T)> {
        (self.count >= 2 && self.last > self.first).then_some((self.count - 1, self.first, self.last))
    }
}

impl OnsetRate<f64> {
    /// The stick-slip frequency [Hz] of onsets in seconds: `None` with fewer than two onsets or
    /// no time between them.
    pub fn hz(&self) -> Option<f64> {
        self.span().map(|(n, first, last)| n as f64 / (last - first))
    }
}

impl OnsetRate<u32> {
    /// The stick-slip frequency [Hz] of onsets at sample indices, sampled at `fs` [Hz]: 0 with
    /// fewer than two onsets or no samples between them.
    pub fn hz_at(&self, fs: f32) -> f32 {
        self.span().map_or(0.0, |(n, first, last)| n as f32 * fs / (last - first) as f32)
    }
}

/// Running extremes of `N` quantities: the one definition the model's statistics (thesis and
/// model 2), the rig's window statistics and pressures, the virtual rig's truth and the
/// recorded-data analysis use. A value replaces an extreme only when strictly beyond it, so a
/// NaN never enters (every comparison with it is false), and an empty quantity keeps its
/// starting values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extremes<T, const N: usize> {
    pub min: [T; N],
    pub max: [T; N],
}

impl<T: Copy + PartialOrd, const N: usize> Extremes<T, N> {
    /// Every quantity at `v`: min = max = v.
    pub const fn of(v: [T; N]) -> Self {
        Extremes { min: v, max: v }
    }

    /// Quantity `i` takes the value `v`.
    #[inline(always)]
    pub fn take(&mut self, i: usize, v: T) {
        if v < self.min[i] {
            self.min[i] = v;
        }
        if v > self.max[i] {
            self.max[i] = v;
        }
    }

    /// Every quantity takes its value of `v`.
    #[inline(always)]
    pub fn take_all(&mut self, v: &[T; N]) {
        for (i, x) in v.iter().enumerate() {
            self.take(i, *x);
        }
    }
}

macro_rules! extremes_of_float {
    ($t:ty) => {
        impl<const N: usize> Extremes<$t, N> {
            /// No value yet: min +inf, max -inf.
            pub const EMPTY: Self = Extremes { min: [<$t>::INFINITY; N], max: [<$t>::NEG_INFINITY; N] };

            /// Whether quantity `i` has taken a value.
            pub fn seen(&self, i: usize) -> bool {
                self.min[i] <= self.max[i]
            }

            /// Peak-to-peak of quantity `i`, max - min (-inf for one that took no value).
            pub fn pp(&self, i: usize) -> $t {
                self.max[i] - self.min[i]
            }
        }
    };
}
extremes_of_float!(f32);
extremes_of_float!(f64);

/// Collects [`RunStats`] from the segments of steps `from_step` onward.
#[derive(Clone, Debug)]
pub struct StatsObserver<T: Real> {
    from_step: u64,
    t_from: f64,
    /// x, x', phi, phi' (`None` until the window's first finite state).
    extremes: Option<Extremes<T, 4>>,
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
            extremes: None,
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

    fn include(&mut self, z: &[T; 4]) {
        // the segments of a step that halts may hold a non-finite state: never let it in
        if !(z[0].is_finite() && z[1].is_finite() && z[2].is_finite() && z[3].is_finite()) {
            return;
        }
        match &mut self.extremes {
            None => self.extremes = Some(Extremes::of(*z)),
            Some(e) => e.take_all(z),
        }
    }

    pub fn finish(&self) -> RunStats {
        let f = |a: [T; 4]| [a[0].to_f64(), a[1].to_f64(), a[2].to_f64(), a[3].to_f64()];
        let hz = self.onsets.hz().unwrap_or(0.0);
        let e = self.extremes.unwrap_or(Extremes::of([T::zero(); 4]));
        RunStats {
            min: f(e.min),
            max: f(e.max),
            stick_fraction: if self.window_s > 0.0 { at_most_one(self.stick_s / self.window_s) } else { 0.0 },
            stick_slip_hz: hz,
            slip_onsets: u64::from(self.onsets.count()),
            transitions: self.transitions,
            window_s: self.window_s,
        }
    }
}

/// A stick fraction (stick time over the window) at most 1: the stick time is a sum of
/// segments, whose rounding can pass the window's length by an ulp or two in a run that sticks
/// throughout (1.0000000000000375 for 1); NaN stays NaN.
pub fn at_most_one(f: f64) -> f64 {
    if f > 1.0 {
        1.0
    } else {
        f
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
            stick_fraction: if window_s > 0.0 { at_most_one(stick_s / window_s) } else { 0.0 },
            stick_slip_hz: hz,
            slip_onsets: u64::from(self.onsets.count()),
            transitions: self.transitions,
            window_s,
        }
    }
}

#[cfg(test)]
mod onset_rate_tests {
    use super::{Extremes, OnsetRate};

    /// Extremes by hand: 3, -1, NaN, 2 on quantity 0 give min -1, max 3, pp 4 (the NaN never
    /// enters); quantity 1 took nothing and is not seen.
    #[test]
    fn extremes_take_values_and_never_a_nan() {
        let mut e = Extremes::<f64, 2>::EMPTY;
        assert!(!e.seen(0) && !e.seen(1));
        for v in [3.0, -1.0, f64::NAN, 2.0] {
            e.take(0, v);
        }
        assert_eq!((e.min[0], e.max[0], e.pp(0)), (-1.0, 3.0, 4.0));
        assert!(e.seen(0) && !e.seen(1));
        let mut f = Extremes::of([1.0f32, 5.0]);
        f.take_all(&[0.5, f32::NAN]);
        assert_eq!((f.min, f.max), ([0.5, 5.0], [1.0, 5.0]));
    }

    /// Onsets at 0.10, 0.20 and 0.35 s: two cycles in 0.25 s, 8 Hz; fewer than two onsets, or
    /// two at one time, give none.
    #[test]
    fn the_rate_is_cycles_over_the_time_they_span() {
        let mut r = OnsetRate::new();
        assert_eq!((r.count(), r.first(), r.hz()), (0, None, None));
        r.add(0.10);
        assert_eq!((r.count(), r.first(), r.hz()), (1, Some(0.10), None));
        r.add(0.20);
        r.add(0.35);
        assert_eq!(r.count(), 3);
        assert!((r.hz().unwrap() - 8.0).abs() < 1e-12, "{:?}", r.hz());
        let mut same = OnsetRate::new();
        same.add(0.5);
        same.add(0.5);
        assert_eq!(same.hz(), None);
    }

    /// The same onsets at sample indices of a 1 kHz record (100, 200, 350): 8 Hz in f32; one
    /// onset, or two at one sample, give 0.
    #[test]
    fn at_sample_indices_the_rate_is_scaled_by_the_sampling_rate() {
        let mut r = OnsetRate::<u32>::new();
        assert_eq!((r.count(), r.first(), r.hz_at(1000.0)), (0, None, 0.0));
        r.add(100);
        assert_eq!((r.count(), r.first(), r.hz_at(1000.0)), (1, Some(100), 0.0));
        r.add(200);
        r.add(350);
        assert_eq!(r.hz_at(1000.0), 8.0);
        let mut same = OnsetRate::<u32>::new();
        same.add(7);
        same.add(7);
        assert_eq!(same.hz_at(1000.0), 0.0);
    }
}
