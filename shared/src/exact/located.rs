//! A step whose guard fires or may crest, with its transitions located by root-finding on the
//! exact flow's Taylor polynomial instead of by binary lifting: for runs that want no state
//! between transitions and no bit-for-bit agreement with the stepped run (the maps' cells).
//!
//! Inside a regime z' = A [z; 1] (the augmented system matrix, [`system_matrix`]), so the
//! exact flow from z over sigma is z(sigma) = sum_n v_n sigma^n with v_0 = z and
//! v_n = A [v_(n-1); delta_(n,1)] / n (the constant 1 enters v_1 only). Over a substep the
//! fastest mode turns by at most a quarter radian, so the terms fall at least as fast as
//! (1/4)^n / n!: (10 to 15 terms for 2^-60: [`TaylorFlows::new`] fixes their number from the fastest mode), and every guard g = c . [z; 1] is then a polynomial in sigma.
//!
//! **The first crossing.** On a substep a guard has at most one extremum (the quarter-radian
//! rule). With g_0 < 0 at the segment's start (the regime holds):
//! - fired at the segment's end (g >= 0): the one zero in (0, end];
//! - not fired there: a crest inside, where g' goes from > 0 to < 0; its zero sigma_c is
//!   found, and if g(sigma_c) >= 0 the crossing is the zero in (0, sigma_c].
//!
//! A guard at or above zero at the start is the one the regime was entered on (or a touch):
//! as in [`crate::exact`]'s lifting, it is not a crossing there; if it departs in its firing
//! direction (g' > 0) the transition follows at once, and if it dips first and comes back
//! above zero by the end, the crossing is the zero after its minimum.
//!
//! Each zero is bracketed ([lo, hi] with g(lo) < 0 <= g(hi)) and found by Newton steps kept
//! inside the bracket (bisection where a step would leave it), to the last bits of sigma; the
//! transition is taken at hi, the first point where the guard has fired (the lifting's
//! `at`). The state there is the polynomial's; the rest of the substep is the new regime's
//! polynomial from it. The times agree with the lifting's (2^-53 of a substep) to rounding
//! and the states to rounding, not bit for bit: the statistics are those of the same
//! continuous motion (tests: `cargo test --release -p stickslip --test map_located`).

use super::*;

/// Most Taylor terms kept (the quarter-radian substep needs 15 for 2^-60): the polynomials
/// are evaluated at this length, zeros beyond their terms, unrolled.
const MAX_TERMS: usize = 16;
/// Root iterations before the bracket's midpoint is taken as the zero (Newton converges in a
/// handful; bisection halves 53 bits in 53).
const MAX_ROOT_ITERATIONS: usize = 80;

/// The augmented system matrices of the three regimes (rows x, x', phi, phi'; columns x, x',
/// phi, phi', 1), in f64, and the Taylor terms a substep needs, for
/// [`ExactTables::step_located`].
#[derive(Clone, Copy, Debug)]
pub struct TaylorFlows {
    a: [[[f64; 5]; 4]; 3],
    /// Terms kept (v_0 .. v_(terms - 1)): the remainder (rate h)^n / n! of the fastest mode
    /// over a substep is below 2^-60 from n = terms - 1 on.
    terms: usize,
}

impl TaylorFlows {
    /// The matrices of a validated `scene` at its step.
    pub fn new(scene: &Scene) -> Self {
        let co = Coefficients::of(scene);
        let mut a = [[[0.0; 5]; 4]; 3];
        for regime in Regime::ALL {
            let m = system_matrix(scene, &co, regime);
            a[regime.index()].copy_from_slice(&m[..4]);
        }
        let n_sub = Propagator::<f64>::substeps(scene, &co, scene.dt);
        let rh = crate::propagator::fastest_rate(scene, &co) * scene.dt / f64::from(n_sub);
        // the smallest n with (rate h)^n / n! <= 2^-60 (below the last bit of every sum), and
        // one more
        let mut n = 1usize;
        let mut term = rh;
        while n + 1 < MAX_TERMS && term > 8.673617379884035e-19 {
            n += 1;
            term *= rh / n as f64;
        }
        TaylorFlows { a, terms: (n + 1).min(MAX_TERMS) }
    }
}

/// The Taylor terms of one regime's flow from one state: z(sigma) = sum_n v[n] sigma^n.
struct Taylor {
    v: [[f64; 4]; MAX_TERMS],
    n: usize,
}

impl Taylor {
    const EMPTY: Taylor = Taylor { v: [[0.0; 4]; MAX_TERMS], n: 1 };

    /// The first `n` terms of the flow of `a` from `z`, in place.
    #[inline]
    fn fill(&mut self, a: &[[f64; 5]; 4], z: &[f64; 4], n: usize) {
        let v = &mut self.v;
        v[0] = *z;
        for r in 0..4 {
            let row = &a[r];
            v[1][r] = row[0] * z[0] + row[1] * z[1] + row[2] * z[2] + row[3] * z[3] + row[4];
        }
        for k in 2..n {
            let prev = v[k - 1];
            let inv = 1.0 / k as f64;
            for r in 0..4 {
                let row = &a[r];
                v[k][r] = (row[0] * prev[0] + row[1] * prev[1] + row[2] * prev[2] + row[3] * prev[3]) * inv;
            }
        }
        self.n = n;
    }

    /// The state at sigma (the terms beyond n are zero).
    #[inline]
    fn state(&self, sigma: f64) -> [f64; 4] {
        let mut out = self.v[MAX_TERMS - 1];
        for k in (0..MAX_TERMS - 1).rev() {
            for (o, vk) in out.iter_mut().zip(self.v[k]) {
                *o = *o * sigma + vk;
            }
        }
        out
    }

    /// The coefficients of guard `c` (g = c . [z; 1]) as a polynomial in sigma, into `p`.
    #[inline]
    fn guard(&self, c: &[f64; 5], p: &mut Poly) {
        // the terms beyond n are zero in v (filled so from EMPTY and never written)
        for k in 0..MAX_TERMS {
            let v = &self.v[k];
            p.c[k] = c[0] * v[0] + c[1] * v[1] + c[2] * v[2] + c[3] * v[3];
        }
        p.c[0] += c[4];
        p.derive();
    }
}

/// A polynomial sum_k c[k] sigma^k, with its derivative's coefficients d[k] = (k + 1) c[k + 1]
/// and its second derivative's e[k] = (k + 1) d[k + 1].
struct Poly {
    c: [f64; MAX_TERMS],
    d: [f64; MAX_TERMS],
    e: [f64; MAX_TERMS],
}

/// sum_k c[k] s^k over all MAX_TERMS coefficients, as its even and odd parts in s^2 (two
/// independent chains, unrolled).
#[inline(always)]
fn horner2(c: &[f64; MAX_TERMS], s: f64) -> f64 {
    let s2 = s * s;
    let mut even = c[MAX_TERMS - 2];
    let mut odd = c[MAX_TERMS - 1];
    let mut k = MAX_TERMS - 2;
    while k >= 2 {
        k -= 2;
        even = even * s2 + c[k];
        odd = odd * s2 + c[k + 1];
    }
    even + s * odd
}

impl Poly {
    const EMPTY: Poly = Poly { c: [0.0; MAX_TERMS], d: [0.0; MAX_TERMS], e: [0.0; MAX_TERMS] };

    /// The derivatives' coefficients from `c` (zeros beyond its terms).
    #[inline(always)]
    fn derive(&mut self) {
        for k in 0..MAX_TERMS - 1 {
            self.d[k] = (k + 1) as f64 * self.c[k + 1];
        }
        self.d[MAX_TERMS - 1] = 0.0;
        for k in 0..MAX_TERMS - 1 {
            self.e[k] = (k + 1) as f64 * self.d[k + 1];
        }
        self.e[MAX_TERMS - 1] = 0.0;
    }

    /// The value and the derivative at sigma.
    #[inline]
    fn eval(&self, sigma: f64) -> (f64, f64) {
        (horner2(&self.c, sigma), horner2(&self.d, sigma))
    }

    /// The derivative's value and its own derivative at sigma.
    #[inline]
    fn eval_rate(&self, sigma: f64) -> (f64, f64) {
        (horner2(&self.d, sigma), horner2(&self.e, sigma))
    }

    /// The zero of `f` (value and derivative at a point) in [lo, hi], where it changes sign:
    /// `below(f(lo))`, `!below(f(hi))`, with f and f' at the ends given (`ends`). The first
    /// point is the root of the cubic Hermite interpolant of the ends (close: the bracket is
    /// at most a substep of a quarter radian), then Newton steps kept in the bracket
    /// (bisection where one would leave it), until a step is below 2^-52 of the bracket's first
    /// width (the lifting's resolution, 2^-53 of a substep); that last Newton point is the zero.
    fn zero(mut lo: f64, mut hi: f64, ends: [(f64, f64); 2], f: impl Fn(f64) -> (f64, f64), below: impl Fn(f64) -> bool) -> f64 {
        let tol = (hi - lo) * f64::EPSILON;
        let mut x = hermite_root(lo, hi, ends);
        for _ in 0..MAX_ROOT_ITERATIONS {
            let (y, dy) = f(x);
            if below(y) {
                lo = x;
            } else {
                hi = x;
            }
            let d = y / dy;
            let next = x - d;
            if libm::fabs(d) <= tol && next >= lo && next <= hi {
                return next;
            }
            if !(hi - lo > tol) {
                break;
            }
            x = if next > lo && next < hi { next } else { 0.5 * (lo + hi) };
            if x <= lo || x >= hi {
                // the bracket is down to adjacent floats
                break;
            }
        }
        hi
    }

    /// The first point in (0, end] where the polynomial is >= 0 (it is < 0 just after 0, or
    /// the guard is the one just entered: see the module documentation); None if it stays
    /// below zero. At most one extremum in [0, end] is assumed.
    fn first_crossing(&self, end: f64) -> Option<f64> {
        let g0 = self.c[0];
        let r0 = self.c[1];
        let (g_end, r_end) = self.eval(end);
        let fired_end = !(g_end < 0.0);
        let value = |s: f64| self.eval(s);
        let rate = |s: f64| self.eval_rate(s);
        if !(g0 < 0.0) {
            // at (or above) zero where the segment starts: entered on it, or touched
            if !(r0 <= 0.0) {
                // departs in the firing direction: at once (one unit of the lifting later)
                return Some(end * f64::EPSILON * 0.5);
            }
            if !fired_end || !(r_end > 0.0) {
                return None;
            }
            // dips, then comes back above zero: the crossing after the minimum
            let ends = [(r0, 2.0 * self.c[2]), self.eval_rate(end)];
            let lo = Self::zero(0.0, end, ends, rate, |r| r < 0.0);
            let at_lo = self.eval(lo);
            if !(at_lo.0 < 0.0) {
                return None;
            }
            return Some(Self::zero(lo, end, [at_lo, (g_end, r_end)], value, |g| g < 0.0));
        }
        if fired_end {
            return Some(Self::zero(0.0, end, [(g0, r0), (g_end, r_end)], value, |g| g < 0.0));
        }
        if r0 > 0.0 && r_end < 0.0 {
            // a crest inside: at the zero of the rate
            let ends = [(r0, 2.0 * self.c[2]), self.eval_rate(end)];
            let crest = Self::zero(0.0, end, ends, rate, |r| r > 0.0);
            let at_crest = self.eval(crest);
            if !(at_crest.0 < 0.0) {
                return Some(Self::zero(0.0, crest, [(g0, r0), at_crest], value, |g| g < 0.0));
            }
        }
        None
    }
}

/// The zero in [lo, hi] of the cubic Hermite interpolant of f and f' at the ends (`ends`,
/// of opposite signs), by a few Newton steps on it from the secant; the midpoint where that
/// fails.
fn hermite_root(lo: f64, hi: f64, ends: [(f64, f64); 2]) -> f64 {
    let w = hi - lo;
    let [(f0, d0), (f1, d1)] = ends;
    // p(t) = f0 + m0 t + (3 (f1 - f0) - 2 m0 - m1) t^2 + (2 (f0 - f1) + m0 + m1) t^3, t in [0, 1]
    let (m0, m1) = (d0 * w, d1 * w);
    let c2 = 3.0 * (f1 - f0) - 2.0 * m0 - m1;
    let c3 = 2.0 * (f0 - f1) + m0 + m1;
    let mut t = f0 / (f0 - f1);
    if !(t > 0.0 && t < 1.0) {
        t = 0.5;
    }
    for _ in 0..4 {
        let p = f0 + t * (m0 + t * (c2 + t * c3));
        let dp = m0 + t * (2.0 * c2 + t * 3.0 * c3);
        let next = t - p / dp;
        if !(next > 0.0 && next < 1.0) {
            break;
        }
        t = next;
    }
    lo + t * w
}

impl ExactTables<f64> {
    /// Whether guard `c` of the regime of `a` may cross zero between `z` and `z_end` (a
    /// segment of at most a substep): fired at the end, or its rate c . A [z; 1] going from
    /// positive to negative (a crest). The polynomial's search decides; a guard that passes neither
    /// test has no crossing there (at most one extremum a substep).
    #[inline(always)]
    fn may_cross(a: &[[f64; 5]; 4], c: &[f64; 5], z: &[f64; 4], z_end: &[f64; 4]) -> bool {
        let g = |v: &[f64; 4]| c[0] * v[0] + c[1] * v[1] + c[2] * v[2] + c[3] * v[3] + c[4];
        if !(g(z_end) < 0.0) {
            return true;
        }
        let rate = |v: &[f64; 4]| {
            let mut r = 0.0;
            for (row, ci) in a.iter().zip(c.iter()) {
                if *ci != 0.0 {
                    r += ci * (row[0] * v[0] + row[1] * v[1] + row[2] * v[2] + row[3] * v[3] + row[4]);
                }
            }
            r
        };
        rate(z) > 0.0 && rate(z_end) < 0.0
    }

    /// One step of the run in `s` (a step of one substep: see [`Self::quiet_steps`]), with its
    /// transitions located on the regimes' Taylor polynomials (`taylor`, built for this scene:
    /// see the module documentation). The transitions are reported as [`Self::step`] reports
    /// them; returns their number. A run of more substeps per step, or one that has halted,
    /// takes [`Self::step`] instead.
    pub fn step_located(&self, taylor: &TaylorFlows, s: &mut ExactState<f64>) -> Result<usize, Halt> {
        if self.prop.n_sub != 1 || s.halted.is_some() {
            return self.step(s);
        }
        let h = self.prop.h_sub;
        s.n_reported = 0;
        let z0 = s.z;
        let first = s.regime;
        // a step with no transition ends where the stepped run's does
        let z1 = self.fast_substep(s, first, &z0);
        let mut pos = 0.0;
        let mut z = z0;
        let mut regime = first;
        let mut entered_stick_at: Option<f64> = None;
        let mut count = 0u32;
        let mut transitions = 0usize;
        let mut touched: Option<(Regime, usize)> = None;
        let mut z_end = z1;
        let mut flow = Taylor::EMPTY;
        let mut poly = Poly::EMPTY;
        loop {
            let span = h - pos;
            let a = &taylor.a[regime.index()];
            // the segment's end if nothing fires: the stepped run's for the step's first
            // segment, else the new regime's polynomial
            let filled = count > 0;
            if filled {
                flow.fill(a, &z, taylor.terms);
                z_end = flow.state(span);
            }
            let (gs, n) = self.guards.of(regime);
            let mut best: Option<(f64, usize)> = None;
            let mut filled = filled;
            for (which, g) in gs.iter().take(n).enumerate() {
                if touched == Some((regime, which)) || !Self::may_cross(a, &g.c, &z, &z_end) {
                    continue;
                }
                if !filled {
                    flow.fill(a, &z, taylor.terms);
                    filled = true;
                }
                flow.guard(&g.c, &mut poly);
                if let Some(sigma) = poly.first_crossing(span) {
                    if best.is_none_or(|b| sigma < b.0) {
                        best = Some((sigma, which));
                    }
                }
            }
            let Some((sigma, which)) = best else {
                break;
            };
            let at = pos + sigma;
            let ze = flow.state(sigma);
            let next = self.guards.next_regime(regime, which, &ze);
            let zn = self.enter(s, next, ze);
            if next == Regime::Stick {
                entered_stick_at = Some(at);
            }
            if next == regime {
                touched = Some((regime, which));
            } else {
                touched = None;
                Self::report(s, Transition { t: s.step as f64 * self.dt + at, from: regime, to: next, state: State::from_array(zn) });
                transitions += 1;
            }
            count += 1;
            if count > MAX_TRANSITIONS_PER_SUBSTEP {
                let hl = Halt::TransitionStorm { t: s.step as f64 * self.dt + at };
                s.halted = Some(hl);
                return Err(hl);
            }
            regime = next;
            pos = at;
            z = zn;
            if !(pos < h) {
                z_end = zn;
                break;
            }
        }
        self.end_substep(s, regime, entered_stick_at.map(|at| h - at), z_end);
        if let Err(hl) = self.check(s, 0) {
            s.halted = Some(hl);
            return Err(hl);
        }
        s.step += 1;
        Ok(transitions)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The polynomial with coefficients `c` (lowest first), with its derivatives.
    fn poly(c: &[f64]) -> Poly {
        let mut p = Poly::EMPTY;
        p.c[..c.len()].copy_from_slice(c);
        p.derive();
        p
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 4.0 * f64::EPSILON * b.abs().max(1.0)
    }

    #[test]
    fn the_first_crossing_is_the_closed_forms_root() {
        // g = (s - 0.3)(s + 2) = s^2 + 1.7 s - 0.6: below zero at 0, one root at 0.3
        let p = poly(&[-0.6, 1.7, 1.0]);
        assert!(close(p.first_crossing(1.0).unwrap(), 0.3));
        // a crest: g = -(s - 0.5)^2 + 0.01 = -0.24 + s - s^2, above zero on (0.4, 0.6): the
        // first crossing 0.4, though g(1) < 0
        let p = poly(&[-0.24, 1.0, -1.0]);
        assert!(close(p.first_crossing(1.0).unwrap(), 0.4));
        // the same crest below zero: g = -(s - 0.5)^2 - 0.01: none
        let p = poly(&[-0.26, 1.0, -1.0]);
        assert_eq!(p.first_crossing(1.0), None);
        // entered on the guard (g(0) = 0), dipping and back above zero: g = s (s - 0.6), the
        // crossing at 0.6 after the minimum at 0.3
        let p = poly(&[0.0, -0.6, 1.0]);
        assert!(close(p.first_crossing(1.0).unwrap(), 0.6));
        // entered on it and dipping for good: none
        assert_eq!(p.first_crossing(0.5), None);
        // entered on it and departing in the firing direction: at once
        let p = poly(&[0.0, 0.6, 1.0]);
        assert!(p.first_crossing(1.0).unwrap() <= f64::EPSILON);
        // a cubic, the root of a transcendental-looking shape: g = s^3 + s - 0.5 (one real
        // root, 0.4238537990...)
        let p = poly(&[-0.5, 1.0, 0.0, 1.0]);
        let r = p.first_crossing(1.0).unwrap();
        assert!((r * r * r + r - 0.5).abs() < 4e-16, "{r}");
    }

    #[test]
    fn the_even_odd_horner_is_horner() {
        let c: [f64; MAX_TERMS] = core::array::from_fn(|k| ((k * 7 + 3) % 11) as f64 - 5.0);
        let p = poly(&c);
        for &s in &[0.0, 0.1, -0.37, 0.9] {
            for n in 1..=MAX_TERMS {
                let mut cn = [0.0; MAX_TERMS];
                cn[..n].copy_from_slice(&p.c[..n]);
                let plain = c[..n].iter().rev().fold(0.0, |acc, &ck| acc * s + ck);
                let two = horner2(&cn, s);
                assert!((plain - two).abs() <= 1e-13 * plain.abs().max(1.0), "n {n} s {s}: {plain} vs {two}");
            }
        }
    }
}
