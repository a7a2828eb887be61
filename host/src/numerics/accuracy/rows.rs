//! A row of the report per method, precision and step (or tolerance): its errors against the
//! truth and its run time.

use super::*;

/// The row of a fixed-step run: its errors against `truth` and its best time `run_s` over
/// `steps` steps.
#[allow(clippy::too_many_arguments)]
pub(super) fn fixed_step_row(
    scene_name: &str,
    method: &str,
    precision: &str,
    scene: &Scene,
    truth: &Truth,
    o: &Observed,
    run_s: f64,
    steps: u64,
) -> Row {
    let (error, ep, ea, ef) = measure(truth, o);
    Row {
        scene: scene_name.into(),
        method: method.into(),
        precision: precision.into(),
        dt: Some(scene.dt),
        error,
        ns_per_step: (steps > 0).then(|| run_s * 1e9 / steps as f64),
        run_s,
        steps,
        outcome: outcome_word(&o.halt),
        rtol: None,
        error_period: ep,
        error_amplitude: ea,
        error_final: ef,
    }
}

pub(super) fn outcome_word(h: &Option<Halt>) -> String {
    match h {
        None => "completed".into(),
        Some(Halt::ContactLoss { .. }) => "contact_loss".into(),
        Some(Halt::Diverged { stiffness_margin, .. }) if *stiffness_margin <= 0.0 => "sprag".into(),
        Some(Halt::Diverged { .. }) => "diverged".into(),
        Some(Halt::NonFinite { .. }) => "non_finite".into(),
        Some(Halt::TransitionStorm { .. }) => "transition_storm".into(),
    }
}

pub(super) fn method_row<T: Real>(scene_name: &str, truth: &Truth, kind: MethodKind, scene: &Scene, repeats: usize) -> Result<Row> {
    let o = observe::<T>(kind, scene)?;
    let (run_s, steps) = time_steps::<T>(kind, scene, repeats)?;
    Ok(fixed_step_row(scene_name, kind.name(), T::NAME, scene, truth, &o, run_s, steps))
}

pub(super) fn adaptive_row(scene_name: &str, truth: &Truth, scene: &Scene, rtol: f64, repeats: usize) -> Result<Row> {
    let tol = Tolerances::loose(rtol);
    let run = thesis::simulate_with(scene, tol, true).map_err(HostError::Input)?;
    let window_onsets: Vec<f64> = run
        .transitions
        .iter()
        .filter(|t| t.1 == thesis::Regime::Stick && t.0 >= scene.stats_from)
        .map(|t| t.0)
        .collect();
    let o = Observed {
        onsets: window_onsets,
        min: run.stats.min,
        max: run.stats.max,
        stick_fraction: run.stats.stick_fraction,
        final_state: run.final_state,
        steps: run.accepted_steps,
        halt: None,
    };
    let (error, ep, ea, ef) = measure(truth, &o);
    let mut best = f64::INFINITY;
    let mut steps = 0;
    for _ in 0..repeats.max(1) {
        let t0 = Instant::now();
        let r = thesis::simulate_with(scene, tol, false).map_err(HostError::Input)?;
        best = best.min(t0.elapsed().as_secs_f64());
        steps = r.accepted_steps;
    }
    Ok(Row {
        scene: scene_name.into(),
        method: "dop853_adaptive".into(),
        precision: "f64".into(),
        dt: None,
        error,
        ns_per_step: (steps > 0).then(|| best * 1e9 / steps as f64),
        run_s: best,
        steps,
        outcome: "completed".into(),
        rtol: Some(rtol),
        error_period: ep,
        error_amplitude: ea,
        error_final: ef,
    })
}

/// The row of a run at a tolerance `rtol` (no fixed step): its errors `err` (error, period,
/// amplitude, final) and its best time `best` over the observed run's steps.
pub(super) fn tolerance_row(name: &str, method: &str, rtol: f64, err: (Option<f64>, Option<f64>, Option<f64>, Option<f64>), o: &Observed, best: f64) -> Row {
    let (error, ep, ea, ef) = err;
    Row {
        scene: name.into(),
        method: method.into(),
        precision: "f64".into(),
        dt: None,
        error,
        ns_per_step: (o.steps > 0).then(|| best * 1e9 / o.steps as f64),
        run_s: best,
        steps: o.steps,
        outcome: outcome_word(&o.halt),
        rtol: Some(rtol),
        error_period: ep,
        error_amplitude: ea,
        error_final: ef,
    }
}
