//! Model 2, part 1: its stepper against the thesis stepper where they must agree, its limits
//! (v_s -> 0 is Coulomb, k_b -> infinity is the constant-speed band), and the linear
//! stability of steady sliding against the closed form of docs/model.md.

use stickslip_model::model2::{AnyModel2Stepper, Model2Stats, Model2StatsObserver};
use stickslip_model::stats::StatsObserver;
use stickslip_model::{Caliper, ExactStepper, FrictionLaw, Real, Regime, Scene};

fn run2<T: Real>(scene: &Scene) -> Model2Stats {
    let mut s = AnyModel2Stepper::<T>::new(scene).unwrap();
    let mut obs = Model2StatsObserver::new(scene.stats_from, scene.v);
    let steps = (scene.duration / scene.dt).round() as u64;
    for _ in 0..steps {
        s.step_observed(&mut obs).unwrap_or_else(|h| panic!("halted: {h:?}"));
    }
    obs.finish()
}

fn run_exact(scene: &Scene) -> stickslip_model::stats::RunStats {
    let mut s = ExactStepper::<f64>::new(scene).unwrap();
    let mut obs = StatsObserver::<f64>::new(scene.stats_from, scene.dt);
    let steps = (scene.duration / scene.dt).round() as u64;
    for _ in 0..steps {
        s.step_observed(&mut obs).unwrap();
    }
    obs.finish()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// With Coulomb friction and no band, the model-2 stepper integrates the thesis model with its
/// own matrices: the periodic pull cases agree with the thesis stepper (transitions to
/// round-off; extremes within the Hermite interpolant's (omega h)^4 / 384, about 3e-7).
#[test]
fn coulomb_without_band_is_the_thesis_model() {
    for beta in [0.025, 0.040, 0.055] {
        let scene = Scene::case(Caliper::Pull, beta);
        let a = run2::<f64>(&scene);
        let b = run_exact(&scene);
        for i in 0..4 {
            assert!(rel(a.pp(i), b.pp(i)) < 1e-6, "beta {beta} q{i}: {} vs {}", a.pp(i), b.pp(i));
        }
        assert!((a.stick_fraction - b.stick_fraction).abs() < 1e-7, "{} {}", a.stick_fraction, b.stick_fraction);
        assert!(rel(a.stick_slip_hz, b.stick_slip_hz) < 1e-7);
        assert_eq!(a.slip_onsets, b.slip_onsets);
    }
}

/// Stribeck friction with v_s -> 0 tends to the Coulomb run (pull_center, f64): the stick
/// fraction, the stick-slip frequency and x's peak-to-peak approach the thesis stepper's, each
/// tenfold smaller v_s bringing them closer.
#[test]
fn stribeck_tends_to_coulomb_as_v_s_vanishes() {
    let base = Scene::case(Caliper::Pull, 0.040);
    let c = run_exact(&base);
    let mut last = f64::INFINITY;
    for vs in [1e-3, 1e-4, 1e-5, 1e-6] {
        let mut s = base;
        s.friction = FrictionLaw::Stribeck;
        s.v_s = vs;
        let a = run2::<f64>(&s);
        let err = rel(a.pp(0), c.pp(0)).max((a.stick_fraction - c.stick_fraction).abs()).max(rel(a.stick_slip_hz, c.stick_slip_hz));
        assert!(err < last, "v_s {vs}: error {err} did not fall below {last}");
        last = err;
    }
    assert!(last < 1e-4, "v_s 1e-6: {last}");
}

/// The band degree of freedom with k_b -> infinity (at a fixed damping ratio of 0.1) tends to the
/// constant-speed band. (At a fixed c_b the damping ratio falls as k_b grows, and a force
/// step on the band rings in the drive spring with an amplitude that does not shrink: the
/// stuck pad feels it through F_req.)
#[test]
fn a_stiff_band_tends_to_the_constant_speed_band() {
    let base = Scene::case(Caliper::Pull, 0.040);
    let c = run_exact(&base);
    let mut errs = Vec::new();
    for kb in [1e8, 1e10, 1e12] {
        let mut s = base;
        s.band = true;
        s.k_b = kb;
        s.c_b = 2.0 * 0.1 * (kb * s.m_b).sqrt();
        let a = run2::<f64>(&s);
        let err = rel(a.pp(0), c.pp(0)).max((a.stick_fraction - c.stick_fraction).abs()).max(rel(a.stick_slip_hz, c.stick_slip_hz));
        // the band's velocity ripple shrinks like 1 / sqrt(k_b)
        assert!(a.pp(4) < 0.02 * (1e6 / kb).sqrt(), "k_b {kb}: band velocity pp {}", a.pp(4));
        errs.push(err);
    }
    assert!(errs[1] < errs[0] && errs[2] < errs[1], "{errs:?}");
    assert!(errs[2] < 1e-5, "{errs:?}");
}

/// The 1-DOF Stribeck oracle: m = 1 kg, k = 100 N/m, N = 10 N, mu_s 0.6, mu_k 0.4, v_s = 0.01 m/s,
/// delta = 1, and c_x set so that V_cr = 0.03 m/s. Steady sliding plus a small perturbation.
fn stribeck_oracle(v: f64) -> Scene {
    let mut s = Scene::oracle_1dof();
    s.friction = FrictionLaw::Stribeck;
    s.v_s = 0.01;
    s.stribeck_exponent = 1.0;
    s.c_x = Scene::ORACLE_N0 * (s.mu_s - s.mu_k) / s.v_s * (-0.03f64 / s.v_s).exp();
    s.v = v;
    s.duration = 3.0;
    s
}

/// Growth rate [1/s] of a perturbation of steady sliding, from the ratio of the first and the
/// last peak of x - x_eq over the run, sampled at every step.
fn growth_rate(scene: &Scene) -> f64 {
    let n = Scene::ORACLE_N0;
    let mu = scene.mu_k + (scene.mu_s - scene.mu_k) * (-scene.v / scene.v_s).exp();
    let x_eq = mu * n / scene.k_g;
    let mut st = AnyModel2Stepper::<f64>::new(scene).unwrap();
    let mut z = st.state();
    z[0] = x_eq + 1e-8;
    z[1] = 0.0;
    st.set_state(z, Regime::SlipSlower);
    let steps = (scene.duration / scene.dt).round() as usize;
    let mut e = Vec::with_capacity(steps);
    for _ in 0..steps {
        st.step().unwrap();
        assert_eq!(st.regime(), Regime::SlipSlower, "t = {}, z = {:?}", st.time(), st.state());
        e.push((st.time(), st.state()[0] - x_eq));
        if (st.state()[0] - x_eq).abs() > 1e-4 {
            break; // the linear range ends (it grows into stick-slip)
        }
    }
    let peaks: Vec<(f64, f64)> = (1..e.len() - 1).filter(|&i| e[i].1 > e[i - 1].1 && e[i].1 >= e[i + 1].1).map(|i| e[i]).collect();
    let (a, b) = (peaks[0], peaks[peaks.len() - 1]);
    (b.1 / a.1).ln() / (b.0 - a.0)
}

#[test]
fn steady_sliding_grows_below_v_cr_and_decays_above() {
    let v_cr = 0.03;
    for (factor, grows) in [(0.99, true), (1.01, false), (0.8, true), (1.2, false)] {
        let s = stribeck_oracle(factor * v_cr);
        let measured = growth_rate(&s);
        let slope = -(s.mu_s - s.mu_k) * (-s.v / s.v_s).exp() / s.v_s; // mu'(V)
        let predicted = -(s.c_x + Scene::ORACLE_N0 * slope) / (2.0 * s.m);
        assert_eq!(measured > 0.0, grows, "V = {factor} V_cr: rate {measured}");
        assert!((measured - predicted).abs() <= 0.02 * predicted.abs(), "V = {factor} V_cr: {measured} vs {predicted}");
    }
}

/// The Stribeck oracle with sustained stick-slip (V = 0.02 m/s < V_cr = 0.03 m/s), 8 s, the
/// statistics over [1.3, 8] s (four cycles).
fn stribeck_cycle() -> Scene {
    let mut s = stribeck_oracle(0.02);
    s.duration = 8.0;
    s.stats_from = 1.3;
    s
}

/// ETDRK4 with exact linear flows converges: at the rig's step (1/25600 s) the period (1 /
/// stick-slip frequency) and the amplitude (x's peak-to-peak) agree with a run at 1/4 of the
/// step to 1e-9 in f64, and the f32 run agrees with f64 to 1e-4.
#[test]
fn the_stribeck_oracle_converges_in_f64_and_holds_in_f32() {
    let mut fine = stribeck_cycle();
    fine.dt = 1.0 / 102400.0;
    let reference = run2::<f64>(&fine);
    assert!(reference.slip_onsets >= 2 && reference.stick_fraction > 0.5, "{reference:?}");
    let rig = stribeck_cycle();
    let a = run2::<f64>(&rig);
    let b = run2::<f32>(&rig);
    let period = |s: &Model2Stats| 1.0 / s.stick_slip_hz;
    assert!(rel(period(&a), period(&reference)) < 1e-9, "f64 period {} vs {}", period(&a), period(&reference));
    assert!(rel(a.pp(0), reference.pp(0)) < 1e-9, "f64 amplitude {} vs {}", a.pp(0), reference.pp(0));
    assert!(rel(period(&b), period(&reference)) < 1e-4, "f32 period {} vs {}", period(&b), period(&reference));
    assert!(rel(b.pp(0), reference.pp(0)) < 1e-4, "f32 amplitude {} vs {}", b.pp(0), reference.pp(0));
}
