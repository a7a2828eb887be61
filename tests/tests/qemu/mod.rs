//! Runs a Cortex-M4F program under QEMU's netduinoplus2 (STM32F405) with semihosting, for the
//! on-target tests: exit status, standard output as bytes, standard error. Each test file
//! compiles this module for itself and uses a part of it.
#![allow(dead_code)]

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Hang guard for QEMU (the whole program takes about a second): not a timing assertion,
/// a program that never exits fails instead of blocking the test run.
const QEMU_WATCHDOG: Duration = Duration::from_secs(600);

pub fn run(elf: &Path) -> (std::process::ExitStatus, Vec<u8>, String) {
    run_with(elf, &[])
}

/// [`run`] with more QEMU options (e.g. `-d unimp`: QEMU's log of accesses to devices it does
/// not emulate, on standard error).
pub fn run_with(elf: &Path, extra: &[&str]) -> (std::process::ExitStatus, Vec<u8>, String) {
    let mut child = Command::new("qemu-system-arm")
        .args(["-M", "netduinoplus2", "-nographic", "-monitor", "none", "-serial", "null"])
        .args(extra)
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
        let mut s = Vec::new();
        stdout.read_to_end(&mut s).map(|_| s)
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
    let out = out_reader.join().expect("stdout reader").expect("QEMU stdout is readable");
    let err = err_reader.join().expect("stderr reader").unwrap_or_default();
    (status, out, err)
}

/// The ELF named by the environment variable `var` (which must be set and name a file).
pub fn elf_from_env(var: &str, bin: &str) -> PathBuf {
    let elf = std::env::var_os(var).map(PathBuf::from).unwrap_or_else(|| {
        panic!(
            "{var} is not set: point it at the cross-built \
             tests/on-target/target/thumbv7em-none-eabihf/release/{bin} (scripts/test-all.sh does)"
        )
    });
    assert!(elf.is_file(), "{var}={} is not a file", elf.display());
    elf
}

/// Starts `elf` under QEMU as [`run`] does and hands over its standard output as it comes
/// (standard error is discarded); [`wait`] ends it.
pub fn spawn(elf: &Path) -> (std::process::Child, std::process::ChildStdout) {
    let mut child = Command::new("qemu-system-arm")
        .args(["-M", "netduinoplus2", "-nographic", "-monitor", "none", "-serial", "null"])
        .args(["-semihosting-config", "enable=on,target=native", "-kernel"])
        .arg(elf)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start qemu-system-arm: {e} (install the Debian package qemu-system-arm)"));
    let stdout = child.stdout.take().expect("piped stdout");
    (child, stdout)
}

/// Waits for a QEMU started by [`spawn`], killed after the hang guard.
pub fn wait(child: &mut std::process::Child) -> std::process::ExitStatus {
    let started = Instant::now();
    loop {
        if let Some(status) = child.try_wait().expect("waiting for QEMU") {
            return status;
        }
        if started.elapsed() > QEMU_WATCHDOG {
            let _ = child.kill();
            let _ = child.wait();
            panic!("QEMU did not exit within {QEMU_WATCHDOG:?}: killed");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}
