//! Markdown and JSON of `compare`: measured against model, per channel side by side.

use super::*;

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
    pub(super) fn of(a: Option<&Analysis>) -> Self {
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
    /// The model side's channel health, as `sil` gives it (a saturated channel's model
    /// peak-to-peak and its ratio are null, as `sil` gives none).
    pub model_health: Channels<Vec<&'static str>>,
    /// Why the virtual rig's estimator cannot tell the model's stick fraction and frequency
    /// (as `sil` says; then the model's values are null), or null.
    pub model_undecided: Option<String>,
    /// The measured side's notes, as `analyze` gives them for the file.
    pub notes: Vec<String>,
}

impl CompareJson {
    pub fn new(file: &str, measured: &Analysis, model: &SilReport) -> Self {
        let m = model.measured.as_ref();
        // the channel-health verdict, as `analyze` gives it: an absent or unhealthy measured
        // channel is not compared (measured null if absent; ratio null if unhealthy)
        // and so is the peak-to-peak of a saturated model channel, which `sil` does not estimate
        // (its flat tops are the rails'): null, as in `sil` (`sil_parts`)
        let ch = |c: usize, f: fn(&ChannelStats) -> Option<f64>, is_pp: bool| {
            let mine = measured.present[c].then(|| f(&measured.channels[c])).flatten();
            let theirs = m.filter(|a| !(is_pp && a.health[c].contains(&"saturated"))).and_then(|a| f(&a.channels[c]));
            let p = Pair::new(mine, theirs);
            if measured.health[c].is_empty() { p } else { Pair { ratio: None, ..p } }
        };
        let decided = measured.undecided.is_none();
        // the model's stick fraction and frequency where the virtual rig's estimator can tell
        // them (`sil` prints none otherwise, and so does `compare`)
        let model_decided = m.filter(|a| a.undecided.is_none());
        CompareJson {
            scene: model.name.clone(),
            file: file.to_string(),
            channels: Channels::from_fn(|c| CompareChannelJson {
                pp: ch(c, |s| Some(s.pp), true),
                peak_hz: ch(c, |s| s.peak_hz, false),
                rms: ch(c, |s| Some(s.rms), false),
                groan_rms: ch(c, |s| Some(s.groan_rms), false),
            }),
            stick_fraction: Pair::new(decided.then_some(measured.stick_fraction), model_decided.map(|a| a.stick_fraction)),
            stick_slip_hz: Pair::new(measured.stick_slip_hz.filter(|_| decided), model_decided.and_then(|a| a.stick_slip_hz)),
            health: Channels::from_fn(|c| measured.health[c].clone()),
            undecided: measured.undecided.clone(),
            model_health: Channels::from_fn(|c| m.map_or_else(Vec::new, |a| a.health[c].clone())),
            model_undecided: m.and_then(|a| a.undecided.clone()),
            notes: measured.notes.clone(),
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
    if let Some(why) = &j.model_undecided {
        verdict.push_str(&format!("Model stick fraction and stick-slip frequency: the virtual rig cannot decide ({why}).\n"));
    }
    for (c, h) in measured.health.iter().enumerate() {
        if !h.is_empty() {
            verdict.push_str(&format!("Measured channel {}: {}: not compared.\n", ACCEL_NAMES[c], h.join(", ")));
        }
        if !measured.present[c] {
            verdict.push_str(&format!("Measured channel {}: absent.\n", ACCEL_NAMES[c]));
        }
    }
    if let Some(a) = model.measured.as_ref() {
        for (c, h) in a.health.iter().enumerate() {
            if !h.is_empty() {
                let not = if h.contains(&"saturated") { ": its peak-to-peak not compared" } else { "" };
                verdict.push_str(&format!("Model channel {} (the virtual rig's): {}{not}.\n", ACCEL_NAMES[c], h.join(", ")));
            }
        }
    }
    for n in &j.notes {
        verdict.push_str(&format!("Note (measured): {n}\n"));
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
