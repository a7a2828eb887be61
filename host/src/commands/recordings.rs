//! Recordings and the rig: `analyze`, `sil`, `compare`, `decode`, `record`, and the checks
//! of their options.

use super::{overrides, stderr_is_terminal, to_json};
use crate::error::{HostError, Result};
use crate::scenes::scene_source::{self, Overrides};

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

/// The front end's gains from `--gain` (none: the rig's 0.2; one: all four; four: each; each
/// value's range is checked by its parser).
fn gains(g: &[f64]) -> Result<[f64; 4]> {
    let rig = crate::recorded::sil::RIG_GAIN;
    let out = match g.len() {
        0 => rig,
        1 => [g[0]; 4],
        4 => [g[0], g[1], g[2], g[3]],
        n => return Err(HostError::Input(format!("--gain: {n} values: give one (all four channels) or four"))),
    };
    Ok(out)
}

/// The read options of `--channel` and `--gaps`.
pub(crate) fn read_options(i: &crate::cli::RecordingInput) -> Result<crate::recorded::ReadOptions> {
    Ok(crate::recorded::ReadOptions {
        channels: crate::recorded::channels::ChannelMap::parse(&i.channels)?,
        split_gaps: i.gaps == "split",
        progress: stderr_is_terminal(),
    })
}

/// The contact thresholds of a measured recording from `--quiet`, `--breakaway-jump` and the
/// scene (shared by `analyze` and `compare`).
fn set_floor(
    cfg: &mut crate::recorded::analysis::AnalysisConfig,
    ns: &scene_source::NamedScene,
    f: &crate::cli::FloorOptions,
) -> Result<()> {
    use crate::recorded::{analysis::FloorSource, sil};
    cfg.floor = floor_source(f.record.breakaway_jump, f.quiet.as_deref())?;
    cfg.breakaway_jump_m_s2 = match cfg.floor {
        FloorSource::Jump => sil::breakaway_jump(ns, f.record.breakaway_jump)?,
        _ => sil::breakaway_jump(ns, None).unwrap_or(sil::NO_JUMP_START_M_S2),
    };
    Ok(())
}

pub fn analyze(a: &crate::cli::AnalyzeArgs) -> Result<String> {
    use crate::recorded::{self, figures, report, sil};
    let ns = scene_source::prepare(scene_source::resolve(&a.scene)?, &Overrides::default())?;
    let mut cfg = sil::analysis_config(&ns.scene, a.from.unwrap_or(f64::NEG_INFINITY), a.floor.record.segment, a.plots.is_some());
    set_floor(&mut cfg, &ns, &a.floor)?;
    cfg.windows = a.windows.is_some();
    let an = recorded::analyze_with(&a.file, cfg, &read_options(&a.input)?)?;
    if an.floor.is_none() {
        // no quiet stretch before a signal: the thresholds came from the jump, which a scene
        // with mu_s = mu_k does not have
        sil::breakaway_jump(&ns, a.floor.record.breakaway_jump)?;
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
    gains(&a.noise.gain)?;
    let ns = scene_source::prepare(scene_source::resolve(&a.scene)?, &overrides(&a.run))?;
    let mut cfg = sil::analysis_config(&ns.scene, a.from.unwrap_or(f64::NEG_INFINITY), a.floor.record.segment, false);
    set_floor(&mut cfg, &ns, &a.floor)?;
    // the model side keeps the scene's own jump unless it has none (mu_s = mu_k)
    let model_jump = match sil::breakaway_jump(&ns, None) {
        Ok(_) => None,
        Err(_) => a.floor.record.breakaway_jump,
    };
    // the measurement first: a bad file is reported before the model runs
    let measured = recorded::analyze_with(&a.file, cfg, &read_options(&a.input)?)?;
    let model = sil::run(&ns, a.run.precision, &sil_options(a.floor.record.segment, &a.noise, false, model_jump)?, None)?;
    Ok(if a.json {
        to_json(&report::CompareJson::new(&a.file, &measured, &model))
    } else {
        report::compare_markdown(&a.file, &measured, &model)
    })
}

pub fn decode(a: &crate::cli::DecodeArgs) -> Result<String> {
    crate::recorded::decode::run_to_stdout(&crate::recorded::decode::DecodeRequest {
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

