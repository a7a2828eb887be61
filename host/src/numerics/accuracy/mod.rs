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

mod markdown;
mod model2_rows;
mod model3_rows;
mod observe;
mod rows;
mod truth;
pub use markdown::*;
use model2_rows::*;
pub use model3_rows::{
    BOUND_PNEUMATIC, BOUND_UNILATERAL, EVENT_METHOD, FULL_EVENT_RTOLS, FULL_PNEUMATIC_RTOLS, PNEUMATIC_METHOD, PNEUMATIC_SCENE, QUICK_EVENT_RTOLS,
    QUICK_PNEUMATIC_RTOLS, UNILATERAL_SCENE, pneumatic_scene, unilateral_scene,
};
use observe::*;
use rows::*;
use truth::*;

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
    // model 3: unilateral contact's event runner against its independent reference
    if opts.progress {
        eprint!("\r{UNILATERAL_SCENE} event runner and reference{:<40}", "");
    }
    let event_rtols: &[f64] = if opts.quick { &QUICK_EVENT_RTOLS } else { &FULL_EVENT_RTOLS };
    rows.extend(model3_rows::unilateral_rows(event_rtols, rtols, opts.repeats)?);
    // model 3: the pneumatic drive's runner against its independent reference
    if opts.progress {
        eprint!("\r{PNEUMATIC_SCENE} pneumatic runner and reference{:<40}", "");
    }
    let pneumatic_rtols: &[f64] = if opts.quick { &QUICK_PNEUMATIC_RTOLS } else { &FULL_PNEUMATIC_RTOLS };
    rows.extend(model3_rows::pneumatic_rows(pneumatic_rtols, rtols, opts.repeats)?);
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
        check(
            &format!("{UNILATERAL_SCENE} event runner f64 error at rtol 1e-12 (unilateral contact)"),
            rows.iter()
                .find(|r| r.scene == UNILATERAL_SCENE && r.method == EVENT_METHOD && r.rtol == Some(1e-12))
                .and_then(|r| r.error),
            BOUND_UNILATERAL,
            false,
        ),
        check(
            &format!("{PNEUMATIC_SCENE} pneumatic runner f64 error at rtol 1e-10 (the pneumatic drive)"),
            rows.iter()
                .find(|r| r.scene == PNEUMATIC_SCENE && r.method == PNEUMATIC_METHOD && r.rtol == Some(1e-10))
                .and_then(|r| r.error),
            BOUND_PNEUMATIC,
            false,
        ),
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

/// Where `--plot` writes.
pub fn default_plot_path() -> PathBuf {
    PathBuf::from("accuracy.svg")
}
