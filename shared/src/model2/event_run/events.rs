//! The event runner's steps and events: a Stribeck step under error control, the watched
//! functions (the regime's guards, the edges' contact guards, the extremes' rates), and the
//! Illinois search that locates the first of them inside a step.

use super::{dot, flow, rate, rk, EventRunner, Fallback, Point, EXTREMES, EXTREME_NOISE, EXTREME_TOL, GUARD_TOL};
use crate::model2::system::{NA, NS};
use crate::stickslip::Regime;

impl EventRunner {
    /// The guards of `regime`: (first slot, count).
    pub(super) fn guard_slots(regime: Regime) -> (usize, usize) {
        match regime {
            Regime::Stick => (0, 2),
            Regime::SlipSlower => (2, 1),
            Regime::SlipFaster => (3, 1),
        }
    }

    /// The rate of extreme `k`'s quantity (its zero is the extreme): x', x'', phi', phi'', u''
    /// (the band velocity's rate), x''' and u''' (the accelerations' rates).
    pub(super) fn extreme_rate(p: &Point, k: usize) -> f64 {
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

    /// One Stribeck step from `p0` of at most `limit` [s]: its length and end point.
    pub(super) fn slip_step(&mut self, regime: Regime, p0: &Point, limit: f64) -> Result<(f64, Point), Fallback> {
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
    pub(super) fn at(&mut self, regime: Regime, p0: &Point, h: f64, taylor: Option<&flow::Taylor>, theta: f64) -> Point {
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
    pub(super) fn watched(&self, regime: Regime, k: usize, p: &Point) -> f64 {
        let n = Self::guard_slots(regime).1 + self.contact_guards();
        if k < n {
            dot(&self.guard_row(regime, k), &p.z)
        } else {
            Self::extreme_rate(p, k - n)
        }
    }

    /// The contact guards watched beside the friction's: one per edge with unilateral
    /// contact, none with bilateral springs.
    #[inline(always)]
    pub(super) fn contact_guards(&self) -> usize {
        if self.unilateral {
            2
        } else {
            0
        }
    }

    /// Guard `k` of `regime` (the friction's first, then the edges'): fires at row . z >= 0.
    /// A closed edge fires as its compression falls through zero (row -d_i), an open one as
    /// it rises through zero (row d_i).
    pub(super) fn guard_row(&self, regime: Regime, k: usize) -> [f64; NA] {
        let (slot, n) = Self::guard_slots(regime);
        if k < n {
            return self.guard_sets[self.contact][slot + k];
        }
        let e = k - n;
        let r = self.compression[e];
        if self.open[e] {
            r
        } else {
            core::array::from_fn(|c| -r[c])
        }
    }

    /// Illinois search for the sign change of `f` on [lo, hi] (f(lo) = flo, f(hi) = fhi of
    /// opposite signs, or fhi = 0 for a guard): the smallest fraction past it and its point.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn locate(
        &mut self,
        regime: Regime,
        p0: &Point,
        h: f64,
        taylor: Option<&flow::Taylor>,
        f: &dyn Fn(&Self, &Point) -> f64,
        lo: (f64, f64),
        hi: (f64, f64, Point),
        tol: f64,
    ) -> (f64, Point) {
        super::illinois::locate(lo, hi, tol, 100, |x| {
            let p = self.at(regime, p0, h, taylor, x);
            (f(self, &p), p)
        })
    }

    /// The first event inside the step from `p0` to `p1` (length `h`): its fraction, point
    /// and whether it is a guard (its index) or an extreme (None).
    pub(super) fn first_event(&mut self, regime: Regime, p0: &Point, p1: &Point, h: f64, taylor: Option<&flow::Taylor>) -> Option<(f64, Point, Option<usize>)> {
        let n = Self::guard_slots(regime).1 + self.contact_guards();
        let mut best: Option<(f64, Point, Option<usize>)> = None;
        for k in 0..n + EXTREMES {
            let f0 = self.watched(regime, k, p0);
            let f1 = self.watched(regime, k, p1);
            let guard = k < n;
            if guard {
                let row = self.guard_row(regime, k);
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
            } else if f0 * f1 < 0.0 && libm::fabs(f0).max(libm::fabs(f1)) > EXTREME_NOISE * self.rate_scale[k - n] {
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
}
