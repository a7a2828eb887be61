//! Model 2's runs at event speed (the maps' runs, f64): Stribeck slip and stick in wide chunks
//! of several steps (`Model2Tables::wide_step`, `wide_stick`), transitions located on the
//! guard's quadratic below 2^-9 of a substep and the substep's last units in one Taylor step
//! (`Model2Observer::LOCATE_BELOW_LEVEL`), slip tables shared by cells that differ in V.
//!
//! The reference is the sampled path: an ETDRK4 chunk per step, transitions lifted over 2^53
//! units of a substep (a different computation at 4^4 = 256 times smaller truncation error);
//! maps against the same maps stepped at every step (`--step-stick`).

mod thesis_common;

use stickslip::scenes::run::{start_state, Start};
use stickslip_model::model2::{AnyModel2Stepper, WideChunks, WideSamples};
use stickslip_model::{Regime, Scene};
use thesis_common::{assert_maps_within, builtin, map_of};

/// The steps of one wide chunk (the map's choice).
const M: usize = stickslip::scenes::run::WIDE_STEPS;

/// The errors of one kind of wide chunk (slip or stick) against the sampled steps.
#[derive(Default, Debug)]
struct Errors {
    /// Chunks taken.
    chunks: usize,
    /// Largest error of x'' [m/s^2], of the sliding velocity [m/s], of each state entry.
    acc: f64,
    v: f64,
    z: [f64; 8],
}

/// Runs `scene` from `z0` (None: from rest) for `seconds` on the sampled path and, at every
/// step where a wide chunk is taken from its state, compares the chunk's samples and end state
/// with the next m sampled steps. Returns, for the slip chunks and for the stick chunks, the
/// chunks taken and the errors, each relative: x'' over the run's largest |x''|, the sliding
/// velocity over V, each state entry over its largest magnitude in the run (the largest).
fn local_errors(scene: &Scene, z0: Option<[f64; 8]>, seconds: f64) -> [(usize, f64, f64, f64); 2] {
    let mut st = AnyModel2Stepper::<f64>::new(scene).unwrap();
    let wide: WideChunks = st.wide_chunks(scene, M).expect("the scene takes wide chunks");
    if let Some(z) = z0 {
        st.set_state(z, Regime::SlipSlower);
    }
    let steps = (seconds / scene.dt).round() as usize;
    let mut errs = [Errors::default(), Errors::default()];
    let (mut acc_scale, mut z_scale) = (0.0f64, [0.0f64; 8]);
    let mut out = WideSamples::default();
    for _ in 0..steps {
        let mut w = st.clone();
        let e = &mut errs[usize::from(st.regime() == Regime::Stick)];
        if w.wide_step(&wide, &mut (), true, &mut out) {
            let mut r = st.clone();
            for k in 0..M {
                r.step().unwrap();
                e.acc = e.acc.max((r.pad_acceleration() - out.pad_acc[k]).abs());
                e.v = e.v.max((r.sliding_velocity(&r.state()) - out.v[k]).abs());
            }
            assert_eq!(w.steps(), r.steps());
            assert_eq!(w.regime(), r.regime());
            for (i, d) in e.z.iter_mut().enumerate() {
                *d = d.max((w.state()[i] - r.state()[i]).abs());
            }
            e.chunks += 1;
        }
        st.step().unwrap();
        acc_scale = acc_scale.max(st.pad_acceleration().abs());
        for (i, s) in z_scale.iter_mut().enumerate() {
            *s = s.max(st.state()[i].abs());
        }
    }
    errs.map(|e| {
        let z = e.z.iter().zip(&z_scale).map(|(d, s)| if *s > 0.0 { d / s } else { 0.0 }).fold(0.0, f64::max);
        (e.chunks, e.acc / acc_scale, e.v / scene.v, z)
    })
}

/// Each wide chunk against the m sampled steps from the same state, on a floating pad and two
/// hinged ones' sets, from perturbed steady sliding and from rest (stick-slip): slip's samples
/// and end state to 2e-5 (ETDRK4 over 4 steps against 4 chunks of one; the samples between from
/// the cubic forcing; measured at most 6e-6), stick's to round-off (both exact flows).
#[test]
fn wide_chunks_are_the_sampled_steps() {
    for name in ["rig_float_push_center", "rig_push_center", "rig_float_pull_lead"] {
        let scene = builtin(name);
        for start in [Start::Sliding { kick: 0.01 }, Start::Rest] {
            let z0 = start_state(&scene, start).unwrap();
            let [slip, stick] = local_errors(&scene, z0, 0.4);
            eprintln!("{name} {start:?}: slip {slip:?}, stick {stick:?} (chunks; x'', v, z)");
            assert!(slip.0 > 100, "{name} {start:?}: slip chunks taken ({})", slip.0);
            assert!(slip.1 <= 2e-5, "{name} {start:?}: slip x'' samples off by {:.2e} of its range", slip.1);
            assert!(slip.2 <= 2e-5, "{name} {start:?}: slip sliding velocity samples off by {:.2e} of V", slip.2);
            assert!(slip.3 <= 2e-5, "{name} {start:?}: slip end states off by {:.2e}", slip.3);
            assert_stick_exact(name, &stick);
        }
    }
}

/// Stick chunks against the sampled steps: both exact flows, to round-off.
fn assert_stick_exact(name: &str, stick: &(usize, f64, f64, f64)) {
    assert!(stick.1 <= 1e-12, "{name}: stick x'' samples off by {:.2e} of its range", stick.1);
    assert!(stick.2 <= 1e-12, "{name}: stick sliding velocity samples off by {:.2e} of V", stick.2);
    assert!(stick.3 <= 1e-12, "{name}: stick end states off by {:.2e}", stick.3);
}

/// A run that stays stuck but for a slip at its start (static friction far above what the load
/// asks): thousands of stick chunks, exact to round-off against the sampled steps.
#[test]
fn wide_stick_chunks_are_exact() {
    let scene = Scene { mu_s: 0.9, ..builtin("rig_float_push_center") };
    let [slip, stick] = local_errors(&scene, None, 0.2);
    eprintln!("stuck: slip {slip:?}, stick {stick:?}");
    assert!(stick.0 > 1000, "stick chunks taken ({})", stick.0);
    assert_stick_exact("stuck", &stick);
}

/// Maps at event speed against the same maps stepped at every step: the same regimes; stick
/// fraction, stick-slip frequency and the peak-to-peak values to 1e-4 (measured on the README's
/// 100 x 100 rig map: at most 2.2e-5, see docs/maps.md), the groan RMS to 3e-3 (a transition
/// that moves by 1e-6 of a sample across a sample boundary moves x'''s jump into the next
/// sample). On the floating rig set over beta x V, the hinged one over V x mu_s; and with a
/// Stribeck exponent of 2, which takes no wide chunks: the sampled path itself, bit for bit.
#[test]
fn wide_maps_are_the_stepped_maps() {
    let cases = [
        ("rig_float_push_center", builtin("rig_float_push_center"), ["beta=0.012:0.068:4", "v=0.001:0.01:4"]),
        ("rig_push_center", builtin("rig_push_center"), ["v=0.002:0.01:4", "mu_s=0.45:0.6:4"]),
        ("rig_push_center, delta 2", Scene { stribeck_exponent: 2.0, ..builtin("rig_push_center") }, ["v=0.002:0.01:4", "beta=0.03:0.05:4"]),
    ];
    for (name, scene, sweeps) in cases {
        let (a, b) = (map_of(name, scene, true, &sweeps), map_of(name, scene, false, &sweeps));
        assert_eq!(a.cells.len(), 16);
        let (_, worst) = assert_maps_within(&format!("{name} at event speed against stepped"), &a, &b, [1e-4, 1e-4, 1e-4, 1e-4, 3e-3], true);
        eprintln!("{name}: worst {:?}", worst.map(|w| format!("{w:.1e}")));
        if scene.stribeck_exponent != 1.0 {
            assert_eq!(worst, [0.0; 5], "{name}: no wide chunks, the sampled path");
        }
    }
}

/// The slip tables a cell takes from an earlier cell of the same thread are the ones it would
/// compute: a map swept in the other order (beta fastest, so that no cell's predecessor shares
/// its tables, against V fastest, so that most do) gives every cell the same values, bit for
/// bit.
#[test]
fn shared_slip_tables_change_no_bit() {
    let scene = builtin("rig_float_push_center");
    let a = map_of("rig_float_push_center", scene, true, &["beta=0.02:0.06:3", "v=0.002:0.008:3"]);
    let b = map_of("rig_float_push_center", scene, true, &["v=0.002:0.008:3", "beta=0.02:0.06:3"]);
    let key = |c: &stickslip::map::cell::CellJson| {
        let p = &c.params;
        (p["beta"].as_f64().unwrap().to_bits(), p["v"].as_f64().unwrap().to_bits())
    };
    let mut n = 0;
    for ca in &a.cells {
        let cb = b.cells.iter().find(|c| key(c) == key(ca)).expect("the same cell in both maps");
        assert_eq!(serde_json::to_string(&ca.from_rest).unwrap(), serde_json::to_string(&cb.from_rest).unwrap());
        assert_eq!(serde_json::to_string(&ca.from_sliding).unwrap(), serde_json::to_string(&cb.from_sliding).unwrap());
        n += 1;
    }
    assert_eq!(n, 9);
}
