//! `simulate` and `scenes`.

use super::{overrides, to_json};
use crate::cli::{ScenesAction, ScenesArgs, SimulateArgs};
use crate::error::Result;
use crate::output::report::{self, SimulateJson};
use crate::scenes::{builtin, event};
use crate::scenes::run::{self, Precision};
use crate::scenes::scene_file;
use crate::scenes::scene_source::{self, Overrides};
use crate::scenes::series::{CsvSink, NoSink};

pub fn simulate(a: &SimulateArgs) -> Result<String> {
    let ns = scene_source::prepare(scene_source::resolve(&a.scene)?, &overrides(&a.run))?;
    let precision = a.run.precision;
    let report = match &a.csv {
        Some(path) => {
            let mut sink = CsvSink::create(path, precision == Precision::F32)?;
            let r = run::run(&ns.scene, precision, &mut sink)?;
            sink.finish()?;
            r
        }
        None => {
            if let Some((r, ev)) = (!a.grid).then(|| event::try_run(&ns.scene, precision, a.events)).transpose()?.flatten() {
                return Ok(if a.json {
                    to_json(&SimulateJson::new(&ns, &r))
                } else {
                    with_method(report::summary(&ns, &r), &ev.describe())
                });
            }
            run::run(&ns.scene, precision, &mut NoSink)?
        }
    };
    Ok(if a.json {
        to_json(&SimulateJson::new(&ns, &report))
    } else {
        report::summary(&ns, &report)
    })
}

/// The summary with the method after its precision line's value ("f64 (event-driven: ...)").
fn with_method(summary: String, method: &str) -> String {
    let mut out = String::with_capacity(summary.len() + method.len() + 3);
    for l in summary.lines() {
        out.push_str(l);
        if l.starts_with("precision ") {
            out.push_str(&format!(" ({method})"));
        }
        out.push('\n');
    }
    out
}

pub fn scenes(a: &ScenesArgs) -> Result<String> {
    match &a.action {
        None => {
            let all = builtin::all();
            let w = all.iter().map(|b| b.name.len()).max().unwrap_or(4).max(4);
            let mut out = format!(
                "{:<w$}  {:<7}  {:>8}  description\n",
                "name", "caliper", "beta [m]"
            );
            for b in all {
                out.push_str(&format!(
                    "{:<w$}  {:<7}  {:>8}  {}\n",
                    b.name,
                    b.scene.caliper.name(),
                    format!("{:.3}", b.scene.beta),
                    b.description
                ));
            }
            out.push_str(
                "\n`stickslip scenes show NAME` prints one as a scene file to copy and edit.\n",
            );
            Ok(out)
        }
        Some(ScenesAction::Show { name }) => {
            let ns = scene_source::prepare(scene_source::resolve(name)?, &Overrides::default())?;
            Ok(scene_file::to_toml(&ns.name, &ns.description, &ns.scene))
        }
    }
}

