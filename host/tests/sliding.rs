//! The linear stability of steady sliding (`stickslip::scenes::sliding`, the model's own
//! linearisation) against an independent two-mode (y, phi) analysis written here from the
//! physics, and against the model's own runs started from perturbed sliding.
//!
//! Two-mode analysis (docs/model.md, "Model 2, part 2"): the floating pad's bounce y and pitch
//! phi about the pivot, mass matrix [[m, m l], [m l, I]], contact stiffness [[k_s, c_N],
//! [c_N, K]] (k_s = k_L + k_T, c_N = k_L d_L + k_T d_T, K = k_L d_L^2 + k_T d_T^2), and the
//! forward friction mu N (N = k_s y + c_N phi) in the moment s w mu N: a non-symmetric
//! stiffness. det(K_f - omega^2 M) = 0 is a quadratic in omega^2; the modes merge (flutter)
//! where its discriminant reaches zero.

use stickslip::scenes::sliding::{instability_threshold_mu, sliding_stability};
use stickslip_model::model2::{AnyModel2Stepper, Y};
use stickslip_model::{Caliper, Regime, Scene};

/// The default pad, floating (k_pivot = 0), face kinematics, Coulomb friction.
fn floating(caliper: Caliper) -> Scene {
    let mut s = Scene::case(caliper, 0.040);
    s.face = true;
    s.k_pivot = 0.0;
    s
}

/// (omega^2 roots or None if complex) of the two-mode problem at friction coefficient mu.
fn two_mode(s: &Scene, mu: f64) -> (f64, f64, f64) {
    let (d_l, d_t, sign) = match s.caliper {
        Caliper::Push => (s.l + s.l_cl, s.l - s.l_ct, 1.0),
        Caliper::Pull => (s.l - s.l_cl, s.l + s.l_ct, -1.0),
    };
    let k_s = s.k_l + s.k_t;
    let c_n = s.k_l * d_l + s.k_t * d_t;
    let k = s.k_l * d_l * d_l + s.k_t * d_t * d_t;
    // order (y, phi): M = [[m, m l], [m l, I]]
    let (m11, m12, m21, m22) = (s.m, s.m * s.l, s.m * s.l, s.inertia);
    // y row: k_s y + c_N phi; phi row: c_N y + K phi - s w mu (k_s y + c_N phi)
    let sw = sign * s.w;
    let (k11, k12, k21, k22) = (k_s, c_n, c_n - sw * mu * k_s, k - sw * mu * c_n);
    let a = m11 * m22 - m12 * m21;
    let b = -(k11 * m22 + k22 * m11 - k12 * m21 - k21 * m12);
    let c = k11 * k22 - k12 * k21;
    (a, b, c)
}

fn two_mode_threshold(s: &Scene) -> f64 {
    let disc = |mu: f64| {
        let (a, b, c) = two_mode(s, mu);
        b * b - 4.0 * a * c
    };
    let (mut lo, mut hi) = (0.0, 2.0);
    assert!(disc(lo) > 0.0 && disc(hi) < 0.0);
    while hi - lo > 1e-12 {
        let mid = 0.5 * (lo + hi);
        if disc(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

#[test]
fn the_floating_pads_modes_and_flutter_threshold_match_the_two_mode_analysis() {
    for caliper in [Caliper::Push, Caliper::Pull] {
        let s = floating(caliper);
        // the modes without friction
        let mut s0 = s;
        s0.mu_k = 0.0;
        let (a, b, c) = two_mode(&s0, 0.0);
        let r = (b * b - 4.0 * a * c).sqrt();
        let f: Vec<f64> = [(-b - r) / (2.0 * a), (-b + r) / (2.0 * a)].iter().map(|l| l.sqrt() / (2.0 * std::f64::consts::PI)).collect();
        let lin = sliding_stability(&s0);
        let mut model_f: Vec<f64> = lin.modes.iter().map(|m| m.frequency_hz).filter(|&h| h > 300.0).collect();
        model_f.sort_by(f64::total_cmp);
        eprintln!("{caliper:?}: two-mode {f:?} Hz, model {model_f:?} Hz (all modes {:?})", lin.modes);
        assert_eq!(model_f.len(), 2);
        for (p, q) in f.iter().zip(&model_f) {
            assert!((p - q).abs() / p < 1e-9, "{caliper:?}: modes {f:?} vs {model_f:?}");
        }
        assert!((f[0] - 400.8).abs() < 0.5 && (f[1] - 448.7).abs() < 0.5, "{f:?}");
        // the flutter threshold in mu
        let closed = two_mode_threshold(&s);
        let model = instability_threshold_mu(&s, 0.0, 1.0, 1e-9).expect("a threshold in [0, 1]");
        eprintln!("{caliper:?}: flutter at mu = {closed:.6} (two-mode), {model:.6} (model's linearisation)");
        assert!((model - closed).abs() / closed < 0.01, "{caliper:?}: {model} vs {closed}");
        assert!((closed - 0.363).abs() < 0.002, "{closed}");
    }
}

/// Growth rate [1/s] of y's deviation from steady sliding in a run started there with a 10 nm
/// perturbation of y, from its RMS over 5 ms at a quarter of the run and over the last 5 ms
/// (the run ends at `seconds` or at its first transition), whether the run left steady sliding
/// (a transition) before `seconds`, and the linearisation's largest growth rate.
fn measured_growth(scene: &Scene, seconds: f64) -> (f64, bool, f64) {
    let lin = sliding_stability(scene);
    let mut st = AnyModel2Stepper::<f64>::new(scene).unwrap();
    let mut z = lin.state;
    z[1] = 0.0;
    z[Y] += 1e-8;
    st.set_state(z, Regime::SlipSlower);
    let steps = (seconds / scene.dt).round() as usize;
    let window = (0.005 / scene.dt).round() as usize;
    let mut dev = Vec::with_capacity(steps);
    for _ in 0..steps {
        st.step().unwrap();
        if st.transitions() > 0 {
            break;
        }
        dev.push(st.state()[Y] - lin.state[Y]);
    }
    let left = dev.len() < steps;
    let rms = |w: &[f64]| (w.iter().map(|d| d * d).sum::<f64>() / w.len() as f64).sqrt();
    let n = dev.len();
    // from a quarter of the run on (the decaying partner modes have gone by then) to its end
    let start = n / 4;
    let first = rms(&dev[start..start + window]);
    let last = rms(&dev[n - window..]);
    let span = (n - window - start) as f64 * scene.dt;
    ((last / first).ln() / span, left, lin.max_growth_rate())
}

/// Either side of the threshold, with 0.5 % damping on every degree of freedom (damping moves
/// the threshold: it is the linearisation's for the damped pad, found by bisection): at 0.6 of
/// it sliding decays, at 1.4 of it the perturbation grows at the linearisation's rate (within
/// 5 %) until the pad sticks (stick-slip takes over).
#[test]
fn sliding_decays_below_the_flutter_threshold_and_grows_above_it() {
    for caliper in [Caliper::Push, Caliper::Pull] {
        let mut s = floating(caliper);
        let k_s = s.k_l + s.k_t;
        s.c_y = 2.0 * 0.005 * (k_s * s.m).sqrt();
        s.c_phi = 2.0 * 0.005 * (stickslip_model::Coefficients::of(&s).k_rot * s.inertia).sqrt();
        s.c_x = 2.0 * 0.005 * (s.k_g * s.m).sqrt();
        s.mu_s = 0.6;
        s.duration = 0.5;
        s.stats_from = 0.1;
        let mu_c = instability_threshold_mu(&s, 0.0, 0.55, 1e-9).expect("a threshold");
        let undamped = two_mode_threshold(&s);
        let mut below = s;
        below.mu_k = 0.6 * mu_c;
        let mut above = s;
        above.mu_k = 1.4 * mu_c;
        let (g_below, left_below, lin_below) = measured_growth(&below, 0.1);
        let (g_above, left_above, lin_above) = measured_growth(&above, 0.5);
        eprintln!(
            "{caliper:?}: threshold mu = {mu_c:.4} damped (0.5 %), {undamped:.4} undamped; mu_k {:.4}: growth {g_below:.2} 1/s (linear, all modes {lin_below:.2}); mu_k {:.4}: growth {g_above:.2} 1/s (linear {lin_above:.2}), left sliding: {left_above}",
            below.mu_k, above.mu_k
        );
        // (below, y's decay is that of the bounce and pitch modes, faster than the slowest
        // mode of all, the pad's x mode, which the linearisation's largest rate is)
        assert!(!left_below && g_below < 0.0 && lin_below < 0.0, "{caliper:?}: sliding below the threshold does not decay");
        assert!(lin_above > 0.0 && g_above > 0.0, "{caliper:?}: sliding above the threshold does not grow");
        assert!((g_above - lin_above).abs() < 0.05 * lin_above, "{caliper:?}: {g_above} vs {lin_above}");
        assert!(left_above, "{caliper:?}: the flutter never reached stick-slip");
    }
}
