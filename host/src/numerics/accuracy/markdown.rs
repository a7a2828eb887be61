//! The report's Markdown tables.

use super::*;

pub(super) fn fmt_opt(v: Option<f64>) -> String {
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
    for scene in ["oracle_1dof", "pull_center", "push_center"].into_iter().chain(MODEL2_SCENES).chain([UNILATERAL_SCENE, PNEUMATIC_SCENE]) {
        if scene == PNEUMATIC_SCENE {
            out.push_str(&format!(
                "Model 3, the pneumatic drive ({scene}: rig_push_center with the drive, a 15 mm column, a 40 / 30 N seal, \
                 1 s): the pneumatic runner (Dormand-Prince 5(4) under error control, at the rtol given) against the \
                 pneumatic drive's reference (DOP853 at rtol 1e-12, its own right-hand side); error as for the periodic \
                 scenes, and the band's mean speed relative to the reference's (1 where the band's breakaways differ in \
                 number).\n\n"
            ));
        }
        if scene == UNILATERAL_SCENE {
            out.push_str(&format!(
                "Model 3, unilateral contact ({scene}: rig_float_push_center turned to pull, beta 11.5 mm, 0.8 s): the event \
                 runner (exact flows, Dormand-Prince 5(4) in Stribeck slip, at the rtol given) against the unilateral-contact \
                 reference (DOP853 at rtol 1e-12 on model 2's reference right-hand side with the open spring taken out); \
                 error as for the periodic scenes, and the edges' open time relative to the reference's (1 where the \
                 openings differ in number).\n\n"
            ));
        }
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
