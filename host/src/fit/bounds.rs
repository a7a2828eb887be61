//! Default bounds of a fit's free keys, from physics: the range a value of that kind can take
//! on a brake or friction rig, not a factor around the scene's start (docs/fit.md has the
//! table and its reasons). `--bounds KEY=LO:HI` replaces them. A start outside its key's range
//! widens the range to the start (a note says so). A key without an entry here keeps the
//! start / [`FALLBACK_FACTOR`] .. start x [`FALLBACK_FACTOR`] of the fits before.
//!
//! Damping is bounded as a ratio: a viscous coefficient c on a mode of stiffness k and mass m
//! is searched inside 2 zeta sqrt(k m) for zeta in [[`ZETA_LO`], [`ZETA_HI`]], with k and m the
//! scene's (at the start).

use stickslip_model::coefficients::Coefficients;
use stickslip_model::Scene;

/// The factor either way of the start for a key without a physical range.
pub const FALLBACK_FACTOR: f64 = 10.0;
/// Lowest damping ratio searched (a log scale cannot reach 0).
pub const ZETA_LO: f64 = 1e-4;
/// Highest damping ratio searched (critical damping).
pub const ZETA_HI: f64 = 1.0;

/// The physical range [lo, hi] of a key and why, in the scene's units; `None`: no entry.
pub fn physical(key: &str) -> Option<(f64, f64, &'static str)> {
    Some(match key {
        "mu_s" | "mu_k" => (0.05, 1.5, "friction coefficients of dry brake and clutch pairs, PTFE to rubber"),
        "v_s" => (1e-5, 1.0, "Stribeck velocity: 10 um/s (boundary films) to 1 m/s (nearly speed-independent)"),
        "stribeck_exponent" => (0.25, 4.0, "shape of the falling friction: 0.5 to 2 in the literature"),
        "k_g" => (1e3, 1e9, "guide/abutment stiffness: a soft test spring to a steel caliper abutment"),
        "k_b" => (1e3, 1e9, "band drive: an air column (k = gamma p A^2 / V, 2e3 to 2.3e4 N/m on this rig) to a steel drive"),
        "k_l" | "k_t" => (1e4, 1e10, "contact springs: a soft pad material to a metal contact"),
        "k_pivot" => (1e3, 1e10, "pivot normal to the band: a loose guide to a stiff hinge"),
        "contact_exponent" => (1.0, 5.0, "contact law F = k0 d^p: linear (1), Hertz (1.5), to stiffness nearly in proportion to load"),
        "contact_ref_load" => (1.0, 1e4, "the contact law's reference load: a light touch to a brake's clamp force"),
        "m" => (1e-3, 10.0, "pad mass: a tribometer pin to a heavy caliper piston"),
        "m_b" => (1e-2, 100.0, "band mass with what moves with it: a strip to a carriage and rod"),
        "inertia" => (1e-7, 1.0, "pad moment of inertia about its pivot"),
        "f_n" => (1.0, 1e5, "normal load: a tribometer's weight to a brake's clamp force"),
        "v" => (1e-5, 10.0, "band speed: creep groan to a slip test"),
        "zeta_x" | "zeta_phi" | "zeta_b" => (ZETA_LO, ZETA_HI, "damping ratio: 0.01 % to critical"),
        _ => return None,
    })
}

/// For a viscous damping key, the k m under its square root (at the scene's values).
fn stiffness_mass(scene: &Scene, key: &str) -> Option<f64> {
    Some(match key {
        "c_x" => scene.k_g * scene.m,
        "c_phi" => Coefficients::of(scene).k_rot * scene.inertia,
        "c_b" => scene.k_b * scene.m_b,
        "c_y" => (scene.k_l + scene.k_t) * scene.m,
        _ => return None,
    })
}

/// The default bounds of `key` starting at `start` in `scene`, and a note when the start
/// widened them or no physical range exists.
pub fn default_bounds(scene: &Scene, key: &str, start: f64) -> (f64, f64, Option<String>) {
    let (lo, hi) = if let Some((lo, hi, _)) = physical(key) {
        (lo, hi)
    } else if let Some(km) = stiffness_mass(scene, key).filter(|km| *km > 0.0) {
        (2.0 * ZETA_LO * km.sqrt(), 2.0 * ZETA_HI * km.sqrt())
    } else {
        return (
            start / FALLBACK_FACTOR,
            start * FALLBACK_FACTOR,
            Some(format!("{key}: no physical range known: bounds start / {FALLBACK_FACTOR} .. start x {FALLBACK_FACTOR}")),
        );
    };
    if start < lo || start > hi {
        let (l, h) = (lo.min(start), hi.max(start));
        return (l, h, Some(format!("{key}: the start {start} is outside its physical range [{lo}, {hi}]: widened to it")));
    }
    (lo, hi, None)
}
