//! The built-in scenes: the six cases of the thesis (push/pull caliper x three load
//! positions), the thesis's own friction law (`thesis-mu`) and the closed-form check
//! (`oracle_1dof`). All of them start from the default pad of the model crate.

use stickslip_model::scene::CASE_BETAS;
use stickslip_model::{Caliper, Scene, DEFAULT_SCENE};

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

/// Every built-in scene, cases first.
pub fn all() -> Vec<Builtin> {
    let mut v = cases();
    v.push(thesis_mu());
    v.push(oracle_1dof());
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
