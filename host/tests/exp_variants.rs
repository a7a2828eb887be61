//! `exp_variants::F32Exp`: f32 with another exponential runs the model's stepper bit for bit as
//! f32 when the exponential is the model's own, and differently with libm's or micromath's (so
//! the accuracy report's rows for the three are what they say).

use stickslip::numerics::exp_variants::{max_rel_error_stribeck_range, ExpF32, F32Exp, LibmExp, MicromathExp, ModelExp};
use stickslip_model::model2::AnyModel2Stepper;
use stickslip_model::{Caliper, FrictionLaw, Real, Scene};

fn stribeck_scene() -> Scene {
    let mut s = Scene::case(Caliper::Push, 0.040);
    s.friction = FrictionLaw::Stribeck;
    s.v_s = 0.002;
    s.stribeck_exponent = 1.0;
    s.dt = 1.0 / 25_600.0;
    s
}

/// The state's bits after every step of 1 s (about 38 stick-slip cycles).
fn trace<T: Real>(to_bits: impl Fn(T) -> u32) -> Vec<u32> {
    let s = stribeck_scene();
    let mut st = AnyModel2Stepper::<T>::new(&s).expect("valid scene");
    let mut out = Vec::new();
    for _ in 0..25_600 {
        st.step().expect("no halt");
        out.extend(st.state().iter().map(|&v| to_bits(v)));
    }
    out
}

fn trace_with<E: ExpF32>() -> Vec<u32> {
    trace::<F32Exp<E>>(|v| v.0.to_bits())
}

#[test]
fn model_exp_wrapper_is_f32_bit_for_bit() {
    let plain = trace::<f32>(f32::to_bits);
    assert!(trace_with::<ModelExp>() == plain, "F32Exp<ModelExp> left f32's bits");
}

#[test]
fn other_exps_change_the_run() {
    let plain = trace::<f32>(f32::to_bits);
    // the model's and libm's agree to within an ulp on most arguments: over a second of
    // Stribeck slip they part (docs/numerics.md, "Transcendentals": the two f32 periods 1.3e-7 apart)
    assert!(trace_with::<LibmExp>() != plain, "libm's expf gave the model's bits: is the wrapper's exp used?");
    assert!(trace_with::<MicromathExp>() != plain, "micromath's exp gave the model's bits");
}

#[test]
fn range_errors_are_the_exps_own() {
    // f64 libm::exp is the reference: the model's and libm's within an ulp, micromath's coarser
    let (model, _) = max_rel_error_stribeck_range::<ModelExp>(200_000);
    let (libm, _) = max_rel_error_stribeck_range::<LibmExp>(200_000);
    let (mm, _) = max_rel_error_stribeck_range::<MicromathExp>(200_000);
    assert!(model < 1.2e-7 && libm < 1.2e-7, "{model:e} {libm:e}");
    assert!(mm > 1e-4 && mm < 1e-2, "{mm:e}");
}
