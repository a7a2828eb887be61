//! Error and time of the event-driven model-2 run (`stickslip_model::model2::event_run`) at a
//! few tolerances, against the model-2 reference (DOP853 at rtol 1e-12), measured as
//! `stickslip accuracy` measures model 2: the larger relative error of the period (mean over
//! the slip onsets in the window) and of the x peak-to-peak.
//!
//! `cargo run --release -p stickslip --example event_speed [SCENE ...]` (default
//! oracle_stribeck). The times are in-process, best of several runs, set-up included; the whole
//! process's time: `perf stat -r 20 target/release/stickslip simulate oracle_stribeck`.

use std::time::Instant;

use stickslip::numerics::reference::{model2 as reference, Regime as RefRegime, Tolerances};
use stickslip::scenes::builtin;
use stickslip_model::model2::event_run::EventRunner;
use stickslip_model::model2::{Model2Observer, Model2Segment, Model2StatsObserver, Model2Transition};
use stickslip_model::{Regime, Scene};

struct Onsets {
    stats: Model2StatsObserver,
    from: f64,
    onsets: Vec<f64>,
}

impl Model2Observer<f64> for Onsets {
    fn segment(&mut self, seg: &Model2Segment<f64>) {
        <Model2StatsObserver as Model2Observer<f64>>::segment(&mut self.stats, seg);
    }
    fn transition(&mut self, tr: &Model2Transition<f64>) {
        <Model2StatsObserver as Model2Observer<f64>>::transition(&mut self.stats, tr);
        if tr.from == Regime::Stick && tr.t >= self.from {
            self.onsets.push(tr.t);
        }
    }
}

fn period(onsets: &[f64]) -> f64 {
    (onsets[onsets.len() - 1] - onsets[0]) / (onsets.len() - 1) as f64
}

/// (period, x pp, accepted steps, located events) of the event run at `rtol`.
fn event_run(scene: &Scene, rtol: f64) -> (f64, f64, u64, u64) {
    let from = (scene.stats_from / scene.dt).round() * scene.dt;
    let t_end = (scene.duration / scene.dt).round() * scene.dt;
    let mut r = EventRunner::new(scene, rtol).expect("a valid scene");
    let mut o = Onsets { stats: Model2StatsObserver::new(from, scene.v).without_interpolation(), from, onsets: Vec::new() };
    r.run(from, t_end, &mut o).expect("the event run covers the scene");
    let s = o.stats.finish();
    eprintln!("{:?}", r.counts());
    (period(&o.onsets), s.pp(0), r.counts().steps, r.counts().events)
}

fn main() {
    let mut names: Vec<String> = std::env::args().skip(1).collect();
    if names.is_empty() {
        names.push("oracle_stribeck".into());
    }
    for name in names {
        let scene = builtin::find(&name).expect("a built-in scene").scene;
        let run = reference::simulate_from(&scene, reference::Start::default_of(&scene), Tolerances::default()).expect("reference");
        let st = run.stats(&scene).expect("reference statistics");
        let onsets: Vec<f64> = run.transitions.iter().filter(|t| t.from == RefRegime::Stick && t.t >= scene.stats_from).map(|t| t.t).collect();
        let (p_ref, a_ref) = (period(&onsets), st.pp(0));
        println!("{name}: reference period {p_ref:.12} s, x pp {a_ref:.12e} m");
        println!("{:>8}  {:>9}  {:>9}  {:>9}  {:>6}  {:>6}  {:>9}", "rtol", "error", "period", "x pp", "steps", "events", "time [ms]");
        for rtol in [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12] {
            let (p, a, steps, events) = event_run(&scene, rtol);
            let (pe, ae) = (((p - p_ref) / p_ref).abs(), ((a - a_ref) / a_ref).abs());
            let mut best = f64::INFINITY;
            for _ in 0..20 {
                let t0 = Instant::now();
                std::hint::black_box(event_run(std::hint::black_box(&scene), rtol));
                best = best.min(t0.elapsed().as_secs_f64());
            }
            println!("{rtol:>8.0e}  {:>9.2e}  {pe:>9.2e}  {ae:>9.2e}  {steps:>6}  {events:>6}  {:>9.3}", pe.max(ae), best * 1e3);
        }
    }
}
