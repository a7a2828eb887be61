//! The numerics reports: `accuracy` and `stability`, with their `--check`.

use super::{stderr_is_terminal, to_json};
use crate::cli::{AccuracyArgs, StabilityArgs};
use crate::error::{HostError, Result};
use crate::numerics::{accuracy, stability};
use crate::output::numerics_plots;

/// A report whose `--check` failed is still printed; the failure sets the exit code.
fn checked(out: String, failures: Vec<String>) -> Result<String> {
    if failures.is_empty() {
        return Ok(out);
    }
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    let _ = stdout.write_all(out.as_bytes()).and_then(|_| stdout.flush());
    Err(HostError::Check(format!("check failed: {}", failures.join("; "))))
}

pub fn accuracy(a: &AccuracyArgs) -> Result<String> {
    let opts = accuracy::Options {
        quick: a.quick,
        repeats: a.repeats.map_or(if a.quick { 1 } else { 3 }, usize::from),
        progress: stderr_is_terminal(),
    };
    let rep = accuracy::run(&opts)?;
    if let Some(path) = &a.plot {
        numerics_plots::accuracy(&rep, path)?;
    }
    let out = if a.report.json { to_json(&rep) } else { accuracy::markdown(&rep) };
    let failures = if a.report.check {
        rep.checks
            .iter()
            .filter(|c| !c.passed)
            .map(|c| format!("{} = {} (bound {:e})", c.what, c.value.map_or("none".into(), |v| format!("{v:.3e}")), c.bound))
            .collect()
    } else {
        Vec::new()
    };
    checked(out, failures)
}

pub fn stability(a: &StabilityArgs) -> Result<String> {
    let rep = stability::run(&stability::Options { quick: a.quick, progress: stderr_is_terminal() })?;
    if let Some(path) = &a.plot {
        numerics_plots::stability(&rep, path)?;
    }
    let out = if a.report.json { to_json(&rep) } else { stability::markdown(&rep) };
    let mut failures = Vec::new();
    if a.report.check {
        for prec in ["f64", "f32"] {
            let ok = rep.rows.iter().any(|r| {
                r.sweep == "contact_stiffness" && r.contact_stiffness == 1e10 && r.method == "exact" && r.precision == prec && r.outcome == "bounded"
            });
            if !ok {
                failures.push(format!("exact {prec} not bounded at contact stiffness 1e10 N/m"));
            }
        }
        if !stability::all_finite(&rep) {
            failures.push("a row holds a non-finite value".into());
        }
        let known = ["bounded", "sprag", "contact_loss", "method_unstable"];
        if rep.rows.iter().any(|r| !known.contains(&r.outcome.as_str())) {
            failures.push("a row is not classified".into());
        }
    }
    checked(out, failures)
}
