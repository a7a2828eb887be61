//! Power spectral density of the four channels by Welch's method, streaming: fixed-size
//! segments, 50 % overlap, periodic Hann window, each segment's mean removed; the segments'
//! periodograms are averaged. Memory: one segment buffer and one spectrum per channel,
//! whatever the record's length.
//!
//! One-sided PSD [(m/s^2)^2/Hz] at f_k = k fs / N, k = 0..=N/2:
//! `P_k = c |X_k|^2 / (fs sum(w^2))`, c = 2 except at 0 and N/2 (c = 1), so that the sum of
//! `P_k fs / N` is the mean square of the windowed, mean-free signal (Parseval).
//!
//! The samples after the last complete segment (less than half a segment) are not in the
//! spectrum. A record shorter than one segment is analysed as one segment of its own length.
//! Two real channels share one complex FFT (`z = a + i b`, then `A_k = (Z_k + conj Z_{N-k}) / 2`,
//! `B_k = (Z_k - conj Z_{N-k}) / 2i`).

use std::sync::Arc;

use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

/// Channels analysed together.
pub const CH: usize = 4;

/// Longest default segment [samples] (reached above 131 kHz).
pub const MAX_DEFAULT_SEGMENT: usize = 1 << 16;

/// The default segment length for a sampling rate: the smallest power of two giving a
/// resolution of 2 Hz or finer, `2^ceil(log2(fs / 2 Hz))`, from 64 to [`MAX_DEFAULT_SEGMENT`]
/// (25.6 kHz: 16384 samples, 1.5625 Hz).
pub fn default_segment(fs_hz: f64) -> usize {
    let want = (fs_hz / 2.0).max(64.0).min(MAX_DEFAULT_SEGMENT as f64);
    (want.ceil() as usize).next_power_of_two()
}

/// The streaming Welch estimator.
pub struct Welch {
    n: usize,
    fft: Arc<dyn Fft<f64>>,
    window: Vec<f64>,
    buf: [Vec<f64>; CH],
    fill: usize,
    acc: [Vec<f64>; CH],
    segments: u64,
    scratch: Vec<Complex<f64>>,
    work: Vec<Complex<f64>>,
}

/// Hann window (periodic, "DFT-even") of length n.
fn hann(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * k as f64 / n as f64).cos())
        .collect()
}

/// The averaged spectra.
#[derive(Clone, Debug)]
pub struct Spectrum {
    /// Segment length [samples].
    pub segment: usize,
    /// Segments averaged.
    pub segments: u64,
    /// Frequency resolution fs / segment [Hz].
    pub resolution_hz: f64,
    /// One-sided PSD per channel, bins 0..=segment/2 [(m/s^2)^2/Hz].
    pub psd: [Vec<f64>; CH],
}

impl Spectrum {
    /// Frequency of bin k [Hz].
    pub fn freq(&self, k: usize) -> f64 {
        k as f64 * self.resolution_hz
    }

    /// The bin of largest PSD above 0 Hz, and its frequency [Hz]; `None` without such a bin.
    pub fn peak(&self, ch: usize) -> Option<(usize, f64)> {
        let p = &self.psd[ch];
        let mut best: Option<usize> = None;
        for (k, &v) in p.iter().enumerate().skip(1) {
            if v > 0.0 && best.is_none_or(|b| v > p[b]) {
                best = Some(k);
            }
        }
        best.map(|k| (k, self.freq(k)))
    }
}

impl Welch {
    /// Segments of `n` samples (even, at least 4).
    pub fn new(n: usize) -> Self {
        let n = n.max(4) & !1;
        let mut planner = FftPlanner::<f64>::new();
        let fft = planner.plan_fft_forward(n);
        let scratch = vec![Complex::default(); fft.get_inplace_scratch_len()];
        Welch {
            n,
            window: hann(n),
            fft,
            buf: std::array::from_fn(|_| vec![0.0; n]),
            fill: 0,
            acc: std::array::from_fn(|_| vec![0.0; n / 2 + 1]),
            segments: 0,
            scratch,
            work: vec![Complex::default(); n],
        }
    }

    pub fn segment(&self) -> usize {
        self.n
    }

    /// Drops the partial segment: the next segment starts with the next sample (after a gap
    /// in the record, a segment must not reach across it).
    pub fn restart(&mut self) {
        self.fill = 0;
    }

    #[inline]
    pub fn push(&mut self, a: &[f64; CH]) {
        let i = self.fill;
        for (b, &v) in self.buf.iter_mut().zip(a) {
            b[i] = v;
        }
        self.fill += 1;
        if self.fill == self.n {
            Self::segment_into(
                &self.buf,
                self.n,
                &self.window,
                self.fft.as_ref(),
                &mut self.work,
                &mut self.scratch,
                &mut self.acc,
            );
            self.segments += 1;
            let half = self.n / 2;
            for b in &mut self.buf {
                b.copy_within(half.., 0);
            }
            self.fill = self.n - half;
        }
    }

    /// Adds the periodogram of the first `n` samples of `buf` to `acc`.
    fn segment_into(
        buf: &[Vec<f64>; CH],
        n: usize,
        window: &[f64],
        fft: &dyn Fft<f64>,
        work: &mut [Complex<f64>],
        scratch: &mut [Complex<f64>],
        acc: &mut [Vec<f64>; CH],
    ) {
        for pair in 0..CH / 2 {
            let (a, b) = (&buf[2 * pair][..n], &buf[2 * pair + 1][..n]);
            let ma = a.iter().sum::<f64>() / n as f64;
            let mb = b.iter().sum::<f64>() / n as f64;
            for k in 0..n {
                work[k] = Complex::new((a[k] - ma) * window[k], (b[k] - mb) * window[k]);
            }
            fft.process_with_scratch(&mut work[..n], scratch);
            for k in 0..=n / 2 {
                let z = work[k];
                let zc = work[(n - k) % n].conj();
                // A = (z + zc) / 2, B = (z - zc) / 2i; |A|^2, |B|^2
                let ar = 0.5 * (z.re + zc.re);
                let ai = 0.5 * (z.im + zc.im);
                let br = 0.5 * (z.im - zc.im);
                let bi = -0.5 * (z.re - zc.re);
                acc[2 * pair][k] += ar * ar + ai * ai;
                acc[2 * pair + 1][k] += br * br + bi * bi;
            }
        }
    }

    /// The averaged one-sided PSD at the sampling rate `fs_hz`; `None` if fewer than 4
    /// samples came.
    pub fn finish(mut self, fs_hz: f64) -> Option<Spectrum> {
        let (n, segments) = if self.segments > 0 {
            (self.n, self.segments)
        } else {
            // a record shorter than one segment: one segment of its own (even) length
            let n = self.fill & !1;
            if n < 4 {
                return None;
            }
            let fft = FftPlanner::<f64>::new().plan_fft_forward(n);
            let mut scratch = vec![Complex::default(); fft.get_inplace_scratch_len()];
            let window = hann(n);
            self.acc = std::array::from_fn(|_| vec![0.0; n / 2 + 1]);
            Self::segment_into(&self.buf, n, &window, fft.as_ref(), &mut self.work, &mut scratch, &mut self.acc);
            self.window = window;
            (n, 1)
        };
        let w2: f64 = self.window.iter().map(|w| w * w).sum();
        let base = 1.0 / (fs_hz * w2 * segments as f64);
        let mut psd = self.acc;
        for p in &mut psd {
            for (k, v) in p.iter_mut().enumerate() {
                let c = if k == 0 || k == n / 2 { 1.0 } else { 2.0 };
                *v *= c * base;
            }
        }
        Some(Spectrum { segment: n, segments, resolution_hz: fs_hz / n as f64, psd })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sine_peak_and_parseval() {
        // 4 channels of sines at bin-centred frequencies; fs 1024 Hz, N 256: 4 Hz bins
        let fs = 1024.0;
        let mut w = Welch::new(256);
        let f = [40.0, 100.0, 200.0, 300.0];
        let amp = [1.0, 2.0, 0.5, 3.0];
        for i in 0..4096 {
            let t = i as f64 / fs;
            let a = std::array::from_fn(|c| amp[c] * (2.0 * std::f64::consts::PI * f[c] * t).sin() + 7.0);
            w.push(&a);
        }
        let s = w.finish(fs).unwrap();
        assert_eq!(s.segments, 4096 / 128 - 1);
        for c in 0..4 {
            let (_, pk) = s.peak(c).unwrap();
            assert_eq!(pk, f[c]);
            // the windowed mean square is A^2/2 * mean(w^2)... the PSD sums to the mean
            // square of the Hann-weighted signal divided by mean(w^2): A^2 / 2
            let total: f64 = s.psd[c].iter().sum::<f64>() * s.resolution_hz;
            assert!((total - amp[c] * amp[c] / 2.0).abs() < 1e-9 * amp[c] * amp[c], "{c}: {total}");
        }
    }

    #[test]
    fn short_record_is_one_segment() {
        let mut w = Welch::new(1024);
        for i in 0..100 {
            let v = (i as f64 * 0.3).sin();
            w.push(&[v, v, v, v]);
        }
        let s = w.finish(1000.0).unwrap();
        assert_eq!((s.segment, s.segments), (100, 1));
        assert_eq!(s.resolution_hz, 10.0);
    }
}
