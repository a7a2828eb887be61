//! Recordings and the rig: `analyze`, `sil`, `compare`, `decode`, `record`, and the checks
//! of their options.

use super::{overrides, stderr_is_terminal, to_json};
use crate::error::{HostError, Result};
use crate::output::format::short;
use crate::scenes::scene_source::{self, Overrides};

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
pub(crate) fn read_options(i: &crate::cli::RecordingInput) -> Result<crate::recorded::ReadOptions> {
    Ok(crate::recorded::ReadOptions {
        channels: crate::recorded::channels::ChannelMap::parse(&i.channels)?,
        split_gaps: i.gaps == "split",
        progress: stderr_is_terminal(),
    })
}

pub(crate) fn check_from(from: Option<f64>) -> Result<()> {
    match from {
        Some(f) if !f.is_finite() => Err(HostError::Input(format!("--from {}: must be a finite time in s", short(f)))),
        _ => Ok(()),
    }
}

/// The Welch segment and the breakaway jump within their ranges (`--help`), shared by every
/// command that analyses a recording.
pub(crate) fn check_record(r: &crate::cli::RecordOptions) -> Result<()> {
    check_segment(r.segment)?;
    check_jump(r.breakaway_jump)
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
    check_record(&a.floor.record)?;
    check_from(a.from)?;
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
    check_record(&a.record)?;
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
    check_record(&a.floor.record)?;
    check_from(a.from)?;
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

