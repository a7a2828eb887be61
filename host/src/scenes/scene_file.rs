//! Scene files: TOML whose keys are the `Scene` field names, plus `name` and an optional
//! `description`. Keys left out take the default pad's value (`DEFAULT_SCENE`, i.e. the
//! built-in `push_center`); unknown keys are an error. `to_toml` writes every key with a
//! comment giving its unit and meaning, in a form `parse` reads back to the same scene.

use serde::Deserialize;
use stickslip_model::{BandDrive, Caliper, Coefficients, ContactLaw, FrictionLaw, Scene, DEFAULT_SCENE};

/// `caliper = "push" | "pull"`.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "lowercase")]
enum CaliperKey {
    Push,
    Pull,
}

/// `friction = "coulomb" | "stribeck"`.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "lowercase")]
enum FrictionKey {
    Coulomb,
    Stribeck,
}

/// `contact = "bilateral" | "unilateral"`.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "lowercase")]
enum ContactKey {
    Bilateral,
    Unilateral,
}

/// `drive = "velocity" | "pneumatic"`.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "lowercase")]
enum DriveKey {
    Velocity,
    Pneumatic,
}

/// The file as written: every key optional.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneToml {
    name: Option<String>,
    description: Option<String>,
    caliper: Option<CaliperKey>,
    m: Option<f64>,
    inertia: Option<f64>,
    l: Option<f64>,
    w: Option<f64>,
    l_cl: Option<f64>,
    l_ct: Option<f64>,
    k_l: Option<f64>,
    k_t: Option<f64>,
    k_g: Option<f64>,
    f_n: Option<f64>,
    beta: Option<f64>,
    v: Option<f64>,
    mu_s: Option<f64>,
    mu_k: Option<f64>,
    c_x: Option<f64>,
    c_phi: Option<f64>,
    rotation: Option<bool>,
    friction: Option<FrictionKey>,
    v_s: Option<f64>,
    stribeck_exponent: Option<f64>,
    band: Option<bool>,
    m_b: Option<f64>,
    k_b: Option<f64>,
    c_b: Option<f64>,
    face: Option<bool>,
    k_pivot: Option<f64>,
    c_y: Option<f64>,
    contact: Option<ContactKey>,
    contact_exponent: Option<f64>,
    contact_ref_load: Option<f64>,
    drive: Option<DriveKey>,
    bore: Option<f64>,
    supply_pressure: Option<f64>,
    throttle_conductance: Option<f64>,
    throttle_critical_ratio: Option<f64>,
    column_length: Option<f64>,
    polytropic_exponent: Option<f64>,
    seal_static: Option<f64>,
    seal_kinetic: Option<f64>,
    seal_v_s: Option<f64>,
    zeta_x: Option<f64>,
    zeta_phi: Option<f64>,
    zeta_b: Option<f64>,
    dt: Option<f64>,
    duration: Option<f64>,
    stats_from: Option<f64>,
}

/// A scene read from a file, not yet validated.
#[derive(Clone, Debug)]
pub struct ParsedScene {
    pub name: Option<String>,
    pub description: Option<String>,
    pub scene: Scene,
}

/// Unit and meaning of each key, in file order (also used for `--help`).
pub const KEYS: [(&str, &str); 49] = [
    ("name", "scene name (reported in every output)"),
    ("description", "one line for `stickslip scenes` (optional)"),
    (
        "caliper",
        "\"push\": guide and pivot at the trailing edge; \"pull\": at the leading edge",
    ),
    ("m", "pad mass m [kg]"),
    (
        "inertia",
        "moment of inertia about the pivot (supported edge, mid-thickness) I [kg m^2]",
    ),
    ("l", "pad half-length l [m] (the pad is 2 l long)"),
    (
        "w",
        "pad half-thickness w [m] (friction face to pivot line)",
    ),
    (
        "l_cl",
        "centre of gravity to the leading contact spring l_cL [m], < l",
    ),
    (
        "l_ct",
        "centre of gravity to the trailing contact spring l_cT [m], < l",
    ),
    ("k_l", "leading contact spring stiffness k_L [N/m]"),
    ("k_t", "trailing contact spring stiffness k_T [N/m]"),
    ("k_g", "guide (abutment) stiffness along x k_g [N/m]"),
    ("f_n", "normal load F_N [N]"),
    (
        "beta",
        "load position from the trailing edge beta [m], 0 <= beta <= 2 l",
    ),
    ("v", "band speed V [m/s], > 0"),
    ("mu_s", "static friction coefficient mu_s [-]"),
    (
        "mu_k",
        "kinetic friction coefficient mu_k [-], 0 <= mu_k <= mu_s",
    ),
    ("c_x", "viscous damping on x c_x [N s/m]"),
    ("c_phi", "viscous damping on phi c_phi [N m s/rad]"),
    (
        "rotation",
        "true: 2-DOF pad; false: phi held at F_N a_N / K (1-DOF mass on a belt, N constant)",
    ),
    (
        "friction",
        "\"coulomb\" (the thesis: mu_s in stick, mu_k in slip) or \"stribeck\": \
         mu(v) = mu_k + (mu_s - mu_k) exp(-(|v| / v_s)^delta) in slip",
    ),
    ("v_s", "Stribeck velocity v_s [m/s], > 0 (friction = \"stribeck\")"),
    (
        "stribeck_exponent",
        "Stribeck exponent delta [-], 0 < delta <= 8 (friction = \"stribeck\")",
    ),
    (
        "band",
        "true: the band is a mass m_b driven at V through k_b, c_b; false: it moves at exactly V",
    ),
    ("m_b", "band mass m_b [kg] (band = true)"),
    ("k_b", "band drive (cylinder) stiffness k_b [N/m] (band = true)"),
    ("c_b", "band drive damping c_b [N s/m] (band = true)"),
    (
        "face",
        "true: friction-face kinematics, the face (w from the pivot) slides at x' + s w phi' less \
         the band's velocity and stick holds it there; false: the thesis's pivot, x' less the band's",
    ),
    (
        "k_pivot",
        "pivot stiffness normal to the band k_pivot [N/m]: inf (the default) is the thesis's hinge; \
         finite, the pad also translates normal to the band (y); 0, a floating pad (needs face = true)",
    ),
    ("c_y", "viscous damping on the pad's normal translation y c_y [N s/m] (finite k_pivot)"),
    (
        "contact",
        "\"bilateral\" (the default: the edge springs push and pull; one that would pull halts the run \
         with contact_loss) or \"unilateral\": they push and never pull, an edge opens and closes \
         again (finite k_pivot; runs event-driven in f64 on the host)",
    ),
    (
        "contact_exponent",
        "exponent p of the edge springs' load law F = k0 d^p, 1 <= p <= 5 (1, the default: linear \
         springs; 1.5: Hertz-like): each spring's stiffness becomes the law's tangent at its static \
         load, k (F / contact_ref_load)^((p - 1) / p)",
    ),
    (
        "contact_ref_load",
        "reference load F_ref [N] at which k_l and k_t are the springs' tangent stiffness \
         (contact_exponent > 1)",
    ),
    (
        "drive",
        "\"velocity\" (the default: the band's drive point moves at exactly v) or \"pneumatic\": a \
         throttled cylinder pushes the band (band = true) through its air column against its seal's \
         friction, the band's speed emerges (k_b is not used, c_b is the band's damping on its guides; \
         runs event-driven in f64 on the host)",
    ),
    ("bore", "pneumatic drive: cylinder bore D [m], piston area pi D^2 / 4"),
    ("supply_pressure", "pneumatic drive: supply pressure p_s, absolute [Pa]"),
    (
        "throttle_conductance",
        "pneumatic drive: the throttle's sonic conductance C [m^3/(s Pa)] (ISO 6358); 0 (the default): \
         solved so that steady sliding runs at v",
    ),
    ("throttle_critical_ratio", "pneumatic drive: the throttle's critical pressure ratio b [-] (ISO 6358), 0 <= b < 1"),
    ("column_length", "pneumatic drive: the air column's length at the start L_0 [m] (dead volume included)"),
    ("polytropic_exponent", "pneumatic drive: polytropic exponent n of the air column, 1 (isothermal) to 1.4 (adiabatic)"),
    ("seal_static", "pneumatic drive: the cylinder seal's static friction [N]"),
    ("seal_kinetic", "pneumatic drive: the seal's kinetic friction [N], <= seal_static"),
    ("seal_v_s", "pneumatic drive: the seal friction's Stribeck velocity [m/s]"),
    (
        "zeta_x",
        "instead of c_x: damping ratio of the x mode in slip, c_x = 2 zeta_x sqrt(k_g m) [-]",
    ),
    (
        "zeta_phi",
        "instead of c_phi: damping ratio of the rotation, c_phi = 2 zeta_phi sqrt(K I) [-]",
    ),
    (
        "zeta_b",
        "instead of c_b: damping ratio of the band drive, c_b = 2 zeta_b sqrt(k_b m_b) [-]",
    ),
    ("dt", "fixed time step [s]"),
    ("duration", "run length [s]"),
    (
        "stats_from",
        "start of the statistics window [s]; the window runs to `duration`",
    ),
];

/// A TOML syntax, type or unknown-key error, located in the file.
#[derive(Debug)]
pub struct ParseError {
    /// 1-based line and column, when the parser gave a position.
    pub line_col: Option<(usize, usize)>,
    pub message: String,
}

fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = &text.as_bytes()[..offset];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |p| p + 1);
    let col = String::from_utf8_lossy(&before[line_start..])
        .chars()
        .count()
        + 1;
    (line, col)
}

/// Reads a scene file's text. The scene is the default pad with the file's keys applied.
pub fn parse(text: &str) -> Result<ParsedScene, ParseError> {
    let t: SceneToml = toml::from_str(text).map_err(|e| {
        let mut message = e.message().trim().to_string();
        // toml says "duplicate key" and points at it: name it
        if let (Some(span), true) = (e.span(), message == "duplicate key") {
            let key = text.get(span.clone()).unwrap_or("").split('=').next().unwrap_or("").trim();
            if !key.is_empty() && key.len() <= 64 {
                message = format!("duplicate key `{key}` (a key may be set once)");
            }
        }
        ParseError { line_col: e.span().map(|s| line_col(text, s.start)), message }
    })?;
    let mut s = DEFAULT_SCENE;
    if let Some(c) = t.caliper {
        s.caliper = match c {
            CaliperKey::Push => Caliper::Push,
            CaliperKey::Pull => Caliper::Pull,
        };
    }
    macro_rules! take {
        ($($f:ident),*) => { $( if let Some(v) = t.$f { s.$f = v; } )* };
    }
    take!(
        m, inertia, l, w, l_cl, l_ct, k_l, k_t, k_g, f_n, beta, v, mu_s, mu_k, c_x, c_phi,
        rotation, v_s, stribeck_exponent, band, m_b, k_b, c_b, face, k_pivot, c_y, contact_exponent, contact_ref_load, bore, supply_pressure, throttle_conductance, throttle_critical_ratio, column_length, polytropic_exponent, seal_static, seal_kinetic, seal_v_s, dt,
        duration, stats_from
    );
    if let Some(c) = t.contact {
        s.contact = match c {
            ContactKey::Bilateral => ContactLaw::Bilateral,
            ContactKey::Unilateral => ContactLaw::Unilateral,
        };
    }
    if let Some(d) = t.drive {
        s.drive = match d {
            DriveKey::Velocity => BandDrive::Velocity,
            DriveKey::Pneumatic => BandDrive::Pneumatic,
        };
    }
    if let Some(f) = t.friction {
        s.friction = match f {
            FrictionKey::Coulomb => FrictionLaw::Coulomb,
            FrictionKey::Stribeck => FrictionLaw::Stribeck,
        };
    }
    // Damping ratios: converted to the viscous coefficient with the scene's own stiffness and
    // inertia, after every other key is applied. A ratio and its coefficient together are
    // ambiguous.
    let co = Coefficients::of(&s);
    let ratios = [
        ("zeta_x", "c_x", t.zeta_x, t.c_x.is_some(), s.k_g * s.m),
        ("zeta_phi", "c_phi", t.zeta_phi, t.c_phi.is_some(), co.k_rot * s.inertia),
        ("zeta_b", "c_b", t.zeta_b, t.c_b.is_some(), s.k_b * s.m_b),
    ];
    for (key, coef, zeta, coef_given, km) in ratios {
        let Some(zeta) = zeta else { continue };
        let err = |message: String| ParseError { line_col: key_line(text, key).map(|l| (l, 1)), message };
        if coef_given {
            return Err(err(format!("`{key}` and `{coef}` both set: give the damping one way")));
        }
        if !(zeta.is_finite() && zeta >= 0.0) {
            return Err(err(format!("`{key}` = {zeta}: a damping ratio must be a finite number >= 0")));
        }
        let c = 2.0 * zeta * km.max(0.0).sqrt();
        match coef {
            "c_x" => s.c_x = c,
            "c_phi" => s.c_phi = c,
            _ => s.c_b = c,
        }
    }
    Ok(ParsedScene {
        name: t.name,
        description: t.description,
        scene: s,
    })
}

/// The 1-based line on which `key` is set, if it is (for pointing at a value that fails
/// validation).
pub fn key_line(text: &str, key: &str) -> Option<usize> {
    text.lines()
        .position(|line| {
            let l = line.trim_start();
            l.strip_prefix(key)
                .map(|rest| rest.trim_start().starts_with('='))
                .unwrap_or(false)
        })
        .map(|i| i + 1)
}

/// A float as a TOML float that parses back to the same f64 (shortest round-trip digits).
pub fn toml_float(v: f64) -> String {
    if v != 0.0 && v == v.trunc() && v.abs() >= 1e4 {
        format!("{v:e}") // 1e6, 2.5e5: valid TOML floats
    } else {
        format!("{v:?}") // 0.3, 150.0, 3.90625e-5
    }
}

fn toml_string(s: &str) -> String {
    // A basic string with the escapes TOML needs.
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 || c as u32 == 0x7f => {
                out.push_str(&format!("\\u{:04X}", c as u32))
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The value of each key of `s`, as TOML, in [`KEYS`] order (name and description excluded).
fn values(s: &Scene) -> Vec<(&'static str, String)> {
    let f = toml_float;
    let mut v = vec![
        ("caliper", toml_string(s.caliper.name())),
        ("m", f(s.m)),
        ("inertia", f(s.inertia)),
        ("l", f(s.l)),
        ("w", f(s.w)),
        ("l_cl", f(s.l_cl)),
        ("l_ct", f(s.l_ct)),
        ("k_l", f(s.k_l)),
        ("k_t", f(s.k_t)),
        ("k_g", f(s.k_g)),
        ("f_n", f(s.f_n)),
        ("beta", f(s.beta)),
        ("v", f(s.v)),
        ("mu_s", f(s.mu_s)),
        ("mu_k", f(s.mu_k)),
        ("c_x", f(s.c_x)),
        ("c_phi", f(s.c_phi)),
        ("rotation", s.rotation.to_string()),
    ];
    // model-2 options: written only when on (a scene carries only what it uses)
    if s.friction == FrictionLaw::Stribeck {
        v.push(("friction", toml_string(s.friction.name())));
        v.push(("v_s", f(s.v_s)));
        v.push(("stribeck_exponent", f(s.stribeck_exponent)));
    }
    if s.band {
        v.push(("band", "true".to_string()));
        v.push(("m_b", f(s.m_b)));
        v.push(("k_b", f(s.k_b)));
        v.push(("c_b", f(s.c_b)));
    }
    if s.face {
        v.push(("face", "true".to_string()));
    }
    if s.floating() {
        v.push(("k_pivot", f(s.k_pivot)));
        v.push(("c_y", f(s.c_y)));
    }
    if s.unilateral() {
        v.push(("contact", toml_string(s.contact.name())));
    }
    if s.contact_exponent != 1.0 {
        v.push(("contact_exponent", f(s.contact_exponent)));
        v.push(("contact_ref_load", f(s.contact_ref_load)));
    }
    if s.pneumatic() {
        v.push(("drive", toml_string(s.drive.name())));
        v.push(("bore", f(s.bore)));
        v.push(("supply_pressure", f(s.supply_pressure)));
        v.push(("throttle_conductance", f(s.throttle_conductance)));
        v.push(("throttle_critical_ratio", f(s.throttle_critical_ratio)));
        v.push(("column_length", f(s.column_length)));
        v.push(("polytropic_exponent", f(s.polytropic_exponent)));
        v.push(("seal_static", f(s.seal_static)));
        v.push(("seal_kinetic", f(s.seal_kinetic)));
        v.push(("seal_v_s", f(s.seal_v_s)));
    }
    v.extend([
        ("dt", f(s.dt)),
        ("duration", f(s.duration)),
        ("stats_from", f(s.stats_from)),
    ]);
    v
}

/// The scene as a complete, commented scene file.
pub fn to_toml(name: &str, description: &str, s: &Scene) -> String {
    let co = Coefficients::of(s);
    let mut out = String::new();
    out.push_str(&format!("# stickslip scene `{name}`: {description}\n"));
    out.push_str(
        "#\n\
         # SI units throughout. Run it with `stickslip simulate FILE`. Keys left out of a scene file\n\
         # take the default pad's value (the built-in push_center); unknown keys are an error.\n\
         # Values that break a rule (e.g. m <= 0, mu_k > mu_s, beta off the pad) are rejected.\n",
    );
    let g = |v: f64| -> String {
        // seven significant digits, shortest form
        format!("{:.6e}", v)
            .parse::<f64>()
            .map_or_else(|_| v.to_string(), |r| format!("{r}"))
    };
    out.push_str(&format!(
        "# Derived, for reference (not keys): K = {} N m/rad, c_N = {} N/rad, a_N = {} m,\n\
         # static rotation phi0 = F_N a_N / K = {} rad, static normal force N0 = c_N phi0 = {} N.\n\n",
        g(co.k_rot),
        g(co.c_n),
        g(co.a_n),
        g(co.phi0),
        g(co.n0)
    ));
    let mut lines: Vec<(String, &str)> = vec![
        (format!("name = {}", toml_string(name)), KEYS[0].1),
        (
            format!("description = {}", toml_string(description)),
            KEYS[1].1,
        ),
    ];
    for (key, value) in values(s) {
        let meaning = KEYS.iter().find(|(k, _)| *k == key).map_or("", |(_, m)| *m);
        lines.push((format!("{key} = {value}"), meaning));
    }
    let width = lines
        .iter()
        .map(|(l, _)| l.len())
        .filter(|&n| n <= 40)
        .max()
        .unwrap_or(0);
    for (line, meaning) in lines {
        let mut comment = meaning.to_string();
        if line.starts_with("dt = ") {
            let rate = 1.0 / s.dt;
            if rate == rate.round() && rate < 1e12 {
                comment.push_str(&format!(" (= 1/{} s)", rate as u64));
            }
        }
        out.push_str(&format!("{line:<width$}  # {comment}\n"));
    }
    out
}

/// The numeric scene keys (those a sweep can set), in [`KEYS`] order.
pub const NUMERIC_KEYS: [&str; 40] = [
    "m", "inertia", "l", "w", "l_cl", "l_ct", "k_l", "k_t", "k_g", "f_n", "beta", "v", "mu_s", "mu_k", "c_x", "c_phi",
    "v_s", "stribeck_exponent", "m_b", "k_b", "c_b", "k_pivot", "c_y", "contact_exponent", "contact_ref_load",
    "bore", "supply_pressure", "throttle_conductance", "throttle_critical_ratio", "column_length", "polytropic_exponent", "seal_static", "seal_kinetic", "seal_v_s", "zeta_x", "zeta_phi", "zeta_b", "dt",
    "duration", "stats_from",
];

/// Why the numeric key `key` does nothing in scene `s` (None: it acts): the Stribeck keys
/// under Coulomb friction, the band's keys without the band, the floating pad's damping on a
/// hinged pad. A fit or a sweep of such a key would vary nothing and report it as a finding.
pub fn inert_key(s: &Scene, key: &str) -> Option<&'static str> {
    match key {
        "v_s" | "stribeck_exponent" if s.friction == stickslip_model::FrictionLaw::Coulomb => {
            Some("the scene has Coulomb friction (friction = \"coulomb\"): the Stribeck keys do nothing; set friction = \"stribeck\"")
        }
        "m_b" | "k_b" | "c_b" | "zeta_b" if !s.band => {
            Some("the scene has no band (band = false): the band's keys do nothing; set band = true")
        }
        "c_y" if !s.floating() => Some("the pad is hinged (k_pivot = inf): c_y does nothing; give a finite k_pivot"),
        "bore" | "supply_pressure" | "throttle_conductance" | "throttle_critical_ratio" | "column_length"
        | "polytropic_exponent" | "seal_static" | "seal_kinetic" | "seal_v_s"
            if !s.pneumatic() =>
        {
            Some("the band is driven at v (drive = \"velocity\"): the cylinder's keys do nothing; set drive = \"pneumatic\"")
        }
        "k_b" | "zeta_b" if s.pneumatic() => {
            Some("the pneumatic drive's air column is the band's spring (drive = \"pneumatic\"): k_b does nothing")
        }
        "contact_ref_load" if s.contact_exponent == 1.0 => {
            Some("the edge springs are linear (contact_exponent = 1): contact_ref_load does nothing; set contact_exponent > 1")
        }
        _ => None,
    }
}

/// The keys a scene file sets to a value other than the default pad's that do nothing in its
/// scene ([`inert_key`]: `v_s` under Coulomb friction, the band's keys without the band, ...),
/// each as a note naming the key, its value and why (the file still runs: the value is unused,
/// and a file written by `scenes show` sets every key at its default).
pub fn inert_notes(text: &str, s: &Scene) -> Vec<String> {
    NUMERIC_KEYS
        .iter()
        .filter(|k| key_line(text, k).is_some())
        .filter_map(|k| {
            let why = inert_key(s, k)?;
            let (v, d) = (get_numeric(s, k)?, get_numeric(&DEFAULT_SCENE, k)?);
            (v.to_bits() != d.to_bits()).then(|| format!("`{k}` = {} does nothing: {why}", crate::output::format::short(v)))
        })
        .collect()
}

/// Sets the numeric key `key` of `s` to `value` (SI units, as in a scene file). A damping ratio
/// (`zeta_x`, `zeta_phi`, `zeta_b`) sets its viscous coefficient from the scene's stiffness and
/// inertia as they are now, so set it after them. The scene is not validated here. Errors:
/// a key that is not a numeric scene key, a damping ratio that is negative or not finite.
pub fn set_numeric(s: &mut Scene, key: &str, value: f64) -> Result<(), String> {
    macro_rules! keys {
        ($($f:ident),*) => {
            match key {
                $( stringify!($f) => { s.$f = value; return Ok(()); } )*
                _ => {}
            }
        };
    }
    keys!(m, inertia, l, w, l_cl, l_ct, k_l, k_t, k_g, f_n, beta, v, mu_s, mu_k, c_x, c_phi, v_s, stribeck_exponent, m_b, k_b, c_b, k_pivot, c_y, contact_exponent, contact_ref_load, bore, supply_pressure, throttle_conductance, throttle_critical_ratio, column_length, polytropic_exponent, seal_static, seal_kinetic, seal_v_s, dt, duration, stats_from);
    let km = match key {
        "zeta_x" => s.k_g * s.m,
        "zeta_phi" => Coefficients::of(s).k_rot * s.inertia,
        "zeta_b" => s.k_b * s.m_b,
        _ => return Err(format!("unknown numeric scene key `{key}` (the numeric keys: {})", NUMERIC_KEYS.join(", "))),
    };
    if !(value.is_finite() && value >= 0.0) {
        return Err(format!("`{key}` = {value}: a damping ratio must be a finite number >= 0"));
    }
    let c = 2.0 * value * km.max(0.0).sqrt();
    match key {
        "zeta_x" => s.c_x = c,
        "zeta_phi" => s.c_phi = c,
        _ => s.c_b = c,
    }
    Ok(())
}

/// The value of the numeric key `key` of `s` (SI units, as in a scene file): a damping
/// ratio is the viscous coefficient over 2 sqrt(stiffness x inertia) as [`set_numeric`] sets
/// it. `None` for a key that is not a numeric scene key.
pub fn get_numeric(s: &Scene, key: &str) -> Option<f64> {
    macro_rules! keys {
        ($($f:ident),*) => {
            match key {
                $( stringify!($f) => return Some(s.$f), )*
                _ => {}
            }
        };
    }
    keys!(m, inertia, l, w, l_cl, l_ct, k_l, k_t, k_g, f_n, beta, v, mu_s, mu_k, c_x, c_phi, v_s, stribeck_exponent, m_b, k_b, c_b, k_pivot, c_y, contact_exponent, contact_ref_load, bore, supply_pressure, throttle_conductance, throttle_critical_ratio, column_length, polytropic_exponent, seal_static, seal_kinetic, seal_v_s, dt, duration, stats_from);
    let (c, km) = match key {
        "zeta_x" => (s.c_x, s.k_g * s.m),
        "zeta_phi" => (s.c_phi, Coefficients::of(s).k_rot * s.inertia),
        "zeta_b" => (s.c_b, s.k_b * s.m_b),
        _ => return None,
    };
    Some(c / (2.0 * km.max(0.0).sqrt()))
}

/// The value of a rejected field as a scene file writes it: a word key's word (`contact =
/// "unilateral"`, `band = true`), a number's short form otherwise (a rule on a word key carries
/// no number worth printing: it printed `contact` = inf).
pub fn rejected_value(s: &Scene, e: &stickslip_model::SceneError) -> String {
    match e.field {
        "caliper" => toml_string(s.caliper.name()),
        "friction" => toml_string(s.friction.name()),
        "contact" => toml_string(s.contact.name()),
        "drive" => toml_string(s.drive.name()),
        "band" => s.band.to_string(),
        "face" => s.face.to_string(),
        "rotation" => s.rotation.to_string(),
        _ => crate::output::format::short(e.value),
    }
}

/// The field a numeric key sets ([`set_numeric`]): the key itself, or a damping ratio's
/// viscous coefficient.
pub fn field_of(key: &str) -> &str {
    match key {
        "zeta_x" => "c_x",
        "zeta_phi" => "c_phi",
        "zeta_b" => "c_b",
        k => k,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::builtin;

    #[test]
    fn get_numeric_reads_what_set_numeric_wrote() {
        let mut s = crate::scenes::builtin::find("rig_pull_lead").unwrap().scene;
        for (i, key) in NUMERIC_KEYS.iter().enumerate() {
            let v = 0.125 + i as f64;
            set_numeric(&mut s, key, v).unwrap();
            let back = get_numeric(&s, key).unwrap();
            assert!((back - v).abs() <= 1e-14 * v, "{key}: set {v}, read {back}");
        }
        assert_eq!(get_numeric(&s, "caliper"), None);
        assert_eq!(get_numeric(&s, "no_such_key"), None);
    }

    #[test]
    fn every_builtin_round_trips_exactly() {
        for b in builtin::all() {
            let text = to_toml(&b.name, &b.description, &b.scene);
            let p = parse(&text).unwrap_or_else(|e| panic!("{}: {:?}\n{text}", b.name, e));
            assert_eq!(p.scene, b.scene, "{}", b.name);
            assert_eq!(p.name.as_deref(), Some(b.name.as_str()));
            assert_eq!(p.description.as_deref(), Some(b.description.as_str()));
        }
    }

    #[test]
    fn omitted_keys_take_the_default_pad() {
        let p = parse("name = \"x\"\nm = 2\n").unwrap();
        let mut want = DEFAULT_SCENE;
        want.m = 2.0;
        assert_eq!(p.scene, want);
    }

    #[test]
    fn floats_survive_formatting() {
        for v in [
            0.3,
            1e6,
            2e5,
            3.90625e-5,
            150.0,
            15.073529411764707,
            1e-12,
            0.0,
            1.5e4,
            123456.0,
            1e300,
        ] {
            let text = format!("m = {}", toml_float(v));
            let t: toml::Table = toml::from_str(&text).unwrap();
            assert_eq!(t["m"].as_float(), Some(v), "{text}");
        }
    }

    #[test]
    fn errors_are_located() {
        let e = parse("m = 1\nbogus = 3\n").unwrap_err();
        assert_eq!(e.line_col.map(|p| p.0), Some(2));
        assert!(e.message.contains("bogus"), "{}", e.message);
        assert_eq!(key_line("# m = 2\n  m= 3\n", "m"), Some(2));
        assert_eq!(key_line("mu_s = 3\n", "m"), None);
    }
}
