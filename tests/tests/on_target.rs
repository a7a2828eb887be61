//! The model on the Cortex-M4F, bit for bit: runs the on-target digest program
//! (tests/on-target, bin `digest`) under QEMU's netduinoplus2 and recomputes every digest it
//! prints on x86-64, with the same source (`tests/on-target/src/scenes.rs`, included below).
//!
//! Ignored by default: it needs qemu-system-arm and the cross-built ELF. `scripts/test-all.sh`
//! builds both and runs
//!
//!     STICKSLIP_ON_TARGET_ELF=tests/on-target/target/thumbv7em-none-eabihf/release/digest \
//!         cargo test --release -p stickslip-crosscheck --test on_target -- --ignored
//!
//! Run without the variable, or with a QEMU that fails, it fails: it never passes vacuously.

use std::io::Read;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[allow(dead_code)]
#[path = "../on-target/src/scenes.rs"]
mod scenes;

use scenes::{Report, CASES};

/// Hang guard for QEMU (the whole program takes about a second): not a timing assertion,
/// a program that never exits fails instead of blocking the test run.
const QEMU_WATCHDOG: Duration = Duration::from_secs(600);

fn run_qemu(elf: &PathBuf) -> (std::process::ExitStatus, String, String) {
    let mut child = Command::new("qemu-system-arm")
        .args(["-M", "netduinoplus2", "-nographic", "-monitor", "none", "-serial", "null"])
        .args(["-semihosting-config", "enable=on,target=native", "-kernel"])
        .arg(elf)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start qemu-system-arm: {e} (install the Debian package qemu-system-arm)"));
    let mut stdout = child.stdout.take().expect("piped stdout");
    let mut stderr = child.stderr.take().expect("piped stderr");
    let out_reader = std::thread::spawn(move || {
        let mut s = String::new();
        stdout.read_to_string(&mut s).map(|_| s)
    });
    let err_reader = std::thread::spawn(move || {
        let mut s = String::new();
        stderr.read_to_string(&mut s).map(|_| s)
    });
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("waiting for QEMU") {
            break status;
        }
        if started.elapsed() > QEMU_WATCHDOG {
            let _ = child.kill();
            let _ = child.wait();
            panic!("QEMU did not exit within {QEMU_WATCHDOG:?}: killed");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let out = out_reader.join().expect("stdout reader").expect("QEMU stdout is UTF-8");
    let err = err_reader.join().expect("stderr reader").unwrap_or_default();
    (status, out, err)
}

/// Digest lines on the target equal the same runs' digests on the host.
#[test]
#[ignore = "needs qemu-system-arm and STICKSLIP_ON_TARGET_ELF (scripts/test-all.sh runs it)"]
fn on_target_digests_equal_host_digests() {
    let elf = std::env::var_os("STICKSLIP_ON_TARGET_ELF").map(PathBuf::from).unwrap_or_else(|| {
        panic!(
            "STICKSLIP_ON_TARGET_ELF is not set: point it at the cross-built \
             tests/on-target/target/thumbv7em-none-eabihf/release/digest (scripts/test-all.sh does)"
        )
    });
    assert!(elf.is_file(), "STICKSLIP_ON_TARGET_ELF={} is not a file", elf.display());

    let (status, out, err) = run_qemu(&elf);
    assert!(
        status.success(),
        "the on-target program failed under QEMU ({status}):\n--- stdout\n{out}\n--- stderr\n{err}"
    );
    let expected_runs = 2 * CASES.len();
    assert!(
        out.lines().any(|l| l.trim() == format!("done runs={expected_runs}")),
        "the on-target program did not report `done runs={expected_runs}`:\n{out}"
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
            assert_eq!(run.steps, scenes::step_count(&scene), "{} {real} stopped early on the host: {:?}", case.name, run.halt);
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
    assert!(mismatches.is_empty(), "host and Cortex-M4F runs differ:\n{}", mismatches.join("\n"));
}
