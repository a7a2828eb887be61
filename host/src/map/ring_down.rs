//! The groan band-pass's free response (zero input) in closed form, for the maps' stick
//! phases: x'' is 0 in stick, so the filter only rings down, and its squared outputs over any
//! number of samples are a quadratic form of where it starts.

use stickslip_model::rig::bandpass::{BandPass, CascadeState, GROAN_SECTIONS};

/// The groan filter's free response (zero input) in closed form: from the cascade's past
/// values s, the outputs are y_k = c Phi^k s, and their squares sum to s' G s with
/// G = sum over k >= 0 of (Phi^k)' c' c Phi^k (the observability Gramian, summed by
/// doubling in f64 with the filter's f32 coefficients). A run of zero input at least
/// `decay_samples` long leaves past values below 1e-9 of where they started (|Phi^k| <
/// 1e-9): the closed form then replaces the run, its sum the Gramian's and the past values
/// zero. Against the filter run sample by sample in f32 this differs by the f32 loop's own
/// rounding (about 1e-7 relative of the ring-down's sum) and the dropped 1e-9 tail.
pub struct RingDown {
    gram: [[f64; RING_DIM]; RING_DIM],
    /// Zero-input runs at least this long leave past values below 1e-9 of where they started.
    pub decay_samples: u64,
    /// pow[j] = Phi^(2^j), for 2^j < decay_samples.
    pow: Vec<RingMat>,
}

/// Zero-input runs shorter than this go through the filter sample by sample.
pub const RING_LOOP_MAX: u64 = 32;

/// The groan cascade's past values: two inputs and two outputs a section.
const RING_DIM: usize = 2 + 2 * GROAN_SECTIONS;
type RingMat = [[f64; RING_DIM]; RING_DIM];

impl RingDown {
    /// Past values: x[-1], x[-2], then each section's y[-1], y[-2].
    pub fn values(st: &CascadeState<GROAN_SECTIONS>) -> [f64; RING_DIM] {
        let mut v = [0.0; RING_DIM];
        let x = st.past_inputs();
        v[0] = f64::from(x[0]);
        v[1] = f64::from(x[1]);
        for (k, y) in st.past_outputs().iter().enumerate() {
            v[2 + 2 * k] = f64::from(y[0]);
            v[3 + 2 * k] = f64::from(y[1]);
        }
        v
    }

    /// One zero-input step of the cascade, as [`BandPass::run`] does it, in f64: the next
    /// past values and the output.
    pub fn step(bp: &BandPass<GROAN_SECTIONS>, s: &[f64; RING_DIM]) -> ([f64; RING_DIM], f64) {
        let mut out = [0.0; RING_DIM];
        let (mut v, mut v2) = (0.0, s[1]);
        out[1] = s[0];
        for (k, sec) in bp.sections.iter().enumerate() {
            let (y0, y1) = (s[2 + 2 * k], s[3 + 2 * k]);
            let o = f64::from(sec.b0) * (v - v2) - f64::from(sec.a1) * y0 - f64::from(sec.a2) * y1;
            v2 = y1;
            out[2 + 2 * k] = o;
            out[3 + 2 * k] = y0;
            v = o;
        }
        (out, v)
    }

    pub fn of(bp: &BandPass<GROAN_SECTIONS>) -> Option<RingDown> {
        const D: usize = RING_DIM;
        // Phi (column i: the step of unit vector i) and c
        let mut phi = [[0.0; D]; D];
        let mut c = [0.0; D];
        for i in 0..D {
            let mut e = [0.0; D];
            e[i] = 1.0;
            let (next, y) = Self::step(bp, &e);
            for r in 0..D {
                phi[r][i] = next[r];
            }
            c[i] = y;
        }
        let mul = |a: &RingMat, b: &RingMat| -> RingMat {
            let mut m = [[0.0; D]; D];
            for i in 0..D {
                for j in 0..D {
                    m[i][j] = (0..D).map(|k| a[i][k] * b[k][j]).sum();
                }
            }
            m
        };
        let norm = |a: &RingMat| a.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        // G_1 = c'c, P = Phi; G_2m = G_m + P' G_m P, P = P^2 (P = Phi^m)
        let mut g = [[0.0; D]; D];
        for i in 0..D {
            for j in 0..D {
                g[i][j] = c[i] * c[j];
            }
        }
        let mut p = phi;
        let mut m: u64 = 1;
        let mut decay = None;
        let mut pow = vec![phi];
        for _ in 0..40 {
            let mut pt = [[0.0; D]; D];
            for i in 0..D {
                for j in 0..D {
                    pt[i][j] = p[j][i];
                }
            }
            let pgp = mul(&pt, &mul(&g, &p));
            for i in 0..D {
                for j in 0..D {
                    g[i][j] += pgp[i][j];
                }
            }
            p = mul(&p, &p);
            m *= 2;
            if decay.is_none() {
                pow.push(p);
            }
            let np = norm(&p);
            if decay.is_none() && np < 1e-9 {
                decay = Some(m);
            }
            if np < 1e-18 {
                break;
            }
        }
        let ok = norm(&p) < 1e-18 && g.iter().flatten().all(|v| v.is_finite());
        ok.then(|| RingDown { gram: g, decay_samples: decay.unwrap_or(m), pow })
    }

    /// The past values `n` zero-input samples on (n < 2^pow.len()).
    pub fn advance(&self, s: &[f64; RING_DIM], n: u64) -> [f64; RING_DIM] {
        let mut v = *s;
        for (j, p) in self.pow.iter().enumerate() {
            if n & (1 << j) != 0 {
                let mut w = [0.0; RING_DIM];
                for (r, wr) in w.iter_mut().enumerate() {
                    *wr = (0..RING_DIM).map(|k| p[r][k] * v[k]).sum();
                }
                v = w;
            }
        }
        v
    }

    /// s' G s for past values s.
    pub fn quad(&self, s: &[f64; RING_DIM]) -> f64 {
        let mut e = 0.0;
        for i in 0..RING_DIM {
            let gi: f64 = (0..RING_DIM).map(|j| self.gram[i][j] * s[j]).sum();
            e += s[i] * gi;
        }
        e
    }

    /// The cascade's state at past values `v` (rounded to f32).
    pub fn state(v: &[f64; RING_DIM]) -> CascadeState<GROAN_SECTIONS> {
        let mut y = [[0.0f32; 2]; GROAN_SECTIONS];
        for (k, yk) in y.iter_mut().enumerate() {
            *yk = [v[2 + 2 * k] as f32, v[3 + 2 * k] as f32];
        }
        CascadeState::from_past([v[0] as f32, v[1] as f32], y)
    }

    /// The sum of the squared outputs of the free response from `st`.
    pub fn energy(&self, st: &CascadeState<GROAN_SECTIONS>) -> f64 {
        self.quad(&Self::values(st))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stickslip_model::rig::bandpass::GROAN_BAND_HZ;

    /// The closed forms against the cascade stepped in f64 one sample at a time ([`RingDown::step`]
    /// is the filter's own recursion; the reference sums its outputs explicitly).
    #[test]
    fn the_closed_form_is_the_summed_ring_down() {
        let bp = BandPass::<GROAN_SECTIONS>::butterworth(GROAN_BAND_HZ.0, GROAN_BAND_HZ.1, 25600.0).unwrap();
        let ring = RingDown::of(&bp).expect("a stable filter");
        assert!(ring.decay_samples >= 256 && ring.decay_samples <= 8192, "decay {}", ring.decay_samples);
        let s0 = [0.7, -1.3, 2.1, 0.4, -3.2, 1.9];
        for n in [1u64, 33, 100, 1000, 1500] {
            let (mut s, mut sum) = (s0, 0.0);
            for _ in 0..n {
                let (next, y) = RingDown::step(&bp, &s);
                sum += y * y;
                s = next;
            }
            let after = ring.advance(&s0, n);
            let closed = ring.quad(&s0) - ring.quad(&after);
            assert!((closed - sum).abs() <= 1e-9 * sum.abs(), "n = {n}: {closed} closed, {sum} summed");
            for (a, b) in after.iter().zip(&s) {
                assert!((a - b).abs() <= 1e-9 * s0.iter().fold(0.0f64, |m, v| m.max(v.abs())), "n = {n}: state");
            }
        }
        // the whole ring-down
        let (mut s, mut sum) = (s0, 0.0);
        for _ in 0..100_000 {
            let (next, y) = RingDown::step(&bp, &s);
            sum += y * y;
            s = next;
        }
        assert!((ring.quad(&s0) - sum).abs() <= 1e-9 * sum, "{} closed, {sum} summed", ring.quad(&s0));
    }
}
