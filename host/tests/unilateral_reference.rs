//! Unilateral contact against its independent reference (issue 34, item 4): the model crate's
//! event runner (exact flows, Dormand-Prince in Stribeck slip, Illinois on its own solution,
//! the edges' contact states from `model2::event_run::edges`) against
//! `numerics::reference::model2::simulate_unilateral` (DOP853 on model 2's reference right-hand
//! side with the open spring taken out, bisection on every guard; docs/model.md's equations,
//! none of the model crate's matrices), both in f64.
//!
//! Measured: `cargo test --release -p stickslip --test unilateral_reference -- --nocapture`.

use stickslip::numerics::reference::model2::{simulate_unilateral, UnilateralRun};
use stickslip::numerics::reference::Tolerances;
use stickslip::scenes::unilateral::UNILATERAL_RTOL;
use stickslip_model::model2::event_run::EventRunner;
use stickslip_model::model2::{Model2Observer, Model2Segment, Model2StatsObserver, Model2Transition};
use stickslip_model::{Regime, Scene};

/// `rig_float_push_center` turned to the pull caliper with the load 11.5 mm from the trailing
/// edge: its lead edge opens and closes about 160 times a second (host/tests/unilateral.rs).
fn chattering(duration: f64) -> Scene {
    // the accuracy report's unilateral scene
    let mut s = stickslip::numerics::accuracy::unilateral_scene();
    s.duration = duration;
    s.stats_from = 0.5 * duration;
    s
}

struct Onsets {
    stats: Model2StatsObserver,
    onsets: Vec<f64>,
    from: f64,
}

impl Model2Observer<f64> for Onsets {
    fn segment(&mut self, seg: &Model2Segment<f64>) {
        self.stats.segment(seg);
    }
    fn transition(&mut self, tr: &Model2Transition<f64>) {
        self.stats.transition(tr);
        if tr.from == Regime::Stick && tr.t >= self.from {
            self.onsets.push(tr.t);
        }
    }
}

/// The product's run: slip onsets in the window, [x, x', phi, phi'] extremes, the final state,
/// each edge's open time and openings.
struct Product {
    onsets: Vec<f64>,
    min: [f64; 4],
    max: [f64; 4],
    final_state: [f64; 8],
    open_s: [f64; 2],
    openings: [u64; 2],
}

fn product(scene: &Scene, rtol: f64) -> Product {
    let mut runner = EventRunner::new(scene, rtol).expect("a valid scene");
    let mut ob = Onsets {
        stats: Model2StatsObserver::new(scene.stats_from, scene.v).without_interpolation(),
        onsets: Vec::new(),
        from: scene.stats_from,
    };
    runner.run(scene.stats_from, scene.duration, &mut ob).expect("the product's run completes");
    let s = ob.stats.finish();
    let e = runner.edges().expect("a unilateral run reports its edges");
    let z = runner.state();
    Product {
        onsets: ob.onsets,
        min: [s.min[0], s.min[1], s.min[2], s.min[3]],
        max: [s.max[0], s.max[1], s.max[2], s.max[3]],
        final_state: [z[0], z[1], z[2], z[3], z[4], z[5], z[6], z[7]],
        open_s: e.open_s,
        openings: e.openings,
    }
}

/// The largest difference of slip onsets [s] (the same count required).
fn onset_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len(), "slip onsets: product {}, reference {}", a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// The largest difference of the [x, x', phi, phi'] extremes over each one's range.
fn extreme_difference(p: &Product, r: &UnilateralRun) -> f64 {
    (0..4)
        .map(|i| {
            let range = r.max[i] - r.min[i];
            ((p.min[i] - r.min[i]).abs().max((p.max[i] - r.max[i]).abs())) / range
        })
        .fold(0.0, f64::max)
}

/// The largest difference of the final [x, x', phi, phi'] over each one's range in the window.
fn final_difference(p: &Product, r: &UnilateralRun) -> f64 {
    (0..4).map(|i| (p.final_state[i] - r.final_state[i]).abs() / (r.max[i] - r.min[i])).fold(0.0, f64::max)
}

#[test]
fn the_event_runner_follows_the_independent_reference_where_an_edge_chatters() {
    let scene = chattering(0.8);
    let t0 = std::time::Instant::now();
    let r = simulate_unilateral(&scene, Tolerances::default()).expect("the reference run");
    let t_ref = t0.elapsed().as_secs_f64();
    let t0 = std::time::Instant::now();
    let p = product(&scene, UNILATERAL_RTOL);
    let t_prod = t0.elapsed().as_secs_f64();
    let opened = r.openings[0] + r.openings[1];
    eprintln!(
        "reference: {} transitions, {} onsets, openings {:?}, open {:?} s, {} steps, {t_ref:.2} s; product openings {:?}, {t_prod:.3} s",
        r.transitions.len(),
        r.onsets.len(),
        r.openings,
        r.open_s,
        r.accepted_steps,
        p.openings
    );
    assert!(opened >= 20, "the scene must chatter: {opened} openings");
    assert_eq!(p.openings, r.openings, "openings per edge [lead, trail]");
    let d_on = onset_difference(&p.onsets, &r.onsets);
    let d_open = (0..2).map(|e| (p.open_s[e] - r.open_s[e]).abs()).fold(0.0, f64::max);
    let d_ext = extreme_difference(&p, &r);
    let d_fin = final_difference(&p, &r);
    eprintln!("product at rtol {UNILATERAL_RTOL:e}: onsets within {d_on:.2e} s, open time within {d_open:.2e} s, extremes within {d_ext:.2e}, final state within {d_fin:.2e} of the ranges");
    assert!(d_on < 1e-8, "slip onsets differ by {d_on:e} s");
    assert!(d_open < 1e-8, "open times differ by {d_open:e} s");
    assert!(d_ext < 1e-7, "extremes differ by {d_ext:e} of their ranges");
    assert!(d_fin < 1e-6, "final states differ by {d_fin:e} of the ranges");
}

#[test]
fn the_reference_converges_with_its_tolerance() {
    // the yardstick's own error: at 1e-10 it moves its events by far less than the bound above
    let scene = chattering(0.8);
    let tight = simulate_unilateral(&scene, Tolerances::default()).expect("rtol 1e-12");
    let loose = simulate_unilateral(&scene, Tolerances { rtol: 1e-10, atol: 1e-14, ..Tolerances::default() }).expect("rtol 1e-10");
    assert_eq!(tight.transitions.len(), loose.transitions.len(), "transitions at 1e-12 and 1e-10");
    let d = tight.transitions.iter().zip(&loose.transitions).map(|(a, b)| {
        assert_eq!((a.1, a.2), (b.1, b.2), "the same sequence of regimes");
        (a.0 - b.0).abs()
    });
    let d = d.fold(0.0, f64::max);
    eprintln!("reference at rtol 1e-12 against 1e-10: transitions within {d:.2e} s");
    assert!(d < 1e-9, "the reference's transitions move by {d:e} s with its tolerance");
}
