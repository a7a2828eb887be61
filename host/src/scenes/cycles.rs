//! Cycle-to-cycle spread of the stick-slip motion in the statistics window: the error bars
//! of the stick-slip frequency and the stick fraction.
//!
//! A cycle runs from one stick-to-slip transition (slip onset) to the next. For each complete
//! cycle in the window the observer takes its period T_i and its stick fraction S_i/T_i (time
//! in stick inside the cycle over its length), and keeps their running mean and standard
//! deviation (Welford). Allocation-free, from the exact transition times.
//!
//! The window's stick-slip frequency (model crate) is 1 / mean(T_i), so the period spread is
//! its natural error bar: sd_f = f sd_T / mean_T to first order.

use stickslip_model::{Observer, Real, Regime, Transition};

/// Running mean and sample variance.
#[derive(Clone, Copy, Debug, Default)]
pub struct Welford {
    pub n: u64,
    mean: f64,
    m2: f64,
}

impl Welford {
    pub fn push(&mut self, x: f64) {
        self.n += 1;
        let d = x - self.mean;
        self.mean += d / self.n as f64;
        self.m2 += d * (x - self.mean);
    }
    pub fn mean(&self) -> Option<f64> {
        (self.n >= 1).then_some(self.mean)
    }
    /// Sample standard deviation (n - 1), from two values on.
    pub fn sd(&self) -> Option<f64> {
        (self.n >= 2).then(|| (self.m2 / (self.n - 1) as f64).max(0.0).sqrt())
    }
}

/// Per-cycle statistics of a run's window.
#[derive(Clone, Copy, Debug, Default)]
pub struct CycleStats {
    /// Period of each complete cycle T_i [s].
    pub period: Welford,
    /// Stick fraction of each complete cycle [-].
    pub stick_fraction: Welford,
}

/// Collects [`CycleStats`] from the transitions at or after `t_from` [s].
#[derive(Clone, Debug)]
pub struct CycleObserver {
    t_from: f64,
    last_onset: Option<f64>,
    /// Time of the last transition seen in the window and whether the pad was sticking since.
    last_t: f64,
    sticking: bool,
    stick_in_cycle: f64,
    stats: CycleStats,
}

impl CycleObserver {
    pub fn new(t_from: f64) -> Self {
        CycleObserver {
            t_from,
            last_onset: None,
            last_t: t_from,
            sticking: false,
            stick_in_cycle: 0.0,
            stats: CycleStats::default(),
        }
    }

    pub fn finish(&self) -> CycleStats {
        self.stats
    }
}

impl<T: Real> Observer<T> for CycleObserver {
    fn transition(&mut self, tr: &Transition<T>) {
        if tr.t < self.t_from {
            return;
        }
        if self.sticking {
            self.stick_in_cycle += tr.t - self.last_t;
        }
        if tr.from == Regime::Stick {
            if let Some(prev) = self.last_onset {
                let period = tr.t - prev;
                if period > 0.0 {
                    self.stats.period.push(period);
                    self.stats.stick_fraction.push(self.stick_in_cycle / period);
                }
            }
            self.last_onset = Some(tr.t);
            self.stick_in_cycle = 0.0;
        }
        self.last_t = tr.t;
        self.sticking = tr.to == Regime::Stick;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stickslip_model::State;

    fn tr(t: f64, from: Regime, to: Regime) -> Transition<f64> {
        Transition {
            t,
            from,
            to,
            state: State::default(),
        }
    }

    #[test]
    fn two_cycles_by_hand() {
        // onsets at 1.0, 1.5, 2.5; sticks 1.2..1.5 (0.3 of 0.5) and 1.6..2.5 (0.9 of 1.0)
        let mut o = CycleObserver::new(0.9);
        let seq = [
            tr(0.5, Regime::Stick, Regime::SlipSlower), // before the window: ignored
            tr(1.0, Regime::Stick, Regime::SlipSlower),
            tr(1.2, Regime::SlipSlower, Regime::Stick),
            tr(1.5, Regime::Stick, Regime::SlipSlower),
            tr(1.6, Regime::SlipSlower, Regime::Stick),
            tr(2.5, Regime::Stick, Regime::SlipFaster),
        ];
        for t in &seq {
            Observer::<f64>::transition(&mut o, t);
        }
        let s = o.finish();
        assert_eq!(s.period.n, 2);
        assert!((s.period.mean().unwrap() - 0.75).abs() < 1e-12); // (0.5 + 1.0) / 2
        assert!((s.period.sd().unwrap() - 0.125f64.sqrt()).abs() < 1e-12); // 0.25^2 * 2 / 1
        assert!((s.stick_fraction.mean().unwrap() - 0.75).abs() < 1e-12); // (0.6 + 0.9) / 2
    }
}
