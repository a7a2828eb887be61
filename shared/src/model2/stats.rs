//! Window statistics of a model-2 run.
//!
//! The state's extremes inside each segment come from the cubic Hermite interpolant of the
//! state and its derivative at the segment's ends (the derivative's zeros inside the segment);
//! the segments are at most one substep long, so the interpolant's error is fourth order in the
//! substep. Accelerations (x'' of the pad, u'' of the band) are taken at the segment ends, which
//! include every transition instant. Stick fraction and stick-slip frequency are as in
//! [`crate::stats`].

use crate::stats::Extremes;
use crate::model2::stepper::{Model2Observer, Model2Segment, Model2Transition};
use crate::real::Real;
use crate::stickslip::Regime;

/// Quantities whose extremes are kept: x [m], x' [m/s], phi [rad], phi' [rad/s], band velocity
/// x_b' [m/s], pad acceleration x'' [m/s^2], band acceleration x_b'' [m/s^2].
pub const QUANTITIES: usize = 7;
/// Names of the quantities, in order.
pub const NAMES: [&str; QUANTITIES] = ["x", "xdot", "phi", "phidot", "band_v", "pad_acc", "band_acc"];

/// Window statistics (SI units).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Model2Stats {
    pub min: [f64; QUANTITIES],
    pub max: [f64; QUANTITIES],
    pub stick_fraction: f64,
    pub stick_slip_hz: f64,
    pub slip_onsets: u64,
    pub transitions: u64,
    /// Window covered [s]; 0 when the run ended before the window.
    pub window_s: f64,
}

impl Model2Stats {
    pub fn pp(&self, i: usize) -> f64 {
        self.max[i] - self.min[i]
    }
}

/// Collects [`Model2Stats`] from the segments ending after `t_from` [s].
#[derive(Clone, Debug)]
pub struct Model2StatsObserver {
    t_from: f64,
    v: f64,
    s: Model2Stats,
    /// The quantities' extremes (`seen`: any finite value taken).
    values: Extremes<f64, QUANTITIES>,
    seen: bool,
    stick_s: f64,
    t_end: f64,
    onsets: crate::stats::OnsetRate,
    /// Keep the extremes (false: only the window's time, stick time and transitions).
    extremes: bool,
    /// Look for extremes inside segments (false: the segments end at every extreme, as the
    /// event run's do).
    interpolate: bool,
}

impl Model2StatsObserver {
    /// `v`: the band drive speed V [m/s] (the band velocity is V + u').
    pub fn new(t_from: f64, v: f64) -> Self {
        Self::with_extremes(t_from, v, true)
    }

    /// [`Self::new`] without the extremes (min and max stay 0): stick fraction, stick-slip
    /// frequency and transitions only.
    pub fn events_only(t_from: f64, v: f64) -> Self {
        Self::with_extremes(t_from, v, false)
    }

    fn with_extremes(t_from: f64, v: f64, extremes: bool) -> Self {
        Model2StatsObserver {
            extremes,
            t_from,
            v,
            s: Model2Stats::default(),
            values: Extremes::<f64, QUANTITIES>::EMPTY,
            seen: false,
            stick_s: 0.0,
            t_end: t_from,
            onsets: crate::stats::OnsetRate::new(),
            interpolate: true,
        }
    }

    /// The same observer for segments that end at every extreme of the quantities (the event
    /// run, [`crate::model2::event_run`]): the values at the segments' ends only, no
    /// interpolation inside.
    pub fn without_interpolation(mut self) -> Self {
        self.interpolate = false;
        self
    }

    fn take(&mut self, i: usize, v: f64) {
        if !v.is_finite() {
            return;
        }
        self.seen = true;
        self.values.take(i, v);
    }

    /// The window statistics so far.
    pub fn finish(&self) -> Model2Stats {
        let mut s = self.s;
        if !self.seen {
            return Model2Stats::default();
        }
        (s.min, s.max) = (self.values.min, self.values.max);
        for i in 0..QUANTITIES {
            if !s.min[i].is_finite() {
                s.min[i] = 0.0;
                s.max[i] = 0.0;
            }
        }
        s.window_s = self.t_end - self.t_from;
        s.stick_fraction = if s.window_s > 0.0 { crate::stats::at_most_one(self.stick_s / s.window_s) } else { 0.0 };
        s.slip_onsets = u64::from(self.onsets.count());
        s.stick_slip_hz = self.onsets.hz().unwrap_or(0.0);
        s
    }
}

/// Cubic Hermite interpolant on [0, 1] of values p0, p1 and slopes m0 = H d0, m1 = H d1: the
/// values at its interior stationary points.
fn hermite_extremes(p0: f64, p1: f64, m0: f64, m1: f64, mut f: impl FnMut(f64)) {
    // P'(s) = a s^2 + b s + c
    let a = 6.0 * (p0 - p1) + 3.0 * (m0 + m1);
    let b = -6.0 * (p0 - p1) - 4.0 * m0 - 2.0 * m1;
    let c = m0;
    let eval = |s: f64| {
        let s2 = s * s;
        let s3 = s2 * s;
        (2.0 * s3 - 3.0 * s2 + 1.0) * p0 + (s3 - 2.0 * s2 + s) * m0 + (-2.0 * s3 + 3.0 * s2) * p1 + (s3 - s2) * m1
    };
    let mut roots = [f64::NAN; 2];
    if libm::fabs(a) < 1e-300 {
        if b != 0.0 {
            roots[0] = -c / b;
        }
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 {
            let r = libm::sqrt(disc);
            // numerically stable pair
            let qq = -0.5 * (b + if b >= 0.0 { r } else { -r });
            roots[0] = qq / a;
            if qq != 0.0 {
                roots[1] = c / qq;
            }
        }
    }
    for s in roots {
        if s > 0.0 && s < 1.0 {
            f(eval(s));
        }
    }
}

impl<T: Real> Model2Observer<T> for Model2StatsObserver {
    fn segment(&mut self, seg: &Model2Segment<T>) {
        if seg.t1 <= self.t_from {
            return;
        }
        let t0 = seg.t0.max(self.t_from);
        if seg.t1 > self.t_end {
            self.t_end = seg.t1;
        }
        if seg.regime == Regime::Stick {
            self.stick_s += seg.t1 - t0;
        }
        if !self.extremes {
            // finish() needs `seen` to report the window
            self.seen = true;
            return;
        }
        let h = seg.t1 - seg.t0;
        let z0: [f64; 6] = core::array::from_fn(|i| seg.z0[i].to_f64());
        let z1: [f64; 6] = core::array::from_fn(|i| seg.z1[i].to_f64());
        let d0: [f64; 6] = core::array::from_fn(|i| seg.zd0[i].to_f64());
        let d1: [f64; 6] = core::array::from_fn(|i| seg.zd1[i].to_f64());
        // (quantity, state index): x, x', phi, phi', u' (band velocity V + u')
        for (q, i) in [(0usize, 0usize), (1, 1), (2, 2), (3, 3), (4, 5)] {
            let off = if q == 4 { self.v } else { 0.0 };
            if seg.t0 >= self.t_from {
                self.take(q, z0[i] + off);
            }
            self.take(q, z1[i] + off);
            if self.interpolate && h > 0.0 && seg.t0 >= self.t_from {
                let mut found = [f64::NAN; 2];
                let mut k = 0;
                hermite_extremes(z0[i], z1[i], h * d0[i], h * d1[i], |v| {
                    found[k] = v;
                    k += 1;
                });
                for v in found.iter().take(k) {
                    self.take(q, v + off);
                }
            }
        }
        // accelerations at the ends
        if seg.t0 >= self.t_from {
            self.take(5, d0[1]);
            self.take(6, d0[5]);
        }
        self.take(5, d1[1]);
        self.take(6, d1[5]);
    }

    fn transition(&mut self, tr: &Model2Transition<T>) {
        if tr.t < self.t_from {
            return;
        }
        self.s.transitions += 1;
        if tr.from == Regime::Stick {
            self.onsets.add(tr.t);
        }
    }
}
