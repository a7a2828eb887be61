//! The built-in scenes: the six cases of the thesis (push/pull caliper x three load
//! positions), the thesis's own friction law (`thesis-mu`) and the closed-form check
//! (`oracle_1dof`). All of them start from the default pad of the model crate.

use stickslip_model::catalogue::CASE_BETAS;
use stickslip_model::{Caliper, FrictionLaw, Scene, DEFAULT_SCENE};

/// A built-in scene.
#[derive(Clone, Debug)]
pub struct Builtin {
    pub name: String,
    pub description: String,
    pub scene: Scene,
}

/// Normal contact force of the `oracle_1dof` scene, N0 = c_N F_N a_N / K [N] (docs: the
/// closed-form mass on a moving belt with N = 10 N).
pub const ORACLE_N0: f64 = Scene::ORACLE_N0;

fn position_word(tag: &str) -> &'static str {
    match tag {
        "trail" => "near the trailing edge",
        "center" => "at the pad centre",
        _ => "near the leading edge",
    }
}

/// The six cases, in the order push_trail, push_center, push_lead, pull_trail, pull_center,
/// pull_lead.
pub fn cases() -> Vec<Builtin> {
    let mut out = Vec::with_capacity(6);
    for caliper in [Caliper::Push, Caliper::Pull] {
        for (tag, beta) in CASE_BETAS {
            out.push(Builtin {
                name: format!("{}_{}", caliper.name(), tag),
                description: format!(
                    "{} caliper, load {} (beta = {} m from the trailing edge)",
                    caliper.name(),
                    position_word(tag),
                    beta
                ),
                scene: Scene::case(caliper, beta),
            });
        }
    }
    out
}

pub use stickslip_model::rig_set::{rig_built_scene, rig_float_scene, rig_quiet_scene, rig_scene, RIG_K_B, RIG_M_B, RIG_V_S, RIG_ZETA, RIG_ZETA_B};

/// The six cases as a derived set: each named `{prefix}{case}`, its description extended by
/// `what`, its scene `scene(caliper, beta)`.
fn derived_cases(prefix: &str, what: &str, scene: fn(Caliper, f64) -> Scene) -> Vec<Builtin> {
    cases()
        .into_iter()
        .map(|b| Builtin {
            name: format!("{prefix}{}", b.name),
            description: format!("{}; {what}, {} % damping", b.description, RIG_ZETA * 100.0),
            scene: scene(b.scene.caliper, b.scene.beta),
        })
        .collect()
}

/// The rig set: the six cases with model 2 on, named `rig_push_trail` ... `rig_pull_lead`.
pub fn rig_cases() -> Vec<Builtin> {
    derived_cases("rig_", "model 2: Stribeck friction, band as a mass, mu_k, v_s, k_b fitted to Table 3.1", rig_scene)
}

/// The rig set with part 2 of model 2: friction-face kinematics and the floating pad, named
/// `rig_float_push_trail` ... `rig_float_pull_lead`.
pub fn rig_float_cases() -> Vec<Builtin> {
    derived_cases(
        "rig_float_",
        "model 2 with the face and a floating pad (k_pivot = 0), Stribeck friction, band as a mass, mu_k, v_s, k_b fitted to Table 3.1",
        rig_float_scene,
    )
}

/// The built rig set (model 3): the floating set with the soft band, unilateral edges and
/// its own mu_k and k_b fitted to Table 3.1, 3 s runs, named `rig_built_push_trail` ...
/// `rig_built_pull_lead`. Unilateral contact runs in f64 only.
pub fn rig_built_cases() -> Vec<Builtin> {
    derived_cases(
        "rig_built_",
        "model 3: the floating set with the soft band (pneumatic drive's air column), unilateral edges, contact exponent 1.5, mu_k and k_b fitted to Table 3.1, 3 s runs, f64 only",
        rig_built_scene,
    )
}

/// The rig set at Table 3.1's signal levels (mu_k = 0.447, V = 1 mm/s), named
/// `rig_quiet_push_trail` ... `rig_quiet_pull_lead`.
pub fn rig_quiet_cases() -> Vec<Builtin> {
    derived_cases(
        "rig_quiet_",
        "model 2 at Table 3.1's levels (mu_k = 0.447, V = 1 mm/s, v_s = 2 mm/s, k_b = 1e6 N/m; chosen, not fitted), Stribeck friction, band as a mass",
        rig_quiet_scene,
    )
}

/// push_center with the thesis's friction law mu_k = mu_s (Eq. 2.10).
fn thesis_mu() -> Builtin {
    let mut scene = DEFAULT_SCENE;
    scene.mu_k = scene.mu_s;
    Builtin {
        name: "thesis-mu".into(),
        description:
            "push_center with mu_k = mu_s = 0.45 (thesis Eq. 2.10): no sustained stick-slip, \
                      the pad ends up sliding"
                .into(),
        scene,
    }
}

/// The 1-DOF mass on a moving belt (rotation off, N constant), which has a closed form:
/// m = 1 kg, k_g = 100 N/m, V = 0.05 m/s, mu_s = 0.6, mu_k = 0.4, N0 = 10 N.
fn oracle_1dof() -> Builtin {
    let scene = Scene::oracle_1dof();
    Builtin {
        name: "oracle_1dof".into(),
        description:
            "1-DOF mass on a moving belt (rotation off, N0 = 10 N, m = 1 kg, k_g = 100 N/m, \
                      V = 0.05 m/s): has a closed form"
                .into(),
        scene,
    }
}

/// The 1-DOF Stribeck oracle: oracle_1dof with falling friction (v_s = 0.01 m/s, delta = 1) and
/// the damping c_x that puts the linear stability limit of steady sliding at V_cr = 0.03 m/s
/// (docs/model.md); the band runs at V = 0.02 m/s, below it: sustained stick-slip.
fn oracle_stribeck() -> Builtin {
    let mut scene = Scene::oracle_1dof();
    scene.friction = FrictionLaw::Stribeck;
    scene.v_s = 0.01;
    scene.c_x = ORACLE_N0 * (scene.mu_s - scene.mu_k) / scene.v_s * (-0.03f64 / scene.v_s).exp();
    scene.v = 0.02;
    Builtin {
        name: "oracle_stribeck".into(),
        description: "oracle_1dof with Stribeck friction (v_s = 0.01 m/s), c_x for V_cr = 0.03 m/s, V = 0.02 m/s"
            .into(),
        scene,
    }
}

/// Every built-in scene: the thesis set (cases first), then the model-2 scenes.
pub fn all() -> Vec<Builtin> {
    let mut v = cases();
    v.push(thesis_mu());
    v.push(oracle_1dof());
    v.push(oracle_stribeck());
    v.extend(rig_cases());
    v.extend(rig_float_cases());
    v.extend(rig_quiet_cases());
    v.extend(rig_built_cases());
    v
}

/// The built-in scene called `name`.
pub fn find(name: &str) -> Option<Builtin> {
    all().into_iter().find(|b| b.name == name)
}

/// The names, comma-separated, for error messages and help texts.
pub fn names() -> String {
    all()
        .iter()
        .map(|b| b.name.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}
