//! The groan band-pass against the analytic Butterworth magnitude, computed here in f64:
//!
//! |H(f)|^2 = 1 / (1 + ((W^2 - W0^2) / (W B))^(2n)),  W = 2 fs tan(pi f / fs),
//! W0^2 = W_lo W_hi,  B = W_hi - W_lo  (the bilinear transform maps f to W exactly).
//!
//! Three checks: the frequency response H(e^jw) evaluated here from the f32 coefficients the
//! filter runs with; the RMS of a pure sine through the filter as run in f32 (the estimator's
//! window statistics); the plain RMS and peak-to-peak of the same sine.

use stickslip_model::rig::bandpass::{BandPass, GROAN_BAND_HZ, GROAN_SECTIONS};
use stickslip_model::rig::calibration::Calibrated;
use stickslip_model::rig::estimator::{Estimator, EstimatorConfig};
use stickslip_model::design::SAMPLE_RATE_HZ;

const FS: f64 = SAMPLE_RATE_HZ;
const FREQS: [f64; 5] = [50.0, 100.0, 300.0, 500.0, 2000.0];

fn analytic_gain(f: f64, lo: f64, hi: f64, n: u32) -> f64 {
    let w = |f: f64| 2.0 * FS * (std::f64::consts::PI * f / FS).tan();
    let (wl, wh, wf) = (w(lo), w(hi), w(f));
    let q = (wf * wf - wl * wh) / (wf * (wh - wl));
    1.0 / (1.0 + q.powi(2 * n as i32)).sqrt()
}

/// |H(e^jw)| of a cascade of b0 (1 - z^-2) / (1 + a1 z^-1 + a2 z^-2) given as (b0, a1, a2), in
/// f64 complex arithmetic.
fn cascade_gain(sections: &[(f64, f64, f64)], f: f64) -> f64 {
    let w = 2.0 * std::f64::consts::PI * f / FS;
    let (c1, s1, c2, s2) = (w.cos(), -w.sin(), (2.0 * w).cos(), -(2.0 * w).sin());
    let mut g = 1.0;
    for &(b0, a1, a2) in sections {
        let num = (b0 * (1.0 - c2), b0 * (-s2));
        let den = (1.0 + a1 * c1 + a2 * c2, a1 * s1 + a2 * s2);
        g *= (num.0.hypot(num.1)) / (den.0.hypot(den.1));
    }
    g
}

/// The response of the f32 coefficients the filter runs with.
fn response<const N: usize>(bp: &BandPass<N>, f: f64) -> f64 {
    let s: Vec<_> = bp.sections.iter().map(|s| (s.b0 as f64, s.a1 as f64, s.a2 as f64)).collect();
    cascade_gain(&s, f)
}

/// The response of the f64 design.
fn design_response<const N: usize>(bp: &BandPass<N>, f: f64) -> f64 {
    let s: Vec<_> = bp.design.iter().map(|s| (s.b0, s.a1, s.a2)).collect();
    cascade_gain(&s, f)
}

#[test]
fn coefficients_follow_the_analytic_butterworth_magnitude() {
    let (lo, hi) = GROAN_BAND_HZ;
    let bp = BandPass::<GROAN_SECTIONS>::butterworth(lo, hi, FS).unwrap();
    for f in FREQS {
        let want = analytic_gain(f, lo, hi, GROAN_SECTIONS as u32);
        // the f64 design is the analytic filter to round-off (measured 6e-14)
        let d = design_response(&bp, f);
        assert!(((d - want) / want).abs() < 1e-10, "{f} Hz: design |H| = {d}, analytic {want}");
        // rounded to f32, the coefficients (poles at |z| ~ 0.98) move it by 5e-6 at most (measured)
        let got = response(&bp, f);
        assert!(((got - want) / want).abs() < 2e-5, "{f} Hz: |H| = {got}, analytic {want}");
    }
    // the edges are at -3 dB, the centre sqrt(100 x 500) Hz (prewarped) at 0 dB
    assert!((analytic_gain(100.0, lo, hi, 2) - 0.5f64.sqrt()).abs() < 1e-12);
    assert!((response(&bp, 100.0) - 0.5f64.sqrt()).abs() < 1e-4);
    assert!((response(&bp, 500.0) - 0.5f64.sqrt()).abs() < 1e-4);
}

#[test]
fn other_orders_odd_and_even_follow_the_analytic_magnitude() {
    fn check<const N: usize>(lo: f64, hi: f64) {
        let bp = BandPass::<N>::butterworth(lo, hi, FS).unwrap();
        for f in [20.0, 50.0, lo, 0.5 * (lo + hi), (lo * hi).sqrt(), hi, 2000.0, 8000.0] {
            let (got, want) = (response(&bp, f), analytic_gain(f, lo, hi, N as u32));
            // relative near the pass band, absolute in the deep stop band (f32 coefficients)
            assert!((got - want).abs() < 1e-4 * want + 1e-6, "N={N} {f} Hz: {got} vs {want}");
            let d = design_response(&bp, f);
            assert!((d - want).abs() < 1e-10 * want + 1e-14, "N={N} {f} Hz: design {d} vs {want}");
        }
    }
    check::<1>(100.0, 500.0);
    check::<3>(100.0, 500.0);
    check::<4>(100.0, 500.0);
    check::<2>(1000.0, 4000.0);
}

#[test]
fn invalid_bands_are_refused() {
    assert!(BandPass::<2>::butterworth(500.0, 100.0, FS).is_err());
    assert!(BandPass::<2>::butterworth(0.0, 100.0, FS).is_err());
    assert!(BandPass::<2>::butterworth(100.0, 12_800.0, FS).is_err());
    assert!(BandPass::<2>::butterworth(100.0, f64::NAN, FS).is_err());
    assert!(BandPass::<0>::butterworth(100.0, 500.0, FS).is_err());
}

/// Runs `amplitude sin(2 pi f t)` on all four accelerometers through the estimator for six
/// windows and returns the last window (100 ms: a whole number of periods at these f).
fn sine_window(f: f64, amplitude: f64) -> stickslip_model::rig::window::WindowReport {
    let mut est = Estimator::new(&EstimatorConfig::default()).unwrap();
    let mut last = None;
    for k in 0..6 * 2560u64 {
        let a = (amplitude * (2.0 * std::f64::consts::PI * f * k as f64 / FS).sin()) as f32;
        // disc_x carries the same sine, so a_rel = 0 and the contact stays in stick
        let c = Calibrated { accel_m_s2: [a; 4], pressure_bar: [5.0, 0.65], ..Default::default() };
        let s = est.update(&c);
        assert!(!s.fault);
        if s.window_ready {
            last = est.take_window();
        }
    }
    last.unwrap()
}

#[test]
fn rms_of_a_pure_sine_through_the_filter() {
    let (lo, hi) = GROAN_BAND_HZ;
    let amplitude = 10.0;
    for f in FREQS {
        let w = sine_window(f, amplitude);
        let want = amplitude / 2f64.sqrt() * analytic_gain(f, lo, hi, GROAN_SECTIONS as u32);
        for i in 0..4 {
            let got = w.groan_rms_m_s2[i] as f64;
            // the transient has died out after 0.5 s; f32 arithmetic and sums
            assert!(((got - want) / want).abs() < 2e-4, "{f} Hz ch {i}: groan rms {got}, analytic {want}");
            let rms = w.rms_m_s2[i] as f64;
            assert!(((rms - amplitude / 2f64.sqrt()) / rms).abs() < 1e-4, "{f} Hz rms {rms}");
            // sampled peaks: at least 2 A cos(pi f / fs)
            let pp = w.pp_m_s2[i] as f64;
            let floor = 2.0 * amplitude * (std::f64::consts::PI * f / FS).cos();
            assert!(pp <= 2.0 * amplitude * (1.0 + 1e-6) && pp >= floor * (1.0 - 1e-6), "{f} Hz pp {pp}");
        }
        assert_eq!(w.stick_fraction, 1.0);
        assert_eq!(w.slip_onsets, 0);
    }
}

/// The design's own sin, cos and tan (kept small for the firmware's flash) against libm's,
/// over the angles the design can meet: within 4e-16 absolute for sin and cos on [-2 pi, 2 pi],
/// and 1e-15 relative (a few ulp) for tan on (0, 1.5].
#[test]
fn the_design_trigonometry_matches_libm() {
    use stickslip_model::rig::bandpass::{sin_cos, tan};
    let n = 200_000;
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..=n {
        let x = -2.0 * core::f64::consts::PI + 4.0 * core::f64::consts::PI * i as f64 / n as f64;
        let (s, c) = sin_cos(x);
        worst.0 = worst.0.max((s - libm::sin(x)).abs());
        worst.1 = worst.1.max((c - libm::cos(x)).abs());
        let t = 1.5 * (i as f64 + 0.5) / (n as f64 + 1.0);
        worst.2 = worst.2.max(((tan(t) - libm::tan(t)) / libm::tan(t)).abs());
    }
    assert!(worst.0 <= 4e-16 && worst.1 <= 4e-16 && worst.2 <= 1e-15, "{worst:?}");
}
