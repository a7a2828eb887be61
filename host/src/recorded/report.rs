//! Markdown and JSON of `analyze`, `sil` and `compare`. JSON keys are SI values in the units
//! the help texts state (m/s^2, Hz, s); a value that does not exist is null.

use serde::Serialize;
use stickslip_model::rig::noise_floor::A_REL;
use stickslip_model::rig::ACCEL_NAMES;

use super::analysis::{Analysis, ChannelStats};
use crate::output::format::{num, opt};
use super::sil::SilReport;



#[derive(Serialize, Clone, Copy)]
pub struct ChannelJson {
    pub pp: f64,
    pub rms: f64,
    pub peak_hz: Option<f64>,
    pub groan_rms: f64,
    pub mean: f64,
    pub min: f64,
    pub max: f64,
}

impl From<&ChannelStats> for ChannelJson {
    fn from(c: &ChannelStats) -> Self {
        ChannelJson { pp: c.pp, rms: c.rms, peak_hz: c.peak_hz, groan_rms: c.groan_rms, mean: c.mean, min: c.min, max: c.max }
    }
}

/// The four channels under their names.
#[derive(Serialize)]
pub struct Channels<T> {
    pub disc_x: T,
    pub pad_x: T,
    pub pad_trail: T,
    pub pad_lead: T,
}

impl<T> Channels<T> {
    pub fn from_fn(mut f: impl FnMut(usize) -> T) -> Self {
        Channels { disc_x: f(0), pad_x: f(1), pad_trail: f(2), pad_lead: f(3) }
    }
}

#[derive(Serialize)]
pub struct SpectrumJson {
    pub method: &'static str,
    pub window: &'static str,
    pub overlap: f64,
    pub segment_samples: usize,
    pub segments: u64,
    pub resolution_hz: f64,
}

#[derive(Serialize)]
pub struct EstimatorJson {
    pub breakaway_jump_m_s2: f64,
    pub slip_onset_m_s2: f64,
    pub stick_max_m_s2: f64,
    pub setup_rate_hz: f64,
    /// "floor" (from the noise floor of a quiet stretch) or "jump" (fixed, from the jump).
    pub thresholds_from: &'static str,
    pub floor: Option<FloorJson>,
    /// Why the estimator cannot decide (its stick fraction and frequency are then null).
    pub undecided: Option<String>,
    /// Per channel, what is wrong with it ("flat", "saturated", "noisier than the signal").
    pub health: Channels<Vec<&'static str>>,
    /// Why no floor was found (the thresholds then came from the jump), or null.
    pub floor_note: Option<String>,
}

#[derive(Serialize)]
pub struct FloorJson {
    pub from_s: f64,
    pub to_s: f64,
    /// "auto" (the first quiet stretch) or "given" (--quiet).
    pub chosen: &'static str,
    pub samples: u32,
    /// Per channel, then a_rel: sigma [m/s^2].
    pub sigma_m_s2: Channels<f64>,
    pub a_rel_sigma_m_s2: f64,
    pub a_rel_mean_m_s2: f64,
    pub quantum_m_s2: f64,
    /// Found anywhere: the quiet blocks of 32 rows it came from (0: one stretch).
    pub quiet_blocks: u64,
}

impl EstimatorJson {
    fn new(a: &Analysis) -> Self {
        EstimatorJson {
            breakaway_jump_m_s2: a.breakaway_jump_m_s2,
            slip_onset_m_s2: a.thresholds.slip_onset_m_s2 as f64,
            stick_max_m_s2: a.thresholds.stick_max_m_s2 as f64,
            setup_rate_hz: a.setup_rate_hz,
            thresholds_from: if a.floor.is_some() { "floor" } else { "jump" },
            floor: a.floor.as_ref().map(|f| FloorJson {
                from_s: f.t_from,
                to_s: f.t_to,
                chosen: if f.auto { "auto" } else { "given" },
                samples: f.report.samples,
                sigma_m_s2: Channels::from_fn(|c| f.report.sigma_m_s2[c] as f64),
                a_rel_sigma_m_s2: f.report.sigma_m_s2[A_REL] as f64,
                a_rel_mean_m_s2: f.report.mean_m_s2[A_REL] as f64,
                quantum_m_s2: f.quantum_m_s2,
                quiet_blocks: f.quiet_blocks,
            }),
            undecided: a.undecided.clone(),
            health: Channels::from_fn(|c| a.health[c].clone()),
            floor_note: a.floor_note.clone(),
        }
    }
}

#[derive(Serialize)]
pub struct GapJson {
    pub line: u64,
    pub t_before_s: f64,
    pub t_after_s: f64,
    pub intervals: f64,
}

#[derive(Serialize)]
pub struct AnalysisJson {
    pub file: String,
    /// "CSV", "UFF dataset 58" or "WAV".
    pub format: &'static str,
    /// null for a channel the recording does not have.
    pub channels: Channels<Option<ChannelJson>>,
    pub present: Channels<bool>,
    /// null where the estimator cannot decide (`estimator.undecided`).
    pub stick_fraction: Option<f64>,
    pub stick_slip_hz: Option<f64>,
    pub slip_onsets: u64,
    /// Time of the estimator's first slip onset in the whole file [s] (the time column's).
    pub first_slip_onset_s: Option<f64>,
    pub sample_rate_hz: f64,
    pub samples: u64,
    pub rows: u64,
    pub duration_s: f64,
    pub from_s: Option<f64>,
    pub t_first_s: f64,
    pub t_last_s: f64,
    pub time_resolution_s: f64,
    pub samples_at_range: u64,
    pub spectrum: Option<SpectrumJson>,
    pub estimator: EstimatorJson,
    /// The jumps in the time column analysed around (`--gaps split`).
    pub gaps: Vec<GapJson>,
    /// What was assumed (absent channels, units).
    pub notes: Vec<String>,
}

fn spectrum_json(a: &Analysis) -> Option<SpectrumJson> {
    a.spectrum.as_ref().map(|s| SpectrumJson {
        method: "welch",
        window: "hann",
        overlap: 0.5,
        segment_samples: s.segment,
        segments: s.segments,
        resolution_hz: s.resolution_hz,
    })
}

impl AnalysisJson {
    pub fn new(file: &str, a: &Analysis) -> Self {
        AnalysisJson {
            file: file.to_string(),
            format: a.format,
            channels: Channels::from_fn(|c| a.present[c].then(|| (&a.channels[c]).into())),
            present: Channels::from_fn(|c| a.present[c]),
            stick_fraction: a.undecided.is_none().then_some(a.stick_fraction),
            stick_slip_hz: a.stick_slip_hz.filter(|_| a.undecided.is_none()),
            slip_onsets: a.slip_onsets,
            first_slip_onset_s: a.first_onset_s,
            sample_rate_hz: a.sample_rate_hz,
            samples: a.samples,
            rows: a.rows,
            duration_s: a.duration_s(),
            from_s: a.from_s.is_finite().then_some(a.from_s),
            t_first_s: a.t_first,
            t_last_s: a.t_last,
            time_resolution_s: a.time_resolution_s,
            samples_at_range: a.samples_at_range,
            spectrum: spectrum_json(a),
            estimator: EstimatorJson::new(a),
            gaps: a.gaps.iter().map(|g| GapJson { line: g.line, t_before_s: g.t_before, t_after_s: g.t_after, intervals: g.intervals }).collect(),
            notes: a.notes.clone(),
        }
    }
}

fn spectrum_line(a: &Analysis) -> String {
    match &a.spectrum {
        Some(s) => format!(
            "Spectra: Welch, periodic Hann window, {} -sample segments with 50 % overlap, {} segment{} averaged, resolution {} Hz (a spectral peak is good to one bin).\n",
            s.segment,
            s.segments,
            if s.segments == 1 { "" } else { "s" },
            num(s.resolution_hz)
        )
        .replace(" -sample", "-sample"),
        None => "Spectra: none (fewer than 4 samples).\n".into(),
    }
}

fn estimator_lines(a: &Analysis) -> String {
    let hz = match a.stick_slip_hz {
        Some(f) => format!("{} Hz ({} slip onsets)", num(f), a.slip_onsets),
        None => format!("none ({} slip onset{}: two are needed)", a.slip_onsets, if a.slip_onsets == 1 { "" } else { "s" }),
    };
    let first = a.first_onset_s.map_or("none".into(), |t| format!("t = {} s", num(t)));
    let source = match &a.floor {
        Some(f) => format!(
            "thresholds from the noise floor of t = {} to {} s ({}, {} rows: a_rel sigma {} m/s^2, quantum {} m/s^2; adaptive up to {}x)",
            num(f.t_from),
            num(f.t_to),
            match (f.auto, f.quiet_blocks) {
                (false, _) => "--quiet".to_string(),
                (true, 0) => "the first quiet stretch".to_string(),
                (true, b) => format!("the quietest {b} blocks of a_rel found anywhere in the record"),
            },
            f.report.samples,
            num(f.report.sigma_m_s2[A_REL] as f64),
            num(f.quantum_m_s2),
            num(a.thresholds.onset_max_factor as f64),
        ),
        None => format!(
            "fixed thresholds from the breakaway jump {} m/s^2 ({})",
            num(a.breakaway_jump_m_s2),
            match &a.floor_note {
                Some(why) => format!("no noise floor: {why}; give --quiet FROM:TO"),
                None => "--breakaway-jump".to_string(),
            }
        ),
    };
    let mut s = match &a.undecided {
        Some(why) => format!("Stick fraction and stick-slip frequency: cannot decide ({why}).\n"),
        None => format!("Stick fraction: {} and stick-slip frequency: {hz}.\n", num(a.stick_fraction)),
    };
    s.push_str(&format!(
        "The rig's estimator: {source}: slip onset above {} m/s^2, stick at most {} m/s^2 of a_rel = pad_x - disc_x. First slip onset in the whole file: {first}.\n",
        num(a.thresholds.slip_onset_m_s2 as f64),
        num(a.thresholds.stick_max_m_s2 as f64),
    ));
    for (c, h) in a.health.iter().enumerate() {
        if !h.is_empty() {
            s.push_str(&format!("Channel {}: {}.\n", ACCEL_NAMES[c], h.join(", ")));
        }
    }
    for n in &a.notes {
        s.push_str(&format!("Note: {n}.\n"));
    }
    if !a.gaps.is_empty() {
        s.push_str(&format!(
            "Gaps (--gaps split: the contiguous blocks analysed, the estimator restarted after each): {}.\n",
            a.gaps
                .iter()
                .map(|g| format!("line {}: t = {} to {} s ({} intervals)", g.line, num(g.t_before), num(g.t_after), crate::output::format::sig4(g.intervals)))
                .collect::<Vec<_>>()
                .join("; ")
        ));
    }
    s
}

/// The Markdown summary of `analyze`.
pub fn analysis_markdown(file: &str, a: &Analysis) -> String {
    let mut s = format!("# {file}\n\n");
    s.push_str(&format!(
        "{} samples analysed, t = {} to {} s ({} s) at {} Hz (from the time axis, {} rows{}).\n\n",
        a.samples,
        num(a.t_first),
        num(a.t_last),
        num(a.duration_s()),
        num(a.sample_rate_hz),
        a.rows,
        if a.format.is_empty() { String::new() } else { format!(", {}", a.format) }
    ));
    s.push_str("| channel | peak-to-peak [m/s^2] | RMS [m/s^2] | spectral peak [Hz] | groan-band RMS [m/s^2] |\n");
    s.push_str("|---|---:|---:|---:|---:|\n");
    for (c, ch) in a.channels.iter().enumerate() {
        if !a.present[c] {
            s.push_str(&format!("| {} | absent | absent | absent | absent |\n", ACCEL_NAMES[c]));
            continue;
        }
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} |\n",
            ACCEL_NAMES[c],
            num(ch.pp),
            num(ch.rms),
            opt(ch.peak_hz),
            num(ch.groan_rms)
        ));
    }
    s.push('\n');
    s.push_str(&estimator_lines(a));
    s.push_str(&spectrum_line(a));
    s.push_str("RMS about zero; groan-band RMS through the rig's 100 to 500 Hz band-pass (4th-order Butterworth).\n");
    if a.samples_at_range > 0 {
        s.push_str(&format!(
            "Warning: {} samples at or beyond the accelerometers' range (700 m/s^2): clipped?\n",
            a.samples_at_range
        ));
    }
    s
}

/// Estimated against true, and the relative error (estimated - true) / true.
#[derive(Serialize, Clone, Copy)]
pub struct VsTruth {
    pub estimated: Option<f64>,
    #[serde(rename = "true")]
    pub truth: Option<f64>,
    pub error: Option<f64>,
}

impl VsTruth {
    pub fn new(estimated: Option<f64>, truth: Option<f64>) -> Self {
        let error = match (estimated, truth) {
            (Some(e), Some(t)) if t != 0.0 => Some((e - t) / t),
            _ => None,
        };
        VsTruth { estimated, truth, error }
    }
}

#[derive(Serialize)]
pub struct SilChannelJson {
    pub pp: VsTruth,
    /// Hard bound of |pp estimated - pp true| [m/s^2]: one ADC count plus the noise's bound.
    pub pp_bound: f64,
    /// The converter's error: RMS of calibrated minus the converter's input [m/s^2] and in
    /// counts of one conversion (null on the ideal front end).
    pub converter_rms: Option<f64>,
    pub converter_rms_counts: Option<f64>,
    pub rms: Option<f64>,
    pub peak_hz: Option<f64>,
    pub groan_rms: Option<f64>,
}

#[derive(Serialize)]
pub struct SilJson {
    pub scene: String,
    pub caliper: &'static str,
    pub beta: f64,
    pub sample_rate_hz: f64,
    pub stats_from: f64,
    pub samples: u64,
    pub steps: u64,
    pub outcome: &'static str,
    pub halt_t_s: Option<f64>,
    pub noise_m_s2: f64,
    pub seed: u32,
    pub gain: Channels<f64>,
    pub oversample: u32,
    pub adc_noise_counts: f64,
    /// "rig" (noise, clipping, 12-bit ADC, calibration) or "ideal" (noise only).
    pub front_end: &'static str,
    pub saturated_frames: u64,
    pub stick_fraction: VsTruth,
    pub stick_slip_hz: VsTruth,
    pub slip_onsets: VsTruth,
    pub channels: Channels<SilChannelJson>,
    /// Why the estimator cannot decide (the channel-health verdict of `analyze`); only when
    /// it cannot.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub undecided: Option<String>,
    /// Each channel's health words; only when the estimator cannot decide or a channel is
    /// saturated.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub health: Option<Channels<Vec<&'static str>>>,
}

/// The estimates against the truth. The channel-health verdict of `analyze` applies to the
/// virtual recording too: where the estimator cannot decide (pad_x flat, saturated or noisier
/// than the signal; disc_x saturated) the stick fraction, the frequency and the onsets are not
/// estimated, and a saturated channel's peak-to-peak (the range's, not the signal's) is not.
fn sil_parts(r: &SilReport) -> (VsTruth, VsTruth, VsTruth, [VsTruth; 4]) {
    let m = r.measured.as_ref();
    let decided = m.filter(|a| a.undecided.is_none());
    let have = r.truth.samples > 0;
    let sf = VsTruth::new(decided.map(|a| a.stick_fraction), have.then_some(r.truth.stick_fraction));
    let hz = VsTruth::new(decided.and_then(|a| a.stick_slip_hz), r.truth.stick_slip_hz);
    let on = VsTruth::new(decided.map(|a| a.slip_onsets as f64), have.then_some(r.truth.slip_onsets as f64));
    let pp = std::array::from_fn(|c| {
        let est = m.filter(|a| !a.health[c].contains(&"saturated")).map(|a| a.channels[c].pp);
        VsTruth::new(est, have.then_some(r.truth.pp[c]))
    });
    (sf, hz, on, pp)
}

/// The virtual recording's health where it matters (the estimator cannot decide, or a channel
/// is saturated): why, and each channel's words; None for a healthy recording.
fn sil_health(r: &SilReport) -> Option<(Option<String>, [Vec<&'static str>; 4])> {
    let a = r.measured.as_ref()?;
    let saturated = a.health.iter().any(|h| h.contains(&"saturated"));
    (a.undecided.is_some() || saturated).then(|| (a.undecided.clone(), a.health.clone()))
}

impl SilJson {
    pub fn new(r: &SilReport) -> Self {
        let (sf, hz, on, pp) = sil_parts(r);
        let m = r.measured.as_ref();
        SilJson {
            scene: r.name.clone(),
            caliper: r.caliper,
            beta: r.beta,
            sample_rate_hz: r.sample_rate_hz,
            stats_from: r.stats_from,
            samples: r.truth.samples,
            steps: r.steps_done,
            outcome: r.outcome,
            halt_t_s: r.halt_t_s,
            noise_m_s2: r.noise_m_s2,
            seed: r.seed,
            gain: Channels::from_fn(|c| r.gain[c]),
            oversample: r.oversample,
            adc_noise_counts: r.adc_noise_counts,
            front_end: r.sensor.name(),
            saturated_frames: r.saturated_frames,
            stick_fraction: sf,
            stick_slip_hz: hz,
            slip_onsets: on,
            channels: Channels::from_fn(|c| SilChannelJson {
                pp: pp[c],
                pp_bound: r.pp_bound_m_s2[c],
                converter_rms: r.converter_rms_m_s2.map(|e| e[c]),
                converter_rms_counts: r.converter_rms_counts.map(|e| e[c]),
                rms: m.map(|a| a.channels[c].rms),
                peak_hz: m.and_then(|a| a.channels[c].peak_hz),
                groan_rms: m.map(|a| a.channels[c].groan_rms),
            }),
            undecided: sil_health(r).and_then(|(u, _)| u),
            health: sil_health(r).map(|(_, h)| Channels::from_fn(|c| h[c].clone())),
        }
    }
}

/// A relative error as a percentage; n/a if it does not exist, four significant digits in
/// scientific notation beyond 1e6 % (never an infinite or 300-digit percentage).
fn pct(e: Option<f64>) -> String {
    match e {
        Some(e) if e.is_finite() && (100.0 * e).abs() < 1e6 => format!("{:+.3} %", 100.0 * e),
        Some(e) if e.is_finite() => format!("{:+.3e} %", 100.0 * e),
        _ => "n/a".into(),
    }
}

/// The Markdown summary of `sil`.
pub fn sil_markdown(r: &SilReport) -> String {
    let (sf, hz, on, pp) = sil_parts(r);
    let mut s = format!(
        "# Virtual rig: {} ({} caliper, beta = {} m)\n\n",
        r.name, r.caliper, r.beta
    );
    let chain = match r.sensor {
        crate::recorded::sil::SensorPath::Rig => format!(
            "rig sensor model (100 mV/g, front-end gain {}, noise {} m/s^2 rms seed {}, 700 m/s^2 clipping, 12-bit ADC{}) -> calibration",
            r.gain.iter().map(|&g| num(g)).collect::<Vec<_>>().join("/"),
            num(r.noise_m_s2),
            r.seed,
            if r.oversample > 1 || r.adc_noise_counts > 0.0 {
                format!(", {} conversions summed per frame, converter noise {} counts rms", r.oversample, num(r.adc_noise_counts))
            } else {
                String::new()
            }
        ),
        crate::recorded::sil::SensorPath::Ideal => format!(
            "ideal front end (noise {} m/s^2 rms seed {}, no clipping, no ADC: a high-resolution logger)",
            num(r.noise_m_s2),
            r.seed
        ),
    };
    s.push_str(&format!(
        "Model ({}) -> {chain} -> the rig's estimator, at {} Hz; statistics over t >= {} s \
         ({} samples). Outcome: {}{}.\n\n",
        r.stepper,
        num(r.sample_rate_hz),
        num(r.stats_from),
        r.truth.samples,
        r.outcome,
        r.halt_t_s.map_or(String::new(), |t| format!(" at t = {} s", num(t)))
    ));
    s.push_str("| quantity | estimated (virtual rig) | true (model) | error | error bound |\n|---|---:|---:|---:|---:|\n");
    let row = |name: &str, v: &VsTruth| {
        format!("| {name} | {} | {} | {} | |\n", opt(v.estimated), opt(v.truth), pct(v.error))
    };
    s.push_str(&row("stick fraction [-]", &sf));
    s.push_str(&row("stick-slip frequency [Hz]", &hz));
    let count = |v: Option<f64>| v.map_or("none".to_string(), |n| format!("{n:.0}"));
    s.push_str(&format!("| slip onsets | {} | {} | {} | |\n", count(on.estimated), count(on.truth), pct(on.error)));
    for c in 0..4 {
        let v = &pp[c];
        let b = r.pp_bound_m_s2[c];
        let bound = match v.truth {
            Some(t) if t > 0.0 => format!("+-{} ({})", num(b), pct(Some(b / t)).replace('+', "+-")),
            _ => format!("+-{}", num(b)),
        };
        s.push_str(&format!(
            "| {} peak-to-peak [m/s^2] | {} | {} | {} | {bound} |\n",
            ACCEL_NAMES[c],
            opt(v.estimated),
            opt(v.truth),
            pct(v.error)
        ));
    }
    s.push_str(
        "\nTrue: the model's own regime at each sample, the exact times of its stick-to-slip transitions, and \
         the noise-free accelerations before clipping and the ADC. Error = (estimated - true) / true. Error \
         bound of a peak-to-peak: one ADC count (each extreme rounded by at most half a count) plus twice the \
         noise's hard bound; a channel whose peak-to-peak spans few counts cannot be estimated closer.\n",
    );
    if let (Some(e), Some(k)) = (r.converter_rms_m_s2, r.converter_rms_counts) {
        s.push_str(&format!(
            "\nEffective resolution (RMS of calibrated minus the converter's input: quantisation and the converter's noise): {}.\n",
            (0..4).map(|c| format!("{} {} m/s^2 = {} counts", ACCEL_NAMES[c], num(e[c]), num(k[c]))).collect::<Vec<_>>().join(", ")
        ));
    }
    if r.saturated_frames > 0 {
        s.push_str(&format!("{} frames had an accelerometer at its range or an ADC rail.\n", r.saturated_frames));
    }
    if let Some((why, health)) = sil_health(r) {
        if let Some(why) = why {
            s.push_str(&format!("Stick fraction and stick-slip frequency: cannot decide ({why}).\n"));
        }
        for (c, h) in health.iter().enumerate() {
            if !h.is_empty() {
                s.push_str(&format!("Channel {}: {}.\n", ACCEL_NAMES[c], h.join(", ")));
            }
        }
    }
    if let Some(b) = r.over_budget {
        s.push_str(&format!("Not run: {}.\n", b.cause()));
    }
    s
}

/// Measured against model, and measured / model.
#[derive(Serialize, Clone, Copy)]
pub struct Pair {
    pub measured: Option<f64>,
    pub model: Option<f64>,
    pub ratio: Option<f64>,
}

impl Pair {
    pub fn new(measured: Option<f64>, model: Option<f64>) -> Self {
        let ratio = match (measured, model) {
            (Some(a), Some(b)) if b != 0.0 => Some(a / b),
            _ => None,
        };
        Pair { measured, model, ratio }
    }
}

#[derive(Serialize)]
pub struct CompareChannelJson {
    pub pp: Pair,
    pub peak_hz: Pair,
    pub rms: Pair,
    pub groan_rms: Pair,
}

#[derive(Serialize)]
pub struct CompareSide {
    pub sample_rate_hz: Option<f64>,
    pub samples: Option<u64>,
    pub duration_s: Option<f64>,
    pub from_s: Option<f64>,
    pub resolution_hz: Option<f64>,
}

impl CompareSide {
    fn of(a: Option<&Analysis>) -> Self {
        CompareSide {
            sample_rate_hz: a.map(|a| a.sample_rate_hz),
            samples: a.map(|a| a.samples),
            duration_s: a.map(|a| a.duration_s()),
            from_s: a.and_then(|a| a.from_s.is_finite().then_some(a.from_s)),
            resolution_hz: a.and_then(|a| a.spectrum.as_ref().map(|s| s.resolution_hz)),
        }
    }
}

#[derive(Serialize)]
pub struct CompareJson {
    pub scene: String,
    pub file: String,
    pub channels: Channels<CompareChannelJson>,
    pub stick_fraction: Pair,
    pub stick_slip_hz: Pair,
    pub measured: CompareSide,
    pub model: CompareSide,
    pub model_outcome: &'static str,
    pub model_noise_m_s2: f64,
    /// The measured channels' health, as `analyze` gives it (a channel with a word is not
    /// compared: its ratios are null).
    pub health: Channels<Vec<&'static str>>,
    /// Why the measured stick fraction and frequency cannot be told (then null), or null.
    pub undecided: Option<String>,
}

impl CompareJson {
    pub fn new(file: &str, measured: &Analysis, model: &SilReport) -> Self {
        let m = model.measured.as_ref();
        // the channel-health verdict, as `analyze` gives it: an absent or unhealthy measured
        // channel is not compared (measured null if absent; ratio null if unhealthy)
        let ch = |c: usize, f: fn(&ChannelStats) -> Option<f64>| {
            let mine = measured.present[c].then(|| f(&measured.channels[c])).flatten();
            let p = Pair::new(mine, m.and_then(|a| f(&a.channels[c])));
            if measured.health[c].is_empty() { p } else { Pair { ratio: None, ..p } }
        };
        let decided = measured.undecided.is_none();
        CompareJson {
            scene: model.name.clone(),
            file: file.to_string(),
            channels: Channels::from_fn(|c| CompareChannelJson {
                pp: ch(c, |s| Some(s.pp)),
                peak_hz: ch(c, |s| s.peak_hz),
                rms: ch(c, |s| Some(s.rms)),
                groan_rms: ch(c, |s| Some(s.groan_rms)),
            }),
            stick_fraction: Pair::new(decided.then_some(measured.stick_fraction), m.map(|a| a.stick_fraction)),
            stick_slip_hz: Pair::new(measured.stick_slip_hz.filter(|_| decided), m.and_then(|a| a.stick_slip_hz)),
            health: Channels::from_fn(|c| measured.health[c].clone()),
            undecided: measured.undecided.clone(),
            measured: CompareSide::of(Some(measured)),
            model: CompareSide::of(m),
            model_outcome: model.outcome,
            model_noise_m_s2: model.noise_m_s2,
        }
    }
}

/// The Markdown table of `compare`.
pub fn compare_markdown(file: &str, measured: &Analysis, model: &SilReport) -> String {
    let j = CompareJson::new(file, measured, model);
    let mut s = format!("# {file} (measured) against {} (model, virtual rig)\n\n", model.name);
    s.push_str("| channel | quantity | measured | model | measured / model |\n|---|---|---:|---:|---:|\n");
    let row = |ch: &str, q: &str, p: &Pair| {
        format!("| {ch} | {q} | {} | {} | {} |\n", opt(p.measured), opt(p.model), p.ratio.map_or("n/a".into(), |r| format!("{r:.3}")))
    };
    let chans = [&j.channels.disc_x, &j.channels.pad_x, &j.channels.pad_trail, &j.channels.pad_lead];
    for (c, cj) in chans.iter().enumerate() {
        s.push_str(&row(ACCEL_NAMES[c], "peak-to-peak [m/s^2]", &cj.pp));
        s.push_str(&row(ACCEL_NAMES[c], "spectral peak [Hz]", &cj.peak_hz));
        s.push_str(&row(ACCEL_NAMES[c], "RMS [m/s^2]", &cj.rms));
    }
    s.push_str(&row("pad", "stick fraction [-]", &j.stick_fraction));
    let mut verdict = String::new();
    if let Some(why) = &j.undecided {
        verdict.push_str(&format!("Measured stick fraction and stick-slip frequency: cannot decide ({why}).\n"));
    }
    for (c, h) in measured.health.iter().enumerate() {
        if !h.is_empty() {
            verdict.push_str(&format!("Measured channel {}: {}: not compared.\n", ACCEL_NAMES[c], h.join(", ")));
        }
        if !measured.present[c] {
            verdict.push_str(&format!("Measured channel {}: absent.\n", ACCEL_NAMES[c]));
        }
    }
    s.push_str(&row("pad", "stick-slip frequency [Hz]", &j.stick_slip_hz));
    s.push('\n');
    s.push_str(&verdict);
    s.push_str(&format!(
        "Measured: {} samples at {} Hz{}; model: `{}` through the virtual rig (noise {} m/s^2 rms), {} samples from t = {} s, outcome {}.\n",
        measured.samples,
        num(measured.sample_rate_hz),
        if measured.from_s.is_finite() { format!(" from t = {} s", num(measured.from_s)) } else { String::new() },
        model.name,
        num(model.noise_m_s2),
        model.truth.samples,
        num(model.stats_from),
        model.outcome
    ));
    s.push_str(
        "Both sides go through the same analysis: peak-to-peak and RMS of the samples, the Welch spectral peak, \
         the rig's estimator for the stick fraction and stick-slip frequency, with the scene's breakaway jump.\n",
    );
    s
}
