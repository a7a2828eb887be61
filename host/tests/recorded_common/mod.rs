//! Helpers shared by the `recorded_*` tests: run the binary, scratch files, CSV generators.
#![allow(dead_code)]

use std::fs;
use std::path::PathBuf;
use std::process::{Command, Output};

use serde_json::Value;

pub mod defmt_fixture;

pub fn stickslip(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_stickslip")).args(args).output().expect("the stickslip binary runs")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs and expects exit code 0; returns stdout.
pub fn ok(args: &[&str]) -> String {
    let o = stickslip(args);
    assert_eq!(o.status.code(), Some(0), "{args:?} failed: {}", stderr(&o));
    String::from_utf8(o.stdout).expect("stdout is UTF-8")
}

pub fn json(args: &[&str]) -> Value {
    let out = ok(args);
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{args:?}: not JSON ({e}):\n{out}"))
}

/// Expects exit code 2, nothing on stdout and one line on stderr starting with "error: " and
/// containing every needle; returns the line.
pub fn bad(args: &[&str], needles: &[&str]) -> String {
    let o = stickslip(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: want exit 2, stderr: {err}");
    assert!(o.stdout.is_empty(), "{args:?}: nothing on stdout on error");
    let line = err.trim_end();
    assert_eq!(line.lines().count(), 1, "{args:?}: one line on stderr, got:\n{err}");
    assert!(line.starts_with("error: "), "{args:?}: {line}");
    assert!(!line.contains("panicked"), "{args:?}: {line}");
    for n in needles {
        assert!(line.contains(n), "{args:?}: `{n}` missing from: {line}");
    }
    line.to_string()
}

/// Gaussian noise from a xorshift generator (Box-Muller), deterministic for a seed.
pub struct Noise(pub u64);

impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    /// A normal number of standard deviation `sigma`.
    pub fn gauss(&mut self, sigma: f64) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        sigma * (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// A fresh directory for one test.
pub fn scratch(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("stickslip-recorded").join(name);
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

pub fn write(dir: &std::path::Path, name: &str, bytes: impl AsRef<[u8]>) -> String {
    let p = dir.join(name);
    fs::write(&p, bytes).unwrap();
    p.to_str().unwrap().to_string()
}

pub fn num(v: &Value, path: &[&str]) -> f64 {
    let mut x = v;
    for k in path {
        x = &x[*k];
    }
    x.as_f64().unwrap_or_else(|| panic!("{path:?} is not a number: {x}"))
}

pub const CHANNELS: [&str; 4] = ["disc_x", "pad_x", "pad_trail", "pad_lead"];
