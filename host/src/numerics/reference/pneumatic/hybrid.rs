//! The pneumatic drive as a hybrid system for the event-driven DOP853 driver: the regime is the
//! pad's (stick, slip slower, slip faster) times the band's (sliding forward, back, stuck), each
//! slip with its arming flag. The driver watches two guards in every regime, the pad's and the
//! band's (each scaled to a force or a speed), and makes the earliest; `guard` (their largest)
//! and `transition` (whichever holds) serve a caller that watches one.

use super::*;

impl Pneu {
    /// The pad's guard (normalised), or None when frictionless.
    fn pad_guard(&self, r: Regime, y: &Y) -> Option<f64> {
        if self.frictionless {
            return None;
        }
        let v = self.slip_v(y);
        Some(match (r.pad, r.pad_armed) {
            (Pad::Stick, _) => (self.f_req(r.band, y).abs() - self.ph.pad.mu_s * self.ph.normal(&z8(y))) / self.force_scale,
            (_, false) => (v.abs() - ARM * self.speed_scale) / self.speed_scale,
            (Pad::Slower, true) => v / self.speed_scale,
            (Pad::Faster, true) => -v / self.speed_scale,
        })
    }

    fn pad_guard_rate(&self, r: Regime, y: &Y, yd: &Y) -> f64 {
        let vd = self.slip_v(yd);
        match (r.pad, r.pad_armed) {
            (Pad::Stick, _) => {
                let f = self.f_req(r.band, y);
                (f.signum() * self.friction_rate(r, y, yd) - self.ph.pad.mu_s * self.ph.normal_rate(&z8(yd))) / self.force_scale
            }
            (_, false) => self.slip_v(y).signum() * vd / self.speed_scale,
            (Pad::Slower, true) => vd / self.speed_scale,
            (Pad::Faster, true) => -vd / self.speed_scale,
        }
    }

    /// The band's guard (normalised).
    fn band_guard(&self, r: Regime, y: &Y) -> f64 {
        let w = y[XB + 1];
        match (r.band, r.band_armed) {
            (Band::Stuck, _) => (self.net_stuck(r, y).abs() - self.f_ss) / self.force_scale,
            (_, false) => (w.abs() - ARM * self.speed_scale) / self.speed_scale,
            (b, true) => -b.dir() * w / self.speed_scale,
        }
    }

    fn band_guard_rate(&self, r: Regime, y: &Y, yd: &Y) -> f64 {
        let wd = yd[XB + 1];
        match (r.band, r.band_armed) {
            (Band::Stuck, _) => {
                let net_rate = self.area * yd[P] - self.friction_rate(r, y, yd);
                self.net_stuck(r, y).signum() * net_rate / self.force_scale
            }
            (_, false) => y[XB + 1].signum() * wd / self.speed_scale,
            (b, true) => -b.dir() * wd / self.speed_scale,
        }
    }

    /// The pad's regime after its velocity match (v = 0 projected): the table of docs/model.md.
    fn after_match(&self, r: Regime, y: &mut Y) -> Pad {
        self.project_stick(r.band, y);
        let f = self.f_req(r.band, y);
        let lim = self.ph.pad.mu_s * self.ph.normal(&z8(y));
        if f.abs() <= lim {
            Pad::Stick
        } else if f > 0.0 {
            Pad::Slower
        } else {
            Pad::Faster
        }
    }

    /// The band's regime after it stopped (x_b' = 0 set): stuck if the net force is within F_ss,
    /// else sliding on in its direction.
    fn after_stop(&self, r: Regime, y: &mut Y) -> Band {
        y[XB + 1] = 0.0;
        if r.pad == Pad::Stick {
            self.project_stick(Band::Stuck, y);
        }
        let net = self.net_stuck(Regime { band: Band::Stuck, ..r }, y);
        if net.abs() <= self.f_ss {
            Band::Stuck
        } else if net > 0.0 {
            Band::Forward
        } else {
            Band::Back
        }
    }
}

impl Hybrid<10> for Pneu {
    type Regime = Regime;
    const NAME: &'static str = "pneumatic reference";

    fn rhs(&self, r: Regime, y: &Y) -> Y {
        self.deriv(r, y)
    }

    fn guard(&self, r: Regime, y: &Y) -> f64 {
        let b = self.band_guard(r, y);
        self.pad_guard(r, y).map_or(b, |p| p.max(b))
    }

    /// The rate of the largest component.
    fn guard_rate(&self, r: Regime, y: &Y) -> Option<f64> {
        let yd = self.deriv(r, y);
        let b = self.band_guard(r, y);
        Some(match self.pad_guard(r, y) {
            Some(p) if p >= b => self.pad_guard_rate(r, y, &yd),
            _ => self.band_guard_rate(r, y, &yd),
        })
    }

    /// Fires the components at or above zero (the pad's first; see [`Pneu::fire`]).
    fn transition(&self, r: Regime, y: &mut Y) -> Regime {
        let pad = self.pad_guard(r, y).is_some_and(|g| g >= 0.0);
        let band = self.band_guard(r, y) >= 0.0;
        self.fire(r, y, pad, band)
    }

    /// Two guards: the pad's (0) and the band's (1), each located on its own (crests included)
    /// by the driver, which makes the earliest.
    fn guard_count(&self) -> usize {
        2
    }

    fn guard_k(&self, r: Regime, y: &Y, k: usize) -> f64 {
        if k == 0 {
            self.pad_guard(r, y).unwrap_or(-1.0)
        } else {
            self.band_guard(r, y)
        }
    }

    fn guard_rate_k(&self, r: Regime, y: &Y, k: usize) -> Option<f64> {
        let yd = self.deriv(r, y);
        if k == 0 {
            self.pad_guard(r, y).map(|_| self.pad_guard_rate(r, y, &yd))
        } else {
            Some(self.band_guard_rate(r, y, &yd))
        }
    }

    /// Guard k fired (the band's too if it holds at the same state).
    fn transition_k(&self, r: Regime, y: &mut Y, k: usize) -> Regime {
        let band = k == 1 || self.band_guard(r, y) >= 0.0;
        self.fire(r, y, k == 0, band)
    }

    /// The model-2 reference's fastest rate of the pad (the band's mass with no drive spring),
    /// and the column at its stiffest (the supply pressure at the start's volume), the seal's
    /// falling slope and the guides' damping on the band.
    fn fastest_rate(&self) -> f64 {
        let pad = <Phys as Hybrid<8>>::fastest_rate(&self.ph);
        let column = (self.n * self.p_s * self.area / self.l0 / self.m_b).sqrt();
        let seal = (self.f_ss - self.f_sk) / self.v_ss / self.m_b;
        let relax = self.n * P_REF * self.conductance * self.p_s / (self.area * self.l0 * self.p_s);
        pad.max(column).max(seal).max(self.c_b / self.m_b).max(relax)
    }
}

impl Pneu {
    /// Fires the pad's component (`pad_fired`), then the band's (`band_fired`, if its guard
    /// still holds), then settles: a stuck pad past mu_s N slips, a stuck band past F_ss breaks
    /// away, until neither holds (a change can leave the other's guard above zero). The
    /// elementary changes go to the log.
    fn fire(&self, r0: Regime, y: &mut Y, pad_fired: bool, band_fired: bool) -> Regime {
        let mut r = r0;
        let mut changes = Vec::new();
        if pad_fired {
            let v = self.slip_v(y);
            let next = match (r.pad, r.pad_armed) {
                (Pad::Stick, _) => {
                    if self.f_req(r.band, y) > 0.0 {
                        Pad::Slower
                    } else {
                        Pad::Faster
                    }
                }
                // left zero in the slip's own direction: arm
                (Pad::Slower, false) if v < 0.0 => Pad::Slower,
                (Pad::Faster, false) if v > 0.0 => Pad::Faster,
                _ => self.after_match(r, y),
            };
            let arming = next == r.pad && !r.pad_armed && next != Pad::Stick && self.slip_v(y) * Phys::sigma(next) < 0.0;
            if next != r.pad {
                changes.push(Change::Pad { from: r.pad, to: next });
            }
            r = Regime { pad: next, pad_armed: next == Pad::Stick || arming, ..r };
        }
        if band_fired && self.band_guard(r, y) >= 0.0 {
            let w = y[XB + 1];
            let next = match (r.band, r.band_armed) {
                (Band::Stuck, _) => {
                    if self.net_stuck(r, y) > 0.0 {
                        Band::Forward
                    } else {
                        Band::Back
                    }
                }
                (Band::Forward, false) if w > 0.0 => Band::Forward,
                (Band::Back, false) if w < 0.0 => Band::Back,
                _ => self.after_stop(r, y),
            };
            let arming = next == r.band && !r.band_armed && next != Band::Stuck && y[XB + 1] * next.dir() > 0.0;
            if next != r.band || (r.band != Band::Stuck && !arming) {
                changes.push(Change::Band { from: r.band, to: next });
            }
            r = Regime { band: next, band_armed: next == Band::Stuck || arming, ..r };
        }
        for _ in 0..8 {
            if !self.frictionless && r.pad == Pad::Stick {
                let f = self.f_req(r.band, y);
                if f.abs() > self.ph.pad.mu_s * self.ph.normal(&z8(y)) {
                    let to = if f > 0.0 { Pad::Slower } else { Pad::Faster };
                    changes.push(Change::Pad { from: Pad::Stick, to });
                    r = Regime { pad: to, pad_armed: false, ..r };
                    continue;
                }
            }
            if r.band == Band::Stuck {
                let net = self.net_stuck(r, y);
                if net.abs() > self.f_ss {
                    let to = if net > 0.0 { Band::Forward } else { Band::Back };
                    changes.push(Change::Band { from: Band::Stuck, to });
                    r = Regime { band: to, band_armed: false, ..r };
                    continue;
                }
            }
            break;
        }
        self.log.borrow_mut().push(changes);
        r
    }
}
