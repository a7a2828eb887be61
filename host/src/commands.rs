//! The commands. Each returns what goes to stdout; errors go back to `main`.

use std::path::Path;

use crate::scenes::builtin;
use crate::cli::{AccuracyArgs, CasesArgs, RunOptions, ScenesAction, ScenesArgs, SimulateArgs, StabilityArgs};
use crate::numerics::{accuracy, stability};
use crate::output::numerics_plots;
use crate::output::format::short;
use crate::error::{HostError, Result};
use crate::output::plots::{self, FigureContext, Line};
use crate::output::report::{self, CaseJson, CasesJson, SimulateJson};
use crate::scenes::run::{self, Precision, RunReport};
use crate::scenes::scene_file;
use crate::scenes::scene_source::{self, NamedScene, Overrides};
use crate::scenes::series::{CsvSink, NoSink, Recorder};

fn overrides(o: &RunOptions) -> Overrides {
    Overrides {
        dt: o.dt,
        duration: o.duration,
        stats_from: o.stats_from,
    }
}

fn to_json<T: serde::Serialize>(v: &T) -> String {
    // Serializing plain structs of numbers and strings cannot fail; no NaN reaches here
    // (non-finite values are None, printed as null).
    let mut s =
        serde_json::to_string_pretty(v).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"));
    s.push('\n');
    s
}

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
        None => run::run(&ns.scene, precision, &mut NoSink)?,
    };
    Ok(if a.json {
        to_json(&SimulateJson::new(&ns, &report))
    } else {
        report::summary(&ns, &report)
    })
}

/// The plotted window [s]: checked against the run length.
fn plot_window(a: &CasesArgs, ns: &NamedScene) -> Result<(f64, f64)> {
    let run_s = run::planned_steps(&ns.scene) as f64 * ns.scene.dt;
    let from = a.plot_from.unwrap_or(ns.scene.stats_from);
    let bad = |opt: &str, v: f64, rule: String| Err(HostError::Input(format!("{opt} {}: {rule}", short(v))));
    if !(from.is_finite() && from >= 0.0 && from < run_s) {
        return bad(
            "--plot-from",
            from,
            format!("plot start must satisfy 0 <= start < run length {run_s} s"),
        );
    }
    let to = a.plot_to.unwrap_or((from + 0.1).min(run_s));
    if !(to.is_finite() && to > from && to <= run_s * (1.0 + 1e-12)) {
        return bad(
            "--plot-to",
            to,
            format!("plot end must satisfy plot start {from} s < end <= run length {run_s} s"),
        );
    }
    Ok((from, to))
}

pub fn cases(a: &CasesArgs) -> Result<String> {
    let ov = overrides(&a.run);
    let set = match a.set {
        crate::cli::CaseSet::Thesis => builtin::cases(),
        crate::cli::CaseSet::Rig => builtin::rig_cases(),
        crate::cli::CaseSet::RigFloat => builtin::rig_float_cases(),
    };
    let scenes = set
        .into_iter()
        .map(|b| scene_source::prepare(NamedScene::from_builtin(b), &ov))
        .collect::<Result<Vec<_>>>()?;
    let window = match &a.plots {
        Some(_) => Some(plot_window(a, &scenes[0])?),
        None => None,
    };
    let mut runs: Vec<(NamedScene, RunReport)> = Vec::with_capacity(scenes.len());
    let mut recorded: Vec<Recorder> = Vec::new();
    for ns in scenes {
        let r = match window {
            Some((from, to)) => {
                let mut rec = Recorder::new(from, to);
                let r = run::run(&ns.scene, a.run.precision, &mut rec)?;
                recorded.push(rec);
                r
            }
            None => run::run(&ns.scene, a.run.precision, &mut NoSink)?,
        };
        runs.push((ns, r));
    }
    if let (Some(dir), Some((from, to))) = (&a.plots, window) {
        let n = write_figures(dir, &runs, &recorded, from, to)?;
        eprintln!("stickslip: wrote {n} SVG figures to {}", dir.display());
    }
    if a.json {
        let (ns0, r0) = &runs[0];
        let j = CasesJson {
            precision: a.run.precision.name(),
            dt: ns0.scene.dt,
            duration: ns0.scene.duration,
            stats_from: r0.window_start,
            cases: runs.iter().map(|(ns, r)| CaseJson::new(ns, r)).collect(),
        };
        Ok(to_json(&j))
    } else {
        let mut out = report::cases_table(&runs);
        if a.set == crate::cli::CaseSet::Thesis {
            out.push_str(&damping_sensitivity(&runs, a.run.precision)?);
        }
        Ok(out)
    }
}

/// The thesis set has no damping, and its push cases hinge on that: each case again with 1 %
/// and 5 % of critical damping on phi (c_phi = 2 zeta sqrt(K I)), each statistic as the
/// relative change from the undamped run.
fn damping_sensitivity(runs: &[(NamedScene, RunReport)], precision: run::Precision) -> Result<String> {
    let mut out = String::from(
        "\nSensitivity to damping on phi (the thesis sets none): each case with zeta_phi = 1 % and 5 %, \
         c_phi = 2 zeta sqrt(K I); relative change from the undamped run above.\n\n\
         | case | zeta_phi | x pp | x' pp | phi pp | phi' pp | stick fraction | stick-slip frequency |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for (ns, r0) in runs {
        for zeta in [0.01, 0.05] {
            let mut s = ns.scene;
            s.c_phi = 2.0 * zeta * (stickslip_model::Coefficients::of(&s).k_rot * s.inertia).sqrt();
            let r = run::run(&s, precision, &mut NoSink)?;
            let change = |a: Option<f64>, b: Option<f64>| match (a, b) {
                (Some(a), Some(b)) if b != 0.0 => format!("{:+.1} %", (a / b - 1.0) * 100.0),
                _ => "n/a".into(),
            };
            let sf = |r: &RunReport| r.has_window().then_some(r.stats.stick_fraction);
            let hz = |r: &RunReport| r.has_window().then_some(r.stats.stick_slip_hz);
            out.push_str(&format!(
                "| {} | {} % | {} | {} | {} | {} | {} | {} |\n",
                ns.name,
                zeta * 100.0,
                change(r.pp(0), r0.pp(0)),
                change(r.pp(1), r0.pp(1)),
                change(r.pp(2), r0.pp(2)),
                change(r.pp(3), r0.pp(3)),
                change(sf(&r), sf(r0)),
                change(hz(&r), hz(r0)),
            ));
        }
    }
    Ok(out)
}

fn write_figures(
    dir: &Path,
    runs: &[(NamedScene, RunReport)],
    rec: &[Recorder],
    from: f64,
    to: f64,
) -> Result<usize> {
    std::fs::create_dir_all(dir).map_err(|e| {
        HostError::Output(format!(
            "{}: cannot create the figure directory: {e}",
            dir.display()
        ))
    })?;
    let mut n = 0;
    for caliper in ["push", "pull"] {
        let idx: Vec<usize> = (0..runs.len())
            .filter(|&i| runs[i].0.scene.caliper.name() == caliper)
            .collect();
        let Some(&first) = idx.first() else { continue };
        let lines: Vec<Line> = idx
            .iter()
            .map(|&i| {
                let ns = &runs[i].0;
                let place = ns.name.rsplit('_').next().unwrap_or("");
                let place = match place {
                    "trail" => "trailing",
                    "center" => "centre",
                    "lead" => "leading",
                    p => p,
                };
                Line {
                    label: format!("β = {:.3} m ({place})", ns.scene.beta),
                    samples: &rec[i].samples,
                }
            })
            .collect();
        let s = &runs[first].0.scene;
        let ctx = FigureContext {
            caliper,
            from,
            to,
            run_s: run::planned_steps(s) as f64 * s.dt,
            v: s.v,
        };
        n += plots::caliper_figures(dir, &ctx, &lines)?.len();
    }
    Ok(n)
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

fn stderr_is_terminal() -> bool {
    use std::io::IsTerminal;
    std::io::stderr().is_terminal()
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
    let out = if a.json { to_json(&rep) } else { accuracy::markdown(&rep) };
    let failures = if a.check {
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
    let out = if a.json { to_json(&rep) } else { stability::markdown(&rep) };
    let mut failures = Vec::new();
    if a.check {
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

fn check_segment(segment: Option<usize>) -> Result<()> {
    match segment {
        Some(n) if n < 16 || n % 2 != 0 || n > 1 << 20 => Err(HostError::Input(format!(
            "--segment {n}: the Welch segment must be an even number of samples from 16 to 1048576"
        ))),
        _ => Ok(()),
    }
}

fn check_jump(jump: Option<f64>) -> Result<()> {
    match jump {
        Some(j) if !(j.is_finite() && j > 0.0 && j <= crate::limits::BREAKAWAY_JUMP_MAX_M_S2) => Err(HostError::Input(format!(
            "--breakaway-jump {}: must be an acceleration with 0 < J <= {} m/s^2",
            short(j),
            short(crate::limits::BREAKAWAY_JUMP_MAX_M_S2)
        ))),
        _ => Ok(()),
    }
}

/// The virtual rig's noise options within their ranges (`--help`): one line naming the option.
fn check_sil_noise(n: &crate::cli::SilNoise) -> Result<()> {
    use crate::limits::{ADC_NOISE_MAX_COUNTS, NOISE_MAX_M_S2, QUIET_LEAD_MAX_S};
    let bad = |opt: &str, v: f64, rule: String| Err(HostError::Input(format!("{opt} {}: {rule}", short(v))));
    if !(n.noise.is_finite() && (0.0..=NOISE_MAX_M_S2).contains(&n.noise)) {
        return bad("--noise", n.noise, format!("the sensor noise must be from 0 to {} m/s^2 rms", short(NOISE_MAX_M_S2)));
    }
    if !(n.quiet_lead.is_finite() && (0.0..=QUIET_LEAD_MAX_S).contains(&n.quiet_lead)) {
        return bad("--quiet-lead", n.quiet_lead, format!("the quiet lead must be from 0 to {} s", short(QUIET_LEAD_MAX_S)));
    }
    if !(n.adc_noise.is_finite() && (0.0..=ADC_NOISE_MAX_COUNTS).contains(&n.adc_noise)) {
        return bad("--adc-noise", n.adc_noise, format!("the converter noise must be from 0 to {} counts rms", short(ADC_NOISE_MAX_COUNTS)));
    }
    Ok(())
}

/// The contact thresholds' source from `--breakaway-jump` and `--quiet FROM:TO`.
fn floor_source(jump: Option<f64>, quiet: Option<&str>) -> Result<crate::recorded::analysis::FloorSource> {
    use crate::recorded::analysis::FloorSource;
    match (jump, quiet) {
        (Some(_), Some(_)) => Err(HostError::Input(
            "--breakaway-jump and --quiet: give one (fixed thresholds, or thresholds from the floor of a quiet stretch)".into(),
        )),
        (Some(_), None) => Ok(FloorSource::Jump),
        (None, None) => Ok(FloorSource::Auto),
        (None, Some(q)) => {
            let bad = |why: &str| HostError::Input(format!("--quiet {q}: {why}"));
            let (a, b) = q.split_once(':').ok_or_else(|| bad("expected FROM:TO in s"))?;
            let num = |v: &str| v.trim().parse::<f64>().ok().filter(|x| x.is_finite());
            match (num(a), num(b)) {
                (Some(f), Some(t)) if f < t => Ok(FloorSource::Range(f, t)),
                (Some(_), Some(_)) => Err(bad("FROM must be below TO")),
                _ => Err(bad("FROM and TO must be finite times in s")),
            }
        }
    }
}

/// The front end's gains from `--gain` (none: the rig's 0.2; one: all four; four: each).
fn gains(g: &[f64]) -> Result<[f64; 4]> {
    let rig = crate::recorded::sil::RIG_GAIN;
    let out = match g.len() {
        0 => rig,
        1 => [g[0]; 4],
        4 => [g[0], g[1], g[2], g[3]],
        n => return Err(HostError::Input(format!("--gain: {n} values: give one (all four channels) or four"))),
    };
    let (lo, hi) = crate::limits::GAIN_RANGE;
    for v in out {
        if !(v.is_finite() && v >= lo && v <= hi) {
            return Err(HostError::Input(format!("--gain {}: the front-end gain must be from {} to {} V/V", short(v), short(lo), short(hi))));
        }
    }
    Ok(out)
}

/// The read options of `--channel` and `--gaps`.
fn read_options(i: &crate::cli::RecordingInput) -> Result<crate::recorded::ReadOptions> {
    Ok(crate::recorded::ReadOptions {
        channels: crate::recorded::channels::ChannelMap::parse(&i.channels)?,
        split_gaps: i.gaps == "split",
        progress: stderr_is_terminal(),
    })
}

fn check_from(from: Option<f64>) -> Result<()> {
    match from {
        Some(f) if !f.is_finite() => Err(HostError::Input(format!("--from {}: must be a finite time in s", short(f)))),
        _ => Ok(()),
    }
}

pub fn analyze(a: &crate::cli::AnalyzeArgs) -> Result<String> {
    use crate::recorded::{self, figures, report, sil};
    check_segment(a.record.segment)?;
    check_jump(a.record.breakaway_jump)?;
    check_from(a.from)?;
    let ns = scene_source::prepare(scene_source::resolve(&a.scene)?, &Overrides::default())?;
    let mut cfg = sil::analysis_config(&ns.scene, a.from.unwrap_or(f64::NEG_INFINITY), a.record.segment, a.plots.is_some());
    cfg.floor = floor_source(a.record.breakaway_jump, a.quiet.as_deref())?;
    cfg.windows = a.windows.is_some();
    cfg.breakaway_jump_m_s2 = match cfg.floor {
        recorded::analysis::FloorSource::Jump => sil::breakaway_jump(&ns, a.record.breakaway_jump)?,
        _ => sil::breakaway_jump(&ns, None).unwrap_or(sil::NO_JUMP_START_M_S2),
    };
    let an = recorded::analyze_with(&a.file, cfg, &read_options(&a.input)?)?;
    if an.floor.is_none() {
        // no quiet stretch before a signal: the thresholds came from the jump, which a scene
        // with mu_s = mu_k does not have
        sil::breakaway_jump(&ns, a.record.breakaway_jump)?;
    }
    if let Some(dir) = &a.plots {
        let n = figures::write_all(dir, &a.file, &an)?.len();
        eprintln!("stickslip: wrote {n} SVG figures to {}", dir.display());
    }
    if let Some(path) = &a.windows {
        recorded::windows::write_csv(path, &an.windows)?;
        eprintln!("stickslip: wrote {} estimator windows to {}", an.windows.len(), path.display());
    }
    Ok(if a.json {
        to_json(&report::AnalysisJson::new(&a.file, &an))
    } else {
        report::analysis_markdown(&a.file, &an)
    })
}

fn sil_options(
    segment: Option<usize>,
    noise: &crate::cli::SilNoise,
    figures: bool,
    breakaway_jump_m_s2: Option<f64>,
) -> Result<crate::recorded::sil::SilOptions> {
    check_sil_noise(noise)?;
    Ok(crate::recorded::sil::SilOptions {
        noise_m_s2: noise.noise,
        seed: noise.seed,
        segment,
        figures,
        breakaway_jump_m_s2,
        sensor: crate::recorded::sil::SensorPath::Rig,
        spectra: true,
        quiet_s: noise.quiet_lead,
        gain: gains(&noise.gain)?,
        oversample: noise.oversample,
        adc_noise_counts: noise.adc_noise,
        windows: false,
    })
}

pub fn sil(a: &crate::cli::SilArgs) -> Result<String> {
    use crate::recorded::{figures, report, sil};
    check_segment(a.record.segment)?;
    check_jump(a.record.breakaway_jump)?;
    let ns = scene_source::prepare(scene_source::resolve(&a.scene)?, &overrides(&a.run))?;
    let mut opts = sil_options(a.record.segment, &a.noise, a.plots.is_some(), a.record.breakaway_jump)?;
    if a.front_end == "ideal" {
        opts.sensor = sil::SensorPath::Ideal;
    }
    opts.windows = a.windows.is_some();
    let r = sil::run(&ns, a.run.precision, &opts, a.csv.as_deref())?;
    if let (Some(dir), Some(m)) = (&a.plots, &r.measured) {
        let n = figures::write_all(dir, &format!("virtual rig, {}", ns.name), m)?.len();
        eprintln!("stickslip: wrote {n} SVG figures to {}", dir.display());
    }
    if let Some(path) = &a.windows {
        // a run that leaves nothing to analyse has no windows: an empty table, said so
        let windows = r.measured.as_ref().map_or(&[][..], |m| &m.windows[..]);
        crate::recorded::windows::write_csv(path, windows)?;
        eprintln!("stickslip: wrote {} estimator windows to {}", windows.len(), path.display());
    }
    Ok(if a.json { to_json(&report::SilJson::new(&r)) } else { report::sil_markdown(&r) })
}

pub fn compare(a: &crate::cli::CompareArgs) -> Result<String> {
    use crate::recorded::{self, report, sil};
    // the options first: a bad option is named before the file is read
    check_sil_noise(&a.noise)?;
    gains(&a.noise.gain)?;
    check_segment(a.record.segment)?;
    check_jump(a.record.breakaway_jump)?;
    check_from(a.from)?;
    let ns = scene_source::prepare(scene_source::resolve(&a.scene)?, &overrides(&a.run))?;
    let mut cfg = sil::analysis_config(&ns.scene, a.from.unwrap_or(f64::NEG_INFINITY), a.record.segment, false);
    cfg.floor = floor_source(a.record.breakaway_jump, a.quiet.as_deref())?;
    cfg.breakaway_jump_m_s2 = match cfg.floor {
        recorded::analysis::FloorSource::Jump => sil::breakaway_jump(&ns, a.record.breakaway_jump)?,
        _ => sil::breakaway_jump(&ns, None).unwrap_or(sil::NO_JUMP_START_M_S2),
    };
    // the model side keeps the scene's own jump unless it has none (mu_s = mu_k)
    let model_jump = match sil::breakaway_jump(&ns, None) {
        Ok(_) => None,
        Err(_) => a.record.breakaway_jump,
    };
    // the measurement first: a bad file is reported before the model runs
    let measured = recorded::analyze_with(&a.file, cfg, &read_options(&a.input)?)?;
    let model = sil::run(&ns, a.run.precision, &sil_options(a.record.segment, &a.noise, false, model_jump)?, None)?;
    Ok(if a.json {
        to_json(&report::CompareJson::new(&a.file, &measured, &model))
    } else {
        report::compare_markdown(&a.file, &measured, &model)
    })
}

pub fn decode(a: &crate::cli::DecodeArgs) -> Result<String> {
    crate::recorded::decode::run(&crate::recorded::decode::DecodeRequest {
        elf: &a.elf,
        input: &a.input,
        json: a.json,
        kind: a.kind.as_deref(),
    })
}

/// `record`.
pub fn record(a: &crate::cli::RecordArgs) -> Result<String> {
    crate::recorded::live::run(&crate::recorded::live::RecordRequest {
        elf: &a.elf,
        input: a.input.as_deref(),
        out: a.out.as_deref(),
        raw: a.raw.as_deref(),
        chip: &a.chip,
        probe: a.probe.as_deref(),
        flash: a.flash.as_deref(),
        status_in_place: stderr_is_terminal(),
    })
}

/// `map` and `map merge`.
pub fn map(a: &crate::cli::MapArgs) -> Result<String> {
    use crate::map::{self, cell::CellOptions, sweep::Grid, sweep::Sweep, MapSpec, Shard};
    let (m, out) = match &a.action {
        Some(crate::cli::MapAction::Merge(mg)) => {
            let mut parts = Vec::new();
            for f in &mg.files {
                parts.push((f.display().to_string(), map::read_json(f)?));
            }
            (map::merge(parts).map_err(HostError::Input)?, &mg.out)
        }
        None => {
            let scene = a.scene.as_deref().unwrap_or("push_center");
            let ns = scene_source::prepare(scene_source::resolve(scene)?, &overrides(&a.run))?;
            let sweeps = a.sweeps.iter().map(|s| Sweep::parse(s)).collect::<std::result::Result<Vec<_>, _>>().map_err(HostError::Input)?;
            let grid = Grid::new(sweeps).map_err(HostError::Input)?;
            if !(a.kick.is_finite() && a.kick > 0.0 && a.kick <= 0.5) {
                return Err(HostError::Input(format!("--kick {}: must satisfy 0 < kick <= 0.5", a.kick)));
            }
            let shard = a.shard.as_deref().map(Shard::parse).transpose().map_err(HostError::Input)?;

            let spec = MapSpec {
                scene_name: ns.name.clone(),
                base: ns.scene,
                grid,
                options: CellOptions { precision: a.run.precision, kick: a.kick },
                shard,
                jobs: a.jobs.map(usize::from),
                progress: true,
            };
            let (m, t) = map::run_map(&spec)?;
            eprintln!(
                "map: {} cells, {} steps in {:.2} s on {} threads: {:.3e} steps/s",
                t.cells,
                t.steps,
                t.seconds,
                t.threads,
                t.steps as f64 / t.seconds.max(1e-9)
            );
            (m, &a.out)
        }
    };
    if let Some(path) = &out.csv {
        map::output::write_csv(&m, path)?;
    }
    if let Some(path) = &out.plot {
        map::plot::write(&m, path)?;
    }
    Ok(if out.json { to_json(&m) } else { map::output::markdown(&m) })
}

/// `fit`.
pub fn fit(a: &crate::cli::FitArgs) -> Result<String> {
    use crate::fit::{self, output, FitRequest};
    check_segment(a.record.segment)?;
    check_jump(a.record.breakaway_jump)?;
    check_from(a.from)?;
    if a.starts == 0 || a.max_iters == 0 {
        return Err(HostError::Input("--starts and --max-iters must be at least 1".into()));
    }
    use crate::limits::{FIT_MAX_BOOTSTRAP, FIT_MAX_ITERS, FIT_MAX_STARTS};
    if a.starts > FIT_MAX_STARTS {
        return Err(HostError::Input(format!("--starts {}: at most {FIT_MAX_STARTS} starts", a.starts)));
    }
    if a.max_iters > FIT_MAX_ITERS {
        return Err(HostError::Input(format!("--max-iters {}: at most {FIT_MAX_ITERS} iterations", a.max_iters)));
    }
    if a.bootstrap > FIT_MAX_BOOTSTRAP {
        return Err(HostError::Input(format!("--bootstrap {}: at most {FIT_MAX_BOOTSTRAP} resamples", a.bootstrap)));
    }
    if a.horizons.len() > 16 {
        return Err(HostError::Input(format!("--horizons: {} stages, at most 16", a.horizons.len())));
    }
    let ns = scene_source::prepare(scene_source::resolve(&a.scene)?, &Overrides::default())?;
    let req = FitRequest {
        free: a.free.clone(),
        bounds: a.bounds.clone(),
        recordings: a.recordings.clone(),
        tables: a.table.clone(),
        holdout: a.holdout.clone(),
        weights: a.weights.clone(),
        from_s: a.from,
        segment: a.record.segment,
        breakaway_jump_m_s2: a.record.breakaway_jump,
        starts: a.starts,
        max_iters: a.max_iters,
        bootstrap: a.bootstrap,
        seed: a.seed,
        progress: stderr_is_terminal(),
        horizons: a.horizons.iter().copied().filter(|n| *n != 0.0).collect(),
        read: read_options(&a.input)?,
        cost: fit::CostKind::parse(&a.cost).ok_or_else(|| {
            HostError::Input(format!("--cost {}: give auto, waveform or statistics", a.cost))
        })?,
    };
    if let Some(n) = a.horizons.iter().find(|n| !(n.is_finite() && **n >= 0.0)) {
        return Err(HostError::Input(format!("--horizons {n}: a horizon is a number of stick-slip periods, finite and >= 0 (0: none)")));
    }
    if let Some(spec) = &a.profile {
        if a.out.is_some() || a.plot.is_some() || !a.holdout.is_empty() {
            return Err(HostError::Input("--profile evaluates the cost only: it takes no --out, --plot or --holdout".into()));
        }
        let p = fit::run_profile(ns, &req, spec)?;
        return Ok(if a.json { to_json(&output::ProfileJson::new(&p)) } else { output::profile_markdown(&p) });
    }
    let r = fit::run_fit(ns, &req)?;
    if let Some(path) = &a.out {
        std::fs::write(path, output::fitted_toml(&r))
            .map_err(|e| HostError::Output(format!("{}: cannot write the fitted scene: {e}", path.display())))?;
    }
    if let Some(path) = &a.plot {
        output::write_plot(&r, path)?;
    }
    Ok(if a.json { to_json(&output::FitJson::new(&r)) } else { output::markdown(&r) })
}
