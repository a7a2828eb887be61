//! Stick at event speed (`ExactTables::jump_stick`, the maps' closed-form ring-down of the
//! groan filter): the jump against the stepper stepping the same steps, whole runs with jumps
//! against the same runs stepped, and maps with the jump against maps sampled at every step.
//! The reference is always the ordinary step, a different computation (per-substep dyadic
//! flows, one step at a time) from the jump's (flows over 2^j steps squared up in f64).

mod thesis_common;

use stickslip_model::{ExactStepper, Real, Regime, Scene, StickJump};
use thesis_common::{assert_maps_agree, builtin, map_of, rel, scenes};

/// The first stick phase from rest, jumped: the jumped stepper, a stepper at the start, and
/// the steps jumped (most of the phase).
fn first_jump<T: Real>(name: &str, scene: &Scene) -> (ExactStepper<T>, ExactStepper<T>, u64) {
    let jump = StickJump::<T>::new(scene);
    let mut jumped = ExactStepper::<T>::new(scene).unwrap();
    let stepped = jumped.clone();
    let n = {
        let (tables, state) = jumped.parts_mut();
        tables.jump_stick(&jump, state, u64::MAX)
    };
    assert!(n > 100, "{name}: the first stick phase from rest should be jumped mostly (jumped {n} steps)");
    (jumped, stepped, n)
}

#[test]
fn a_jump_lands_where_the_steps_land() {
    for (name, scene) in scenes() {
        let (mut jumped, mut stepped, n) = first_jump::<f64>(&name, &scene);
        for k in 0..n {
            stepped.step().unwrap();
            assert_eq!(stepped.regime(), Regime::Stick, "{name}: the jump of {n} steps passed a breakaway at step {}", k + 1);
        }
        assert_eq!(jumped.steps(), stepped.steps());
        let (a, b) = (jumped.state(), stepped.state());
        // x from the same anchor and substep count: the same bits
        assert_eq!(a.x, b.x, "{name}: x");
        assert_eq!(a.xdot, b.xdot, "{name}: x'");
        assert!(rel(a.phi, b.phi) < 1e-12, "{name}: phi {} vs {}", a.phi, b.phi);
        let scale = b.phidot.abs().max(1e-9 * scene.v / scene.l);
        assert!((a.phidot - b.phidot).abs() / scale < 1e-9, "{name}: phi' {} vs {}", a.phidot, b.phidot);
        // and the breakaway that follows is where the stepped run finds it
        let t_break = |st: &mut ExactStepper<f64>| -> f64 {
            for _ in 0..200_000 {
                st.step().unwrap();
                if let Some(tr) = st.transitions().first() {
                    return tr.t;
                }
            }
            panic!("{name}: no breakaway");
        };
        let (ta, tb) = (t_break(&mut jumped), t_break(&mut stepped));
        assert!((ta - tb).abs() < 1e-12, "{name}: breakaway at {ta} s after the jump, {tb} s stepped");
    }
}

/// In f32 the jump (flows over 2^j steps squared in f64, then rounded) is no less accurate
/// than f32's own steps: both against the f64 stepped state, phi within twice the stepped
/// f32 error or 3e-7 relative (a few f32 ulps; measured 3e-9 to 1.2e-7 jumped, 2e-8 to 6.3e-7
/// stepped, over the six cases and the 1-DOF scene).
#[test]
fn an_f32_jump_is_as_accurate_as_f32_steps() {
    for (name, scene) in scenes() {
        let (jumped, mut stepped, n) = first_jump::<f32>(&name, &scene);
        let mut exact = ExactStepper::<f64>::new(&scene).unwrap();
        for _ in 0..n {
            stepped.step().unwrap();
            exact.step().unwrap();
            assert_eq!(exact.regime(), Regime::Stick, "{name}: the f32 jump passed the f64 run's breakaway");
        }
        assert_eq!(jumped.state().x, stepped.state().x, "{name}: x");
        let phi = exact.state().phi;
        let (e_jump, e_step) = (rel(jumped.state().phi as f64, phi), rel(stepped.state().phi as f64, phi));
        assert!(e_jump <= (2.0 * e_step).max(3e-7), "{name}: phi error {e_jump:e} jumped, {e_step:e} stepped (f32 against f64)");
    }
}

/// A whole run's transitions, jumping over stick (`jump`) or stepping every step.
fn transitions(scene: &Scene, jump: bool) -> (Vec<(f64, Regime, Regime)>, u64) {
    let j = StickJump::<f64>::new(scene);
    let mut st = ExactStepper::<f64>::new(scene).unwrap();
    let steps = (scene.duration / scene.dt).round() as u64;
    let mut out = Vec::new();
    let mut jumped = 0;
    while st.steps() < steps {
        if jump {
            let left = steps - st.steps();
            let (tables, state) = st.parts_mut();
            let n = tables.jump_stick(&j, state, left);
            if n > 0 {
                jumped += n;
                continue;
            }
        }
        st.step().unwrap();
        out.extend(st.transitions().iter().map(|tr| (tr.t, tr.from, tr.to)));
    }
    (out, jumped)
}

#[test]
fn runs_with_jumps_have_the_stepped_runs_transitions() {
    for (name, scene) in scenes() {
        let (a, jumped) = transitions(&scene, true);
        let (b, _) = transitions(&scene, false);
        let steps = (scene.duration / scene.dt).round() as u64;
        assert!(jumped * 2 > steps, "{name}: only {jumped} of {steps} steps jumped");
        assert_eq!(a.len(), b.len(), "{name}: {} transitions with jumps, {} stepped", a.len(), b.len());
        assert!(a.len() >= 4, "{name}: a stick-slip run");
        for (x, y) in a.iter().zip(&b) {
            assert_eq!((x.1, x.2), (y.1, y.2), "{name}: transition kinds");
            // rounding-level at first; a run that amplifies differences (push_trail: 1e-16 s
            // at 0.03 s, tenfold every 0.1 s to 6e-9 s at 1 s, as a one-ulp change of mu_s
            // does to the stepped run) may carry them to 1e-8 s by the run's end
            let tol = if y.0 < 0.2 { 1e-13 } else { 1e-7 };
            assert!((x.0 - y.0).abs() < tol, "{name}: transition at {} s with jumps, {} s stepped", x.0, y.0);
        }
    }
}

/// The maps' statistics with the jump and with every step sampled: the event times to
/// rounding as the run amplifies it, so the stick fraction, the frequency and the
/// peak-to-peak values to 1e-6; the groan RMS to 1e-5 (the ring-down in closed form in f64
/// where the sampled path runs the filter in f32: measured 3e-7 median, 2.7e-6 worst over
/// the 8,121 cells of the README's map whose stick fraction agrees to 1e-9).
#[test]
fn a_map_with_the_jump_is_the_sampled_map() {
    let sweeps = ["beta=0.02:0.075:6", "mu_s=0.4:0.8:5"];
    let map = |jump| map_of("push_center", builtin("push_center"), jump, &sweeps);
    let (a, b) = (map(true), map(false));
    assert_eq!(a.cells.len(), 30);
    let stick_slip = assert_maps_agree("push_center with the jump against sampled", &a, &b);
    assert!(stick_slip >= 20, "the map should be mostly stick-slip from rest ({stick_slip})");
}
