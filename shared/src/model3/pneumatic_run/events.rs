//! The pneumatic runner's steps and events: an error-controlled Dormand-Prince step, the
//! first guard inside it (Illinois), and what each guard does (the pad's transitions, the band's
//! stop and breakaway).

use super::{PneumaticRunner, PneumaticStop, GUARD_TOL, NP};
use crate::model2::event_run::{illinois, rk};
use crate::model2::stepper::{Model2Observer, Model2Transition};
use crate::stickslip::Regime;

impl PneumaticRunner {
    /// One error-controlled step from `w0` (slope `d0`) of at most `limit` [s].
    pub(super) fn step(&mut self, w0: &[f64; NP], d0: &[f64; NP], limit: f64) -> Result<(f64, [f64; NP], [f64; NP]), PneumaticStop> {
        let (regime, band) = (self.regime, self.band);
        loop {
            let h = self.h.min(limit).min(self.h_max);
            if !(h > 1e-15 * (libm::fabs(self.t) + 1e-3)) {
                return Err(PneumaticStop::Stalled { t: self.t });
            }
            let mut f = |w: &[f64; NP]| self.derivative(regime, band, w);
            let (w1, d1, err) = rk::step(&mut f, w0, d0, h);
            let mut worst: f64 = 0.0;
            for i in 0..NP {
                let sc = self.rtol * self.scale[i].max(libm::fabs(w0[i])).max(libm::fabs(w1[i]));
                worst = worst.max(libm::fabs(err[i]) / sc);
            }
            if !worst.is_finite() {
                worst = f64::INFINITY;
            }
            let factor = if worst > 0.0 { 0.9 * libm::pow(worst, -0.2) } else { 5.0 };
            if worst <= 1.0 {
                let next = h * factor.clamp(0.2, 5.0);
                self.h = if h < self.h { self.h.max(next) } else { next };
                self.counts.steps += 1;
                return Ok((h, w1, d1));
            }
            self.counts.rejected += 1;
            self.h = h * factor.clamp(0.1, 0.9);
        }
    }

    /// The first guard that fires inside the step of length `h` from `w0` (slope `d0`) to `w1`:
    /// its time fraction, state and slope, and which guard (the pad's first, then the band's).
    pub(super) fn first_guard(&mut self, w0: &[f64; NP], d0: &[f64; NP], h: f64, w1: &[f64; NP]) -> Option<(f64, [f64; NP], usize)> {
        let (regime, band) = (self.regime, self.band);
        let (g0, n) = self.guards(regime, band, w0);
        let (g1, _) = self.guards(regime, band, w1);
        let mut best: Option<(f64, [f64; NP], usize)> = None;
        for k in 0..n {
            if !(g0[k] < 0.0) || g1[k] < 0.0 {
                continue;
            }
            // Illinois on the step's own solution from its start
            let (hi, whi) = illinois::locate((0.0, g0[k]), (1.0, g1[k], *w1), GUARD_TOL, 200, |x| {
                let mut f = |w: &[f64; NP]| self.derivative(regime, band, w);
                let (wx, _, _) = rk::step(&mut f, w0, d0, x * h);
                (self.guards(regime, band, &wx).0[k], wx)
            });
            if best.as_ref().is_none_or(|b| hi < b.0) {
                best = Some((hi, whi, k));
            }
        }
        best
    }

    /// Applies guard `k` of the current regimes at `w` (time `t`); returns the new state.
    pub(super) fn fire<O: Model2Observer<f64>>(&mut self, k: usize, mut w: [f64; NP], t: f64, t_from: f64, obs: &mut O) -> [f64; NP] {
        let pad_guards = if self.frictionless { 0 } else if self.regime == Regime::Stick { 2 } else { 1 };
        if k < pad_guards {
            let from = self.regime;
            let next = match from {
                Regime::Stick => {
                    if k == 0 {
                        Regime::SlipSlower
                    } else {
                        Regime::SlipFaster
                    }
                }
                _ => self.after_velocity_match(self.band, &w),
            };
            if next == Regime::Stick {
                self.enter_stick(self.band, &mut w);
            }
            if next != from {
                self.regime = next;
                self.counts.transitions += 1;
                obs.transition(&Model2Transition { t, from, to: next, z: Self::z(&w) });
            }
            if next != Regime::Stick {
                self.h = self.h.min(self.h_max * 1e-3);
            }
        } else if self.band == 0 {
            // breakaway at the seal
            let f = self.net_band_force(self.regime, &w);
            self.band = if f > 0.0 { 1 } else { -1 };
            self.counts.band_changes += 1;
            if t > t_from {
                self.stats.breakaways += 1;
            }
            self.h = self.h.min(self.h_max * 1e-3);
        } else {
            // the band stops: stuck, or sliding the other way
            w[5] = -self.v;
            if self.regime == Regime::Stick {
                self.enter_stick(0, &mut w);
            }
            let f = self.net_band_force(self.regime, &w);
            self.band = if libm::fabs(f) <= self.cyl.f_ss {
                0
            } else if f > 0.0 {
                1
            } else {
                -1
            };
            self.counts.band_changes += 1;
            self.h = self.h.min(self.h_max * 1e-3);
        }
        self.settle(&mut w, t, t_from, obs);
        w
    }

    /// After a change: a guard that already holds strictly fires at once (a few times at
    /// most): a guard is watched only as it crosses zero from below, so one that a change left
    /// above zero would never fire.
    pub(super) fn settle<O: Model2Observer<f64>>(&mut self, w: &mut [f64; NP], t: f64, t_from: f64, obs: &mut O) {
        for _ in 0..8 {
            // the pad's static limit exceeded (e.g. as the band breaks away)
            if !self.frictionless && self.regime == Regime::Stick {
                let (g, _) = self.guards(self.regime, self.band, w);
                if g[0] > 0.0 || g[1] > 0.0 {
                    let from = self.regime;
                    self.regime = if g[0] > 0.0 { Regime::SlipSlower } else { Regime::SlipFaster };
                    self.counts.transitions += 1;
                    obs.transition(&Model2Transition { t, from, to: self.regime, z: Self::z(w) });
                    continue;
                }
            }
            // the seal's static friction exceeded (e.g. as the pad sticks on the stuck band: its
            // friction jumps from the kinetic level to what holds it)
            if self.band == 0 {
                let f = self.net_band_force(self.regime, w);
                if libm::fabs(f) > self.cyl.f_ss {
                    self.band = if f > 0.0 { 1 } else { -1 };
                    self.counts.band_changes += 1;
                    if t > t_from {
                        self.stats.breakaways += 1;
                    }
                    self.h = self.h.min(self.h_max * 1e-3);
                    continue;
                }
            }
            return;
        }
    }
}
