//! The effect of the f32 exponential on a Stribeck run (docs/numerics.md, "Transcendentals on
//! the Cortex-M4F"): push_center with Stribeck friction (v_s = 0.002 m/s, delta = 1), 1 s at
//! dt = 1/25 600 s, statistics over [0.5, 1] s, in f32 and f64 on `AnyModel2Stepper`.
//!
//!     cargo run --release -p stickslip-model --example stribeck_exp
//!     cargo run --release -p stickslip-model --example stribeck_exp --features libm-exp
//!     cargo run --release -p stickslip-model --example stribeck_exp --features micromath
//!
//! The first uses the model's own `expf::expf` for f32, the second libm::expf, the third
//! micromath's exp (f64 is libm in all three). Each
//! prints one line per precision: `exp=<f32 exp> <precision> period_s=... x_pp_m=...
//! stick_fraction=... transitions=...`, with the full significand so two runs can be compared.
use stickslip_model::model2::{AnyModel2Stepper, Model2Stats, Model2StatsObserver};
use stickslip_model::{Caliper, FrictionLaw, Real, Scene};

fn scene() -> Scene {
    let mut s = Scene::case(Caliper::Push, 0.040);
    s.friction = FrictionLaw::Stribeck;
    s.v_s = 0.002;
    s.stribeck_exponent = 1.0;
    s.dt = 1.0 / 25_600.0;
    s.duration = 1.0;
    s.stats_from = 0.5;
    s
}

fn run<T: Real>(scene: &Scene) -> Model2Stats {
    let mut st = AnyModel2Stepper::<T>::new(scene).expect("valid scene");
    let mut obs = Model2StatsObserver::new(scene.stats_from, scene.v);
    let steps = (scene.duration / scene.dt).round() as u64;
    for _ in 0..steps {
        st.step_observed(&mut obs).unwrap_or_else(|h| panic!("{} run halted: {h:?}", T::NAME));
    }
    obs.finish()
}

fn main() {
    let exp = if cfg!(feature = "micromath") {
        "micromath"
    } else if cfg!(feature = "libm-exp") {
        "libm"
    } else {
        "model"
    };
    let s = scene();
    for (name, st) in [("f32", run::<f32>(&s)), ("f64", run::<f64>(&s))] {
        println!(
            "exp={exp} {name} period_s={:.17e} x_pp_m={:.17e} stick_fraction={:.6} transitions={}",
            1.0 / st.stick_slip_hz,
            st.pp(0),
            st.stick_fraction,
            st.transitions
        );
    }
}
