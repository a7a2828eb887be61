//! `stickslip stability`: sweeps of stiff and extreme cases around the default scene
//! (push_center), every method, f32 and f64, each run classified:
//!
//! - `bounded`: the run completed;
//! - `sprag`: the model itself diverges (a slip regime with rotational stiffness
//!   K_eff = K - s sigma mu_k w c_N <= 0), or self-locks in stick (s mu_s w c_N >= K: the pad
//!   never breaks away); the row gives the stiffness margin;
//! - `contact_loss`: N = c_N phi < 0, the model is outside its validity;
//! - `method_unstable`: an artefact of the method (it halted where the exact method, the
//!   arbiter, does not); the row gives omega_max dt and the method's limit on it.
//!
//! Whether a halt is the model's or the method's is decided by the exact f64 run of the same
//! scene. No NaN or infinity reaches an output: every stepper stops the step that would
//! produce one.

use serde::Serialize;
use stickslip_model::methods::{AnyMethod, Method, MethodKind};
use stickslip_model::propagator::fastest_rate;
use stickslip_model::model2::AnyModel2Stepper;
use stickslip_model::{Coefficients, Halt, Real, Regime, Scene};

use crate::scenes::builtin;
use crate::error::{HostError, Result};

/// One swept parameter: its key in the rows and its values.
pub struct Sweep {
    pub key: &'static str,
    pub unit: &'static str,
    pub values: &'static [f64],
    apply: fn(&mut Scene, f64),
}

fn set_contact(s: &mut Scene, v: f64) {
    s.k_l = v;
    s.k_t = v;
}
fn set_mu(s: &mut Scene, v: f64) {
    // keep the default ratio mu_k / mu_s = 0.35 / 0.45 (so mu_k <= mu_s)
    s.mu_s = v;
    s.mu_k = v * (0.35 / 0.45);
}
fn set_damping(s: &mut Scene, zeta: f64) {
    let co = Coefficients::of(s);
    s.c_x = zeta * 2.0 * (s.k_g * s.m).sqrt();
    s.c_phi = zeta * 2.0 * (co.k_rot * s.inertia).sqrt();
}

pub const SWEEPS: [Sweep; 8] = [
    Sweep { key: "contact_stiffness", unit: "N/m", values: &[1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10], apply: set_contact },
    Sweep { key: "k_g", unit: "N/m", values: &[1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9], apply: |s, v| s.k_g = v },
    // 0 to 2 as asked, then 4 and 8: past K / (w c_N) = 6.0 the default pad sprags
    Sweep { key: "mu_s", unit: "-", values: &[0.0, 0.25, 0.5, 1.0, 1.5, 2.0, 4.0, 8.0], apply: set_mu },
    Sweep { key: "v", unit: "m/s", values: &[1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0, 10.0], apply: |s, v| s.v = v },
    Sweep { key: "beta", unit: "m", values: &[0.0, 0.02, 0.04, 0.06, 0.08], apply: |s, v| s.beta = v },
    Sweep { key: "f_n", unit: "N", values: &[0.0, 10.0, 100.0, 1e3, 1e4], apply: |s, v| s.f_n = v },
    Sweep { key: "damping_ratio", unit: "-", values: &[0.0, 0.01, 0.1, 0.5, 1.0], apply: set_damping },
    Sweep { key: "dt", unit: "s", values: &[1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2], apply: |s, v| s.dt = v },
];

fn set_damping_all(s: &mut Scene, zeta: f64) {
    set_damping(s, zeta);
    s.c_b = zeta * 2.0 * (s.k_b * s.m_b).sqrt();
}

/// Model 2's extremes, around the rig set's push_center (Stribeck friction, the band, 2 %
/// damping), on the model-2 stepper (the only method that carries them).
pub const MODEL2_SWEEPS: [Sweep; 4] = [
    // toward Coulomb: the stiff extreme
    Sweep { key: "v_s", unit: "m/s", values: &[1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0], apply: |s, v| s.v_s = v },
    Sweep { key: "k_b", unit: "N/m", values: &[1e3, 1e4, 1e6, 1e8, 1e10], apply: |s, v| s.k_b = v },
    Sweep { key: "damping_ratio_all", unit: "-", values: &[0.0, 0.01, 0.1, 0.5, 1.0], apply: set_damping_all },
    Sweep { key: "m_b", unit: "kg", values: &[1e-3, 1e-2, 1.0, 1e2, 1e3], apply: |s, v| s.m_b = v },
];

/// Part 2's extremes, around the rig set's push_center with the face and the floating pad
/// (`rig_float_push_center`): the pivot from floating to the hinge's stiffness, and the contact
/// springs (both) from soft to 1e10 N/m, which the floating pad rides on.
pub const FLOAT_SWEEPS: [Sweep; 3] = [
    Sweep { key: "k_pivot", unit: "N/m", values: &[0.0, 1e4, 1e6, 1e8, 1e10], apply: |s, v| s.k_pivot = v },
    Sweep {
        key: "float_contact_stiffness",
        unit: "N/m",
        values: &[1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10],
        apply: set_contact,
    },
    // model 3: the contact that stiffens with load (the springs' tangents at their static
    // loads, reference load 75 N), from linear to the law's largest exponent
    Sweep { key: "contact_exponent", unit: "-", values: &[1.0, 1.5, 2.0, 3.0, 5.0], apply: set_contact_exponent },
];

fn set_contact_exponent(s: &mut Scene, p: f64) {
    s.contact_exponent = p;
    s.contact_ref_load = 75.0;
}

/// The method name of the model-2 rows.
pub const MODEL2_METHOD: &str = "model2";
/// The method of model 3's pneumatic rows: the pneumatic runner (Dormand-Prince 5(4) under
/// error control, rtol 1e-10; f64 only).
pub const MODEL3_METHOD: &str = "pneumatic";

/// Model 3's pneumatic band drive around `rig_push_center` (`drive = "pneumatic"`, no drive
/// damping; docs/model.md, "Model 3, part 3"): each cylinder key to its extremes.
pub const MODEL3_SWEEPS: [Sweep; 5] = [
    Sweep { key: "column_length", unit: "m", values: &[0.005, 0.02, 0.05, 0.2, 1.0], apply: |s, v| s.column_length = v },
    Sweep { key: "polytropic_exponent", unit: "-", values: &[1.0, 1.2, 1.4], apply: |s, v| s.polytropic_exponent = v },
    // the seal's drop from static (80 N) to kinetic friction: none to all of it
    Sweep { key: "seal_kinetic", unit: "N", values: &[0.0, 40.0, 80.0], apply: |s, v| s.seal_kinetic = v },
    Sweep { key: "seal_v_s", unit: "m/s", values: &[1e-4, 1e-3, 5e-3, 5e-2], apply: |s, v| s.seal_v_s = v },
    Sweep { key: "supply_pressure", unit: "Pa", values: &[2.5e5, 6e5, 1e6], apply: |s, v| s.supply_pressure = v },
];

/// The event runner's method name in the unilateral rows (f64 only).
pub const EVENT_METHOD: &str = "event";

/// Model 3's unilateral contact around `rig_float_push_center` with `contact = "unilateral"`
/// (docs/model.md, "Model 3, part 1"), on the event runner that carries it: the load from the
/// trailing edge to the leading one (edges that open, the pad that tips), the edge springs from
/// soft to 1e10 N/m, the pivot from floating to the hinge's stiffness.
pub const UNILATERAL_SWEEPS: [Sweep; 3] = [
    Sweep { key: "unilateral_beta", unit: "m", values: &[0.0, 0.0115, 0.04, 0.07, 0.08], apply: |s, v| s.beta = v },
    Sweep {
        key: "unilateral_contact_stiffness",
        unit: "N/m",
        values: &[1e4, 1e6, 1e8, 1e10],
        apply: set_contact,
    },
    Sweep { key: "unilateral_k_pivot", unit: "N/m", values: &[0.0, 1e4, 1e6, 1e8, 1e10], apply: |s, v| s.k_pivot = v },
];

#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// Which parameter this row's sweep varies.
    pub sweep: String,
    pub method: String,
    pub precision: String,
    pub dt: f64,
    pub contact_stiffness: f64,
    pub k_g: f64,
    pub mu_s: f64,
    pub mu_k: f64,
    pub v: f64,
    pub beta: f64,
    pub f_n: f64,
    pub damping_ratio: f64,
    /// Model-2 rows only (null elsewhere): Stribeck velocity [m/s], band stiffness [N/m], band
    /// mass [kg].
    pub v_s: Option<f64>,
    pub k_b: Option<f64>,
    pub m_b: Option<f64>,
    /// Floating-pad rows only (null elsewhere, and for the hinge): the pivot's stiffness [N/m].
    pub k_pivot: Option<f64>,
    /// Floating-pad rows only: the contact law's exponent p (1: linear springs).
    pub contact_exponent: Option<f64>,
    /// Model 3's pneumatic rows only: the swept cylinder key's value (SI, as in a scene file).
    pub cylinder_value: Option<f64>,
    /// Fastest mode of the scene times dt [rad].
    pub omega_dt: f64,
    /// The method's stability limit on omega dt for an undamped oscillator; null: none.
    pub omega_dt_limit: Option<f64>,
    /// bounded | sprag | contact_loss | method_unstable
    pub outcome: String,
    /// Time of the halt [s], null when bounded.
    pub t_halt: Option<f64>,
    /// Smallest rotational stiffness margin of the scene, K_eff [N m/rad] (<= 0: sprag).
    pub stiffness_margin: f64,
    pub detail: String,
}

impl Row {
    /// The row of a run of `scene` in `sweep`: its parameters, halt and outcome. The method,
    /// precision, damping ratio and omega dt are left empty or 0, the model-2 fields null: the
    /// caller sets them.
    fn of(sweep: &str, scene: &Scene, co: &Coefficients, halt: Option<Halt>, outcome: &str, detail: String) -> Row {
        Row {
            sweep: sweep.into(),
            method: String::new(),
            precision: String::new(),
            dt: scene.dt,
            contact_stiffness: scene.k_l,
            k_g: scene.k_g,
            mu_s: scene.mu_s,
            mu_k: scene.mu_k,
            v: scene.v,
            beta: scene.beta,
            f_n: scene.f_n,
            damping_ratio: 0.0,
            v_s: None,
            k_b: None,
            m_b: None,
            k_pivot: None,
            contact_exponent: None,
            cylinder_value: None,
            omega_dt: 0.0,
            omega_dt_limit: None,
            outcome: outcome.into(),
            t_halt: halt.map(|h| h.time()),
            stiffness_margin: co.sprag_margin(scene),
            detail,
        }
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub rows: Vec<Row>,
    pub duration_s: f64,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Verdict {
    Bounded,
    Sprag,
    ContactLoss,
    Other,
}

/// Runs a method over the scene: its halt, if any, and whether the pad ever left stick.
fn run_method<T: Real>(kind: MethodKind, scene: &Scene) -> Result<(Option<Halt>, bool)> {
    let mut m = AnyMethod::<T>::new(kind, scene).map_err(|e| HostError::Input(format!("stability scene: {e}")))?;
    Ok(run_steps(scene, || m.step().map(|_| m.regime())))
}

/// round(duration / dt) steps of `step` (which returns the regime after the step): the halt, if
/// any, and whether the regime was ever other than stick (a halt counts as having slipped).
fn run_steps<E>(scene: &Scene, mut step: impl FnMut() -> core::result::Result<Regime, E>) -> (Option<E>, bool) {
    let n = (scene.duration / scene.dt).round() as u64;
    let mut slipped = false;
    for _ in 0..n {
        match step() {
            Ok(regime) => slipped |= regime != Regime::Stick,
            Err(h) => return (Some(h), true),
        }
    }
    (None, slipped)
}

/// The model's own verdict on a scene: the exact f64 run, plus self-locking in stick.
fn arbiter(scene: &Scene) -> Result<(Verdict, Option<Halt>)> {
    let co = Coefficients::of(scene);
    let mut m = AnyMethod::<f64>::new(MethodKind::Exact, scene).map_err(|e| HostError::Input(e.to_string()))?;
    let n = (scene.duration / scene.dt).round() as u64;
    let mut slipped = false;
    for _ in 0..n {
        match m.step() {
            Err(h) => {
                let v = match h {
                    Halt::Diverged { stiffness_margin, .. } if stiffness_margin <= 0.0 => Verdict::Sprag,
                    Halt::ContactLoss { .. } => Verdict::ContactLoss,
                    _ => Verdict::Other,
                };
                return Ok((v, Some(h)));
            }
            Ok(_) => slipped |= m.regime() != Regime::Stick,
        }
    }
    if !slipped && co.quasi_static_first_slip(scene).is_infinite() && scene.f_n > 0.0 {
        return Ok((Verdict::Sprag, None));
    }
    Ok((Verdict::Bounded, None))
}

fn classify(halt: Option<Halt>, slipped: bool, model: Verdict) -> (&'static str, String) {
    match (halt, model) {
        (None, Verdict::Sprag) if !slipped => ("sprag", "self-locking in stick: the pad never breaks away".into()),
        (None, _) => ("bounded", String::new()),
        (Some(Halt::Diverged { stiffness_margin, regime, .. }), Verdict::Sprag) => {
            ("sprag", format!("phi diverged in {} with K_eff = {stiffness_margin:.4e} N m/rad", regime.name()))
        }
        (Some(Halt::ContactLoss { n, .. }), Verdict::ContactLoss) => ("contact_loss", format!("N = {n:.3e} N < 0")),
        (Some(h), _) => ("method_unstable", format!("{h:?}")),
    }
}

pub struct Options {
    pub quick: bool,
    pub progress: bool,
}

/// Runs every sweep.
pub fn run(opts: &Options) -> Result<Report> {
    let mut base = builtin::find("push_center").expect("built-in").scene;
    base.duration = if opts.quick { 0.1 } else { 0.2 };
    base.stats_from = base.duration / 2.0;
    let total: usize = SWEEPS.iter().map(|s| s.values.len()).sum::<usize>() * MethodKind::ALL.len() * 2;
    let bar = if opts.progress {
        let b = indicatif::ProgressBar::new(total as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} runs, {elapsed} {msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        Some(b)
    } else {
        None
    };
    let mut rows = Vec::new();
    for sweep in &SWEEPS {
        for &value in sweep.values {
            let mut scene = base;
            (sweep.apply)(&mut scene, value);
            scene.validate().map_err(|e| HostError::Input(format!("sweep {} = {value}: {e}", sweep.key)))?;
            let co = Coefficients::of(&scene);
            let (model, _) = arbiter(&scene)?;
            let omega_dt = fastest_rate(&scene, &co) * scene.dt;
            let zeta = if sweep.key == "damping_ratio" { value } else { 0.0 };
            for kind in MethodKind::ALL {
                for precision in ["f64", "f32"] {
                    if let Some(b) = &bar {
                        b.set_message(format!("{} = {value:e}, {} {precision}", sweep.key, kind.name()));
                    }
                    let (halt, slipped) =
                        if precision == "f64" { run_method::<f64>(kind, &scene)? } else { run_method::<f32>(kind, &scene)? };
                    let (outcome, detail) = classify(halt, slipped, model);
                    rows.push(Row {
                        method: kind.name().into(),
                        precision: precision.into(),
                        damping_ratio: zeta,
                        omega_dt,
                        omega_dt_limit: kind.omega_dt_limit(),
                        ..Row::of(sweep.key, &scene, &co, halt, outcome, detail)
                    });
                    if let Some(b) = &bar {
                        b.inc(1);
                    }
                }
            }
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    rows.extend(model2_rows(base.duration)?);
    rows.extend(model3_rows(base.duration)?);
    rows.extend(unilateral_rows(base.duration)?);
    Ok(Report { rows, duration_s: base.duration })
}

/// Runs the model-2 stepper over a scene: its halt, if any, and whether the pad ever slipped.
fn run_model2<T: Real>(scene: &Scene) -> Result<(Option<Halt>, bool)> {
    let mut m = AnyModel2Stepper::<T>::new(scene).map_err(|e| HostError::Input(format!("stability scene: {e}")))?;
    Ok(run_steps(scene, || m.step().map(|_| m.regime())))
}

/// The model-2 sweeps: f64 is the arbiter of the model's own findings (sprag, contact loss);
/// an f32 run that halts where f64 does not is `method_unstable`, and so is any f64 halt that
/// is not a model finding.
fn model2_rows(duration: f64) -> Result<Vec<Row>> {
    let mut rows = Vec::new();
    for (base_name, sweeps) in [("rig_push_center", &MODEL2_SWEEPS[..]), ("rig_float_push_center", &FLOAT_SWEEPS[..])] {
    let mut base = builtin::find(base_name).expect("built-in").scene;
    base.duration = duration;
    base.stats_from = duration / 2.0;
    for sweep in sweeps {
        for &value in sweep.values {
            let mut scene = base;
            (sweep.apply)(&mut scene, value);
            scene.validate().map_err(|e| HostError::Input(format!("sweep {} = {value}: {e}", sweep.key)))?;
            let co = Coefficients::of(&scene);
            let (h64, slipped64) = run_model2::<f64>(&scene)?;
            let model = match h64 {
                Some(Halt::Diverged { stiffness_margin, .. }) if stiffness_margin <= 0.0 => Verdict::Sprag,
                Some(Halt::ContactLoss { .. }) => Verdict::ContactLoss,
                Some(_) => Verdict::Other,
                None => Verdict::Bounded,
            };
            scene.validate().map_err(|e| HostError::Input(e.to_string()))?;
            let rate = stickslip_model::model2::System::of(&scene, &co).linear_rate(&scene, &co);
            for precision in ["f64", "f32"] {
                let (halt, slipped) = if precision == "f64" { (h64, slipped64) } else { run_model2::<f32>(&scene)? };
                let (outcome, detail) = classify(halt, slipped, model);
                rows.push(Row {
                    method: MODEL2_METHOD.into(),
                    precision: precision.into(),
                    damping_ratio: if sweep.key == "damping_ratio_all" { value } else { 0.02 },
                    v_s: Some(scene.v_s),
                    k_b: Some(scene.k_b),
                    m_b: Some(scene.m_b),
                    k_pivot: scene.floating().then_some(scene.k_pivot),
                    contact_exponent: scene.floating().then_some(scene.contact_exponent),
                    omega_dt: rate * scene.dt,
                    ..Row::of(sweep.key, &scene, &co, halt, outcome, detail)
                });
            }
        }
    }
    }
    Ok(rows)
}

/// The pneumatic drive's sweeps: the runner in f64 (it has no f32 form); a halt that is not the
/// model's own (contact loss, sprag) is `method_unstable`, and so is a stall.
fn model3_rows(duration: f64) -> Result<Vec<Row>> {
    use stickslip_model::model3::pneumatic_run::{PneumaticRunner, PneumaticSample};
    let mut base = builtin::find("rig_push_center").expect("built-in").scene;
    base.duration = duration;
    base.stats_from = duration / 2.0;
    base.drive = stickslip_model::BandDrive::Pneumatic;
    base.c_b = 0.0;
    let mut rows = Vec::new();
    for sweep in &MODEL3_SWEEPS {
        for &value in sweep.values {
            let mut scene = base;
            (sweep.apply)(&mut scene, value);
            let mut runner = PneumaticRunner::new(&scene, crate::scenes::pneumatic::PNEUMATIC_RTOL)
                .map_err(|e| HostError::Input(format!("sweep {} = {value}: {e}", sweep.key)))?;
            let co = Coefficients::of(&scene);
            let mut slipped = false;
            let result = runner.run_sampled(0.0, scene.duration, scene.dt, &mut (), &mut |g: &PneumaticSample| {
                slipped |= g.regime != Regime::Stick;
                true
            });
            let halt = result.err().map(crate::scenes::pneumatic::halt_of);
            let model = match halt {
                Some(Halt::Diverged { stiffness_margin, .. }) if stiffness_margin <= 0.0 => Verdict::Sprag,
                Some(Halt::ContactLoss { .. }) => Verdict::ContactLoss,
                Some(_) => Verdict::Other,
                None => Verdict::Bounded,
            };
            let (outcome, detail) = classify(halt, slipped, model);
            let equivalent = stickslip_model::model3::cylinder::small_signal_scene(&scene).unwrap_or(scene);
            let eco = Coefficients::of(&equivalent);
            let rate = stickslip_model::model2::System::of(&equivalent, &eco).linear_rate(&equivalent, &eco);
            rows.push(Row {
                method: MODEL3_METHOD.into(),
                precision: "f64".into(),
                damping_ratio: 0.02,
                v_s: Some(scene.v_s),
                k_b: Some(equivalent.k_b),
                m_b: Some(scene.m_b),
                cylinder_value: Some(value),
                omega_dt: rate * scene.dt,
                ..Row::of(sweep.key, &scene, &co, halt, outcome, detail)
            });
        }
    }
    Ok(rows)
}

/// Whether a run ever left stick.
struct Slipped(bool);

impl stickslip_model::model2::Model2Observer<f64> for Slipped {
    fn transition(&mut self, tr: &stickslip_model::model2::Model2Transition<f64>) {
        self.0 |= tr.to != Regime::Stick;
    }
}

/// The unilateral sweeps on the event runner at the host's tolerance for unilateral contact
/// (f64): both edges open, or one open with the pad tipping over the closed one, is the model's
/// own `contact_loss`; any other stop (a stall, a step below round-off) is `method_unstable`.
fn unilateral_rows(duration: f64) -> Result<Vec<Row>> {
    use crate::scenes::unilateral::{halt_of, UNILATERAL_RTOL};
    use stickslip_model::model2::event_run::EventRunner;
    let mut base = builtin::find("rig_float_push_center").expect("built-in").scene;
    base.duration = duration;
    base.stats_from = duration / 2.0;
    base.contact = stickslip_model::ContactLaw::Unilateral;
    let mut rows = Vec::new();
    for sweep in &UNILATERAL_SWEEPS {
        for &value in sweep.values {
            let mut scene = base;
            (sweep.apply)(&mut scene, value);
            scene.validate().map_err(|e| HostError::Input(format!("sweep {} = {value}: {e}", sweep.key)))?;
            let co = Coefficients::of(&scene);
            let mut runner = EventRunner::new(&scene, UNILATERAL_RTOL)
                .map_err(|e| HostError::Input(format!("sweep {} = {value}: {e}", sweep.key)))?;
            let mut slipped = Slipped(false);
            let halt = runner.run(0.0, scene.duration, &mut slipped).err().map(|f| halt_of(&runner, f));
            let model = match halt {
                Some(Halt::ContactLoss { .. }) => Verdict::ContactLoss,
                Some(_) => Verdict::Other,
                None => Verdict::Bounded,
            };
            let (outcome, mut detail) = classify(halt, slipped.0 || halt.is_some(), model);
            if model == Verdict::ContactLoss {
                detail = format!("the pad leaves the band (both edges open, or one open and the pad tipping over the other) at t = {:.6} s", halt.map_or(0.0, |h| h.time()));
            }
            let rate = stickslip_model::model2::System::of(&scene, &co).linear_rate(&scene, &co);
            rows.push(Row {
                method: EVENT_METHOD.into(),
                precision: "f64".into(),
                damping_ratio: 0.02,
                v_s: Some(scene.v_s),
                k_b: Some(scene.k_b),
                m_b: Some(scene.m_b),
                k_pivot: Some(scene.k_pivot),
                contact_exponent: Some(scene.contact_exponent),
                omega_dt: rate * scene.dt,
                ..Row::of(sweep.key, &scene, &co, halt, outcome, detail)
            });
        }
    }
    Ok(rows)
}

/// Every numeric field of every row is finite (the report's promise).
pub fn all_finite(rep: &Report) -> bool {
    rep.rows.iter().all(|r| {
        [r.dt, r.contact_stiffness, r.k_g, r.mu_s, r.mu_k, r.v, r.beta, r.f_n, r.damping_ratio, r.omega_dt, r.stiffness_margin]
            .iter()
            .chain(r.t_halt.iter())
            .chain(r.v_s.iter())
            .chain(r.k_b.iter())
            .chain(r.m_b.iter())
            .chain(r.k_pivot.iter())
            .chain(r.contact_exponent.iter())
            .chain(r.cylinder_value.iter())
            .chain(r.omega_dt_limit.iter())
            .all(|v| v.is_finite())
    })
}

/// The Markdown summary: per sweep, the outcome of each method and precision at each value.
pub fn markdown(rep: &Report) -> String {
    let mut out = format!(
        "# Stability sweeps around push_center ({} s runs)\n\nOutcomes: bounded, sprag (the model diverges), contact_loss \
         (N < 0: outside the model's validity), method_unstable (an artefact of the method; see omega_max dt against the \
         method's limit: explicit Euler none, symplectic Euler 2, RK4 2.83, exact and Moreau-Jean unconditional).\n\n",
        rep.duration_s
    );
    for sweep in &SWEEPS {
        sweep_header(&mut out, sweep);
        // omega dt per value (the same for every method)
        out.push_str("| omega_max dt | |");
        for v in sweep.values {
            let w = rep.rows.iter().find(|r| r.sweep == sweep.key && value_of(r, sweep.key) == *v).map(|r| r.omega_dt);
            out.push_str(&format!(" {} |", w.map_or("-".into(), |w| format!("{w:.2e}"))));
        }
        out.push('\n');
        for kind in MethodKind::ALL {
            for precision in ["f64", "f32"] {
                out.push_str(&format!("| {} | {precision} |", kind.name()));
                for v in sweep.values {
                    let r = rep.rows.iter().find(|r| {
                        r.sweep == sweep.key && r.method == kind.name() && r.precision == precision && value_of(r, sweep.key) == *v
                    });
                    out.push_str(&format!(" {} |", r.map_or("-", |r| r.outcome.as_str())));
                }
                out.push('\n');
            }
        }
        out.push('\n');
    }
    out.push_str(
        "# Model 2 sweeps around rig_push_center (Stribeck friction, the band, 2 % damping)\n\n\
         The model-2 stepper (exact flows, ETDRK4 in Stribeck slip) is the only method that carries them; f64 \
         decides the model's own findings, and f32 is checked against it.\n\n",
    );
    for (i, sweep) in MODEL2_SWEEPS.iter().chain(&FLOAT_SWEEPS).enumerate() {
        if i == MODEL2_SWEEPS.len() {
            out.push_str(
                "# Model 2, part 2: around rig_float_push_center (the face, the floating pad, k_pivot = 0)\n\n\
                 The guide friction mu_g is not in the model (docs/model.md), so it has no sweep.\n\n",
            );
        }
        sweep_header(&mut out, sweep);
        for precision in ["f64", "f32"] {
            out.push_str(&format!("| {MODEL2_METHOD} | {precision} |"));
            for v in sweep.values {
                let r = rep
                    .rows
                    .iter()
                    .find(|r| r.sweep == sweep.key && r.precision == precision && value_of(r, sweep.key) == *v);
                out.push_str(&format!(" {} |", r.map_or("-", |r| r.outcome.as_str())));
            }
            out.push('\n');
        }
        out.push('\n');
    }
    out.push_str(
        "# Model 3: the pneumatic band drive around rig_push_center (drive = \"pneumatic\", no drive damping)\n\n\
         The pneumatic runner (Dormand-Prince 5(4) under error control, rtol 1e-10) is the only method that \
         carries it, in f64 only.\n\n",
    );
    f64_method_tables(&mut out, rep, &MODEL3_SWEEPS, MODEL3_METHOD);
    out.push_str(
        "# Model 3: unilateral contact around rig_float_push_center (contact = \"unilateral\")\n\n\
         The event runner (exact flows, Dormand-Prince 5(4) in Stribeck slip, rtol 1e-12) is the only method that \
         carries it, in f64 only; contact_loss is the pad leaving the band (both edges open, or one open and the pad \
         tipping over the other).\n\n",
    );
    f64_method_tables(&mut out, rep, &UNILATERAL_SWEEPS, EVENT_METHOD);
    out
}

/// The tables of sweeps that one method runs in f64 only: its outcome at each value.
fn f64_method_tables(out: &mut String, rep: &Report, sweeps: &[Sweep], method: &str) {
    for sweep in sweeps {
        sweep_header(out, sweep);
        out.push_str(&format!("| {method} | f64 |"));
        for v in sweep.values {
            let r = rep.rows.iter().find(|r| r.sweep == sweep.key && r.method == method && value_of(r, sweep.key) == *v);
            out.push_str(&format!(" {} |", r.map_or("-", |r| r.outcome.as_str())));
        }
        out.push_str("\n\n");
    }
}

/// A sweep's table head: one column per swept value.
fn sweep_header(out: &mut String, sweep: &Sweep) {
    out.push_str(&format!("## {} [{}]\n\n| method | precision |", sweep.key, sweep.unit));
    for v in sweep.values {
        out.push_str(&format!(" {v:e} |"));
    }
    out.push_str("\n|---|---|");
    for _ in sweep.values {
        out.push_str("---|");
    }
    out.push('\n');
}

/// The swept value of a row.
pub fn value_of(r: &Row, key: &str) -> f64 {
    match key {
        "contact_stiffness" | "float_contact_stiffness" | "unilateral_contact_stiffness" => r.contact_stiffness,
        "k_pivot" | "unilateral_k_pivot" => r.k_pivot.unwrap_or(f64::NAN),
        "unilateral_beta" => r.beta,
        "contact_exponent" => r.contact_exponent.unwrap_or(f64::NAN),
        "k_g" => r.k_g,
        "mu_s" => r.mu_s,
        "v" => r.v,
        "beta" => r.beta,
        "f_n" => r.f_n,
        "damping_ratio" | "damping_ratio_all" => r.damping_ratio,
        "v_s" => r.v_s.unwrap_or(f64::NAN),
        "k_b" => r.k_b.unwrap_or(f64::NAN),
        "m_b" => r.m_b.unwrap_or(f64::NAN),
        "column_length" | "polytropic_exponent" | "seal_kinetic" | "seal_v_s" | "supply_pressure" => r.cylinder_value.unwrap_or(f64::NAN),
        _ => r.dt,
    }
}
