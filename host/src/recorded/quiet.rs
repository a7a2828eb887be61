//! The noise floor found anywhere in a recording: the contact thresholds come from the
//! record's own stick phases wherever they are, so a recording that starts inside the
//! stick-slip cycle (no clamped, band-still lead-in) needs no flag.
//!
//! In stick the pad moves with the band, so a_rel = pad_x - disc_x (+ the face term) is the
//! sensors' noise alone, as in the clamped phase; in slip it carries the slip's acceleration.
//! The search:
//! 1. a_rel (computed in f32 as the rig computes it) in blocks of [`BLOCK`] rows (1.25 ms at
//!    25.6 kHz, shorter than the shortest stick phases of Table 3.1's levels), each block's
//!    mean square about zero (a_rel's value in stick; the sensors are AC-coupled): a slip's
//!    plateau of nearly constant acceleration (Coulomb friction) is as still as stick within a
//!    block but not near zero, so it ranks loud;
//! 2. the blocks sorted by that mean square into a histogram of [`BINS_PER_DECADE`] bins per
//!    decade (bounded memory: each bin holds the sums of the rows of its blocks, not the
//!    rows), a bin of its own for blocks that are exactly zero;
//! 3. the reference v_ref: the [`QUIET_QUANTILE`] quantile of the blocks (robust to a few odd
//!    blocks; the stick phases of a stick-slip record are far more than 1 % of it); quiet
//!    blocks: mean square at most [`QUIET_FACTOR`] x v_ref (RMS at most twice; pure noise in
//!    32 samples exceeds that with probability 6e-4), to one bin (7.5 %);
//! 4. checks that what is called quiet is quiet: a block louder than
//!    [`super::analysis::QUIET_LOUD_FACTOR`] x v_ref exists (quiet against a signal); at least
//!    `MIN_FLOOR_SAMPLES` (256) quiet rows; and the quiet blocks lie at one level: the
//!    variance of all their rows about their common mean is at most [`LEVEL_FACTOR`] x their
//!    mean within-block variance (plus 4 quanta^2), so slow motion, a drifting offset or
//!    flat stretches at different levels (a clipped signal at its two rails) are not a floor;
//!    and at most [`TREND_SHARE`] of their variance within a block is a straight line through
//!    it (where that spread is two quanta or more), so the zero crossings of a signal that
//!    never sticks (a slow sine: each crossing a ramp, quieter than anything else in it) are
//!    not a floor either;
//! 5. the floor of each channel and of a_rel from the quiet rows (mean, sigma, peak-to-peak),
//!    and the quantum: the larger smallest nonzero step of pad_x and disc_x over the record.
//!
//! **Fill.** Loggers fill the time before their trigger (and sometimes after the stop) with
//! one value repeated on every channel, and some hold the last value through a dropout: no
//! sensor noise at all, so as a floor it would put the slip threshold at its minimum and call
//! the real stick phases' noise slip. The whole blocks of every run of identical rows (all
//! four channels) are held aside: when the floor found without them resolves its noise
//! (a_rel's sigma at least [`FILL_NOISE_QUANTA`] quanta, so that 32 identical rows on every
//! channel cannot be noise), they are left out of it and reported
//! ([`FloorOutcome::fill_lead`], `fill_trail` at the record's ends, `fill_inside` between);
//! else (a coarse converter, whose stick phases are runs of one count) they are quiet blocks
//! like any other. So are the runs inside the record where they hold more than half as many
//! rows as the quiet rows found without them ([`INSIDE_FILL_SHARE`]): runs that recur every cycle are its stick phases on a coarse
//! converter, and the floor found without them is the quietest of the slip's blocks (a
//! campaign: pad_x alone at the rig's 0.395 m/s^2 a count with 0.005 m/s^2 of noise, built at a
//! stick fraction of 0.2 and 120 Hz, read 0.147 at 105 Hz; the rig's own pull recordings
//! reduced to pad_x were "noisier than the signal"); the runs at the ends are then fill only
//! where the floor with the runs inside resolves its noise. A floor that only the fill makes is
//! no floor.
//!
//! Memory: 1,281 bins of 200 bytes (5 x 4 sums and a few counts), 256 KB, whatever the
//! record's length.

use stickslip_model::rig::noise_floor::{FloorReport, FLOOR_VALUES, MIN_FLOOR_SAMPLES};

use super::analysis::{FloorOutcome, QUIET_LOUD_FACTOR};

/// Rows per block.
pub const BLOCK: usize = 32;
/// Histogram bins per decade of block variance.
pub const BINS_PER_DECADE: usize = 32;
/// The histogram's range of block variance [log10 (m/s^2)^2].
const LOG_RANGE: (f64, f64) = (-30.0, 10.0);
const BINS: usize = ((LOG_RANGE.1 - LOG_RANGE.0) as usize) * BINS_PER_DECADE;
/// The quantile of the blocks' variances taken as the reference.
pub const QUIET_QUANTILE: f64 = 0.01;
/// A block is quiet with a variance up to this times the reference.
pub const QUIET_FACTOR: f64 = 4.0;
/// The quiet rows' variance about their common mean, at most this times their mean
/// within-block variance.
pub const LEVEL_FACTOR: f64 = 4.0;
/// The quiet blocks are smooth motion, not noise, where more than this share of their variance
/// within a block is a straight line through it (white noise: about 1/31; noise band-limited to
/// a quarter of the sampling rate: about 0.1).
pub const TREND_SHARE: f64 = 0.5;
/// A run of identical rows at the record's start or end is fill, not stick, where the floor
/// without it has a_rel's sigma of at least this many quanta (module documentation).
pub const FILL_NOISE_QUANTA: f64 = 4.0;
/// The runs of identical rows inside a record are a logger's dropouts only where the quiet rows
/// found without them are at least this many times their rows (module documentation).
pub const INSIDE_FILL_SHARE: u64 = 2;

#[derive(Clone, Copy)]
struct Bin {
    blocks: u64,
    n: u64,
    /// Sums of the values relative to the record's first row, and of their squares.
    sum: [f64; FLOOR_VALUES],
    sq: [f64; FLOOR_VALUES],
    min: [f64; FLOOR_VALUES],
    max: [f64; FLOOR_VALUES],
    /// Sum over its blocks of rows x the block's variance of a_rel.
    within: f64,
    /// Sum over its blocks of the part of that a straight line through the block explains
    /// (the least-squares line's sum of squares about the block's mean).
    trend: f64,
    t_first: f64,
    t_last: f64,
}

const EMPTY: Bin = Bin {
    blocks: 0,
    n: 0,
    sum: [0.0; FLOOR_VALUES],
    sq: [0.0; FLOOR_VALUES],
    min: [f64::INFINITY; FLOOR_VALUES],
    max: [f64::NEG_INFINITY; FLOOR_VALUES],
    within: 0.0,
    trend: 0.0,
    t_first: f64::INFINITY,
    t_last: f64::NEG_INFINITY,
};

/// The search, fed row by row (see the module documentation).
pub struct QuietSearch {
    face: f32,
    origin: Option<[f64; FLOOR_VALUES]>,
    block: [[f64; FLOOR_VALUES]; BLOCK],
    fill: usize,
    block_t: (f64, f64),
    /// bins[0]: blocks that do not change; bins[1..]: by log10 variance.
    bins: Vec<Bin>,
    prev: [f64; 2],
    step: [f64; 2],
    rows: u64,
    /// The run of identical rows (all four channels) the last row ends: its rows, its first
    /// and last row's time, and its value.
    run: (u64, f64, f64, [f64; 4]),
    /// The whole blocks of that run, held aside (identical blocks: one bin, summed) and their
    /// bin: until a row breaks the run they may be the record's trailing fill.
    pending: Option<(usize, Bin)>,
    /// Whether the run started at the record's first row.
    run_is_lead: bool,
    /// The leading fill's blocks and the time span of its rows.
    lead: Option<(usize, Bin, (f64, f64))>,
    /// The held blocks of the runs between (by bin), their runs, and the first run's span.
    inside: Vec<(usize, Bin)>,
    inside_runs: u64,
    inside_first: Option<(f64, f64)>,
}

impl QuietSearch {
    /// `face_coefficient`: the estimator's face term (0 without the face).
    pub fn new(face_coefficient: f32) -> Self {
        QuietSearch {
            face: face_coefficient,
            origin: None,
            block: [[0.0; FLOOR_VALUES]; BLOCK],
            fill: 0,
            block_t: (0.0, 0.0),
            bins: vec![EMPTY; BINS + 1],
            prev: [0.0; 2],
            step: [f64::INFINITY; 2],
            rows: 0,
            run: (0, 0.0, 0.0, [f64::NAN; 4]),
            pending: None,
            run_is_lead: true,
            lead: None,
            inside: Vec::new(),
            inside_runs: 0,
            inside_first: None,
        }
    }

    /// One row: time [s], disc_x, pad_x, pad_trail, pad_lead [m/s^2].
    pub fn push(&mut self, t: f64, a: &[f64; 4]) {
        let rel = (a[1] - a[0]) as f32 + self.face * (a[3] - a[2]) as f32;
        let v = [a[0], a[1], a[2], a[3], rel as f64];
        // the channels relative to the first row (the squares then do not cancel an offset);
        // a_rel as it is: it is ranked by its mean square about zero
        let v0 = [a[0], a[1], a[2], a[3], 0.0];
        if self.rows > 0 {
            for (k, c) in [1usize, 0].iter().enumerate() {
                let d = (a[*c] - self.prev[k]).abs();
                if d > 0.0 && d < self.step[k] {
                    self.step[k] = d;
                }
            }
        }
        self.prev = [a[1], a[0]];
        if self.rows > 0 && *a == self.run.3 {
            self.run.0 += 1;
            self.run.2 = t;
        } else {
            if self.rows > 0 {
                self.end_run();
            }
            self.run = (1, t, t, *a);
        }
        self.rows += 1;
        let o = *self.origin.get_or_insert(v0);
        if self.fill == 0 {
            self.block_t.0 = t;
        }
        self.block_t.1 = t;
        self.block[self.fill] = std::array::from_fn(|i| v[i] - o[i]);
        self.fill += 1;
        if self.fill == BLOCK {
            self.close_block();
        }
    }

    /// A row broke the run of identical rows: its held blocks are the leading fill (the run
    /// started the record) or a fill inside it.
    fn end_run(&mut self) {
        if let Some((k, held)) = self.pending.take() {
            if self.run_is_lead {
                self.lead = Some((k, held, (self.run.1, self.run.2)));
            } else {
                match self.inside.iter_mut().find(|(kk, _)| *kk == k) {
                    Some((_, b)) => merge(b, &held),
                    None => self.inside.push((k, held)),
                }
                self.inside_runs += 1;
                self.inside_first.get_or_insert((self.run.1, self.run.2));
            }
        }
        self.run_is_lead = false;
    }

    fn close_block(&mut self) {
        // a block inside the run of identical rows is held aside (maybe fill)
        let constant = self.run.0 >= BLOCK as u64;
        let b = &self.block[..self.fill];
        let n = b.len() as f64;
        let mean = b.iter().map(|r| r[4]).sum::<f64>() / n;
        let var = b.iter().map(|r| (r[4] - mean).powi(2)).sum::<f64>() / n;
        let ms = var + mean * mean;
        let k = if ms > 0.0 {
            let x = ((ms.log10() - LOG_RANGE.0) * BINS_PER_DECADE as f64).floor();
            1 + (x.max(0.0) as usize).min(BINS - 1)
        } else {
            0
        };
        let bin = if constant {
            match &mut self.pending {
                Some((_, held)) => held,
                None => &mut self.pending.insert((k, EMPTY)).1,
            }
        } else {
            &mut self.bins[k]
        };
        bin.blocks += 1;
        bin.n += b.len() as u64;
        bin.within += var * n;
        // the line's share: (sum (t - t_mean) x)^2 / sum (t - t_mean)^2 over the block's rows
        let t_mean = 0.5 * (n - 1.0);
        let sxt: f64 = b.iter().enumerate().map(|(t, r)| (t as f64 - t_mean) * (r[4] - mean)).sum();
        let stt = n * (n * n - 1.0) / 12.0;
        if stt > 0.0 {
            bin.trend += sxt * sxt / stt;
        }
        bin.t_first = bin.t_first.min(self.block_t.0);
        bin.t_last = bin.t_last.max(self.block_t.1);
        for r in b {
            for i in 0..FLOOR_VALUES {
                bin.sum[i] += r[i];
                bin.sq[i] += r[i] * r[i];
                bin.min[i] = bin.min[i].min(r[i]);
                bin.max[i] = bin.max[i].max(r[i]);
            }
        }
        self.fill = 0;
    }

    /// Rows taken.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// The floor, or why there is none (one clause, for the report); the record ends here
    /// (the run of identical rows it ends in may be fill: module documentation).
    pub fn finish(mut self) -> Result<FloorOutcome, String> {
        let (lead, trail) = if self.run_is_lead {
            // one run from the first row to the last: no signal to tell fill from
            if let Some((k, held)) = self.pending.take() {
                merge(&mut self.bins[k], &held);
            }
            (None, None)
        } else {
            (self.lead.take(), self.pending.take().map(|(k, held)| (k, held, (self.run.1, self.run.2))))
        };
        if lead.is_none() && trail.is_none() && self.inside.is_empty() {
            return self.floor(true);
        }
        let resolved = |f: &FloorOutcome| {
            let sigma = f.report.sigma_m_s2[4] as f64;
            sigma > 0.0 && sigma >= FILL_NOISE_QUANTA * f.quantum_m_s2
        };
        // (whether the runs are fill is decided on the floor without them whatever its blocks'
        // shape; a floor returned is tested for it)
        let without = self.floor(false);
        let without_failed = without.is_err();
        let inside_rows: u64 = self.inside.iter().map(|(_, b)| b.n).sum();
        if let Ok(mut f) = without {
            // the runs inside are a logger's dropouts where they are at most half as many rows
            // as the quiet rows found without them; runs that hold more are the record's stick
            // phases on a coarse converter (they recur every cycle), and the floor found without
            // them is the quietest of the slip's blocks (about as many rows as the runs: 2,560
            // quiet rows for 2,528 in runs on the campaign's record)
            if resolved(&f) && INSIDE_FILL_SHARE * inside_rows <= f.report.samples as u64 {
                self.floor(true)?;
                f.fill_lead = lead.map(|l| l.2);
                f.fill_trail = trail.map(|l| l.2);
                f.fill_inside = self.inside_first.map(|span| (self.inside_runs, inside_rows, span));
                return Ok(f);
            }
        }
        // the runs inside are stick: with them back, the runs at the ends are fill where the
        // floor then resolves its noise
        let inside_were_held = !self.inside.is_empty();
        for (k, held) in std::mem::take(&mut self.inside) {
            merge(&mut self.bins[k], &held);
        }
        if inside_were_held && (lead.is_some() || trail.is_some()) {
            if let Ok(mut f) = self.floor(true) {
                if resolved(&f) {
                    f.fill_lead = lead.map(|l| l.2);
                    f.fill_trail = trail.map(|l| l.2);
                    return Ok(f);
                }
            }
        }
        // the noise is not resolved (a coarse converter): runs of one value are its stick
        for (k, held, _) in lead.iter().chain(trail.iter()) {
            merge(&mut self.bins[*k], held);
        }
        match self.floor(true) {
            Ok(f) if f.report.sigma_m_s2[4] == 0.0 && without_failed => {
                let span = |s: &Option<(usize, Bin, (f64, f64))>| s.as_ref().map(|l| format!("t = {} to {} s", l.2 .0, l.2 .1));
                let inside = self.inside_first.map(|(a, b)| format!("{} between, the first t = {a} to {b} s", self.inside_runs));
                let spans: Vec<String> = [span(&lead), span(&trail), inside].into_iter().flatten().collect();
                Err(format!(
                    "the only quiet rows are runs of one value on every channel ({}: a logger's fill?), no noise to set the thresholds from",
                    spans.join(" and ")
                ))
            }
            other => other,
        }
    }

    /// The floor from the blocks in the histogram (`test_trend`: with the test that its blocks
    /// are not straight lines, [`TREND_SHARE`]).
    fn floor(&self, test_trend: bool) -> Result<FloorOutcome, String> {
        // a partial last block is left out: its variance is over fewer rows
        let total: u64 = self.bins.iter().map(|b| b.blocks).sum();
        if total == 0 {
            return Err(format!("fewer than {BLOCK} rows: no block of a_rel to call quiet"));
        }
        let target = ((QUIET_QUANTILE * total as f64).ceil() as u64).max(1);
        let mut seen = 0;
        let mut kr = 0;
        for (k, b) in self.bins.iter().enumerate() {
            seen += b.blocks;
            if seen >= target {
                kr = k;
                break;
            }
        }
        let upper = |k: usize| if k == 0 { 0.0 } else { 10f64.powf(LOG_RANGE.0 + k as f64 / BINS_PER_DECADE as f64) };
        let lower = |k: usize| if k == 0 { 0.0 } else { 10f64.powf(LOG_RANGE.0 + (k - 1) as f64 / BINS_PER_DECADE as f64) };
        let v_ref = upper(kr);
        let loudest = (0..self.bins.len()).rev().find(|&k| self.bins[k].blocks > 0).unwrap_or(0);
        if !(lower(loudest) > QUIET_LOUD_FACTOR * v_ref) || loudest == kr {
            return Err(format!(
                "no block of a_rel is {QUIET_LOUD_FACTOR} times louder (in mean square) than its quietest 1 %: no stick phase against a signal"
            ));
        }
        let last_quiet = if kr == 0 { 0 } else { (kr..self.bins.len()).take_while(|&k| upper(k) <= QUIET_FACTOR * v_ref * 1.000_001).last().unwrap_or(kr) };
        let mut q = EMPTY;
        for b in &self.bins[..=last_quiet] {
            if b.blocks == 0 {
                continue;
            }
            merge(&mut q, b);
        }
        if q.n < MIN_FLOOR_SAMPLES as u64 {
            return Err(format!("{} quiet rows of a_rel: the floor needs at least {MIN_FLOOR_SAMPLES}", q.n));
        }
        let n = q.n as f64;
        let mean: [f64; FLOOR_VALUES] = std::array::from_fn(|i| q.sum[i] / n);
        let var: [f64; FLOOR_VALUES] = std::array::from_fn(|i| (q.sq[i] / n - mean[i] * mean[i]).max(0.0));
        let within = q.within / n;
        let quantum = [self.step[0], self.step[1]].into_iter().filter(|v| v.is_finite()).fold(0.0, f64::max);
        if !(var[4] <= LEVEL_FACTOR * within + 4.0 * quantum * quantum) {
            return Err(format!(
                "the quietest blocks of a_rel do not lie at one level (their variance about their common mean is {:.4} times their variance within a block): slow motion or a drifting offset, not stick",
                var[4] / within.max(f64::MIN_POSITIVE)
            ));
        }
        // noise spreads over a block's 31 degrees of freedom (a line takes about 1/31 of white
        // noise, a few times that of noise band-limited well below the sampling rate); smooth
        // motion through zero (the crossings of a slow oscillation, the quietest stretches of a
        // signal that never sticks) is a line
        // (tested where the quiet rows' spread within a block is resolved, two quanta and
        // more: on a coarse converter stick is runs of one count, and the few quiet blocks
        // with any spread are the stick's edges, a step of a count or two)
        let trend = q.trend / q.within.max(f64::MIN_POSITIVE);
        if test_trend && within > 4.0 * quantum * quantum && !(trend <= TREND_SHARE) {
            return Err(format!(
                "the quietest blocks of a_rel are straight lines ({:.0} % of their variance within a block is a trend through it): smooth motion through zero, not stick's noise",
                100.0 * trend
            ));
        }
        let o = self.origin.expect("rows were taken");
        let report = FloorReport {
            samples: q.n.min(u32::MAX as u64) as u32,
            mean_m_s2: std::array::from_fn(|i| (mean[i] + o[i]) as f32),
            sigma_m_s2: std::array::from_fn(|i| var[i].sqrt() as f32),
            pp_m_s2: std::array::from_fn(|i| (q.max[i] - q.min[i]) as f32),
        };
        Ok(FloorOutcome {
            t_from: q.t_first,
            t_to: q.t_last,
            auto: true,
            report,
            quantum_m_s2: quantum,
            quiet_blocks: q.blocks,
            fill_lead: None,
            fill_trail: None,
            fill_inside: None,
        })
    }

    /// Ends a search over the first rows of a record that goes on (standard input's preview):
    /// [`Self::finish`] with the run the rows end in ended as a row that breaks it would end
    /// it (inside the record, or its leading fill), not taken for trailing fill.
    pub fn finish_preview(mut self) -> Result<FloorOutcome, String> {
        if self.rows > 0 {
            self.end_run();
        }
        self.finish()
    }
}

/// Adds the blocks of `from` to `into`.
fn merge(into: &mut Bin, from: &Bin) {
    into.blocks += from.blocks;
    into.n += from.n;
    into.within += from.within;
    into.trend += from.trend;
    into.t_first = into.t_first.min(from.t_first);
    into.t_last = into.t_last.max(from.t_last);
    for i in 0..FLOOR_VALUES {
        into.sum[i] += from.sum[i];
        into.sq[i] += from.sq[i];
        into.min[i] = into.min[i].min(from.min[i]);
        into.max[i] = into.max[i].max(from.max[i]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic uniform number in [-1, 1) (xorshift).
    fn noise(state: &mut u32) -> f64 {
        *state ^= *state << 13;
        *state ^= *state >> 17;
        *state ^= *state << 5;
        (*state as f64 / u32::MAX as f64) * 2.0 - 1.0
    }

    /// Stick phases of 3 ms (noise sigma s) between slips (a 300 Hz burst of 1 m/s^2): the
    /// floor's sigma is the noise's within 5 %, from the stick rows only.
    #[test]
    fn stick_phases_anywhere_give_the_noise() {
        let fs = 25_600.0;
        let s = 0.01;
        let mut st = 7u32;
        let mut q = QuietSearch::new(0.0);
        for i in 0..(fs as usize) {
            let t = i as f64 / fs;
            let phase = (t * 100.0).fract(); // 100 Hz cycle: 30 % stick
            let slip = if phase >= 0.3 { (2.0 * std::f64::consts::PI * 300.0 * t).sin() } else { 0.0 };
            // uniform noise of sigma s: amplitude s sqrt(3)
            let pad = slip + s * 3f64.sqrt() * noise(&mut st);
            q.push(t, &[0.0, pad, 0.0, 0.0]);
        }
        let f = q.finish().unwrap();
        let sigma = f.report.sigma_m_s2[4] as f64;
        assert!((sigma / s - 1.0).abs() < 0.05, "sigma {sigma}");
        assert!(f.report.samples > 2000 && f.report.samples < 9000, "{}", f.report.samples);
    }

    #[test]
    fn steady_sines_and_a_clipped_signal_have_no_floor() {
        let mut q = QuietSearch::new(0.0);
        for i in 0..20_000 {
            let t = i as f64 / 25_600.0;
            q.push(t, &[0.0, (2.0 * std::f64::consts::PI * 200.0 * t).sin(), 0.0, 0.0]);
        }
        assert!(q.finish().is_err());
        // flat at two rails: quiet blocks at two levels
        let mut q = QuietSearch::new(0.0);
        for i in 0..20_000 {
            let v = if (i / 640) % 2 == 0 { 700.0 } else { -700.0 };
            let v = if i % 640 < 32 { v * (i % 640) as f64 / 32.0 } else { v };
            q.push(i as f64 / 25_600.0, &[0.0, v, 0.0, 0.0]);
        }
        assert!(q.finish().is_err());
    }
}
