//! Markdown and JSON of `analyze`, `sil` and `compare`. JSON keys are SI values in the units
//! the help texts state (m/s^2, Hz, s); a value that does not exist is null.

use serde::Serialize;
use stickslip_model::rig::noise_floor::A_REL;
use stickslip_model::rig::ACCEL_NAMES;

use super::analysis::{Analysis, ChannelStats};
use crate::output::format::{num, opt};
use super::sil::SilReport;

mod compare;
mod sil;
pub use compare::*;
pub use sil::*;

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
    /// The intervals between consecutive slip onsets (within blocks).
    pub onset_intervals: IntervalsJson,
}

/// The intervals between slip onsets [s]: their count, mean, standard deviation and median (to
/// 1/32 octave; all null without an interval), and how many are under a third of the median
/// (split slips or onsets from noise) or over three times it (onsets missed): the contact
/// estimate is not told where those are 2 % or more of them.
#[derive(Serialize)]
pub struct IntervalsJson {
    pub count: u64,
    pub mean_s: Option<f64>,
    pub sd_s: Option<f64>,
    pub median_s: Option<f64>,
    pub under_a_third_of_median: u64,
    pub over_three_times_median: u64,
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
    /// A logger's fill (one value on every channel) at the record's start and at its end
    /// [s, s]: left out of the floor and the statistics (null: none).
    pub fill_lead_s: Option<[f64; 2]>,
    pub fill_trail_s: Option<[f64; 2]>,
    /// Runs of one value on every channel inside the record, left out of the floor only.
    pub fill_inside_runs: u64,
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
                fill_lead_s: f.fill_lead.map(|(a, b)| [a, b]),
                fill_trail_s: f.fill_trail.map(|(a, b)| [a, b]),
                fill_inside_runs: f.fill_inside.map_or(0, |x| x.0),
            }),
            undecided: a.undecided.clone(),
            health: Channels::from_fn(|c| a.health[c].clone()),
            floor_note: a.floor_note.clone(),
            onset_intervals: {
                let i = &a.onset_intervals;
                let some = |v: f64| (i.count > 0).then_some(v);
                IntervalsJson { count: i.count, mean_s: some(i.mean_s), sd_s: some(i.sd_s), median_s: some(i.median_s), under_a_third_of_median: i.short, over_three_times_median: i.long }
            },
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
    /// Per channel, the analysed samples at the format's full scale (an integer WAV's extreme
    /// codes); null for a format without one.
    pub samples_at_full_scale: Option<Channels<u64>>,
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
            samples_at_full_scale: a.full_scale.as_ref().map(|_| Channels::from_fn(|c| a.at_full_scale[c])),
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
    let i = &a.onset_intervals;
    if i.count > 0 {
        s.push_str(&format!(
            "Intervals between slip onsets: {}, mean {} ms, standard deviation {} ms, median {} ms; {} under a third of the median, {} over three times it.\n",
            i.count,
            num(1e3 * i.mean_s),
            num(1e3 * i.sd_s),
            num(1e3 * i.median_s),
            i.short,
            i.long
        ));
    }
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
    if let Some(what) = &a.full_scale {
        for c in 0..a.at_full_scale.len() {
            let n = a.at_full_scale[c];
            if n >= crate::recorded::wav::FULL_SCALE_MIN_SAMPLES {
                s.push_str(&format!("Warning: {}: {n} samples at the file's full scale ({what}): clipped.\n", ACCEL_NAMES[c]));
            }
        }
    }
    s
}

