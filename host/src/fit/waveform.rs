//! The time-domain cost of a fit to recordings of a 1-DOF scene (rotation off, no band: the
//! mass on a belt at constant speed, N constant), by multiple shooting over the recording's
//! stick-slip cycles.
//!
//! **Why.** A whole record's statistics jump wherever the kind of cycle changes (docs/fit.md);
//! a single run compared with the samples over 3 s is no better: a period error of 0.1 % puts
//! the model a third of a cycle off by the end, and the cost has a local minimum at every
//! whole number of cycles of drift. Multiple shooting (Bock 1983; Timmer and Voss for
//! oscillators) restarts the model at states the data pin down, so a parameter error shows as
//! the error of one cycle, not of the record.
//!
//! **The known states.** In the 1-DOF model every slip starts from the same state: the pad
//! moves with the belt (x' = V) and breaks away where the spring and damper force reaches the
//! static friction, x_s = (mu_s N - c_x V) / k_g. So after the first breakaway the motion is
//! periodic: stick for T_stick = (x_s - x_r) / V from the re-stick position x_r, then the slip,
//! the same each cycle. One slip is integrated per evaluation (below); the model's cycle is
//! then placed on each of the recording's cycles.
//!
//! **Segments.** The recording's re-sticks (the first sample of a quiet run after a slip: the
//! pad's acceleration falls from the slip's to 0) cut it into segments, each ending at a
//! re-stick. In segment k the model's cycle is placed so that its re-stick falls at the
//! recording's plus a shift delta_k, |delta_k| <= [`SHIFT_SAMPLES`] samples, chosen to fit
//! that segment best (a 1-D golden-section search: the segment's start state is the known
//! breakaway state, its start time the one free quantity per segment, solved for inside each
//! evaluation). The samples where the model's or the recording's re-stick may fall, and with
//! Coulomb friction its breakaways (a jump of the friction there too), are left out
//! ([`MASK_SAMPLES`] either side): a re-stick a sample late would be a residual of the whole
//! friction jump, and the cost would jump with it. The cost is then smooth in the parameters.
//!
//! **The friction level.** The slip's shape depends only on the drop mu_s - mu_k, v_s, c_x,
//! k_g and m; the level comes from the first breakaway, t_1 = x_s / V after the band's start
//! (t = 0 of the recording). One more residual compares the model's first re-stick t_1 +
//! T_slip with the recording's (its re-stick sample plus delta_0), in units of the timing's
//! standard error sigma / sqrt(sum of the slip's squared jerk over its samples) (the Fisher
//! information of a time shift of the first segment).
//!
//! **The model side.** The slip is integrated by classical RK4 on the sliding velocity at a
//! step of at most 1/20 of the slip's fastest time scale (the Stribeck slope's
//! m v_s / (N (mu_s - mu_k))) and 1/50 of a period, and 1/8 of the sampling interval where
//! [`STEP_BUDGET`] steps over 20 periods allow it; its end (the sliding
//! velocity back at 0) is located inside the step on the cubic Hermite interpolant, so the
//! model's events are placed far inside a sample; between steps the acceleration is
//! interpolated by Catmull-Rom splines.
//!
//! **Residuals.** (recorded pad_x - model pad_x) / sigma_0 at every sample not left out, with
//! sigma_0 the recording's noise estimated before the fit from its second differences (their
//! median absolute deviation / sqrt(6): robust against the slips); cost = sum r^2 / 2 = chi^2 / 2.

use stickslip_model::coefficients::Coefficients;
use stickslip_model::{FrictionLaw, Scene};

use crate::error::{HostError, Result};
use crate::recorded::{source, ReadOptions};

/// The shift of the model's cycle on a segment's re-stick: at most this many samples.
pub const SHIFT_SAMPLES: usize = 2;
/// Samples left out on either side of a recorded re-stick (and, with Coulomb friction, of a
/// recorded breakaway): the shift's range and one sample more.
pub const MASK_SAMPLES: usize = SHIFT_SAMPLES + 1;
/// A quiet sample is within this many sigma_0 of zero.
const QUIET_SIGMA: f64 = 4.0;
/// A slip holds a sample beyond this many sigma_0.
const LOUD_SIGMA: f64 = 8.0;
/// A stick is a quiet run of at least this many samples.
const QUIET_RUN: usize = 8;
/// A quiet run whose trend's t statistic is above this is a slip's zero crossing, not a stick
/// ([`Trace::trend_t`]).
const TREND_T: f64 = 3.5;
/// The trend is measured over at most this many samples of a quiet run.
const TREND_SAMPLES: usize = 4096;
/// A slip still going after this many periods of the pad on its spring counts as steady
/// sliding (no cycle to place).
const MAX_SLIP_PERIODS: f64 = 20.0;
/// Most RK4 steps one slip may take: beyond, the point is rejected (in practice only points of the global screen with v_s far below the
/// truth's).
const STEP_BUDGET: usize = 400_000;
/// pad_x's column in a recording's row.
const PAD_X: usize = 1;

/// A recording's pad_x series and its cycles.
#[derive(Clone, Debug)]
pub struct Trace {
    pub case: String,
    pub path: String,
    /// Index of its case in the problem's cases.
    pub case_index: usize,
    pub t: Vec<f64>,
    pub a: Vec<f64>,
    /// Sampling interval [s].
    pub dt: f64,
    /// sigma_0: the noise from the second differences [m/s^2].
    pub sigma0: f64,
    /// The noise of the recording's quantisation, q / sqrt(12) for its smallest step q between
    /// samples [m/s^2]: the floor of every noise estimate (a converter's counts in a stick
    /// phase are often all equal: their spread, 0, is not the noise).
    pub noise_floor: f64,
    /// Index of the first quiet sample after each slip (the recorded re-sticks).
    pub resticks: Vec<usize>,
    /// Index of the first loud sample of each slip (the recorded breakaways).
    pub breakaways: Vec<usize>,
    /// Samples left out.
    pub masked: Vec<bool>,
}

/// Whether the scene is the 1-DOF model this cost is written for.
pub fn applies(scene: &Scene) -> bool {
    !scene.rotation && !scene.band
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        return f64::NAN;
    }
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// The noise of `a`'s quantisation, q / sqrt(12), where q is the smallest step between
/// consecutive samples (above 1e-9 of the largest |sample|: the rounding of a calibration's
/// scale is not a step); `None` when no sample differs from its neighbour. A recording through
/// a converter has steps of one count and more (q the count); one without quantisation has a
/// q far below its noise, and the floor is then negligible against the second differences'
/// estimate.
pub fn quantisation_noise(a: &[f64]) -> Option<f64> {
    let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let q = a.windows(2).map(|w| (w[1] - w[0]).abs()).filter(|d| *d > 1e-9 * scale).fold(f64::INFINITY, f64::min);
    q.is_finite().then(|| q / 12f64.sqrt())
}

/// Reads pad_x of the recording at `path` (any format `analyze` reads, its channels mapped by
/// `opts` as there) and finds its cycles. The samples must be evenly spaced (a gap or a jitter
/// over 1 % of the interval is refused: the model is placed on the samples' times).
pub fn read_trace(case: &str, case_index: usize, path: &str, coulomb: bool, opts: &ReadOptions) -> Result<Trace> {
    let mut rows = source::Recording::open(path, &opts.channels)?;
    let (mut t, mut a) = (Vec::new(), Vec::new());
    while let Some(row) = rows.next_row()? {
        t.push(row.t);
        a.push(row.accel[PAD_X]);
    }
    if t.len() < 64 {
        return Err(HostError::Input(format!("{path}: {} rows: too short for the time-domain cost", t.len())));
    }
    let dt = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    if !(dt.is_finite() && dt > 0.0) {
        return Err(HostError::Input(format!("{path}: the time axis does not increase: no sampling interval for the time-domain cost")));
    }
    if let Some(i) = (1..t.len()).find(|&i| ((t[i] - t[i - 1]) / dt - 1.0).abs() > 0.01) {
        return Err(HostError::Input(format!(
            "{path}: row {} of the samples: an interval of {:.6e} s where the mean is {dt:.6e} s: the time-domain cost needs evenly spaced samples (--cost statistics reads gaps)",
            i + 1,
            t[i] - t[i - 1]
        )));
    }
    let mut d2: Vec<f64> = a.windows(3).map(|w| (w[2] - 2.0 * w[1] + w[0]).abs()).collect();
    let floor = quantisation_noise(&a).ok_or_else(|| {
        HostError::Input(format!("{path}: pad_x is constant over its {} rows: nothing for the time-domain cost to fit", a.len()))
    })?;
    let sigma0 = (1.4826 * median(&mut d2) / 6f64.sqrt()).max(floor);
    let mut tr = Trace {
        case: case.into(),
        path: path.into(),
        case_index,
        t,
        a,
        dt,
        sigma0,
        noise_floor: floor,
        resticks: Vec::new(),
        breakaways: Vec::new(),
        masked: Vec::new(),
    };
    tr.find_cycles(coulomb);
    Ok(tr)
}

impl Trace {
    /// The recorded re-sticks and breakaways, and the samples left out around them.
    fn find_cycles(&mut self, coulomb: bool) {
        let n = self.a.len();
        let quiet: Vec<bool> = self.a.iter().map(|x| x.abs() <= QUIET_SIGMA * self.sigma0).collect();
        let loud: Vec<bool> = self.a.iter().map(|x| x.abs() > LOUD_SIGMA * self.sigma0).collect();
        let mut in_slip = false;
        let mut i = 0;
        while i < n {
            if !in_slip {
                if loud[i] {
                    in_slip = true;
                    // the slip's first sample: back to the end of the quiet run before it
                    let mut b = i;
                    while b > 0 && !quiet[b - 1] {
                        b -= 1;
                    }
                    self.breakaways.push(b);
                }
                i += 1;
            } else if quiet[i] && i + QUIET_RUN <= n && quiet[i..i + QUIET_RUN].iter().all(|q| *q) {
                // a quiet run: a stick (flat at 0) or the slip's acceleration passing through
                // zero slowly (a slow cycle's slip can stay inside the quiet band for many
                // samples); the crossing shows as a trend up to the next loud sample, the
                // stick does not
                let span = loud[i..].iter().take_while(|l| !**l).count();
                if self.trend_t(i, span) > TREND_T {
                    i += quiet[i..].iter().take_while(|q| **q).count();
                    continue;
                }
                self.resticks.push(i);
                in_slip = false;
                i += QUIET_RUN;
            } else {
                i += 1;
            }
        }
        self.masked = vec![false; n];
        let mut mask_at = |c: usize| {
            for j in c.saturating_sub(MASK_SAMPLES + 1)..(c + MASK_SAMPLES + 1).min(n) {
                self.masked[j] = true;
            }
        };
        for &r in &self.resticks {
            mask_at(r);
        }
        if coulomb {
            for &b in &self.breakaways {
                mask_at(b);
            }
        }
    }

    /// The t statistic of a linear trend over the first three quarters of the `run` samples
    /// from `i` up to the next loud one (at least [`QUIET_RUN`], at most [`TREND_SAMPLES`]):
    /// the slope's least-squares estimate over its standard error sigma_0 sqrt(12 / (n (n^2 -
    /// 1))). The last quarter is left out: a stick's end may hold the start of the next slip.
    /// A zero crossing of slope s per sample from a quiet sample to the loud band (8 sigma_0)
    /// spans L >= 4 sigma_0 / s samples and gives t of about 0.75 sqrt(L) or more (6 at
    /// L = 64); a stick's noise gives |t| > 3.5 in one run of about 2000.
    fn trend_t(&self, i: usize, run: usize) -> f64 {
        let n = (3 * run / 4).clamp(QUIET_RUN.min(run), TREND_SAMPLES);
        if n < 3 {
            return 0.0;
        }
        let xm = 0.5 * (n - 1) as f64;
        let am = self.a[i..i + n].iter().sum::<f64>() / n as f64;
        let sxy: f64 = self.a[i..i + n].iter().enumerate().map(|(j, a)| (j as f64 - xm) * (a - am)).sum();
        let nf = n as f64;
        let sxx = nf * (nf * nf - 1.0) / 12.0;
        let slope = sxy / sxx;
        let se = self.sigma0 / sxx.sqrt();
        if se > 0.0 {
            (slope / se).abs()
        } else if slope != 0.0 {
            f64::INFINITY
        } else {
            0.0
        }
    }

    /// Residuals: the samples' count plus the first re-stick's timing (the features' count
    /// with `features`).
    pub fn residual_count(&self, features: bool) -> usize {
        if features {
            5
        } else {
            self.a.len() + 1
        }
    }
}

/// One slip of the 1-DOF model from its breakaway state, integrated finely.
#[derive(Clone, Debug)]
pub struct Cycle {
    /// Step of the stored slip [s].
    pub h: f64,
    /// pad_x at the steps 0, h, 2h, ... up to the slip's end (and one step past it).
    pub acc: Vec<f64>,
    /// Duration of the slip [s].
    pub t_slip: f64,
    /// Duration of the stick that follows [s].
    pub t_stick: f64,
    /// The first breakaway after the band's start [s].
    pub t_first: f64,
}

impl Cycle {
    pub fn period(&self) -> f64 {
        self.t_slip + self.t_stick
    }

    /// pad_x tau after a breakaway (0 <= tau < t_slip), by Catmull-Rom interpolation.
    fn slip_acc(&self, tau: f64) -> f64 {
        let x = tau / self.h;
        let last = self.acc.len() - 1;
        let j = (x.floor().max(0.0) as usize).min(last.saturating_sub(1));
        let f = x - j as f64;
        let p = |k: isize| self.acc[(j as isize + k).clamp(0, last as isize) as usize];
        let (p0, p1, p2, p3) = (p(-1), p(0), p(1), p(2));
        0.5 * (2.0 * p1 + (-p0 + p2) * f + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * f * f + (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * f * f * f)
    }

    /// pad_x at time t of a periodic cycle whose re-stick is at `t_restick` (any cycle).
    pub fn acc_after_restick(&self, t: f64, t_restick: f64) -> f64 {
        let tc = self.period();
        let phase = (t - t_restick).rem_euclid(tc);
        if phase < self.t_stick {
            0.0
        } else {
            self.slip_acc(phase - self.t_stick)
        }
    }

    /// pad_x at time t of the run from the band's start (stick to t_first, then the cycles).
    pub fn acc_absolute(&self, t: f64) -> f64 {
        if t < self.t_first {
            0.0
        } else {
            self.acc_after_restick(t, self.t_first - self.t_stick)
        }
    }
}

/// The 1-DOF slip of `scene` from its breakaway, sampled at interval `dt`; an error where the
/// slip does not end inside `max_s` seconds (steady sliding) or reverses (the pad faster than
/// the belt: not written here).
pub fn cycle(scene: &Scene, dt: f64, max_s: f64) -> std::result::Result<Cycle, String> {
    let co = Coefficients::of(scene);
    let (m, k, c, v) = (scene.m, scene.k_g, scene.c_x, scene.v);
    let n = co.n0;
    let (mu_s, mu_k) = (scene.mu_s, scene.mu_k);
    let stribeck = scene.friction == FrictionLaw::Stribeck;
    let (vs, ex) = (scene.v_s, scene.stribeck_exponent);
    let mu = |speed: f64| if stribeck { mu_k + (mu_s - mu_k) * (-(speed / vs).powf(ex)).exp() } else { mu_k };
    let x_s = (mu_s * n - c * v) / k;
    // sliding velocity w = x' - V < 0 in the slip (friction +mu N)
    let acc = |x: f64, w: f64| (-k * x - c * (w + v) + mu(w.abs()) * n) / m;
    let omega = (k / m).sqrt();
    // the step accuracy asks for: 1/50 of a period, 1/20 of the Stribeck slope's time scale
    let mut h_acc = 0.02 * std::f64::consts::TAU / omega;
    if stribeck && mu_s > mu_k {
        h_acc = h_acc.min(0.05 * m * vs / (n * (mu_s - mu_k) * ex.max(1.0)));
    }
    // a slip lasts about one period of the pad on its spring; one still going after
    // MAX_SLIP_PERIODS is steady sliding (decaying toward it)
    let max_s = max_s.min(MAX_SLIP_PERIODS * std::f64::consts::TAU / omega);
    // 1/8 of a sample where the budget allows, never coarser than accuracy asks
    let mut h = h_acc.min(dt / 8.0);
    if max_s / h > STEP_BUDGET as f64 {
        h = max_s / STEP_BUDGET as f64;
    }
    if h > h_acc {
        return Err(format!("the slip would need steps of {h_acc:.3e} s over {max_s:.3e} s (a Stribeck slope too steep for this cost)"));
    }
    let steps_max = (max_s / h).ceil() as usize + 2;
    let (mut x, mut w) = (x_s, 0.0f64);
    let mut out = vec![acc(x, w)];
    let arm = -1e-9 * v;
    let mut armed = false;
    for step in 0..steps_max {
        let f = |x: f64, w: f64| (w + v, acc(x, w));
        let (k1x, k1w) = f(x, w);
        let (k2x, k2w) = f(x + 0.5 * h * k1x, w + 0.5 * h * k1w);
        let (k3x, k3w) = f(x + 0.5 * h * k2x, w + 0.5 * h * k2w);
        let (k4x, k4w) = f(x + h * k3x, w + h * k3w);
        let (x1, w1) = (x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x), w + h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w));
        let a1 = acc(x1, w1);
        if armed && w1 >= 0.0 {
            // the end inside the step: root of the cubic Hermite interpolant of w
            let (a0, w0) = (out[step], w);
            let herm = |s: f64| {
                let (s2, s3) = (s * s, s * s * s);
                (2.0 * s3 - 3.0 * s2 + 1.0) * w0 + (s3 - 2.0 * s2 + s) * h * a0 + (-2.0 * s3 + 3.0 * s2) * w1 + (s3 - s2) * h * a1
            };
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if herm(mid) < 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let s = 0.5 * (lo + hi);
            let t_slip = (step as f64 + s) * h;
            let x_r = x + s * (x1 - x);
            // re-stick holds if the force needed is within static friction
            let f_req = k * x_r + c * v;
            if f_req.abs() > mu_s * n * (1.0 + 1e-9) {
                return Err(format!("the slip reverses at its end (|F_req| {:.4e} N > mu_s N {:.4e} N)", f_req.abs(), mu_s * n));
            }
            out.push(a1);
            let t_stick = ((x_s - x_r) / v).max(0.0);
            return Ok(Cycle { h, acc: out, t_slip, t_stick, t_first: x_s / v });
        }
        if w1 < arm {
            armed = true;
        }
        x = x1;
        w = w1;
        out.push(a1);
        if !(x.is_finite() && w.is_finite()) {
            return Err("the slip diverges".into());
        }
    }
    Err(format!("no re-stick within {max_s:.4} s of the breakaway (steady sliding)"))
}

/// The model's pad_x at t in a segment whose re-stick is placed at `t_r`: the periodic cycle,
/// and in the first segment nothing before its breakaway (the stick from the band's start).
fn segment_acc(cy: &Cycle, t: f64, t_r: f64, first: bool) -> f64 {
    if first && t < t_r - cy.t_slip {
        0.0
    } else {
        cy.acc_after_restick(t, t_r)
    }
}

/// Sum of squared residuals of the samples in `range` with the model's cycle on the re-stick
/// at `t_r`.
fn segment_sse(tr: &Trace, cy: &Cycle, range: std::ops::Range<usize>, t_r: f64, first: bool, sigma: f64) -> f64 {
    range
        .filter(|&i| !tr.masked[i])
        .map(|i| {
            let r = (tr.a[i] - segment_acc(cy, tr.t[i], t_r, first)) / sigma;
            r * r
        })
        .sum()
}

/// The residuals of `tr` against the model `scene` (see the module documentation); also the
/// model's pad_x at the samples (with each segment's shift) when `model_out` is given.
pub fn residuals(tr: &Trace, scene: &Scene, model_out: Option<&mut Vec<f64>>) -> std::result::Result<Vec<f64>, String> {
    let n = tr.a.len();
    let sigma = tr.sigma0;
    let t_end = tr.t[n - 1];
    let cy = cycle(scene, tr.dt, t_end.max(tr.dt * 64.0))?;
    let mut model = vec![0.0; n];
    let mut r = vec![0.0; n + 1];
    if tr.resticks.is_empty() {
        // no cycle to place (in the recording or the model in its span): the run from the
        // band's start compared as it is
        for i in 0..n {
            model[i] = cy.acc_absolute(tr.t[i]);
            if !tr.masked[i] {
                r[i] = (tr.a[i] - model[i]) / sigma;
            }
        }
        // the timing residual: the model's first re-stick against the recording's, in samples
        if let Some(&r0) = tr.resticks.first() {
            r[n] = (cy.t_first + cy.t_slip - tr.t[r0]) / tr.dt;
        }
    } else {
        let shift = SHIFT_SAMPLES as f64 * tr.dt;
        let mut start = 0usize;
        let mut shifts = Vec::with_capacity(tr.resticks.len());
        for (k, &rk) in tr.resticks.iter().enumerate() {
            let end = if k + 1 == tr.resticks.len() { n } else { rk + MASK_SAMPLES + 1 };
            let end = end.min(n);
            // the recorded re-stick: between the last loud sample and the first quiet one
            let t_rec = tr.t[rk] - 0.5 * tr.dt;
            // the shift is chosen on the slip that ends at this re-stick (the samples it can
            // cover): the rest of the segment is stick in the model near the optimum
            let idx = |t: f64| (((t - tr.t[0]) / tr.dt).floor().max(0.0) as usize).min(n);
            let lo_i = idx(t_rec - shift - cy.t_slip - tr.dt).max(start).min(end);
            let hi_i = (idx(t_rec + shift + tr.dt) + 1).min(end).max(lo_i);
            let f = |d: f64| segment_sse(tr, &cy, lo_i..hi_i, t_rec + d, k == 0, sigma);
            let (mut a, mut b) = (-shift, shift);
            let g = 0.5 * (5f64.sqrt() - 1.0);
            let (mut c1, mut c2) = (b - g * (b - a), a + g * (b - a));
            let (mut f1, mut f2) = (f(c1), f(c2));
            for _ in 0..24 {
                if f1 <= f2 {
                    b = c2;
                    c2 = c1;
                    f2 = f1;
                    c1 = b - g * (b - a);
                    f1 = f(c1);
                } else {
                    a = c1;
                    c1 = c2;
                    f1 = f2;
                    c2 = a + g * (b - a);
                    f2 = f(c2);
                }
            }
            let d = 0.5 * (a + b);
            shifts.push(d);
            for i in start..end {
                model[i] = segment_acc(&cy, tr.t[i], t_rec + d, k == 0);
                if !tr.masked[i] {
                    r[i] = (tr.a[i] - model[i]) / sigma;
                }
            }
            start = end;
        }
        // the level: the model's first re-stick from the band's start against the recording's
        // (placed by the first segment's shift), over the timing's standard error
        let t0_rec = tr.t[tr.resticks[0]] - 0.5 * tr.dt + shifts[0];
        let jerk2: f64 = (0..tr.resticks[0].min(n))
            .filter(|&i| !tr.masked[i])
            .map(|i| {
                let tt = tr.t[i];
                let d = (segment_acc(&cy, tt + 0.5 * tr.dt, t0_rec, true) - segment_acc(&cy, tt - 0.5 * tr.dt, t0_rec, true)) / tr.dt;
                d * d
            })
            .sum();
        let sd_t = if jerk2 > 0.0 { sigma / jerk2.sqrt() } else { tr.dt };
        r[n] = (cy.t_first + cy.t_slip - t0_rec) / sd_t.max(1e-3 * tr.dt);
    }
    if let Some(out) = model_out {
        *out = model;
    }
    Ok(r)
}

/// Scale of the features' log ratios in the global stage's cost: 1 %.
pub const FEATURE_SCALE: f64 = 0.01;

/// Sampling phases over which the model's slip extremes are taken ([`model_features`]).
const FEATURE_PHASES: usize = 8;

/// A cycle's features: the first re-stick after the band's start [s], the period [s], the
/// slip's largest and most negative pad_x [m/s^2] and its mean square integral over a cycle
/// [m^2/s^3]. The extremes as the recording's samples see them: a slip's pad_x can peak
/// sharply (with falling friction it steepens over the last samples before a re-stick), and a
/// sample interval `dt` misses most of such a peak; the recording's extreme is the median over
/// its cycles, each sampled at its own phase, so the model's is the median over
/// [`FEATURE_PHASES`] phases of the slip sampled at `dt`.
fn model_features(cy: &Cycle, dt: f64) -> [f64; 5] {
    let mut sq = 0.0;
    let steps = (cy.t_slip / cy.h).floor() as usize;
    for a in cy.acc.iter().take(steps + 1) {
        sq += a * a * cy.h;
    }
    let (mut his, mut los) = (Vec::with_capacity(FEATURE_PHASES), Vec::with_capacity(FEATURE_PHASES));
    for k in 0..FEATURE_PHASES {
        let (mut hi, mut lo) = (0.0f64, 0.0f64);
        let mut tau = (k as f64 + 0.5) / FEATURE_PHASES as f64 * dt;
        while tau < cy.t_slip {
            let a = cy.slip_acc(tau);
            hi = hi.max(a);
            lo = lo.min(a);
            tau += dt;
        }
        his.push(hi);
        los.push(lo);
    }
    [cy.t_first + cy.t_slip, cy.period(), median(&mut his), -median(&mut los), sq]
}

impl Trace {
    /// The recording's features as [`model_features`] (the extremes and the integral the
    /// medians over its whole cycles; the integral less the noise's sigma_0^2 per sample);
    /// `None` with fewer than two re-sticks.
    pub fn features(&self) -> Option<[f64; 5]> {
        if self.resticks.len() < 2 {
            return None;
        }
        let r = &self.resticks;
        let period = (self.t[r[r.len() - 1]] - self.t[r[0]]) / (r.len() - 1) as f64;
        let (mut his, mut los, mut sqs) = (Vec::new(), Vec::new(), Vec::new());
        for w in r.windows(2) {
            let seg = &self.a[w[0]..w[1]];
            his.push(seg.iter().copied().fold(f64::NEG_INFINITY, f64::max));
            los.push(-seg.iter().copied().fold(f64::INFINITY, f64::min));
            sqs.push(seg.iter().map(|a| (a * a - self.sigma0 * self.sigma0) * self.dt).sum::<f64>());
        }
        Some([self.t[r[0]] - 0.5 * self.dt, period, median(&mut his), median(&mut los), median(&mut sqs)])
    }
}

/// The global stage's residuals: ln(model / recorded) of each feature over [`FEATURE_SCALE`]
/// (a feature at or below 0 on either side counts as a ratio of e^7). Smooth and cheap (one
/// slip per evaluation): it finds the basin, the samples then pin the optimum.
pub fn feature_residuals(tr: &Trace, scene: &Scene) -> std::result::Result<Vec<f64>, String> {
    let data = tr.features().ok_or_else(|| format!("{}: fewer than two re-sticks: no features", tr.path))?;
    let cy = cycle(scene, tr.dt, tr.t[tr.t.len() - 1].max(tr.dt * 64.0))?;
    let m = model_features(&cy, tr.dt);
    Ok(m.iter()
        .zip(&data)
        .map(|(x, d)| if *x > 0.0 && *d > 0.0 { (x / d).ln() / FEATURE_SCALE } else { 7.0 / FEATURE_SCALE })
        .collect())
}

/// The recording's noise from the samples where the fitted model is in stick (pad_x exactly 0,
/// not left out), at least its quantisation's ([`Trace::noise_floor`]), and their count: the
/// honest yardstick of the fit's residuals.
pub fn stick_noise(tr: &Trace, model: &[f64]) -> (f64, usize) {
    let v: Vec<f64> = (0..tr.a.len()).filter(|&i| !tr.masked[i] && model[i] == 0.0).map(|i| tr.a[i]).collect();
    if v.len() < 16 {
        return (tr.sigma0, v.len());
    }
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt();
    (sd.max(tr.noise_floor), v.len())
}
