//! A Butterworth band-pass as a cascade of biquads: designed once in f64 by the bilinear
//! transform, run per sample in f32.
//!
//! **Design.** Band edges f_lo, f_hi [Hz] at rate fs are prewarped, Omega = 2 fs tan(pi f / fs),
//! so that the digital filter has exactly the analog response at those edges. The analog
//! prototype is the order-n Butterworth low-pass, poles p_k = exp(j theta_k),
//! theta_k = pi/2 + pi (2k + 1) / (2n), k = 0..n. The low-pass to band-pass substitution
//! S = (s^2 + Omega_0^2) / (B s), with Omega_0^2 = Omega_lo Omega_hi and B = Omega_hi - Omega_lo,
//! turns each factor 1 / (S - p) into B s / (s^2 - p B s + Omega_0^2): two poles, the roots of
//! s^2 - p B s + Omega_0^2. Each upper-half prototype pole p gives two roots s_1, s_2 and its
//! conjugate gives their conjugates, so the 2n band-pass poles pair into n real sections
//!
//! ```text
//! H_i(s) = B s / (s^2 + a_1 s + a_0),   a_1 = -2 Re(s_i),  a_0 = |s_i|^2
//! ```
//!
//! (an odd n adds the real prototype pole -1: s^2 + B s + Omega_0^2). The product has unit gain
//! at Omega_0, and |H(j Omega)|^2 = 1 / (1 + ((Omega^2 - Omega_0^2) / (Omega B))^(2n)). The
//! bilinear transform s = K (1 - z^-1) / (1 + z^-1), K = 2 fs, maps each section to
//!
//! ```text
//! H_i(z) = b_0 (1 - z^-2) / (1 + a_1' z^-1 + a_2' z^-2)
//! b_0 = B K / d,  a_1' = 2 (a_0 - K^2) / d,  a_2' = (K^2 - a_1 K + a_0) / d,  d = K^2 + a_1 K + a_0
//! ```
//!
//! and the digital magnitude at f is the analog one at Omega = 2 fs tan(pi f / fs), up to the
//! rounding of the coefficients to f32.
//!
//! **Run.** Direct form I, y = b_0 (x - x[-2]) - a_1' y[-1] - a_2' y[-2]: three multiplies, three
//! additions, no division. Direct form I keeps the section's state as past inputs and outputs,
//! which are of the signal's own size (no internal gain), the safer choice in f32 for poles
//! close to z = 1 (here |z| > 0.98 for a 100 Hz edge at 25.6 kHz).

use super::{check, ConfigError};

/// Sections of the groan-band filter: a 4th-order band-pass (2nd-order Butterworth prototype).
pub const GROAN_SECTIONS: usize = 2;
/// The groan band [Hz].
pub const GROAN_BAND_HZ: (f64, f64) = (100.0, 500.0);

/// One band-pass section, H(z) = b0 (1 - z^-2) / (1 + a1 z^-1 + a2 z^-2).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Section<T> {
    pub b0: T,
    pub a1: T,
    pub a2: T,
}

/// The past values of a cascade of `N` sections (direct form I): the cascade's last two inputs,
/// and each section's last two outputs, which are also the next section's last two inputs (kept
/// once).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CascadeState<const N: usize> {
    /// x[-1], x[-2] of the cascade's input.
    x: [f32; 2],
    /// y[-1], y[-2] of each section.
    y: [[f32; 2]; N],
}

impl<const N: usize> CascadeState<N> {
    /// At rest: every past value 0.
    pub const ZERO: Self = CascadeState { x: [0.0; 2], y: [[0.0; 2]; N] };

    /// The cascade's last two inputs x[-1], x[-2] (for a host's closed forms of the filter's
    /// free response).
    pub fn past_inputs(&self) -> [f32; 2] {
        self.x
    }

    /// Each section's last two outputs y[-1], y[-2].
    pub fn past_outputs(&self) -> &[[f32; 2]; N] {
        &self.y
    }

    /// The state with these past values ([`Self::past_inputs`], [`Self::past_outputs`]).
    pub fn from_past(x: [f32; 2], y: [[f32; 2]; N]) -> Self {
        CascadeState { x, y }
    }
}

impl<const N: usize> Default for CascadeState<N> {
    fn default() -> Self {
        Self::ZERO
    }
}

/// A designed band-pass: the f64 design and its f32 coefficients.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BandPass<const N: usize> {
    /// The design in f64.
    pub design: [Section<f64>; N],
    /// The coefficients the filter runs with (the design rounded to f32).
    pub sections: [Section<f32>; N],
    /// Prewarped analog band edges Omega_lo, Omega_hi [rad/s].
    pub omega_edges: (f64, f64),
}

#[derive(Clone, Copy, Debug)]
struct Complex {
    re: f64,
    im: f64,
}

impl Complex {
    fn mul(self, o: Complex) -> Complex {
        Complex { re: self.re * o.re - self.im * o.im, im: self.re * o.im + self.im * o.re }
    }
    fn sub(self, o: Complex) -> Complex {
        Complex { re: self.re - o.re, im: self.im - o.im }
    }
    fn add(self, o: Complex) -> Complex {
        Complex { re: self.re + o.re, im: self.im + o.im }
    }
    fn scale(self, k: f64) -> Complex {
        Complex { re: self.re * k, im: self.im * k }
    }
    /// Principal square root, with sqrt only: sqrt((|z| + re) / 2) + j sign(im) sqrt((|z| - re) / 2).
    fn sqrt(self) -> Complex {
        let r = libm::sqrt(self.re * self.re + self.im * self.im);
        let re = libm::sqrt(((r + self.re) * 0.5).max(0.0));
        let im = libm::sqrt(((r - self.re) * 0.5).max(0.0));
        Complex { re, im: if self.im < 0.0 { -im } else { im } }
    }
}

impl<const N: usize> BandPass<N> {
    /// Designs the N-section (order 2N) Butterworth band-pass with edges `f_lo_hz`, `f_hi_hz`
    /// at the sampling rate `fs_hz`.
    pub fn butterworth(f_lo_hz: f64, f_hi_hz: f64, fs_hz: f64) -> Result<Self, ConfigError> {
        check(N >= 1, "bandpass.sections", "must be >= 1", N as f64)?;
        check(fs_hz.is_finite() && fs_hz > 0.0, "bandpass.fs_hz", "must be > 0 Hz", fs_hz)?;
        check(f_lo_hz.is_finite() && f_lo_hz > 0.0, "bandpass.f_lo_hz", "must be > 0 Hz", f_lo_hz)?;
        check(
            f_hi_hz.is_finite() && f_hi_hz > f_lo_hz && f_hi_hz < 0.5 * fs_hz,
            "bandpass.f_hi_hz",
            "must satisfy f_lo < f_hi < fs / 2",
            f_hi_hz,
        )?;
        let pi = core::f64::consts::PI;
        let k = 2.0 * fs_hz;
        let w_lo = k * tan(pi * f_lo_hz / fs_hz);
        let w_hi = k * tan(pi * f_hi_hz / fs_hz);
        let bw = w_hi - w_lo;
        let w0_sq = w_lo * w_hi;
        let mut analog = [(0.0f64, 0.0f64); N]; // (a1, a0) of s^2 + a1 s + a0
        let mut n = 0usize;
        for i in 0..N / 2 {
            let theta = pi / 2.0 + pi * (2 * i + 1) as f64 / (2 * N) as f64;
            let (sin, cos) = sin_cos(theta);
            let p = Complex { re: cos, im: sin };
            // roots of s^2 - p B s + Omega_0^2
            let pb = p.scale(bw);
            let disc = pb.mul(pb).sub(Complex { re: 4.0 * w0_sq, im: 0.0 }).sqrt();
            for s in [pb.add(disc).scale(0.5), pb.sub(disc).scale(0.5)] {
                analog[n] = (-2.0 * s.re, s.re * s.re + s.im * s.im);
                n += 1;
            }
        }
        if N % 2 == 1 {
            analog[n] = (bw, w0_sq);
        }
        let mut design = [Section::<f64>::default(); N];
        let mut sections = [Section::<f32>::default(); N];
        for (i, &(a1, a0)) in analog.iter().enumerate() {
            let d = k * k + a1 * k + a0;
            let s = Section { b0: bw * k / d, a1: 2.0 * (a0 - k * k) / d, a2: (k * k - a1 * k + a0) / d };
            design[i] = s;
            sections[i] = Section { b0: s.b0 as f32, a1: s.a1 as f32, a2: s.a2 as f32 };
        }
        Ok(BandPass { design, sections, omega_edges: (w_lo, w_hi) })
    }

    /// Filters one sample through the cascade; `state` holds one channel's past values.
    /// Section k's input is section k - 1's output, so its x[-2] is that section's y[-2] (read
    /// before the update): each past value is loaded and stored once.
    #[inline(always)]
    pub fn run(&self, state: &mut CascadeState<N>, x: f32) -> f32 {
        let mut v = x;
        let mut v2 = state.x[1];
        state.x = [x, state.x[0]];
        for (s, y) in self.sections.iter().zip(state.y.iter_mut()) {
            let out = s.b0 * (v - v2) - s.a1 * y[0] - s.a2 * y[1];
            v2 = y[1];
            *y = [out, y[0]];
            v = out;
        }
        v
    }
}

/// sin and cos of |x| <= 2 pi for the set-up of the design (f64): Cody-Waite reduction by
/// pi/2 (two-part constant) and Taylor series on |r| <= pi/4 to the 25th order (truncation
/// below 1e-20). The firmware designs its filter at boot; libm's sin, cos and tan would link
/// their general argument reduction (kilobytes of flash: `scripts/build-firmware.sh` prints the
/// builds' sizes) for these few small angles.
pub fn sin_cos(x: f64) -> (f64, f64) {
    const PIO2_HI: f64 = core::f64::consts::FRAC_PI_2; // nearest f64 to pi/2
    const PIO2_LO: f64 = 6.123_233_995_736_766e-17; // pi/2 - PIO2_HI
    let k = libm::round(x / PIO2_HI);
    let r = (x - k * PIO2_HI) - k * PIO2_LO;
    let r2 = r * r;
    // Horner from the highest term: sin r = r (1 - r^2/(2*3) (1 - r^2/(4*5) (...)))
    let (mut s, mut c) = (1.0, 1.0);
    let mut n = 24.0;
    while n >= 2.0 {
        s = 1.0 - r2 / (n * (n + 1.0)) * s;
        c = 1.0 - r2 / ((n - 1.0) * n) * c;
        n -= 2.0;
    }
    let (sr, cr) = (r * s, c);
    match (k as i64).rem_euclid(4) {
        0 => (sr, cr),
        1 => (cr, -sr),
        2 => (-sr, -cr),
        _ => (-cr, sr),
    }
}

/// tan x for |x| < pi/2 (the prewarp of a band edge below fs / 2), from [`sin_cos`].
pub fn tan(x: f64) -> f64 {
    let (s, c) = sin_cos(x);
    s / c
}
