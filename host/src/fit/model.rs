//! The model side of a fit: the scene of each case, the free keys applied to it, and its
//! statistics from the virtual rig on the ideal sensor path (`sil::SensorPath::Ideal`: the
//! model's accelerations at the samples through the same analysis as a recording, so the
//! cost is smooth in the parameters instead of a staircase of ADC counts).

use stickslip_model::coefficients::Coefficients;
use stickslip_model::catalogue::CASE_BETAS;
use stickslip_model::{Caliper, Scene};

use crate::recorded::analysis::Analysis;
use crate::recorded::sil::{self, SensorPath, SilOptions};
use crate::scenes::run::Precision;
use crate::scenes::scene_file;
use crate::scenes::scene_source::{NamedScene, Origin};

/// The six case names (caliper_position).
pub fn case_names() -> Vec<String> {
    let mut v = Vec::new();
    for c in [Caliper::Push, Caliper::Pull] {
        for (tag, _) in CASE_BETAS {
            v.push(format!("{}_{tag}", c.name()));
        }
    }
    v
}

/// The scene of `case` from the base scene: the base itself for its own name; for one of the
/// six case names the base with that case's caliper and load position, and the rotation's
/// viscous damping c_phi rescaled so that its damping ratio c_phi / (2 sqrt(K I)) stays the
/// base's (K, the rotational stiffness about the pivot, changes with the caliper). Every other
/// key is the base's. `None` for an unknown case.
pub fn case_scene(base: &NamedScene, case: &str) -> Option<Scene> {
    if case == base.name {
        return Some(base.scene);
    }
    for caliper in [Caliper::Push, Caliper::Pull] {
        for (tag, beta) in CASE_BETAS {
            if case == format!("{}_{tag}", caliper.name()) {
                let mut s = base.scene;
                let k_base = Coefficients::of(&s).k_rot;
                s.caliper = caliper;
                s.beta = beta;
                let k_case = Coefficients::of(&s).k_rot;
                if s.c_phi != 0.0 && k_base > 0.0 && k_case > 0.0 {
                    s.c_phi *= (k_case / k_base).sqrt();
                }
                return Some(s);
            }
        }
    }
    None
}

/// A free key, fitted on a log scale between its bounds: the search's coordinate is
/// u = ln((value - origin) / (start - origin)), so value = origin + (start - origin) e^u.
/// `origin` is 0 for every key but mu_k with mu_s held, where it is mu_s: mu_k is then searched
/// as its drop mu_s - mu_k on a log scale ([`drop_coordinate`]), because the stick-slip
/// amplitude scales with the drop (docs/fit.md, "Coordinates").
#[derive(Clone, Debug)]
pub struct FreeKey {
    pub key: String,
    pub start: f64,
    pub lo: f64,
    pub hi: f64,
    pub origin: f64,
}

/// The smallest friction drop mu_s - mu_k searched with mu_s held, relative to mu_s (a log
/// scale cannot reach a drop of 0).
pub const DROP_FLOOR: f64 = 1e-4;

impl FreeKey {
    /// A key on the plain log scale (origin 0).
    pub fn new(key: &str, start: f64, lo: f64, hi: f64) -> FreeKey {
        FreeKey { key: key.to_string(), start, lo, hi, origin: 0.0 }
    }

    /// The value at coordinate `u`.
    #[inline]
    pub fn value(&self, u: f64) -> f64 {
        self.origin + (self.start - self.origin) * u.exp()
    }

    /// The coordinate of `value` (NaN on the wrong side of the origin).
    #[inline]
    pub fn coord(&self, value: f64) -> f64 {
        ((value - self.origin) / (self.start - self.origin)).ln()
    }

    /// The bounds as a range of the coordinate, (lower, upper).
    pub fn u_range(&self) -> (f64, f64) {
        let (a, b) = (self.coord(self.lo), self.coord(self.hi));
        (a.min(b), a.max(b))
    }

    /// |d value / d u| at `value`: a standard error in u times this is one in the value.
    #[inline]
    pub fn scale(&self, value: f64) -> f64 {
        (value - self.origin).abs()
    }

    /// What the coordinate is, for the report: `ln(mu_k)` or `ln(mu_s - mu_k)`.
    pub fn coordinate_name(&self) -> String {
        if self.origin == 0.0 {
            format!("ln({})", self.key)
        } else {
            format!("ln({} - {})", self.origin, self.key)
        }
    }
}

/// mu_k with mu_s held (not free): search it as its drop below mu_s on a log scale, its upper
/// bound at most mu_s (1 - [`DROP_FLOOR`]). Returns a note when the bound was lowered; nothing
/// changes when the start is within that floor of mu_s (then the plain log scale stays).
pub fn drop_coordinate(keys: &mut [FreeKey], mu_s: f64) -> Option<String> {
    if keys.iter().any(|f| f.key == "mu_s") {
        return None;
    }
    let f = keys.iter_mut().find(|f| f.key == "mu_k")?;
    let top = mu_s * (1.0 - DROP_FLOOR);
    if !(mu_s.is_finite() && f.start < top && f.lo < top) {
        return None;
    }
    f.origin = mu_s;
    if f.hi > top {
        f.hi = top;
        return Some(format!(
            "mu_k: searched as the drop mu_s - mu_k on a log scale (mu_s = {mu_s} held), its upper bound lowered to mu_s (1 - {DROP_FLOOR}) = {top}"
        ));
    }
    Some(format!("mu_k: searched as the drop mu_s - mu_k on a log scale (mu_s = {mu_s} held)"))
}

/// The keys a fit may not free: the case's own (beta, set per case) and the run's.
pub const NOT_FREE: [&str; 4] = ["beta", "dt", "duration", "stats_from"];

/// `scene` with the free keys at `values` (in the order of `free`), validated.
pub fn with_values(scene: &Scene, free: &[FreeKey], values: &[f64]) -> Result<Scene, String> {
    with_values_held(scene, free, values, &[])
}

/// The damping ratios a scene file gives (`zeta_x`, `zeta_phi`, `zeta_b`) and their values,
/// for a scene loaded from a file (a built-in scene holds viscous coefficients): a fit holds
/// them, so that the damping follows the stiffness and mass it frees (e.g. zeta_b = 0.05 with
/// k_b and m_b free keeps 5 % of critical). A ratio whose coefficient is free is not held.
pub fn held_ratios(base: &NamedScene, free: &[FreeKey]) -> Vec<(String, f64)> {
    let moved: Vec<&str> = free.iter().map(|f| f.key.as_str()).collect();
    crate::scenes::scene_source::file_ratios(base, &moved)
}

/// `scene` with the free keys at `values`, then the held damping `ratios` re-applied on the
/// new stiffness and mass (see [`held_ratios`]), validated.
pub fn with_values_held(scene: &Scene, free: &[FreeKey], values: &[f64], ratios: &[(String, f64)]) -> Result<Scene, String> {
    let mut s = *scene;
    for (f, v) in free.iter().zip(values) {
        scene_file::set_numeric(&mut s, &f.key, *v)?;
    }
    for (z, v) in ratios {
        scene_file::set_numeric(&mut s, z, *v)?;
    }
    s.validate().map_err(|e| format!("field `{}` = {}: {}", e.field, scene_file::rejected_value(&s, &e), e.rule))?;
    Ok(s)
}

/// The statistics of `scene` (named `name`) through the virtual rig's ideal sensor path, with
/// the estimator's breakaway jump `jump_m_s2` and Welch segment `segment` (spectra only if
/// `spectra`). An error for a run
/// that halts (sprag, contact loss) or leaves nothing to analyse.
pub fn statistics(name: &str, scene: &Scene, jump_m_s2: f64, segment: Option<usize>, spectra: bool) -> Result<Analysis, String> {
    let ns = NamedScene { name: name.to_string(), description: String::new(), origin: Origin::Builtin, scene: *scene };
    if scene.uses_model2() {
        // the same samples into the same analysis as `sil::run` with the options below, without
        // the converter's counts and the truth's statistics (about an eighth of a run's time)
        return match sil::ideal_model2_statistics(&ns, jump_m_s2, segment, spectra) {
            Ok(Some(a)) => Ok(a),
            Ok(None) => Err("nothing to analyse".to_string()),
            Err(sil::IdealRunError::Outcome(outcome, halt_t_s)) => Err(format!("the run ends in {outcome} at t = {halt_t_s:?} s")),
            Err(sil::IdealRunError::Input(m)) => Err(m),
        };
    }
    let opts = SilOptions {
        noise_m_s2: 0.0,
        seed: sil::DEFAULT_SEED,
        segment,
        figures: false,
        breakaway_jump_m_s2: Some(jump_m_s2),
        quiet_s: 0.0,
        gain: crate::recorded::sil::RIG_GAIN,
        oversample: 1,
        adc_noise_counts: 0.0,
        sensor: SensorPath::Ideal,
        spectra,
        windows: false,
    };
    let r = sil::run(&ns, Precision::F64, &opts, None).map_err(|e| e.to_string())?;
    if r.outcome != "completed" {
        return Err(format!("the run ends in {} at t = {:?} s", r.outcome, r.halt_t_s));
    }
    r.measured.ok_or_else(|| "nothing to analyse".to_string())
}
