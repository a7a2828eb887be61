//! One step of each method, f32 and f64, on the 2-DOF pull_center scene at the rig's rate
//! (1/25600 s) and on the 1-DOF oracle: `cargo bench -p stickslip-model --bench step`.
//! The steppers run on continuously, so the measured mean includes transitions at their
//! natural rate (about 90 per second of simulated time, one per 290 steps); a run that
//! halts (explicit Euler loses contact on pull_center) is restarted, outside the timing.
//!
//! Model 2: 1000 steps of each composition's specialised stepper (`model2_1000_steps/<composition>/<T>`)
//! on pull_center with that composition's options of the rig set (docs/numerics.md,
//! "Compositions"), continuing from run to run (stick, slip and transitions at their rate);
//! part 2's `stribeck+band+face` (the same scene with the face) and `stribeck+float+face`
//! (rig_float_pull_center).

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use std::hint::black_box;
use stickslip_model::methods::{AnyMethod, Method, MethodKind};
use stickslip_model::model2::{Band, Composition, Model2Stepper, Stribeck, StribeckBand, StribeckBandFace, StribeckFloatFace};
use stickslip_model::rig_set::pre_fit_rig_scene;
use stickslip_model::{Caliper, ExactStepper, FrictionLaw, Real, Scene};

fn model2<T: Real, C: Composition>(c: &mut Criterion) {
    // the rig set before its Table 3.1 fit (a friction drop of 0.10): the scenes the
    // documented figures (docs/numerics.md, "Compositions") were measured on
    let mut scene = pre_fit_rig_scene(Caliper::Pull, 0.040);
    scene.band = C::BAND;
    if !C::STRIBECK {
        scene.friction = FrictionLaw::Coulomb;
    }
    // part 2: the face, and the floating pad as in the rig set with part 2 (rig_float_scene,
    // with the pre-fit friction and drive)
    scene.face = C::FACE;
    if C::FLOAT {
        scene = stickslip_model::rig_set::pre_fit(stickslip_model::rig_set::rig_float_scene(Caliper::Pull, 0.040));
    }
    let id = format!("model2_1000_steps/{}/{}", C::NAME, T::NAME);
    let mut st = Model2Stepper::<T, C>::new(&scene).unwrap();
    c.bench_function(&id, |b| {
        b.iter(|| {
            for _ in 0..1000 {
                black_box(st.step()).unwrap();
            }
        })
    });
}

fn bench_method<T: Real>(c: &mut Criterion, scene_name: &str, scene: &Scene, kind: MethodKind) {
    let id = format!("step/{scene_name}/{}/{}", kind.name(), T::NAME);
    c.bench_function(&id, |b| {
        b.iter_batched_ref(
            || AnyMethod::<T>::new(kind, scene).unwrap(),
            |m| {
                for _ in 0..1000 {
                    if black_box(m.step()).is_err() {
                        break;
                    }
                }
            },
            BatchSize::LargeInput,
        )
    });
}

fn exact_direct<T: Real>(c: &mut Criterion, scene_name: &str, scene: &Scene) {
    // the exact stepper without the enum dispatch: the figure the bound is about
    let id = format!("exact_direct_1000_steps/{scene_name}/{}", T::NAME);
    let mut st = ExactStepper::<T>::new(scene).unwrap();
    c.bench_function(&id, |b| {
        b.iter(|| {
            for _ in 0..1000 {
                black_box(st.step()).unwrap();
            }
        })
    });
}

fn for_each_model2<T: Real>(c: &mut Criterion) {
    model2::<T, Band>(c);
    model2::<T, Stribeck>(c);
    model2::<T, StribeckBand>(c);
    model2::<T, StribeckBandFace>(c);
    model2::<T, StribeckFloatFace>(c);
}

fn benches(c: &mut Criterion) {
    let pull = Scene::case(Caliper::Pull, 0.040);
    let oracle = Scene::oracle_1dof();
    exact_direct::<f64>(c, "pull_center", &pull);
    exact_direct::<f32>(c, "pull_center", &pull);
    exact_direct::<f64>(c, "oracle_1dof", &oracle);
    // damping is part of each regime's flow: it must cost nothing per step
    let mut damped = pull;
    damped.c_x = 50.0;
    damped.c_phi = 0.05;
    exact_direct::<f64>(c, "pull_center_damped", &damped);
    for_each_model2::<f64>(c);
    for_each_model2::<f32>(c);
    for kind in MethodKind::ALL {
        bench_method::<f64>(c, "pull_center", &pull, kind);
        bench_method::<f32>(c, "pull_center", &pull, kind);
    }
}

criterion_group! {
    name = step;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(300)).measurement_time(std::time::Duration::from_secs(1));
    targets = benches
}
criterion_main!(step);
