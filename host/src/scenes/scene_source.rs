//! Where a scene comes from (a built-in name or a scene file), the command-line overrides,
//! and validation with messages that name the file, the field and the rule.

use std::path::{Path, PathBuf};

use stickslip_model::{Scene, SceneError};

use crate::scenes::builtin;
use crate::error::{HostError, Result};
use crate::scenes::scene_file;

/// Where a scene was read from.
#[derive(Clone, Debug)]
pub enum Origin {
    Builtin,
    /// The file and its text (to point at the line of a rejected value).
    File(PathBuf, String),
}

/// A scene with its name, description and origin.
#[derive(Clone, Debug)]
pub struct NamedScene {
    pub name: String,
    pub description: String,
    pub origin: Origin,
    pub scene: Scene,
}

impl NamedScene {
    pub fn from_builtin(b: builtin::Builtin) -> Self {
        NamedScene {
            name: b.name,
            description: b.description,
            origin: Origin::Builtin,
            scene: b.scene,
        }
    }

    /// How to name the scene's origin in a message.
    pub fn origin_label(&self) -> String {
        match &self.origin {
            Origin::Builtin => format!("built-in scene `{}`", self.name),
            Origin::File(p, _) => p.display().to_string(),
        }
    }

    /// "built-in" or the file path, for summaries.
    pub fn origin_short(&self) -> String {
        match &self.origin {
            Origin::Builtin => "built-in".into(),
            Origin::File(p, _) => p.display().to_string(),
        }
    }
}

fn looks_like_path(arg: &str) -> bool {
    arg.contains('/') || arg.contains('\\') || arg.ends_with(".toml") || Path::new(arg).is_file()
}

/// The damping ratios (`zeta_x`, `zeta_phi`, `zeta_b`) a scene's file gives, with their values
/// (none for a built-in scene, which holds viscous coefficients): what a command holds while it
/// moves the stiffness and mass they refer to (a fit's free keys, a map's sweeps), so that the
/// damping follows them (zeta_b = 0.05 keeps 5 % of critical at every k_b and m_b). A ratio
/// whose key or coefficient is among `moved` (the keys the command sets itself) is left out.
pub fn file_ratios(ns: &NamedScene, moved: &[&str]) -> Vec<(String, f64)> {
    let Origin::File(_, text) = &ns.origin else { return Vec::new() };
    ["zeta_x", "zeta_phi", "zeta_b"]
        .into_iter()
        .filter(|z| scene_file::key_line(text, z).is_some())
        .filter(|z| !moved.iter().any(|k| scene_file::field_of(k) == scene_file::field_of(z)))
        .filter_map(|z| scene_file::get_numeric(&ns.scene, z).map(|v| (z.to_string(), v)))
        .collect()
}

/// A built-in name or a path to a scene file. Not yet validated.
pub fn resolve(arg: &str) -> Result<NamedScene> {
    // A built-in name wins over a file of the same name (write `./NAME` for the file).
    if let Some(b) = builtin::find(arg) {
        return Ok(NamedScene::from_builtin(b));
    }
    if !looks_like_path(arg) {
        return Err(HostError::Input(format!(
            "unknown scene `{arg}`: not a built-in scene ({}) and not a scene file",
            builtin::names()
        )));
    }
    load_file(Path::new(arg))
}

/// Reads and parses a scene file (syntax, types and unknown keys are checked here).
pub fn load_file(path: &Path) -> Result<NamedScene> {
    let shown = path.display();
    let text = crate::limits::read_text(path, "scene file", crate::limits::SCENE_FILE_MAX_BYTES)?;
    let parsed = scene_file::parse(&text).map_err(|e| {
        let at = e
            .line_col
            .map_or(String::new(), |(l, c)| format!("line {l}, column {c}: "));
        HostError::Input(format!("{shown}: {at}{}", e.message))
    })?;
    let stem = path
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    Ok(NamedScene {
        name: parsed.name.unwrap_or(stem),
        description: parsed.description.unwrap_or_default(),
        origin: Origin::File(path.to_path_buf(), text),
        scene: parsed.scene,
    })
}

/// Run settings given on the command line; each replaces the scene's value.
#[derive(Clone, Copy, Debug, Default)]
pub struct Overrides {
    pub dt: Option<f64>,
    pub duration: Option<f64>,
    pub stats_from: Option<f64>,
}

impl Overrides {
    fn option_for(&self, field: &str) -> Option<(&'static str, f64)> {
        match field {
            "dt" => self.dt.map(|v| ("--dt", v)),
            "duration" => self.duration.map(|v| ("--duration", v)),
            "stats_from" => self.stats_from.map(|v| ("--stats-from", v)),
            _ => None,
        }
    }

    fn describe(&self) -> String {
        let mut parts = Vec::new();
        for (opt, v) in [
            ("--dt", self.dt),
            ("--duration", self.duration),
            ("--stats-from", self.stats_from),
        ] {
            if let Some(v) = v {
                parts.push(format!("{opt} {}", crate::output::format::short(v)));
            }
        }
        parts.join(" ")
    }

    fn any(&self) -> bool {
        self.dt.is_some() || self.duration.is_some() || self.stats_from.is_some()
    }
}

/// Applies the overrides and validates the scene; the error names the file (and line) or the
/// option, the field and the rule.
pub fn prepare(mut ns: NamedScene, ov: &Overrides) -> Result<NamedScene> {
    if let Some(v) = ov.dt {
        ns.scene.dt = v;
    }
    if let Some(v) = ov.duration {
        ns.scene.duration = v;
    }
    if let Some(v) = ov.stats_from {
        ns.scene.stats_from = v;
    }
    if let Err(e) = ns.scene.validate() {
        return Err(HostError::Input(validation_message(&ns, ov, &e)));
    }
    // a key the scene does not read (the floating pad's c_y on a hinged pad, ...) must still
    // hold a value it could read: a NaN or a negative damping is a mistake wherever it is
    for &key in scene_file::NUMERIC_KEYS.iter().filter(|k| !k.starts_with("zeta_")) {
        let Some(v) = scene_file::get_numeric(&ns.scene, key) else { continue };
        let damping = key.starts_with("c_");
        if v.is_nan() || (damping && !(v.is_finite() && v >= 0.0)) {
            let e = SceneError { field: scene_file::field_of(key), rule: if damping { "damping must be a finite number >= 0" } else { "not a number" }, value: v };
            return Err(HostError::Input(validation_message(&ns, ov, &e)));
        }
    }
    // the statistics window must hold a step: with dt about the window's length every
    // statistic would be n/a
    let s = &ns.scene;
    let steps = crate::scenes::run::planned_steps(s);
    let from_step = (s.stats_from / s.dt).round();
    if from_step >= steps as f64 {
        use crate::output::format::short;
        let culprit = match (ov.dt, ov.duration, ov.stats_from) {
            (Some(_), _, _) => "--dt".to_string(),
            (None, Some(_), _) => "--duration".to_string(),
            (None, None, Some(_)) => "--stats-from".to_string(),
            _ => ns.origin_label(),
        };
        return Err(HostError::Input(format!(
            "{culprit}: the statistics window from stats_from = {} s to duration = {} s holds no step of dt = {} s \
             (the window starts at the step nearest stats_from): give a dt below duration - stats_from",
            short(s.stats_from),
            short(s.duration),
            short(s.dt)
        )));
    }
    // a valid file's keys that do nothing in its scene: a note each, once per process (a fit
    // prepares its scene per case)
    if let Origin::File(path, text) = &ns.origin {
        static NOTED: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());
        for note in scene_file::inert_notes(text, &ns.scene) {
            let line = format!("stickslip: {}: note: {note}", path.display());
            if let Ok(mut seen) = NOTED.lock() {
                if !seen.contains(&line) {
                    eprintln!("{line}");
                    seen.push(line);
                }
            }
        }
    }
    Ok(ns)
}

fn validation_message(ns: &NamedScene, ov: &Overrides, e: &SceneError) -> String {
    let value = scene_file::rejected_value(&ns.scene, e);
    let detail = format!("field `{}` = {value}: {}", e.field, e.rule);
    if let Some((opt, _)) = ov.option_for(e.field) {
        return format!("{opt}: {detail} (scene `{}`)", ns.name);
    }
    let mut origin = ns.origin_label();
    if let Origin::File(_, text) = &ns.origin {
        match scene_file::key_line(text, e.field) {
            Some(line) => origin.push_str(&format!(": line {line}")),
            None => origin.push_str(&format!(" (`{}` not set: default pad value)", e.field)),
        }
    }
    if ov.any() {
        origin.push_str(&format!(" with {}", ov.describe()));
    }
    let hint = if e.field == "stats_from" && ov.duration.is_some() && ov.stats_from.is_none() {
        " (give --stats-from below the duration)"
    } else {
        ""
    };
    format!("{origin}: {detail}{hint}")
}
