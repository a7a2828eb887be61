//! Model 3's options, cost per grid step (1/25600 s) on the host, f64:
//! `cargo bench -p stickslip-model --features model3 --bench model3`. Each measures 256 grid
//! steps (10 ms of simulated time) of a run already 0.5 s in (stick-slip established), from a
//! copy of it: the event runner on `rig_float_push_center` as it is (bilateral, the baseline of
//! the event path), with unilateral contact on its chattering twin (the pull caliper at beta
//! 11.5 mm, host/tests/unilateral.rs), and the pneumatic drive on `rig_push_center`.
//! Divide the time by 256 for a grid step's cost.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use std::hint::black_box;
use stickslip_model::model2::event_run::{EventRunner, GridSample};
use stickslip_model::model3::pneumatic_run::{PneumaticRunner, PneumaticSample};
use stickslip_model::{rig_set, BandDrive, Caliper, ContactLaw, Scene};

const STEPS: f64 = 256.0;

fn event_runner(c: &mut Criterion, name: &str, scene: &Scene, rtol: f64) {
    let mut warm = EventRunner::new(scene, rtol).expect("scene");
    warm.run_sampled(0.0, 0.5, scene.dt, &mut (), &mut |_: &GridSample| true).expect("warm-up");
    let t_end = 0.5 + STEPS * scene.dt;
    c.bench_function(&format!("model3_256_grid_steps/{name}/f64"), |b| {
        b.iter_batched(
            || warm.clone(),
            |mut r| {
                black_box(r.run_sampled(0.5, t_end, scene.dt, &mut (), &mut |_: &GridSample| true)).expect("run");
            },
            BatchSize::SmallInput,
        )
    });
}

fn benches(c: &mut Criterion) {
    let float = rig_set::rig_float_scene(Caliper::Push, 0.04);
    event_runner(c, "event_bilateral_rig_float_push_center", &float, 1e-10);
    let mut chatter = float;
    chatter.caliper = Caliper::Pull;
    chatter.beta = 0.0115;
    chatter.contact = ContactLaw::Unilateral;
    event_runner(c, "unilateral_chattering", &chatter, 1e-12);
    let mut pn = rig_set::rig_scene(Caliper::Push, 0.04);
    pn.drive = BandDrive::Pneumatic;
    pn.c_b = 0.0;
    let mut warm = PneumaticRunner::new(&pn, 1e-10).expect("scene");
    warm.run_sampled(0.0, 0.5, pn.dt, &mut (), &mut |_: &PneumaticSample| true).expect("warm-up");
    let t_end = 0.5 + STEPS * pn.dt;
    c.bench_function("model3_256_grid_steps/pneumatic_rig_push_center/f64", |b| {
        b.iter_batched(
            || warm.clone(),
            |mut r| {
                black_box(r.run_sampled(0.5, t_end, pn.dt, &mut (), &mut |_: &PneumaticSample| true)).expect("run");
            },
            BatchSize::SmallInput,
        )
    });
}

criterion_group! {
    name = model3;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(300)).measurement_time(std::time::Duration::from_secs(2));
    targets = benches
}
criterion_main!(model3);
