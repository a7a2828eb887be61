//! Markdown and JSON of `sil`: the virtual rig's estimates against the scene's truth.

use super::*;

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
pub(super) fn sil_parts(r: &SilReport) -> (VsTruth, VsTruth, VsTruth, [VsTruth; 4]) {
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
pub(super) fn sil_health(r: &SilReport) -> Option<(Option<String>, [Vec<&'static str>; 4])> {
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
pub(super) fn pct(e: Option<f64>) -> String {
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
