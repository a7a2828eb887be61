//! The model and the rig's per-sample code on the Cortex-M4F, bit for bit: runs the on-target
//! programs (tests/on-target) under QEMU's netduinoplus2 and recomputes every digest they print
//! on x86-64, with the same sources (included below):
//!
//! - bin `digest`: the exact stepper in f32 and f64, and each model-2 composition in f32 (the
//!   firmware's lockstep models: `Band`, `Stribeck`, `StribeckBand` on the rig set's push_center)
//!   (`tests/cases/src/scenes.rs`);
//! - bin `rig`: frames from the sensor model through calibration, estimator (window statistics,
//!   lockstep model) and sequencer: the one rig, `stickslip_model::rig::pipeline::Rig`, which
//!   the firmware runs, digested by `stickslip_model::harness::replay` (`tests/cases/src/rig_scenes.rs`).
//!
//! Ignored by default: they need qemu-system-arm and the cross-built ELFs. `scripts/test-all.sh`
//! builds both and runs
//!
//!     STICKSLIP_ON_TARGET_ELF=tests/on-target/target/thumbv7em-none-eabihf/release/digest \
//!     STICKSLIP_ON_TARGET_RIG_ELF=tests/on-target/target/thumbv7em-none-eabihf/release/rig \
//!         cargo test --release -p stickslip-crosscheck --test on_target -- --ignored
//!
//! Run without its variable, or with a QEMU that fails, each fails: it never passes vacuously.

use std::path::Path;

mod qemu;

use qemu::elf_from_env;

// The runs the on-target program prints (tests/cases), built for the host: the same code the
// Cortex-M4F runs.
use stickslip_crosscheck_cases::{rig_scenes, scenes};

use rig_scenes::{RigReport, RIG_CASES};
use scenes::{Report, Report2, CASES};
use stickslip_model::model2::{Band, Composition, Stribeck, StribeckBand};

/// Runs an on-target program under QEMU: its exit status, standard output (UTF-8 text for
/// these programs) and standard error.
fn run_qemu(elf: &Path) -> (std::process::ExitStatus, String, String) {
    let (status, out, err) = qemu::run(elf);
    (status, String::from_utf8(out).expect("QEMU stdout is UTF-8"), err)
}


/// Digest lines on the target equal the same runs' digests on the host.
#[test]
#[ignore = "needs qemu-system-arm and STICKSLIP_ON_TARGET_ELF (scripts/test-all.sh runs it)"]
fn on_target_digests_equal_host_digests() {
    let elf = elf_from_env("STICKSLIP_ON_TARGET_ELF", "digest");

    let (status, out, err) = run_qemu(&elf);
    assert!(
        status.success(),
        "the on-target program failed under QEMU ({status}):\n--- stdout\n{out}\n--- stderr\n{err}"
    );
    let expected_runs = 2 * CASES.len();
    assert!(
        out.lines().any(|l| l.trim() == format!("done runs={expected_runs} model2_runs=3")),
        "the on-target program did not report `done runs={expected_runs} model2_runs=3`:\n{out}"
    );

    let target_lines: Vec<&str> = out.lines().map(str::trim).filter(|l| l.starts_with("digest ")).collect();
    assert_eq!(target_lines.len(), expected_runs, "digest lines from the target:\n{out}");

    let mut mismatches = Vec::new();
    for case in CASES {
        let scene = (case.scene)();
        for real in ["f32", "f64"] {
            let run = match real {
                "f32" => scenes::run::<f32>(&scene),
                _ => scenes::run::<f64>(&scene),
            }
            .unwrap_or_else(|e| panic!("scene {} rejected on the host: {e}", case.name));
            assert_eq!(
                run.steps,
                scenes::step_count(&scene),
                "{} {real} stopped early on the host: {:?}",
                case.name,
                run.halt
            );
            let host = Report { scene: case.name, real, run: &run }.to_string();
            let prefix = format!("digest {} {real} ", case.name);
            let target: Vec<&&str> = target_lines.iter().filter(|l| l.starts_with(&prefix)).collect();
            assert_eq!(target.len(), 1, "expected one line starting with `{prefix}` from the target:\n{out}");
            println!("host:   {host}\ntarget: {}", target[0]);
            if *target[0] != host {
                mismatches.push(format!("host   {host}\ntarget {}", target[0]));
            }
        }
    }
    // model 2, each composition in f32 (the firmware's lockstep models)
    fn host2<C: Composition>() -> (String, scenes::RunDigest) {
        let run = scenes::run_model2::<f32, C>(&scenes::model2_scene::<C>()).unwrap();
        (Report2 { composition: C::NAME, real: "f32", run: &run }.to_string(), run)
    }
    for (host, run) in [host2::<Band>(), host2::<Stribeck>(), host2::<StribeckBand>()] {
        assert!(run.halt.is_none() && run.transitions > 10, "model-2 run on the host: {host}");
        let prefix = host.splitn(4, ' ').take(3).collect::<Vec<_>>().join(" ") + " ";
        let target: Vec<&str> = target_lines2(&out).into_iter().filter(|l| l.starts_with(&prefix)).collect();
        assert_eq!(target.len(), 1, "expected one line starting with `{prefix}` from the target:\n{out}");
        println!("host:   {host}\ntarget: {}", target[0]);
        if target[0] != host {
            mismatches.push(format!("host   {host}\ntarget {}", target[0]));
        }
    }
    assert!(mismatches.is_empty(), "host and Cortex-M4F runs differ:\n{}", mismatches.join("\n"));
}

/// The model-2 digest lines of the target's output.
fn target_lines2(out: &str) -> Vec<&str> {
    out.lines().map(str::trim).filter(|l| l.starts_with("digest2 ")).collect()
}

/// The rig cases' digest lines on the target equal the same runs' digests on the host: the
/// whole per-sample chain (calibration, estimator with its windows and the lockstep model,
/// sequencer: the one rig, in the replay's scripts) is bit-identical.
#[test]
#[ignore = "needs qemu-system-arm and STICKSLIP_ON_TARGET_RIG_ELF (scripts/test-all.sh runs it)"]
fn on_target_rig_digests_equal_host_digests() {
    let elf = elf_from_env("STICKSLIP_ON_TARGET_RIG_ELF", "rig");

    let (status, out, err) = run_qemu(&elf);
    assert!(
        status.success(),
        "the on-target rig program failed under QEMU ({status}):\n--- stdout\n{out}\n--- stderr\n{err}"
    );
    let done = format!("done rig_cases={}", RIG_CASES.len());
    assert!(out.lines().any(|l| l.trim() == done), "the on-target program did not report `{done}`:\n{out}");
    let target_lines: Vec<&str> = out.lines().map(str::trim).filter(|l| l.starts_with("rig_digest ")).collect();
    assert_eq!(target_lines.len(), RIG_CASES.len(), "rig_digest lines from the target:\n{out}");

    let mut mismatches = Vec::new();
    for case in &RIG_CASES {
        let run =
            rig_scenes::run(case).unwrap_or_else(|e| panic!("rig case {} refused on the host: {}", case.name, e.0));
        assert!(!run.sensor_halted, "rig case {}: the sensor model halted on the host", case.name);
        assert!(run.windows >= 4, "rig case {}: only {} windows closed on the host", case.name, run.windows);
        assert!(run.slip_onsets >= 1, "rig case {}: no slip onset found on the host", case.name);
        let host = RigReport { case: case.name, run: &run }.to_string();
        let prefix = format!("rig_digest {} ", case.name);
        let target: Vec<&&str> = target_lines.iter().filter(|l| l.starts_with(&prefix)).collect();
        assert_eq!(target.len(), 1, "expected one line starting with `{prefix}` from the target:\n{out}");
        println!("host:   {host}\ntarget: {}", target[0]);
        if *target[0] != host {
            mismatches.push(format!("host   {host}\ntarget {}", target[0]));
        }
    }
    // the stack the firmware's set-up takes, as measured on the target (informative)
    for l in out.lines().filter(|l| l.starts_with("stack ")) {
        println!("target: {l}");
    }
    assert!(mismatches.is_empty(), "host and Cortex-M4F rig runs differ:\n{}", mismatches.join("\n"));
}
