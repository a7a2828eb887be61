//! The model-2 rows of the report: the Stribeck scenes, their onsets observed in the model-2
//! stepper and in the model-2 reference, and the stepper's and the adaptive baseline's rows.

use super::*;

pub(super) fn model2_scene(name: &str) -> Scene {
    if name == "pull_center_stribeck" {
        let mut s = builtin::find("pull_center").expect("built-in").scene;
        s.friction = stickslip_model::FrictionLaw::Stribeck;
        s.v_s = 0.002;
        return s;
    }
    builtin::find(name).expect("built-in").scene
}

pub(super) struct Model2OnsetObserver {
    pub(super) stats: Model2StatsObserver,
    pub(super) onsets: Vec<f64>,
    pub(super) from: f64,
}

impl<T: Real> Model2Observer<T> for Model2OnsetObserver {
    fn segment(&mut self, seg: &Model2Segment<T>) {
        <Model2StatsObserver as Model2Observer<T>>::segment(&mut self.stats, seg);
    }
    fn transition(&mut self, tr: &Model2Transition<T>) {
        <Model2StatsObserver as Model2Observer<T>>::transition(&mut self.stats, tr);
        if tr.from == Regime::Stick && tr.t >= self.from {
            self.onsets.push(tr.t);
        }
    }
}

/// The model-2 stepper in precision `T` with observation (untimed).
pub(super) fn observe_model2<T: Real>(scene: &Scene) -> Result<Observed> {
    let mut st = AnyModel2Stepper::<T>::new(scene).map_err(|e| HostError::Input(e.to_string()))?;
    let from = (scene.stats_from / scene.dt).round() * scene.dt;
    let mut ob = Model2OnsetObserver { stats: Model2StatsObserver::new(from, scene.v), onsets: Vec::new(), from };
    let mut o = Observed::default();
    for _ in 0..steps_of(scene) {
        if let Err(h) = st.step_observed(&mut ob) {
            o.halt = Some(h);
            break;
        }
        o.steps += 1;
    }
    let s = ob.stats.finish();
    let z = st.state();
    o.onsets = ob.onsets;
    o.min = [s.min[0], s.min[1], s.min[2], s.min[3]];
    o.max = [s.max[0], s.max[1], s.max[2], s.max[3]];
    o.stick_fraction = s.stick_fraction;
    o.final_state = [z[0].to_f64(), z[1].to_f64(), z[2].to_f64(), z[3].to_f64()];
    Ok(o)
}

/// The model-2 reference (DOP853, its own right-hand side) at `tol`, as an observed run.
pub(super) fn observe_model2_reference(scene: &Scene, tol: Tolerances) -> Result<Observed> {
    let run = model2_reference::simulate_from(scene, model2_reference::Start::default_of(scene), tol).map_err(HostError::Input)?;
    let st = run.stats(scene).map_err(HostError::Input)?;
    Ok(Observed {
        onsets: run
            .transitions
            .iter()
            .filter(|t| t.from == model2_reference::Regime::Stick && t.t >= scene.stats_from)
            .map(|t| t.t)
            .collect(),
        min: [st.min[0], st.min[1], st.min[2], st.min[3]],
        max: [st.max[0], st.max[1], st.max[2], st.max[3]],
        stick_fraction: st.stick_fraction,
        final_state: [run.final_state[0], run.final_state[1], run.final_state[2], run.final_state[3]],
        steps: run.accepted_steps,
        halt: None,
    })
}

pub(super) fn periodic_truth(o: &Observed) -> Truth {
    Truth::Periodic {
        period: o.period().unwrap_or(f64::NAN),
        amplitude: o.pp(0),
        final_state: o.final_state,
        scale: [o.pp(0), o.pp(1), o.pp(2), o.pp(3)],
    }
}

pub(super) fn model2_row<T: Real>(name: &str, truth: &Truth, scene: &Scene, repeats: usize) -> Result<Row> {
    let o = observe_model2::<T>(scene)?;
    let (best, steps) = time_loop(
        steps_of(scene),
        repeats,
        || AnyModel2Stepper::<T>::new(scene).map_err(|e| HostError::Input(e.to_string())),
        |m| std::hint::black_box(m.step()).is_ok(),
    )?;
    Ok(fixed_step_row(name, MODEL2_METHOD, T::NAME, scene, truth, &o, best, steps))
}

pub(super) fn model2_adaptive_row(name: &str, truth: &Truth, scene: &Scene, rtol: f64, repeats: usize) -> Result<Row> {
    let tol = Tolerances::loose(rtol);
    let mut best = f64::INFINITY;
    let mut o = Observed::default();
    for _ in 0..repeats.max(1) {
        let t0 = Instant::now();
        o = observe_model2_reference(scene, tol)?;
        best = best.min(t0.elapsed().as_secs_f64());
    }
    Ok(tolerance_row(name, "dop853_adaptive", rtol, measure(truth, &o), &o, best))
}
