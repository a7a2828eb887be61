//! Checks of the model-2 reference (`stickslip::numerics::reference::model2`) against yardsticks
//! that do not come from it: the thesis-model reference (`reference::thesis`, its own right-hand
//! side), the linear stability of steady
//! Stribeck sliding, the stiff-band limit, and a closed-form breakaway of the stuck pad + band.

use stickslip::numerics::reference::model2::{self, Regime, Start};
use stickslip::numerics::reference::thesis::{self, Regime as ReferenceRegime};
use stickslip::numerics::reference::Tolerances;
use stickslip_model::{Caliper, FrictionLaw, Scene};

fn rel(a: f64, b: f64, scale: f64) -> f64 {
    (a - b).abs() / scale.max(f64::MIN_POSITIVE)
}

fn same_mode(m: ReferenceRegime, r: Regime) -> bool {
    matches!((m, r), (ReferenceRegime::Stick, Regime::Stick) | (ReferenceRegime::Slower, Regime::Slower) | (ReferenceRegime::Faster, Regime::Faster))
}

/// Check 1: Every model-2 option off: the same transitions and statistics as `reference.rs`.
#[test]
fn options_off_agrees_with_the_thesis_reference_on_pull_center() {
    let scene = Scene::case(Caliper::Pull, 0.040);
    assert!(!scene.uses_model2());
    let old = thesis::simulate(&scene);
    let new = model2::simulate(&scene).expect("model-2 reference run");
    assert_eq!(old.transitions.len(), new.transitions.len(), "transition counts");
    assert!(old.transitions.len() > 50, "a stick-slip run: {} transitions", old.transitions.len());
    let mut worst_t: f64 = 0.0;
    for (a, b) in old.transitions.iter().zip(&new.transitions) {
        assert!(same_mode(a.1, b.from) && same_mode(a.2, b.to), "{a:?} against {b:?}");
        worst_t = worst_t.max((a.0 - b.t).abs());
    }
    let st = new.stats(&scene).expect("window stats");
    let mut worst_s: f64 = 0.0;
    for i in 0..4 {
        let scale = old.stats.pp(i).max(old.stats.max[i].abs()).max(old.stats.min[i].abs());
        worst_s = worst_s.max(rel(st.min[i], old.stats.min[i], scale)).max(rel(st.max[i], old.stats.max[i], scale));
        // the peak-to-peak itself
        worst_s = worst_s.max(rel(st.pp(i), old.stats.pp(i), old.stats.pp(i)));
    }
    worst_s = worst_s
        .max(rel(st.stick_fraction, old.stats.stick_fraction, old.stats.stick_fraction))
        .max(rel(st.stick_slip_hz, old.stats.stick_slip_hz, old.stats.stick_slip_hz));
    assert_eq!(st.slip_onsets, old.stats.slip_onsets);
    // without the band, the band moves at exactly V and does not accelerate
    assert_eq!((st.min[4], st.max[4]), (scene.v, scene.v));
    assert_eq!((st.min[5], st.max[5]), (0.0, 0.0));
    for (i, (a, b)) in new.final_state.iter().zip(&old.final_state).enumerate() {
        worst_s = worst_s.max(rel(*a, *b, old.stats.pp(i)));
    }
    eprintln!(
        "pull_center: {} transitions, worst time difference {worst_t:.3e} s, worst statistic {worst_s:.3e} relative, {} Hz",
        new.transitions.len(),
        st.stick_slip_hz
    );
    assert!(worst_t <= 1e-9, "worst transition time difference {worst_t:e} s");
    assert!(worst_s <= 1e-8, "worst statistic difference {worst_s:e}");
}

/// The 1-DOF Stribeck oracle: N = 10 N, m = 1 kg, k = 100 N/m, mu_s = 0.6, mu_k = 0.4,
/// v_s = 0.01 m/s, delta = 1, c_x chosen so that V_cr = 0.05 m/s.
fn stribeck_oracle(v: f64) -> (Scene, f64) {
    let mut s = Scene::oracle_1dof();
    s.friction = FrictionLaw::Stribeck;
    s.v_s = 0.01;
    s.stribeck_exponent = 1.0;
    let n = Scene::ORACLE_N0;
    // V_cr = v_s ln(N (mu_s - mu_k) / (c_x v_s)) = 5 v_s
    s.c_x = n * (s.mu_s - s.mu_k) / s.v_s * (-5.0f64).exp();
    s.v = v;
    s.duration = 20.0;
    s.stats_from = 0.0;
    let v_cr = s.v_s * (n * (s.mu_s - s.mu_k) / (s.c_x * s.v_s)).ln();
    assert!((v_cr - 0.05).abs() < 1e-15);
    (s, v_cr)
}

/// Measured exponential rate of the oscillation about steady sliding, and the linear theory's.
fn sliding_growth(frac: f64) -> (f64, f64) {
    let (mut s, v_cr) = stribeck_oracle(0.0);
    s.v = frac * v_cr;
    let n = Scene::ORACLE_N0;
    let mu = |w: f64| s.mu_k + (s.mu_s - s.mu_k) * (-w / s.v_s).exp();
    let x_eq = mu(s.v) * n / s.k_g;
    let eps = 1e-6;
    let start = Start { state: [x_eq + eps, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], regime: Regime::Slower };
    let run = model2::simulate_from(&s, start, Tolerances::default()).expect("run");
    assert!(run.transitions.is_empty(), "steady sliding must not stick: {:?}", run.transitions.first());
    let h = 1e-3;
    let times: Vec<f64> = (0..=20_000).map(|k| k as f64 * h).collect();
    let zs = run.sample(&times).expect("samples");
    let e: Vec<f64> = zs.iter().map(|z| z[0] - x_eq).collect();
    // local maxima of e, refined by a parabola through three samples
    let mut peaks = Vec::new();
    for k in 1..e.len() - 1 {
        if e[k] > e[k - 1] && e[k] >= e[k + 1] && e[k] > 0.0 {
            let (a, b, c) = (e[k - 1], e[k], e[k + 1]);
            let d = 0.5 * (a - c) / (a - 2.0 * b + c);
            let peak = b - 0.25 * (a - c) * d;
            peaks.push((times[k] + d * h, peak));
        }
    }
    assert!(peaks.len() >= 25, "{} peaks", peaks.len());
    // least-squares slope of ln(peak) against time
    let nn = peaks.len() as f64;
    let mt = peaks.iter().map(|p| p.0).sum::<f64>() / nn;
    let ml = peaks.iter().map(|p| p.1.ln()).sum::<f64>() / nn;
    let sxy: f64 = peaks.iter().map(|p| (p.0 - mt) * (p.1.ln() - ml)).sum();
    let sxx: f64 = peaks.iter().map(|p| (p.0 - mt).powi(2)).sum();
    let measured = sxy / sxx;
    let mu_slope = -(s.mu_s - s.mu_k) * (-s.v / s.v_s).exp() / s.v_s;
    let predicted = -(s.c_x + n * mu_slope) / (2.0 * s.m);
    (measured, predicted)
}

/// Check 2: Steady Stribeck sliding grows below V_cr and decays above it, at the linear rate.
#[test]
fn stribeck_sliding_stability_follows_the_linear_rate() {
    for frac in [0.97, 1.03] {
        let (measured, predicted) = sliding_growth(frac);
        eprintln!(
            "V = {frac} V_cr: measured rate {measured:.6} 1/s, predicted {predicted:.6} 1/s, error {:.3e}",
            measured / predicted - 1.0
        );
        if frac < 1.0 {
            assert!(measured > 0.0 && predicted > 0.0, "grows below V_cr");
        } else {
            assert!(measured < 0.0 && predicted < 0.0, "decays above V_cr");
        }
        assert!((measured / predicted - 1.0).abs() < 0.02, "rate {measured} against {predicted}");
    }
}

/// Check 3: A band with a huge drive stiffness (and a moderate damping ratio) behaves like the band
/// at exactly V.
#[test]
fn stiff_band_tends_to_the_constant_speed_band() {
    let mut s = Scene::case(Caliper::Pull, 0.040);
    s.duration = 0.3;
    s.stats_from = 0.1;
    let plain = model2::simulate(&s).expect("no band");
    let a = plain.stats(&s).expect("stats");
    let mut sb = s;
    sb.band = true;
    sb.k_b = 1e12;
    sb.m_b = 1e3;
    // damping ratio 0.5: with c_b held fixed the band's ringing after a friction jump keeps an
    // acceleration amplitude of about dF / m_b whatever k_b (only its frequency grows), and the
    // stuck pad feels m x'' of it in F_req; with a fixed damping ratio it dies out in a few
    // periods 2 pi sqrt(m_b / k_b)
    sb.c_b = 2.0 * 0.5 * (sb.k_b * sb.m_b).sqrt();
    let banded = model2::simulate(&sb).expect("band");
    let b = banded.stats(&sb).expect("stats");
    assert_eq!(plain.transitions.len(), banded.transitions.len());
    assert!(a.slip_onsets >= 5, "{} onsets", a.slip_onsets);
    let mut worst: f64 = 0.0;
    for i in 0..4 {
        worst = worst.max(rel(a.pp(i), b.pp(i), a.pp(i)));
        let scale = a.pp(i).max(a.max[i].abs());
        worst = worst.max(rel(a.min[i], b.min[i], scale)).max(rel(a.max[i], b.max[i], scale));
    }
    worst = worst
        .max(rel(a.stick_fraction, b.stick_fraction, a.stick_fraction))
        .max(rel(a.stick_slip_hz, b.stick_slip_hz, a.stick_slip_hz))
        .max(rel(b.min[4], s.v, s.v))
        .max(rel(b.max[4], s.v, s.v));
    let worst_t = plain.transitions.iter().zip(&banded.transitions).map(|(p, q)| (p.t - q.t).abs()).fold(0.0, f64::max);
    eprintln!(
        "stiff band: worst statistic {worst:.3e} relative, worst transition shift {worst_t:.3e} s, band velocity in [{}, {}] m/s, u'' in [{:.3e}, {:.3e}] m/s^2",
        b.min[4], b.max[4], b.min[5], b.max[5]
    );
    assert!(worst <= 1e-4, "worst statistic {worst:e}");
}

/// Closed form of the stuck pad + band from the initial state (x = u = 0, x' = V, u' = 0):
/// x = u + V t, (m + m_b) u'' + (c_x + c_b) u' + (k_g + k_b) u = -(k_g V t + c_x V). Returns the
/// required friction F_req(t) = m x'' + k_g x + c_x x'.
fn stuck_f_req(s: &Scene, t: f64) -> f64 {
    let (m, mm, kk, cc, v) = (s.m, s.m + s.m_b, s.k_g + s.k_b, s.c_x + s.c_b, s.v);
    let a = -s.k_g * v / kk;
    let b = -(s.c_x * v + cc * a) / kk;
    let alpha = cc / (2.0 * mm);
    let beta = (kk / mm - alpha * alpha).sqrt();
    let c1 = -b;
    let c2 = (-a + alpha * c1) / beta;
    let (ex, co, si) = ((-alpha * t).exp(), (beta * t).cos(), (beta * t).sin());
    let u = a * t + b + ex * (c1 * co + c2 * si);
    // derivatives of e^{-alpha t} (c1 cos + c2 sin)
    let p1 = -alpha * c1 + beta * c2;
    let p2 = -alpha * c2 - beta * c1;
    let ud = a + ex * (p1 * co + p2 * si);
    let q1 = -alpha * p1 + beta * p2;
    let q2 = -alpha * p2 - beta * p1;
    let udd = ex * (q1 * co + q2 * si);
    m * udd + s.k_g * (u + v * t) + s.c_x * (v + ud)
}

/// Check 4: Band, Coulomb, 1-DOF: the first breakaway of the stuck pad + band at F_req = mu_s N.
#[test]
fn band_first_breakaway_matches_the_closed_form() {
    let mut s = Scene::oracle_1dof();
    s.band = true;
    s.m_b = 0.5;
    s.k_b = 1e4;
    s.c_b = 2.0;
    s.c_x = 0.5;
    s.duration = 1.5;
    s.stats_from = 0.0;
    let limit = s.mu_s * Scene::ORACLE_N0;
    // the first crossing on a fine grid, then bisection
    let h = 1e-4;
    let mut k = 0;
    while stuck_f_req(&s, (k + 1) as f64 * h) < limit {
        k += 1;
    }
    let (mut lo, mut hi) = (k as f64 * h, (k + 1) as f64 * h);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if stuck_f_req(&s, mid) >= limit {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let t_closed = hi;
    let run = model2::simulate(&s).expect("run");
    let first = run.transitions.first().expect("a breakaway");
    assert_eq!((first.from, first.to), (Regime::Stick, Regime::Slower));
    // the quasi-static estimate without the band's dynamics, to show the test discriminates
    let t_qs = limit / (s.k_g * s.v) * (1.0 + s.k_g / s.k_b) - s.c_x / s.k_g;
    eprintln!(
        "band breakaway: model-2 reference {:.12} s, closed form {t_closed:.12} s, difference {:.3e} s (quasi-static {t_qs:.6} s)",
        first.t,
        first.t - t_closed
    );
    assert!((first.t - t_closed).abs() < 1e-9, "{} against {t_closed}", first.t);
    assert!((t_qs - t_closed).abs() > 1e-5, "the closed form differs from the quasi-static estimate");
    // the stuck motion itself: sampled states against the closed form
    let ts = [0.3, 0.7, first.t];
    let zs = run.sample(&ts).expect("samples");
    for (t, z) in ts.iter().zip(&zs).take(2) {
        let v_rel = z[1] - s.v - z[5];
        assert!(v_rel.abs() < 1e-12, "stick holds v = 0: {v_rel:e} at {t}");
        assert!((z[0] - z[4] - s.v * t).abs() < 1e-12, "x = u + V t");
    }
    // at the breakaway state, F_req = m x'' + k x + c x' equals mu_s N
    let z = first.state;
    let xdd = (-s.k_g * z[0] - s.c_x * z[1] - s.k_b * z[4] - s.c_b * z[5]) / (s.m + s.m_b);
    let f = s.m * xdd + s.k_g * z[0] + s.c_x * z[1];
    assert!((f - limit).abs() < 1e-8 * limit, "F_req at breakaway {f} against {limit}");
}

/// Check 5: Stribeck friction with the band (all of model 2, part 1): breakaway starts slip at v = 0
/// with v' = 0, and the armed guard must neither end the slip at its start nor miss its end.
#[test]
fn stribeck_band_stick_slip_runs_and_is_consistent() {
    let mut s = Scene::case(Caliper::Push, 0.040);
    s.friction = FrictionLaw::Stribeck;
    s.v_s = 0.005;
    s.band = true;
    s.c_b = 2.0 * 0.05 * (s.k_b * s.m_b).sqrt();
    s.duration = 0.4;
    s.stats_from = 0.2;
    let run = model2::simulate(&s).expect("run");
    let st = run.stats(&s).expect("stats");
    let slips = run.transitions.iter().filter(|t| t.from != Regime::Stick).count();
    let mut shortest_slip = f64::INFINITY;
    let mut prev = 0.0;
    for tr in &run.transitions {
        if tr.from != Regime::Stick {
            shortest_slip = shortest_slip.min(tr.t - prev);
        }
        prev = tr.t;
        if tr.to == Regime::Stick {
            // stick starts with v = 0 exactly up to round-off
            assert!((tr.state[1] - s.v - tr.state[5]).abs() < 1e-15, "{tr:?}");
        }
    }
    // dense output: a transition's time gives the state the new regime starts from
    let probe: Vec<f64> = run.transitions.iter().take(6).map(|t| t.t).collect();
    let zs = run.sample(&probe).expect("samples");
    for (z, tr) in zs.iter().zip(&run.transitions) {
        assert_eq!(*z, tr.state);
    }
    eprintln!(
        "stribeck + band: {} transitions, {slips} slip ends, shortest slip {shortest_slip:.3e} s, {:.3} Hz, stick fraction {:.4}, \
         band velocity [{:.6e}, {:.6e}] m/s, u'' [{:.3e}, {:.3e}] m/s^2",
        run.transitions.len(),
        st.stick_slip_hz,
        st.stick_fraction,
        st.min[4],
        st.max[4],
        st.min[5],
        st.max[5]
    );
    assert!(st.slip_onsets >= 5 && st.stick_fraction > 0.0 && st.stick_fraction < 1.0);
    assert!(shortest_slip > 1e-4, "no slip phase ends at its own start: {shortest_slip:e} s");
    assert!(st.max[4] > s.v && st.min[4] < s.v, "the band's velocity varies");
}

/// Check 6: A Stribeck slip phase that starts at (round-off of) v = 0 with v' a hair above 0 must not
/// end at a crest of v within its first instants: the slip->stick guard is armed only once v
/// has been clearly negative (module doc of reference::model2).
#[test]
fn stribeck_slip_is_not_ended_by_round_off_at_its_start() {
    let (mut s, _) = stribeck_oracle(0.05);
    s.c_x = 0.0;
    s.duration = 1.0;
    let n = Scene::ORACLE_N0;
    // just below breakaway (x'' > 0 for a moment) and v = +1e-13 m/s: v crests at about
    // +1e-13 m/s within ~2e-8 s, then falls as the spring's force grows
    let start = Start { state: [s.mu_s * n / s.k_g - 1e-9, s.v + 1e-13, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], regime: Regime::Slower };
    let run = model2::simulate_from(&s, start, Tolerances::default()).expect("run");
    let first = run.transitions.first().expect("the slip ends");
    eprintln!("slip from v = +1e-13 m/s: first transition {:?} -> {:?} at {:.6} s", first.from, first.to, first.t);
    assert_eq!(first.from, Regime::Slower);
    assert!(first.t > 0.1, "the slip phase ended at its start: {first:?}");
}
