//! The regression anchors' check (`thesis_anchor.rs`, `model2_anchor.rs`): every scene of a
//! set at the rig's step (1/25600 s) and at 1 ms, its f32 and f64 digests against the pinned
//! rows; on a difference, the names that changed and every row as it is now (to re-pin).

use stickslip_model::Scene;

/// (scene, dt [s], f32 digest, f64 digest).
pub type PinnedRow = (&'static str, f64, u64, u64);

/// Steps of the anchors [s]: the rig's and 1 ms.
pub const ANCHOR_DTS: [f64; 2] = [1.0 / 25600.0, 1e-3];

pub fn assert_pinned(set: Vec<(String, Scene)>, pinned: &[PinnedRow], digests: impl Fn(&Scene) -> (u64, u64)) {
    let mut rows = Vec::new();
    let mut bad = Vec::new();
    for (name, base) in set {
        for dt in ANCHOR_DTS {
            let mut s = base;
            s.dt = dt;
            let (d32, d64) = digests(&s);
            rows.push(format!("    (\"{name}\", {dt:?}, 0x{d32:016x}, 0x{d64:016x}),"));
            match pinned.iter().find(|r| r.0 == name && r.1 == dt) {
                Some(r) if r.2 == d32 && r.3 == d64 => {}
                _ => bad.push(format!("{name} at dt {dt}")),
            }
        }
    }
    assert!(bad.is_empty(), "changed: {bad:?}\nnow:\n{}", rows.join("\n"));
}
