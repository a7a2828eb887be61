//! `stickslip accuracy`: the work-precision report. Every method of the model crate, in f32 and
//! f64, at several fixed steps, on three scenes, against references that do not come from the
//! method under test; plus the adaptive DOP853 baseline at several tolerances.
//!
//! Errors (relative unless said otherwise):
//! - periodic scenes (`oracle_1dof`, `pull_center`): the larger of the period error (mean
//!   interval between slip onsets in the window) and the amplitude error (x peak-to-peak in the
//!   window). The final-state error (each of x, x', phi, phi' at the end of the run, over that
//!   quantity's peak-to-peak in the reference) is reported beside it, not folded in: it is the
//!   period error turned into phase and accumulated over the run's cycles, so it grows with the
//!   run length (in f32 at the rig's rate: a 1.7e-7 period error gives 1.3e-5 after 4 cycles);
//! - `push_center` (irregular: its trajectory is sensitive to round-off): the largest of the
//!   relative errors of the four peak-to-peak values and the stick-slip frequency, and the
//!   absolute error of the stick fraction.
//!
//! References: the closed form of docs/model.md for `oracle_1dof`; for the 2-DOF scenes the
//! exact propagator in f64 at 1/25600 s (transitions located to 2^-53 of a step, about
//! 4e-21 s), cross-checked live against DOP853 at rtol 1e-12 (the agreement is printed).
//!
//! Model 2 (`MODEL2_SCENES`): the model-2 stepper in f64 and f32 against the independent
//! model-2 reference (`reference::model2`, DOP853 at rtol 1e-12), and in f32 with each alternative
//! exponential the firmware can build with (`exp_variants`: libm's, micromath's; plain "f32"
//! rows use the model's own), beside the exponentials' own errors on the Stribeck range.
//!
//! Cost: wall time of the plain stepping loop (no statistics), the minimum over repeats;
//! ns per step = that time / steps. Peak-to-peak values of the approximate methods come from
//! their samples; the exact method's from its exact extrema (as the product reports them).

use std::path::PathBuf;
use std::time::Instant;

use serde::Serialize;
use stickslip_model::methods::{AnyMethod, Method, MethodKind};
use stickslip_model::stats::StatsObserver;
use stickslip_model::{ExactStepper, Halt, Observer, Real, Regime, Scene, Segment, Transition};
use stickslip_model::propagator::Propagator;

use crate::scenes::builtin;
use crate::error::{HostError, Result};
use crate::numerics::exp_variants::{max_rel_error_stribeck_range, ExpF32, F32Exp, LibmExp, MicromathExp, ModelExp};
use crate::numerics::reference::{model2 as model2_reference, thesis, Tolerances};
use stickslip_model::model2::{AnyModel2Stepper, Model2Observer, Model2Segment, Model2StatsObserver, Model2Transition};

/// The rig's sample period [s].
pub const RIG_DT: f64 = 1.0 / stickslip_model::design::SAMPLE_RATE_HZ;

/// Step sizes of the full report [s].
pub const FULL_DTS: [f64; 6] = [1e-6, 1e-5, RIG_DT, 1e-4, 2.5e-4, 1e-3];
/// Step sizes of `--quick` [s].
pub const QUICK_DTS: [f64; 3] = [RIG_DT, 2.5e-4, 1e-3];
/// DOP853 relative tolerances of the adaptive baseline.
pub const FULL_RTOLS: [f64; 5] = [1e-5, 1e-7, 1e-9, 1e-11, 1e-13];
pub const QUICK_RTOLS: [f64; 3] = [1e-6, 1e-8, 1e-10];

/// The bounds `--check` holds the report to.
pub const BOUND_ORACLE_F64: f64 = 1e-9;
pub const BOUND_ORACLE_F32: f64 = 1e-5;
pub const EQUAL_ERROR: f64 = 1e-6;
pub const BOUND_SPEEDUP: f64 = 10.0;
/// Model 2: the Stribeck oracle at the rig's step, against the adaptive reference.
pub const BOUND_STRIBECK_F64: f64 = 1e-6;
pub const BOUND_STRIBECK_F32: f64 = 1e-4;
/// Evenly spaced arguments of the exponentials' error over [-20, 0].
const EXP_POINTS: u32 = 200_000;
/// The model-2 stepper's method name in the rows.
pub const MODEL2_METHOD: &str = "model2";
/// Model-2 scenes of the report: the 1-DOF Stribeck oracle, a 2-DOF Stribeck case (pull_center
/// with v_s = 2 mm/s), a rig-set case and the rig set's floating-pad case (part 2: the face, a
/// floating pad); all periodic.
pub const MODEL2_SCENES: [&str; 4] = ["oracle_stribeck", "pull_center_stribeck", "rig_pull_center", "rig_float_pull_center"];

fn model2_scene(name: &str) -> Scene {
    if name == "pull_center_stribeck" {
        let mut s = builtin::find("pull_center").expect("built-in").scene;
        s.friction = stickslip_model::FrictionLaw::Stribeck;
        s.v_s = 0.002;
        return s;
    }
    builtin::find(name).expect("built-in").scene
}

struct Model2OnsetObserver {
    stats: Model2StatsObserver,
    onsets: Vec<f64>,
    from: f64,
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
fn observe_model2<T: Real>(scene: &Scene) -> Result<Observed> {
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
fn observe_model2_reference(scene: &Scene, tol: Tolerances) -> Result<Observed> {
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

fn periodic_truth(o: &Observed) -> Truth {
    Truth::Periodic {
        period: o.period().unwrap_or(f64::NAN),
        amplitude: o.pp(0),
        final_state: o.final_state,
        scale: [o.pp(0), o.pp(1), o.pp(2), o.pp(3)],
    }
}

fn model2_row<T: Real>(name: &str, truth: &Truth, scene: &Scene, repeats: usize) -> Result<Row> {
    let o = observe_model2::<T>(scene)?;
    let (best, steps) = time_loop(
        steps_of(scene),
        repeats,
        || AnyModel2Stepper::<T>::new(scene).map_err(|e| HostError::Input(e.to_string())),
        |m| std::hint::black_box(m.step()).is_ok(),
    )?;
    Ok(fixed_step_row(name, MODEL2_METHOD, T::NAME, scene, truth, &o, best, steps))
}

/// The row of a fixed-step run: its errors against `truth` and its best time `run_s` over
/// `steps` steps.
#[allow(clippy::too_many_arguments)]
fn fixed_step_row(
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

fn model2_adaptive_row(name: &str, truth: &Truth, scene: &Scene, rtol: f64, repeats: usize) -> Result<Row> {
    let tol = Tolerances::loose(rtol);
    let mut best = f64::INFINITY;
    let mut o = Observed::default();
    for _ in 0..repeats.max(1) {
        let t0 = Instant::now();
        o = observe_model2_reference(scene, tol)?;
        best = best.min(t0.elapsed().as_secs_f64());
    }
    let (error, ep, ea, ef) = measure(truth, &o);
    Ok(Row {
        scene: name.into(),
        method: "dop853_adaptive".into(),
        precision: "f64".into(),
        dt: None,
        error,
        ns_per_step: (o.steps > 0).then(|| best * 1e9 / o.steps as f64),
        run_s: best,
        steps: o.steps,
        outcome: "completed".into(),
        rtol: Some(rtol),
        error_period: ep,
        error_amplitude: ea,
        error_final: ef,
    })
}

#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub scene: String,
    pub method: String,
    pub precision: String,
    /// Fixed step [s]; null for the adaptive baseline.
    pub dt: Option<f64>,
    /// The scene's error measure (see the module doc); null when the run halted.
    pub error: Option<f64>,
    pub ns_per_step: Option<f64>,
    pub run_s: f64,
    pub steps: u64,
    /// completed, or the halt's keyword.
    pub outcome: String,
    /// For the adaptive baseline: its relative tolerance.
    pub rtol: Option<f64>,
    pub error_period: Option<f64>,
    pub error_amplitude: Option<f64>,
    pub error_final: Option<f64>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub rows: Vec<Row>,
    /// pull_center: adaptive run time / exact f64 run time, at the cheapest runs of each with
    /// error <= 1e-6.
    pub speedup_at_equal_error: Option<f64>,
    /// Cross-check of the 2-DOF reference: exact f64 against DOP853 at rtol 1e-12 on
    /// pull_center: worst transition time difference [s] and worst pp relative difference.
    pub reference_check: ReferenceCheck,
    pub checks: Vec<Check>,
    /// The f32 exponentials Stribeck slip can use on the Cortex-M4F: each one's own error over
    /// exp(-y), y in [0, 20]; their effect on the runs is in the model-2 rows (precision
    /// "f32" is the model's own exp, "f32 libm exp" and "f32 micromath exp" the others).
    pub exp_f32: Vec<ExpRow>,
}

#[derive(Clone, Debug, Serialize)]
pub struct ExpRow {
    pub exp: String,
    /// The precision label of its model-2 rows ("f32" rows use the model's exp).
    pub precision: String,
    /// Max relative error of exp(-y) against f64 libm::exp, y in [0, 20].
    pub max_rel_error: f64,
    pub at_y: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct ReferenceCheck {
    pub transitions: usize,
    pub worst_time_difference_s: f64,
    pub worst_pp_difference: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct Check {
    pub what: String,
    pub value: Option<f64>,
    pub bound: f64,
    pub passed: bool,
}

/// What a run of a method shows about the motion.
#[derive(Clone, Debug, Default)]
struct Observed {
    onsets: Vec<f64>,
    min: [f64; 4],
    max: [f64; 4],
    stick_fraction: f64,
    final_state: [f64; 4],
    steps: u64,
    halt: Option<Halt>,
}

impl Observed {
    fn period(&self) -> Option<f64> {
        (self.onsets.len() >= 2).then(|| (self.onsets[self.onsets.len() - 1] - self.onsets[0]) / (self.onsets.len() - 1) as f64)
    }
    fn pp(&self, i: usize) -> f64 {
        self.max[i] - self.min[i]
    }
}

struct ExactObserver<T: Real> {
    stats: StatsObserver<T>,
    onsets: Vec<f64>,
    from: f64,
}

impl<T: Real> Observer<T> for ExactObserver<T> {
    fn segment(&mut self, seg: &Segment<T>, prop: &Propagator<T>) {
        self.stats.segment(seg, prop);
    }
    fn transition(&mut self, tr: &Transition<T>) {
        self.stats.transition(tr);
        if tr.from == Regime::Stick && tr.t >= self.from {
            self.onsets.push(tr.t);
        }
    }
}

fn steps_of(scene: &Scene) -> u64 {
    (scene.duration / scene.dt).round() as u64
}

fn to_f64(z: stickslip_model::State<impl Real>) -> [f64; 4] {
    [z.x.to_f64(), z.xdot.to_f64(), z.phi.to_f64(), z.phidot.to_f64()]
}

/// Runs `kind` in precision `T` with observation (untimed).
#[allow(clippy::needless_range_loop)] // min and max of the same component
fn observe<T: Real>(kind: MethodKind, scene: &Scene) -> Result<Observed> {
    let n = steps_of(scene);
    let window_from = (scene.stats_from / scene.dt).round() as u64;
    if kind == MethodKind::Exact {
        let mut st = ExactStepper::<T>::new(scene).map_err(|e| HostError::Input(e.to_string()))?;
        let mut ob = ExactObserver { stats: StatsObserver::<T>::new(scene.stats_from, scene.dt), onsets: Vec::new(), from: window_from as f64 * scene.dt };
        let mut halt = None;
        let mut steps = 0;
        for _ in 0..n {
            if let Err(h) = st.step_observed(&mut ob) {
                halt = Some(h);
                break;
            }
            steps += 1;
        }
        let s = ob.stats.finish();
        return Ok(Observed {
            onsets: ob.onsets,
            min: s.min,
            max: s.max,
            stick_fraction: s.stick_fraction,
            final_state: to_f64(st.state()),
            steps,
            halt,
        });
    }
    let mut m = AnyMethod::<T>::new(kind, scene).map_err(|e| HostError::Input(e.to_string()))?;
    let mut o = Observed { min: [f64::INFINITY; 4], max: [f64::NEG_INFINITY; 4], ..Default::default() };
    let (mut stick, mut in_window) = (0u64, 0u64);
    for i in 0..n {
        if let Err(h) = m.step() {
            o.halt = Some(h);
            break;
        }
        o.steps += 1;
        if i + 1 >= window_from {
            for tr in m.transitions() {
                if tr.from == Regime::Stick {
                    o.onsets.push(tr.t);
                }
            }
            let z = to_f64(m.state());
            for k in 0..4 {
                o.min[k] = o.min[k].min(z[k]);
                o.max[k] = o.max[k].max(z[k]);
            }
            in_window += 1;
            if m.regime() == Regime::Stick {
                stick += 1;
            }
        }
    }
    o.stick_fraction = if in_window > 0 { stick as f64 / in_window as f64 } else { 0.0 };
    o.final_state = to_f64(m.state());
    Ok(o)
}

/// Wall time of a plain loop of `n` steps (`step` false: the run halted), the minimum over
/// `repeats` fresh steppers from `make` [s], and the steps done.
fn time_loop<S>(
    n: u64,
    repeats: usize,
    mut make: impl FnMut() -> Result<S>,
    mut step: impl FnMut(&mut S) -> bool,
) -> Result<(f64, u64)> {
    let mut best = f64::INFINITY;
    let mut steps = 0;
    for _ in 0..repeats.max(1) {
        let mut m = make()?;
        let t0 = Instant::now();
        let mut k = 0;
        while k < n {
            if !step(&mut m) {
                break;
            }
            k += 1;
        }
        best = best.min(t0.elapsed().as_secs_f64());
        steps = k;
    }
    Ok((best, steps))
}

/// Wall time of the plain stepping loop of a method, the minimum over `repeats` [s].
fn time_steps<T: Real>(kind: MethodKind, scene: &Scene, repeats: usize) -> Result<(f64, u64)> {
    time_loop(
        steps_of(scene),
        repeats,
        || AnyMethod::<T>::new(kind, scene).map_err(|e| HostError::Input(e.to_string())),
        |m| std::hint::black_box(m.step()).is_ok(),
    )
}

/// The reference against which a scene's runs are measured.
#[derive(Clone, Debug)]
enum Truth {
    Periodic { period: f64, amplitude: f64, final_state: [f64; 4], scale: [f64; 4] },
    Statistics { pp: [f64; 4], stick_fraction: f64, hz: f64 },
}

/// The closed form of the mass on a moving belt (docs/model.md), N = ORACLE_N0.
fn oracle_truth(scene: &Scene) -> Truth {
    let (m, k, n, v) = (scene.m, scene.k_g, builtin::ORACLE_N0, scene.v);
    let (mu_s, mu_k) = (scene.mu_s, scene.mu_k);
    let omega = (k / m).sqrt();
    let delta = (mu_s - mu_k) * n / k;
    let x_k = mu_k * n / k;
    let x_r = (2.0 * mu_k - mu_s) * n / k;
    let r = (delta * delta + (v / omega).powi(2)).sqrt();
    let t_stick = 2.0 * delta / v;
    let t_slip = (2.0 * std::f64::consts::PI - 2.0 * (omega * delta / v).atan()) / omega;
    let period = t_stick + t_slip;
    // from rest the pad sticks until k x = mu_s N: t_b = mu_s N / (k V); then periodic
    let t_b = mu_s * n / (k * v);
    let tau = (scene.duration - t_b).rem_euclid(period);
    let (x, xd) = if tau < t_slip {
        let (s, c) = (omega * tau).sin_cos();
        (x_k + delta * c + v / omega * s, -delta * omega * s + v * c)
    } else {
        (x_r + v * (tau - t_slip), v)
    };
    let v_min = -((omega * delta).powi(2) + v * v).sqrt();
    Truth::Periodic { period, amplitude: 2.0 * r, final_state: [x, xd, 0.0, 0.0], scale: [2.0 * r, v - v_min, 0.0, 0.0] }
}

fn exact_truth(scene: &Scene, periodic: bool) -> Result<Truth> {
    let mut s = *scene;
    s.dt = RIG_DT;
    let o = observe::<f64>(MethodKind::Exact, &s)?;
    if let Some(h) = o.halt {
        return Err(HostError::Input(format!("the reference run of the scene halted: {h:?}")));
    }
    Ok(if periodic {
        Truth::Periodic {
            period: o.period().unwrap_or(f64::NAN),
            amplitude: o.pp(0),
            final_state: o.final_state,
            scale: [o.pp(0), o.pp(1), o.pp(2), o.pp(3)],
        }
    } else {
        let hz = o.period().map_or(0.0, |p| 1.0 / p);
        Truth::Statistics { pp: [o.pp(0), o.pp(1), o.pp(2), o.pp(3)], stick_fraction: o.stick_fraction, hz }
    })
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

/// (error, period error, amplitude error, final-state error) of an observed run.
fn measure(truth: &Truth, o: &Observed) -> (Option<f64>, Option<f64>, Option<f64>, Option<f64>) {
    if o.halt.is_some() {
        return (None, None, None, None);
    }
    match truth {
        Truth::Periodic { period, amplitude, final_state, scale } => {
            let pe = o.period().map_or(1.0, |p| rel(p, *period));
            let ae = rel(o.pp(0), *amplitude);
            let mut fe: f64 = 0.0;
            for i in 0..4 {
                if scale[i] > 0.0 {
                    fe = fe.max((o.final_state[i] - final_state[i]).abs() / scale[i]);
                }
            }
            (Some(pe.max(ae)), Some(pe), Some(ae), Some(fe))
        }
        Truth::Statistics { pp, stick_fraction, hz } => {
            let mut e: f64 = (o.stick_fraction - stick_fraction).abs();
            for (i, p) in pp.iter().enumerate() {
                e = e.max(rel(o.pp(i), *p));
            }
            let h = o.period().map_or(0.0, |p| 1.0 / p);
            e = e.max(if *hz > 0.0 { rel(h, *hz) } else { h });
            (Some(e), None, None, None)
        }
    }
}

fn outcome_word(h: &Option<Halt>) -> String {
    match h {
        None => "completed".into(),
        Some(Halt::ContactLoss { .. }) => "contact_loss".into(),
        Some(Halt::Diverged { stiffness_margin, .. }) if *stiffness_margin <= 0.0 => "sprag".into(),
        Some(Halt::Diverged { .. }) => "diverged".into(),
        Some(Halt::NonFinite { .. }) => "non_finite".into(),
        Some(Halt::TransitionStorm { .. }) => "transition_storm".into(),
    }
}

fn method_row<T: Real>(scene_name: &str, truth: &Truth, kind: MethodKind, scene: &Scene, repeats: usize) -> Result<Row> {
    let o = observe::<T>(kind, scene)?;
    let (run_s, steps) = time_steps::<T>(kind, scene, repeats)?;
    Ok(fixed_step_row(scene_name, kind.name(), T::NAME, scene, truth, &o, run_s, steps))
}

fn adaptive_row(scene_name: &str, truth: &Truth, scene: &Scene, rtol: f64, repeats: usize) -> Result<Row> {
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

/// Options of the report.
#[derive(Clone, Debug)]
pub struct Options {
    pub quick: bool,
    pub repeats: usize,
    /// Called with a line of progress for stderr.
    pub progress: bool,
}

fn cross_check() -> Result<ReferenceCheck> {
    let scene = builtin::find("pull_center").expect("built-in").scene;
    let r = thesis::simulate(&scene);
    let mut st = ExactStepper::<f64>::new(&scene).map_err(|e| HostError::Input(e.to_string()))?;
    let mut ob = ExactObserver { stats: StatsObserver::<f64>::new(scene.stats_from, scene.dt), onsets: Vec::new(), from: 0.0 };
    let mut times = Vec::new();
    for _ in 0..steps_of(&scene) {
        st.step_observed(&mut ob).map_err(|h| HostError::Input(format!("{h:?}")))?;
        times.extend(st.transitions().iter().map(|t| t.t));
    }
    let s = ob.stats.finish();
    let worst_t = times.iter().zip(&r.transitions).map(|(a, b)| (a - b.0).abs()).fold(0.0, f64::max);
    let worst_pp = (0..4).map(|i| rel(s.pp(i), r.stats.pp(i))).fold(0.0, f64::max);
    let transitions = if times.len() == r.transitions.len() { times.len() } else { 0 };
    Ok(ReferenceCheck { transitions, worst_time_difference_s: worst_t, worst_pp_difference: worst_pp })
}

/// Runs the whole report.
pub fn run(opts: &Options) -> Result<Report> {
    let dts: &[f64] = if opts.quick { &QUICK_DTS } else { &FULL_DTS };
    let rtols: &[f64] = if opts.quick { &QUICK_RTOLS } else { &FULL_RTOLS };
    let mut rows = Vec::new();
    let scenes = [("oracle_1dof", true), ("pull_center", true), ("push_center", false)];
    let total = scenes.len() * (dts.len() * MethodKind::ALL.len() * 2 + rtols.len());
    let mut done = 0;
    let tick = |done: &mut usize, what: &str| {
        *done += 1;
        if opts.progress {
            eprint!("\r[{:>3}/{total}] {what:<60}", *done);
        }
    };
    for (name, periodic) in scenes {
        let base = builtin::find(name).expect("built-in scene").scene;
        let truth = if name == "oracle_1dof" { oracle_truth(&base) } else { exact_truth(&base, periodic)? };
        for &dt in dts {
            let mut scene = base;
            scene.dt = dt;
            for kind in MethodKind::ALL {
                tick(&mut done, &format!("{name} {} f64 dt {dt:.2e}", kind.name()));
                rows.push(method_row::<f64>(name, &truth, kind, &scene, opts.repeats)?);
                tick(&mut done, &format!("{name} {} f32 dt {dt:.2e}", kind.name()));
                rows.push(method_row::<f32>(name, &truth, kind, &scene, opts.repeats)?);
            }
        }
        for &rtol in rtols {
            tick(&mut done, &format!("{name} dop853 rtol {rtol:.0e}"));
            rows.push(adaptive_row(name, &truth, &base, rtol, opts.repeats)?);
        }
    }
    // model 2: its stepper in f32 and f64 against the independent adaptive reference at
    // rtol 1e-12 (reference::model2: its own right-hand side from docs/model.md)
    for name in MODEL2_SCENES {
        let base = model2_scene(name);
        let truth = periodic_truth(&observe_model2_reference(&base, Tolerances::default())?);
        for &dt in dts {
            let mut scene = base;
            scene.dt = dt;
            if opts.progress {
                eprint!("\r{name} model2 dt {dt:.2e}{:<40}", "");
            }
            rows.push(model2_row::<f64>(name, &truth, &scene, opts.repeats)?);
            rows.push(model2_row::<f32>(name, &truth, &scene, opts.repeats)?);
            // the firmware's alternative f32 exponentials, same stepper (exp_variants)
            rows.push(model2_row::<F32Exp<LibmExp>>(name, &truth, &scene, opts.repeats)?);
            rows.push(model2_row::<F32Exp<MicromathExp>>(name, &truth, &scene, opts.repeats)?);
        }
        for &rtol in rtols {
            rows.push(model2_adaptive_row(name, &truth, &base, rtol, opts.repeats)?);
        }
    }
    if opts.progress {
        eprintln!();
    }
    let speedup = speedup_at(&rows, "pull_center", EQUAL_ERROR);
    let reference_check = cross_check()?;
    let find = |scene: &str, prec: &str| {
        rows.iter()
            .find(|r| r.scene == scene && r.method == "exact" && r.precision == prec && r.dt == Some(RIG_DT))
            .and_then(|r| r.error)
    };
    let find_model2 = |scene: &str, prec: &str| {
        rows.iter()
            .find(|r| r.scene == scene && r.method == MODEL2_METHOD && r.precision == prec && r.dt == Some(RIG_DT))
            .and_then(|r| r.error)
    };
    let checks = vec![
        check("oracle_1dof exact f64 error at 1/25600 s", find("oracle_1dof", "f64"), BOUND_ORACLE_F64, false),
        check("oracle_1dof exact f32 error at 1/25600 s", find("oracle_1dof", "f32"), BOUND_ORACLE_F32, false),
        check("pull_center speed-up of exact f64 over DOP853 at error <= 1e-6", speedup, BOUND_SPEEDUP, true),
        check("oracle_stribeck model2 f64 error at 1/25600 s", find_model2("oracle_stribeck", "f64"), BOUND_STRIBECK_F64, false),
        check("oracle_stribeck model2 f32 error at 1/25600 s", find_model2("oracle_stribeck", "f32"), BOUND_STRIBECK_F32, false),
    ];
    let exp_f32 = vec![exp_row::<ModelExp>(), exp_row::<LibmExp>(), exp_row::<MicromathExp>()];
    Ok(Report { rows, speedup_at_equal_error: speedup, reference_check, checks, exp_f32 })
}

/// One f32 exponential's own error over the Stribeck law's range.
fn exp_row<E: ExpF32>() -> ExpRow {
    let (max_rel_error, at_y) = max_rel_error_stribeck_range::<E>(EXP_POINTS);
    ExpRow { exp: E::WHAT.into(), precision: E::NAME.into(), max_rel_error, at_y: at_y as f64 }
}

fn check(what: &str, value: Option<f64>, bound: f64, at_least: bool) -> Check {
    let passed = match value {
        Some(v) if at_least => v >= bound,
        Some(v) => v <= bound,
        None => false,
    };
    Check { what: what.into(), value, bound, passed }
}

/// Adaptive run time / exact f64 run time at the cheapest runs with error <= `level`.
pub fn speedup_at(rows: &[Row], scene: &str, level: f64) -> Option<f64> {
    let cheapest = |pred: &dyn Fn(&Row) -> bool| {
        rows.iter()
            .filter(|r| r.scene == scene && pred(r) && r.error.is_some_and(|e| e <= level))
            .map(|r| r.run_s)
            .fold(None, |a: Option<f64>, b| Some(a.map_or(b, |a| a.min(b))))
    };
    let exact = cheapest(&|r| r.method == "exact" && r.precision == "f64")?;
    let adaptive = cheapest(&|r| r.method == "dop853_adaptive")?;
    Some(adaptive / exact)
}

fn fmt_opt(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.2e}"))
}

/// The Markdown tables.
pub fn markdown(rep: &Report) -> String {
    let mut out = String::new();
    out.push_str("# Error against run time\n\n");
    out.push_str(
        "Error: periodic scenes (oracle_1dof, pull_center): max of the relative errors of the period and \
         the x amplitude (the final-state error, over each quantity's peak-to-peak, is the next column: it \
         is the period error accumulated as phase over the run); push_center: max of the relative errors of the four \
         peak-to-peak values and the stick-slip frequency, and the absolute error of the stick fraction. \
         Cost: minimum wall time over repeats of the plain stepping loop on this machine.\n\n",
    );
    let rc = &rep.reference_check;
    out.push_str(&format!(
        "2-DOF reference cross-check (pull_center, exact f64 against DOP853 at rtol 1e-12): {} transitions, \
         worst time difference {:.1e} s, worst peak-to-peak difference {:.1e}.\n\n",
        rc.transitions, rc.worst_time_difference_s, rc.worst_pp_difference
    ));
    for scene in ["oracle_1dof", "pull_center", "push_center"].into_iter().chain(MODEL2_SCENES) {
        if MODEL2_SCENES.contains(&scene) {
            out.push_str(&format!(
                "Model 2 ({scene}): the model-2 stepper (exact flows, ETDRK4 in Stribeck slip) against the model-2 \
                 reference (DOP853 at rtol 1e-12, its own right-hand side); period and amplitude as for the periodic \
                 scenes.\n\n"
            ));
        }
        out.push_str(&format!("## {scene}\n\n| method | precision | dt [s] | error | period | amplitude | final | ns/step | run [s] | outcome |\n|---|---|---|---|---|---|---|---|---|---|\n"));
        for r in rep.rows.iter().filter(|r| r.scene == scene) {
            let dt = match (r.dt, r.rtol) {
                (Some(dt), _) => format!("{dt:.3e}"),
                (None, Some(t)) => format!("adaptive, rtol {t:.0e}"),
                _ => "-".into(),
            };
            out.push_str(&format!(
                "| {} | {} | {} | {} | {} | {} | {} | {} | {:.3e} | {} |\n",
                r.method,
                r.precision,
                dt,
                fmt_opt(r.error),
                fmt_opt(r.error_period),
                fmt_opt(r.error_amplitude),
                fmt_opt(r.error_final),
                r.ns_per_step.map_or("-".into(), |v| format!("{v:.1}")),
                r.run_s,
                r.outcome
            ));
        }
        out.push('\n');
    }
    out.push_str(&format!(
        "pull_center at equal error (<= {EQUAL_ERROR:.0e}): DOP853 run time / exact f64 run time = {}\n\n",
        rep.speedup_at_equal_error.map_or("n/a (a method never reached that error)".into(), |s| format!("{s:.1}x"))
    ));
    out.push_str(
        "## f32 exp on the Cortex-M4F\n\nStribeck slip evaluates exp four times per ETDRK4 chunk. The model's own \
         expf is the f32 default; libm's and micromath's are the alternatives (model crate features), run by the same \
         stepper in the model-2 rows above (precision `f32 libm exp`, `f32 micromath exp`; plain `f32` is the model's \
         exp). Their own error over exp(-y), y in [0, 20], against f64:\n\n\
         | exp | model-2 rows | max relative error | at y |\n|---|---|---|---|\n",
    );
    for e in &rep.exp_f32 {
        let rows = if e.precision == ModelExp::NAME { "f32" } else { e.precision.as_str() };
        out.push_str(&format!("| {} | {} | {:.2e} | {:.4} |\n", e.exp, rows, e.max_rel_error, e.at_y));
    }
    out.push('\n');
    out.push_str("## Checks\n\n| check | value | bound | result |\n|---|---|---|---|\n");
    for c in &rep.checks {
        out.push_str(&format!("| {} | {} | {:.1e} | {} |\n", c.what, fmt_opt(c.value), c.bound, if c.passed { "pass" } else { "FAIL" }));
    }
    out
}

/// Where `--plot` writes.
pub fn default_plot_path() -> PathBuf {
    PathBuf::from("accuracy.svg")
}
