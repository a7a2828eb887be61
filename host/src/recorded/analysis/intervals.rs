//! The intervals between slip onsets, in bounded memory: their count, mean and standard
//! deviation (Welford's running sums), and their median and the intervals far below it, from a
//! histogram of log2(interval) in 1/32-octave bins.
//!
//! **Why.** Where the noise reaches the slip-onset level, the estimator splits a slip in two (a
//! false re-stick a few ms after the onset, then a second onset) or takes noise for an onset.
//! Each split adds an onset: the frequency is biased up and the stick fraction moves, by an
//! amount the mean alone cannot show. Stick-slip's cycles, periodic or not, are of one scale:
//! on the virtual rig's six cases and eighteen rig sets (`sil`, default noise, 2 s) no interval
//! is under 0.86 of the median; with the noise near the onset level (`sil push_center --noise
//! 4` to `5`, `pull_lead --noise 3`) 10 to 35 % of them are under a third of it (3.3 ms + 17.7 ms
//! for one cycle of 21 ms). Onsets at random (noise alone, a Poisson process) put 21 % of their
//! intervals under a third of the median. Onsets missed, or a stick-slip that stops and starts
//! again, make intervals over three times the median: the frequency, onsets over their span,
//! is then biased too (`sil oracle_1dof --gain 2`: a slow slip cut by the drift guard, 1.72 Hz
//! for 0.86, its intervals 0.19 s and 1 s in turn).

/// An interval under this fraction of the median is "short" (a split cycle or a noise onset).
pub const SHORT_OF_MEDIAN: f64 = 1.0 / 3.0;
/// An interval over this multiple of the median is "long".
pub const LONG_OF_MEDIAN: f64 = 3.0;
/// The contact estimate is not told where at least this many intervals are short or long ...
pub const SPLIT_MIN_COUNT: u64 = 1;
/// ... and they are at least this share of the intervals (one split in 50 cycles biases the
/// frequency by 2 %: `sil pull_trail --noise 5 --seed 4`, one in 16, gave +6.2 %).
pub const SPLIT_MIN_FRACTION: f64 = 0.02;

const BINS_PER_OCTAVE: usize = 32;
/// The histogram spans 2^LOW_OCTAVE s (about 1 us) to 2^(LOW_OCTAVE + OCTAVES) s (4.5 hours);
/// intervals beyond it count in its end bins.
const LOW_OCTAVE: i32 = -20;
const OCTAVES: usize = 34;
const BINS: usize = OCTAVES * BINS_PER_OCTAVE;

/// The intervals' running sums and histogram (8.7 KB, whatever the record's length).
#[derive(Clone, Debug)]
pub struct OnsetIntervals {
    n: u64,
    mean: f64,
    m2: f64,
    bins: Box<[u64; BINS]>,
}

/// What [`OnsetIntervals`] found [s].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct IntervalStats {
    pub count: u64,
    pub mean_s: f64,
    /// Standard deviation (n - 1 in the denominator; 0 for one interval).
    pub sd_s: f64,
    /// The median to 1/32 octave (2.2 %): the geometric middle of its bin.
    pub median_s: f64,
    /// Intervals under [`SHORT_OF_MEDIAN`] of the median: counted from the bins wholly below a
    /// third of the median bin's lower edge, so an interval counted is surely short (one just
    /// under a third may be missed).
    pub short: u64,
    /// Intervals over [`LONG_OF_MEDIAN`] times the median (missed onsets, or a stick-slip that
    /// stops and starts again), counted from the bins wholly above three times the median bin's
    /// upper edge.
    pub long: u64,
}

impl IntervalStats {
    /// Whether the intervals far from their median (short or long) are too many for the
    /// contact estimate to be told ([`SPLIT_MIN_COUNT`], [`SPLIT_MIN_FRACTION`]).
    pub fn split(&self) -> bool {
        let far = self.short + self.long;
        far >= SPLIT_MIN_COUNT && far as f64 >= SPLIT_MIN_FRACTION * self.count as f64
    }
}

impl Default for OnsetIntervals {
    fn default() -> Self {
        OnsetIntervals { n: 0, mean: 0.0, m2: 0.0, bins: Box::new([0; BINS]) }
    }
}

fn bin_of(dt_s: f64) -> usize {
    let b = ((dt_s.log2() - f64::from(LOW_OCTAVE)) * BINS_PER_OCTAVE as f64).floor();
    if b.is_nan() || b < 0.0 {
        0
    } else {
        (b as usize).min(BINS - 1)
    }
}

/// The lower edge of bin `b` [s].
fn lower_edge(b: usize) -> f64 {
    (f64::from(LOW_OCTAVE) + b as f64 / BINS_PER_OCTAVE as f64).exp2()
}

impl OnsetIntervals {
    /// One interval [s] (> 0; others are left out).
    pub fn add(&mut self, dt_s: f64) {
        if !(dt_s > 0.0 && dt_s.is_finite()) {
            return;
        }
        self.n += 1;
        let d = dt_s - self.mean;
        self.mean += d / self.n as f64;
        self.m2 += d * (dt_s - self.mean);
        self.bins[bin_of(dt_s)] += 1;
    }

    pub fn stats(&self) -> IntervalStats {
        if self.n == 0 {
            return IntervalStats::default();
        }
        let half = self.n.div_ceil(2);
        let mut cum = 0;
        let mut median_bin = BINS - 1;
        for (b, &c) in self.bins.iter().enumerate() {
            cum += c;
            if cum >= half {
                median_bin = b;
                break;
            }
        }
        let median_s = (lower_edge(median_bin) * lower_edge(median_bin + 1)).sqrt();
        // bins whose upper edge is at most a third of the median bin's lower edge
        let limit = lower_edge(median_bin) * SHORT_OF_MEDIAN;
        let short = (0..median_bin).take_while(|&b| lower_edge(b + 1) <= limit).map(|b| self.bins[b]).sum();
        let above = lower_edge(median_bin + 1) * LONG_OF_MEDIAN;
        let long = (median_bin + 1..BINS).filter(|&b| lower_edge(b) >= above).map(|b| self.bins[b]).sum();
        IntervalStats {
            count: self.n,
            mean_s: self.mean,
            sd_s: if self.n > 1 { (self.m2 / (self.n - 1) as f64).sqrt() } else { 0.0 },
            median_s,
            short,
            long,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The median and the short count against a sort of the same intervals.
    #[test]
    fn median_and_short_intervals_agree_with_a_sort() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..5 {
            let mut all = vec![];
            let mut iv = OnsetIntervals::default();
            for i in 0..1001 {
                // cycles of 20 ms +- 5 %, every 7th split 3 ms + 17 ms (case 1), or random (case 2)
                let v: Vec<f64> = match case {
                    0 => vec![0.02 * (0.95 + 0.1 * next())],
                    1 if i % 7 == 0 => vec![0.003, 0.017],
                    1 => vec![0.02 * (0.95 + 0.1 * next())],
                    // a slow slip cut in two: 0.19 s and 1 s in turn, more of the latter
                    3 if i % 3 == 0 => vec![0.19],
                    3 => vec![1.0 + 0.01 * next()],
                    // ... more of the former
                    4 if i % 3 == 0 => vec![1.0 + 0.01 * next()],
                    4 => vec![0.19],
                    _ => vec![-0.01 * (1.0 - next()).ln()],
                };
                for d in v {
                    iv.add(d);
                    all.push(d);
                }
            }
            all.sort_by(f64::total_cmp);
            let median = all[all.len().div_ceil(2) - 1];
            let s = iv.stats();
            assert_eq!(s.count, all.len() as u64);
            assert!((s.median_s / median).log2().abs() <= 1.0 / 32.0, "case {case}: {} against {median}", s.median_s);
            let mean = all.iter().sum::<f64>() / all.len() as f64;
            let sd = (all.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (all.len() - 1) as f64).sqrt();
            assert!((s.mean_s - mean).abs() <= 1e-12 * mean && (s.sd_s - sd).abs() <= 1e-9 * sd, "case {case}");
            // counted short: surely under a third of the median, and at least those under
            // (1/3) 2^(-2/32) of it
            let under = |f: f64| all.iter().filter(|&&d| d < f * median).count() as u64;
            assert!(s.short <= under(SHORT_OF_MEDIAN) && s.short >= under(SHORT_OF_MEDIAN * (-2.0f64 / 32.0).exp2()), "case {case}: {}", s.short);
            let over = |f: f64| all.iter().filter(|&&d| d > f * median).count() as u64;
            assert!(s.long <= over(LONG_OF_MEDIAN) && s.long >= over(LONG_OF_MEDIAN * (2.0f64 / 32.0).exp2()), "case {case}: {}", s.long);
            match case {
                0 => assert!(s.short == 0 && s.long == 0 && !s.split()),
                3 => assert!(s.short == 334 && s.long == 0 && s.split(), "{} {}", s.short, s.long),
                4 => assert!(s.short == 0 && s.long == 334 && s.split(), "{} {}", s.short, s.long),
                1 => assert!(s.short == 143 && s.split(), "{}", s.short),
                _ => assert!(s.split() && (s.short as f64 / s.count as f64 - 0.206).abs() < 0.04, "{} of {}", s.short, s.count),
            }
        }
    }
}
