//! The alternative methods against the closed form of the 1-DOF mass on a moving belt: each
//! converges as the step shrinks (first order through the transitions), and the exact method
//! does not need to.

use stickslip_model::methods::{AnyMethod, Method, MethodKind};
use stickslip_model::{Real, Regime, Scene};

fn oracle(dt: f64) -> Scene {
    let mut s = Scene::oracle_1dof();
    s.dt = dt;
    s
}

/// T_stick + T_slip of model.md's check values.
fn true_period() -> f64 {
    let (omega, delta, v) = (10.0f64, 0.02f64, 0.05f64);
    2.0 * delta / v + (2.0 * std::f64::consts::PI - 2.0 * (omega * delta / v).atan()) / omega
}

fn period<T: Real>(kind: MethodKind, dt: f64) -> f64 {
    let s = oracle(dt);
    let mut m = AnyMethod::<T>::new(kind, &s).unwrap();
    let mut onsets = Vec::new();
    for _ in 0..(s.duration / s.dt).round() as u64 {
        m.step().unwrap();
        onsets.extend(m.transitions().iter().filter(|t| t.from == Regime::Stick).map(|t| t.t));
    }
    assert!(onsets.len() >= 4, "{}: {} slip onsets", kind.name(), onsets.len());
    (onsets[onsets.len() - 1] - onsets[0]) / (onsets.len() - 1) as f64
}

#[test]
fn first_order_methods_converge_on_the_closed_form() {
    let p = true_period();
    for kind in [MethodKind::ExplicitEuler, MethodKind::SymplecticEuler, MethodKind::MoreauJean] {
        let coarse = ((period::<f64>(kind, 1e-3) - p) / p).abs();
        let fine = ((period::<f64>(kind, 1e-5) - p) / p).abs();
        eprintln!("{}: period error {coarse:.2e} at 1 ms, {fine:.2e} at 10 us", kind.name());
        // first order: 100x smaller step, at least 20x smaller error
        assert!(fine < coarse / 20.0, "{}: {coarse} -> {fine}", kind.name());
        assert!(fine < 1e-4, "{}: {fine}", kind.name());
    }
}

#[test]
fn rk4_karnopp_approaches_the_closed_form() {
    let p = true_period();
    let coarse = ((period::<f64>(MethodKind::Rk4Karnopp, 1e-3) - p) / p).abs();
    let fine = ((period::<f64>(MethodKind::Rk4Karnopp, 1e-5) - p) / p).abs();
    eprintln!("rk4_karnopp: period error {coarse:.2e} at 1 ms, {fine:.2e} at 10 us");
    assert!(fine < coarse, "{coarse} -> {fine}");
    assert!(fine < 1e-2, "{fine}");
}

#[test]
fn exact_method_is_exact_at_any_step() {
    let p = true_period();
    for dt in [1e-3, 1e-5] {
        let e = ((period::<f64>(MethodKind::Exact, dt) - p) / p).abs();
        assert!(e < 1e-12, "dt {dt}: {e}");
    }
}

#[test]
fn every_method_runs_in_both_precisions() {
    for kind in MethodKind::ALL {
        let a = period::<f64>(kind, 1.0 / 25600.0);
        let b = period::<f32>(kind, 1.0 / 25600.0);
        assert!(((a - b) / a).abs() < 1e-2, "{}: f64 {a} f32 {b}", kind.name());
    }
}
