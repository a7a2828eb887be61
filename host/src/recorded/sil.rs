//! The virtual rig ("software in the loop"): a scene's motion, through the rig's sensor model,
//! into the same analysis as a recording, against the truth of the model run itself.
//!
//! Per sample i (t = (i + 1) dt, one exact step of the scene per sample, so the virtual rig
//! samples at 1 / dt: 25.6 kHz for the default dt):
//! 1. `shared::harness::sensor_model::SensorModel` steps the model and makes the rig's ADC frame:
//!    `disc_x` the band's acceleration (0: the model's band runs at constant V), `pad_x` = x'',
//!    `pad_trail` and `pad_lead` = r phi'' at the sensors' lever arms about the pivot (5 mm in
//!    from each edge of the pad; plus y'' where the pad floats), plus seeded white noise, clipped at the sensors' +-700 m/s^2,
//!    through the front end (100 mV/g, gain 0.2) into the 12-bit ADC;
//! 2. `shared::rig::calibration::Calibrator` turns the counts back into m/s^2 (0.395 m/s^2 per
//!    count), as the firmware does;
//! 3. the calibrated channels go into [`super::analysis::Analyzer`], which plays them back
//!    through the rig (`shared::rig::pipeline::Rig::for_recording`: the firmware's rig type,
//!    each row through `Rig::play`, the firmware's chain after its calibration), its contact
//!    thresholds from the floor of the quiet lead (or the scene's breakaway jump).
//!
//! The truth, over the same samples (t >= stats_from): stick fraction = samples at which the
//! model is in stick / samples; stick-slip frequency = (n - 1) / (t_n - t_1) over the exact
//! times of the model's n stick-to-slip transitions; peak-to-peak of the noise-free,
//! unclipped, unquantised accelerations the sensor model computed.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use stickslip_model::rig::calibration::{Calibrator, RIG_CALIBRATION};
use stickslip_model::stats::{Extremes, OnsetRate};
use stickslip_model::rig::contact::ContactThresholds;
use stickslip_model::harness::prng::XorShift32;
use stickslip_model::harness::sensor_model::{
    sensed_accelerations, Model2Motion, Motion, Noise, SensorGeometry, SensorModel, SensorModelConfig, SensorModelError,
};
use stickslip_model::{Real, Regime};

use super::analysis::{Analysis, AnalysisConfig, Analyzer, FloorSource};
use stickslip_model::rig::estimator::EstimatorConfig;
use super::spectrum::CH;
use crate::error::{HostError, Result};
use crate::scenes::run::{self, Outcome, Precision};
use crate::scenes::scene_source::NamedScene;

/// Default noise on each accelerometer [m/s^2 rms]: the order of a 100 mV/g piezoelectric
/// accelerometer's residual noise over 1 Hz to 8 kHz (a few mm/s^2), well below one ADC count
/// (0.395 m/s^2), so the 12-bit quantization is what limits the virtual rig, as on the real one.
/// `--noise` raises it to stress the estimator (0.5 m/s^2, 1.3 counts, is still handled).
pub const DEFAULT_NOISE_M_S2: f64 = 0.005;
/// Default seed of the noise generator.
pub const DEFAULT_SEED: u32 = 1;

/// What the analysis sees.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SensorPath {
    /// The rig's chain: noise, clipping, the 12-bit ADC and the calibration (what `sil` runs).
    #[default]
    Rig,
    /// The model's accelerations at the samples plus the sensor noise, neither clipped nor
    /// quantised: a high-resolution logger. With no noise it is the expectation of what a fine
    /// converter records, smooth in the scene's parameters (`stickslip fit` runs its model
    /// through it: the rig's path would make its cost a staircase of ADC counts).
    Ideal,
}

impl SensorPath {
    pub fn name(self) -> &'static str {
        match self {
            SensorPath::Rig => "rig",
            SensorPath::Ideal => "ideal",
        }
    }
}

/// How to run the virtual rig.
#[derive(Clone, Debug)]
pub struct SilOptions {
    pub noise_m_s2: f64,
    pub seed: u32,
    pub segment: Option<usize>,
    pub figures: bool,
    /// The estimator's breakaway jump [m/s^2]; default the scene's.
    pub breakaway_jump_m_s2: Option<f64>,
    pub sensor: SensorPath,
    /// Compute the Welch spectra (`AnalysisConfig::spectra`).
    pub spectra: bool,
    /// The clamped, band-still phase before the run [s]: quiet frames (noise only) written
    /// before t = 0, from which the estimator measures its noise floor (0: none).
    pub quiet_s: f64,
    /// Front-end gain of the accelerometer channels [V/V] (the rig's default 0.2).
    pub gain: [f64; CH],
    /// Conversions summed per frame (the firmware's oversampling; 1: none).
    pub oversample: u32,
    /// The converter's own noise per conversion [counts rms] (0: none).
    pub adc_noise_counts: f64,
    /// Keep the estimator's window statistics (`Analysis::windows`, from the first frame,
    /// the quiet lead's included).
    pub windows: bool,
}

/// The rig's accelerometer front-end gains [V/V].
pub const RIG_GAIN: [f64; CH] = [stickslip_model::rig::calibration::AccelChannel::RIG.front_end_gain; CH];

/// Length of the virtual rig's clamped, band-still phase by default [s].
pub const DEFAULT_QUIET_S: f64 = 0.1;

/// The breakaway jump the estimator uses for `ns`: `given`, else the scene's
/// (mu_s - mu_k) N0 / m; an error if that is not positive (mu_s = mu_k) and none was given.
pub fn breakaway_jump(ns: &NamedScene, given: Option<f64>) -> Result<f64> {
    if let Some(j) = given {
        return Ok(j);
    }
    let j = ContactThresholds::breakaway_jump(&ns.scene);
    if j.is_finite() && j > 0.0 {
        Ok(j)
    } else {
        Err(HostError::Input(format!(
            "{}: the breakaway jump (mu_s - mu_k) N0 / m = {j} m/s^2 is not positive (mu_s = {}, mu_k = {}): \
             the estimator's thresholds need one: give --breakaway-jump M_S2",
            ns.origin_label(),
            ns.scene.mu_s,
            ns.scene.mu_k
        )))
    }
}

/// The starting jump of a scene without one (mu_s = mu_k) when the floor designs the
/// thresholds anyway [m/s^2] (`contact::MIN_DESIGN_JUMP_M_S2`).
pub const NO_JUMP_START_M_S2: f64 = stickslip_model::rig::contact::MIN_DESIGN_JUMP_M_S2;

/// The model's own statistics over the analysed samples.
#[derive(Clone, Copy, Debug, Default)]
pub struct Truth {
    pub samples: u64,
    pub stick_fraction: f64,
    /// `None` with fewer than two onsets.
    pub stick_slip_hz: Option<f64>,
    pub slip_onsets: u64,
    /// Noise-free peak-to-peak of disc_x, pad_x, pad_trail, pad_lead [m/s^2].
    pub pp: [f64; CH],
}

/// One virtual-rig run.
#[derive(Clone, Debug)]
pub struct SilReport {
    pub name: String,
    /// Which stepper made the motion.
    pub stepper: &'static str,
    pub caliper: &'static str,
    pub beta: f64,
    /// Sampling rate 1 / dt [Hz].
    pub sample_rate_hz: f64,
    pub steps_planned: u64,
    pub steps_done: u64,
    pub stats_from: f64,
    pub outcome: &'static str,
    pub halt_t_s: Option<f64>,
    pub noise_m_s2: f64,
    pub seed: u32,
    /// The accelerometers' front-end gains [V/V].
    pub gain: [f64; CH],
    /// Conversions summed per frame, and the converter's noise per conversion [counts rms].
    pub oversample: u32,
    pub adc_noise_counts: f64,
    /// The converter's error per accelerometer over the statistics window: RMS of calibrated
    /// minus what reached the converter (the truth with the sensors' noise, clipped) [m/s^2],
    /// and the same in counts of one conversion (the effective resolution of the chain:
    /// quantisation and the converter's noise, after the oversampling's sum). `None` on the
    /// ideal front end.
    pub converter_rms_m_s2: Option<[f64; CH]>,
    pub converter_rms_counts: Option<[f64; CH]>,
    pub sensor: SensorPath,
    /// Frames with an accelerometer at its range or at an ADC rail.
    pub saturated_frames: u64,
    /// The hard bound of |estimated - true| peak-to-peak per channel [m/s^2]: each extreme is
    /// off by at most half an ADC count (rounding) plus the noise's bound
    /// (`prng::UNIT_NOISE_BOUND` sigma), so the peak-to-peak by one count plus twice that
    /// (without clipping: see `saturated_frames`). See [`pp_error_bound`].
    pub pp_bound_m_s2: [f64; CH],
    pub truth: Truth,
    /// The analysis of the virtual rig's channels; `None` if the run halted before
    /// `stats_from`.
    pub measured: Option<Analysis>,
    /// The run was over the work budget and not stepped (outcome `budget`).
    pub over_budget: Option<run::OverBudget>,
}

/// Runs `ns` through the virtual rig; writes every frame's calibrated channels to `csv` if
/// given (header `t_s,disc_x_m_s2,pad_x_m_s2,pad_trail_m_s2,pad_lead_m_s2`; values printed
/// so that they read back to the same f64).
pub fn run(ns: &NamedScene, precision: Precision, opts: &SilOptions, csv: Option<&Path>) -> Result<SilReport> {
    match precision {
        Precision::F32 => run_in::<f32>(ns, opts, csv),
        Precision::F64 => run_in::<f64>(ns, opts, csv),
    }
}

/// The analysis configuration the virtual rig and `compare` use for `scene`: the scene's
/// breakaway jump and band speed, statistics from `stats_from`.
pub fn analysis_config(scene: &stickslip_model::Scene, from_s: f64, segment: Option<usize>, figures: bool) -> AnalysisConfig {
    AnalysisConfig {
        from_s,
        segment,
        breakaway_jump_m_s2: ContactThresholds::breakaway_jump(scene),
        floor: FloorSource::Jump,
        face_coefficient: EstimatorConfig::face_coefficient_for(scene, &SensorGeometry::RIG) as f32,
        band_speed_m_s: scene.v,
        figures,
        spectra: true,
        windows: false,
    }
}

struct CsvOut {
    path: String,
    w: BufWriter<File>,
}

impl CsvOut {
    fn err(&self, e: std::io::Error) -> HostError {
        HostError::Output(format!("{}: cannot write the CSV: {e}", self.path))
    }
}

fn run_in<T: Real>(ns: &NamedScene, opts: &SilOptions, csv: Option<&Path>) -> Result<SilReport> {
    let scene = &ns.scene;
    let bad_option = |what: &str, v: f64, rule: &str| HostError::Input(format!("{what} {v}: {rule}"));
    if !(opts.noise_m_s2.is_finite() && opts.noise_m_s2 >= 0.0) {
        return Err(bad_option("--noise", opts.noise_m_s2, "must be >= 0 m/s^2"));
    }
    if !(opts.quiet_s.is_finite() && opts.quiet_s >= 0.0) {
        return Err(bad_option("--quiet-lead", opts.quiet_s, "must be >= 0 s"));
    }
    if !(opts.adc_noise_counts.is_finite() && opts.adc_noise_counts >= 0.0) {
        return Err(bad_option("--adc-noise", opts.adc_noise_counts, "must be >= 0 counts"));
    }
    let mut cfg = SensorModelConfig::RIG;
    cfg.noise =
        Noise { accel_rms_m_s2: opts.noise_m_s2, pressure_rms_bar: 0.0, seed: opts.seed, adc_rms_counts: opts.adc_noise_counts };
    cfg.calibration = rig_calibration(opts);
    let to_input = |e: SensorModelError| {
        HostError::Input(match e {
            SensorModelError::Scene(s) => format!("{}: {s}", ns.origin_label()),
            SensorModelError::Config(c) => format!("virtual rig: {c}"),
        })
    };
    // a scene with Stribeck friction or the band runs model 2 (disc_x = the band's x_b'')
    if scene.uses_model2() {
        let motion = Model2Motion::<T>::new(scene).map_err(|e| to_input(e.into()))?;
        let budget = run::OverBudget::of(motion.stepper().substeps(), run::planned_steps(scene));
        let sensor = SensorModel::with_motion(motion, scene, &cfg).map_err(to_input)?;
        sample_run(ns, opts, csv, sensor, budget)
    } else {
        let budget = run::over_budget(scene)?;
        let sensor = SensorModel::<T>::new(scene, &cfg).map_err(to_input)?;
        sample_run(ns, opts, csv, sensor, budget)
    }
}

/// The channel-health verdict of the analysis (shared::rig::health, the words `analyze`
/// prints) with the channels the virtual rig saw saturate (`saturated_ch`: frames at a range or
/// a rail per channel) marked saturated, and the estimator's verdict made again on them.
fn mark_saturated(a: &mut Analysis, saturated_ch: &[u64; CH]) {
    use stickslip_model::rig::health::{ChannelHealth, HealthReport};
    use stickslip_model::rig::{DISC_X, PAD_X};
    if saturated_ch.iter().all(|&n| n == 0) {
        return;
    }
    let bit = |w: &str| match w {
        "flat" => ChannelHealth::FLAT,
        "saturated" => ChannelHealth::SATURATED,
        _ => ChannelHealth::NOISY,
    };
    let verdict = HealthReport::new(std::array::from_fn(|c| {
        let bits = a.health[c].iter().fold(0, |b, w| b | bit(w));
        ChannelHealth(bits | if saturated_ch[c] > 0 { ChannelHealth::SATURATED } else { 0 })
    }));
    a.health = std::array::from_fn(|c| verdict.channels[c].words().collect());
    if verdict.undecidable() {
        // the analysis's wording (recorded::analysis, `undecided`)
        let mut bad = vec![];
        for (c, name) in [(PAD_X, "pad_x"), (DISC_X, "disc_x")] {
            for what in verdict.channels[c].words() {
                if !(c == DISC_X && what == "flat") {
                    bad.push(format!("{name} {what}"));
                }
            }
        }
        a.undecided = Some(format!("{}: the contact estimate (stick fraction, frequency) would be a guess", bad.join(", ")));
    }
}

/// The rig's calibration with the options' front-end gains and oversampling.
pub fn rig_calibration(opts: &SilOptions) -> stickslip_model::rig::calibration::Calibration {
    let mut calibration = RIG_CALIBRATION;
    for (c, g) in calibration.accel.iter_mut().zip(opts.gain) {
        c.front_end_gain = g;
    }
    calibration.adc.oversample = opts.oversample;
    calibration
}

/// The virtual rig's run: frames from the sensor model into the analysis, and the truth beside.
fn sample_run<T: Real, M: Motion<T>>(
    ns: &NamedScene,
    opts: &SilOptions,
    csv: Option<&Path>,
    mut sensor: SensorModel<T, M>,
    budget: Option<run::OverBudget>,
) -> Result<SilReport> {
    let scene = &ns.scene;
    let calibration = rig_calibration(opts);
    let cal = Calibrator::new(&calibration).map_err(|e| HostError::Input(format!("virtual rig: {e}")))?;
    let mut out = match csv {
        Some(p) => {
            let path = p.display().to_string();
            let f = File::create(p).map_err(|e| HostError::Output(format!("{path}: cannot create the CSV: {e}")))?;
            let mut o = CsvOut { path, w: BufWriter::new(f) };
            writeln!(o.w, "t_s,disc_x_m_s2,pad_x_m_s2,pad_trail_m_s2,pad_lead_m_s2").map_err(|e| o.err(e))?;
            Some(o)
        }
        None => None,
    };
    let dt = scene.dt;
    let from_eff = scene.stats_from - 0.25 * dt;
    let mut acfg = analysis_config(scene, scene.stats_from, opts.segment, opts.figures);
    acfg.spectra = opts.spectra;
    acfg.windows = opts.windows;
    acfg.breakaway_jump_m_s2 = breakaway_jump(ns, opts.breakaway_jump_m_s2).unwrap_or(crate::recorded::sil::NO_JUMP_START_M_S2);
    if opts.breakaway_jump_m_s2.is_some() || opts.quiet_s == 0.0 {
        // fixed thresholds: the given jump, or the scene's without a quiet phase to measure
        acfg.breakaway_jump_m_s2 = breakaway_jump(ns, opts.breakaway_jump_m_s2)?;
    } else {
        acfg.floor = FloorSource::Lead;
    }
    let mut analyzer = Analyzer::new(acfg);
    let steps_planned = run::planned_steps(scene);
    let mut truth = Truth::default();
    let mut extremes = Extremes::<f64, CH>::EMPTY;
    let (mut stick, mut onsets) = (0u64, OnsetRate::new());
    // a run over the work budget is not stepped (outcome `budget`)
    let mut outcome = budget.map_or(Outcome::Completed, Outcome::Budget);
    let mut steps_done = 0;
    let mut saturated_frames = 0;
    // frames of the analysed stretch with each accelerometer at its range or an ADC rail (the
    // analysis sees only calibrated values: a front-end gain shrinks the range it can see)
    let mut saturated_ch = [0u64; CH];
    // the converter's error: sum of (calibrated - converter input)^2 per channel
    let mut conv_sq = [0.0f64; CH];
    // the ideal path's noise: its own stream of the same generator and seed
    let mut rng = XorShift32::new(opts.seed);
    let sigma = opts.noise_m_s2;
    // the clamped, band-still phase: quiet frames at t <= 0 (none for a run over the work
    // budget, which is not run: at its step they could be as many as its steps)
    let quiet = if budget.is_some() { 0 } else { (opts.quiet_s / dt).round() as u64 };
    for q in 0..quiet {
        crate::cancel::check_every(q)?;
        let frame = sensor.quiet_frame();
        let t = -((quiet - 1 - q) as f64) * dt;
        let a: [f64; CH] = match opts.sensor {
            SensorPath::Rig => cal.calibrate(&frame).accel_m_s2.map(|v| v as f64),
            SensorPath::Ideal if sigma > 0.0 => [(); CH].map(|_| sigma * rng.unit_noise::<f64>()),
            SensorPath::Ideal => [0.0; CH],
        };
        if let Some(o) = &mut out {
            writeln!(o.w, "{t},{},{},{},{}", a[0], a[1], a[2], a[3]).map_err(|e| o.err(e))?;
        }
        analyzer
            .push(q + 2, t, 0.0, &a)
            .map_err(|m| HostError::Input(format!("virtual rig of {}: {m}", ns.origin_label())))?;
    }
    for i in 0..if budget.is_some() { 0 } else { steps_planned } {
        crate::cancel::check_every(i)?;
        let frame = match sensor.next_frame() {
            Ok(f) => f,
            Err(halt) => {
                outcome = Outcome::halted(scene, halt);
                break;
            }
        };
        steps_done += 1;
        let t = (i + 1) as f64 * dt;
        let a: [f64; CH] = match opts.sensor {
            SensorPath::Rig => {
                let c = cal.calibrate(&frame);
                if c.saturation.any_accel() {
                    saturated_frames += 1;
                    if t >= from_eff {
                        for (ch, n) in saturated_ch.iter_mut().enumerate() {
                            *n += u64::from(c.saturation.range(ch) || c.saturation.rail(ch));
                        }
                    }
                }
                c.accel_m_s2.map(|v| v as f64)
            }
            SensorPath::Ideal => {
                let tr = sensor.truth().accel_m_s2.map(|v| v.to_f64());
                if sigma > 0.0 {
                    tr.map(|v| v + sigma * rng.unit_noise::<f64>())
                } else {
                    tr
                }
            }
        };
        if let Some(o) = &mut out {
            writeln!(o.w, "{t},{},{},{},{}", a[0], a[1], a[2], a[3]).map_err(|e| o.err(e))?;
        }
        analyzer
            .push(quiet + i + 2, t, 0.0, &a)
            .map_err(|m| HostError::Input(format!("virtual rig of {}: {m}", ns.origin_label())))?;
        if t >= from_eff {
            if opts.sensor == SensorPath::Rig {
                let input = sensor.converter_input_m_s2();
                for ch in 0..CH {
                    let e = a[ch] - input[ch].to_f64();
                    conv_sq[ch] += e * e;
                }
            }
            let tr = sensor.truth();
            truth.samples += 1;
            if tr.regime == Some(Regime::Stick) {
                stick += 1;
            }
            for ch in 0..CH {
                extremes.take(ch, tr.accel_m_s2[ch].to_f64());
            }
            for &t_onset in sensor.motion().slip_onsets() {
                onsets.add(t_onset);
            }
        }
    }
    if let Some(mut o) = out {
        o.w.flush().map_err(|e| o.err(e))?;
    }
    if truth.samples > 0 {
        truth.stick_fraction = stick as f64 / truth.samples as f64;
        truth.pp = std::array::from_fn(|c| extremes.pp(c));
        truth.slip_onsets = u64::from(onsets.count());
        truth.stick_slip_hz = onsets.hz();
    }
    // a run that halts early (a finding) may leave too little to analyse: no statistics then
    let measured = match analyzer.finish() {
        Ok(mut a) if truth.samples > 0 => {
            mark_saturated(&mut a, &saturated_ch);
            Some(a)
        }
        Ok(_) => None,
        Err(_) if outcome != Outcome::Completed => None,
        Err(m) => return Err(HostError::Input(format!("virtual rig of {}: {m}", ns.origin_label()))),
    };
    // no floor measured (no quiet stretch before a signal): the thresholds came from the jump,
    // which a scene with mu_s = mu_k does not have
    if opts.breakaway_jump_m_s2.is_none() && measured.as_ref().is_some_and(|a| a.floor.is_none()) {
        breakaway_jump(ns, None)?;
    }
    let converter_rms = (opts.sensor == SensorPath::Rig && truth.samples > 0)
        .then(|| conv_sq.map(|q| (q / truth.samples as f64).sqrt()));
    Ok(SilReport {
        name: ns.name.clone(),
        stepper: if scene.uses_model2() { "model-2 stepper" } else { "exact stepper" },
        caliper: scene.caliper.name(),
        beta: scene.beta,
        sample_rate_hz: 1.0 / dt,
        steps_planned,
        steps_done,
        stats_from: scene.stats_from,
        outcome: outcome.keyword(),
        halt_t_s: outcome.halt_time(),
        over_budget: budget,
        noise_m_s2: opts.noise_m_s2,
        seed: opts.seed,
        gain: opts.gain,
        oversample: opts.oversample,
        adc_noise_counts: opts.adc_noise_counts,
        converter_rms_m_s2: converter_rms,
        converter_rms_counts: converter_rms
            .map(|e| std::array::from_fn(|c| e[c] * calibration.accel[c].counts_per_m_s2(&calibration.adc))),
        sensor: opts.sensor,
        saturated_frames,
        pp_bound_m_s2: match opts.sensor {
            SensorPath::Rig => pp_error_bound(&calibration, opts.noise_m_s2, opts.adc_noise_counts),
            SensorPath::Ideal => [2.0 * stickslip_model::harness::prng::UNIT_NOISE_BOUND * opts.noise_m_s2; CH],
        },
        truth,
        measured,
    })
}

/// The hard error bound of a peak-to-peak through the virtual rig, per accelerometer [m/s^2]:
/// one ADC count (`1 / counts_per_m_s2`: the two extremes each rounded by at most half a
/// count; with oversampling each is the mean of N conversions rounded so) plus
/// `2 UNIT_NOISE_BOUND` times the sensor noise and the converter's noise (in counts, each
/// extreme moved by at most their bounds). Valid while no sample clips.
pub fn pp_error_bound(cal: &stickslip_model::rig::calibration::Calibration, noise_m_s2: f64, adc_noise_counts: f64) -> [f64; CH] {
    let b = stickslip_model::harness::prng::UNIT_NOISE_BOUND;
    std::array::from_fn(|c| (1.0 + 2.0 * b * adc_noise_counts) / cal.accel[c].counts_per_m_s2(&cal.adc) + 2.0 * b * noise_m_s2)
}

/// The statistics of a model-2 scene (Stribeck friction or the band) through the virtual
/// rig's ideal sensor path without noise and without a quiet lead, the estimator's thresholds
/// from the breakaway jump `jump_m_s2`: what [`run`] gives as `measured` for those options
/// (the same samples into the same analysis), without the converter's counts, the truth's
/// statistics and the report that the fit does not use. `Ok(None)`: nothing to analyse.
/// An error names the outcome of a run that does not complete (over the work budget, a halt)
/// as [`run`]'s report would: `(keyword, halt time)`.
pub fn ideal_model2_statistics(
    ns: &NamedScene,
    jump_m_s2: f64,
    segment: Option<usize>,
    spectra: bool,
) -> std::result::Result<Option<Analysis>, IdealRunError> {
    let scene = &ns.scene;
    let input = |m: String| IdealRunError::Input(m);
    let mut motion = Model2Motion::<f64>::new(scene).map_err(|e| input(format!("{}: {e}", ns.origin_label())))?;
    if let Some(b) = run::OverBudget::of(motion.stepper().substeps(), run::planned_steps(scene)) {
        let o = Outcome::Budget(b);
        return Err(IdealRunError::Outcome(o.keyword(), o.halt_time()));
    }
    let geometry = SensorModelConfig::RIG.geometry;
    let (arm_trail, arm_lead) = geometry.arms(scene).map_err(|e| input(format!("virtual rig: {e}")))?;
    let y_polarity = geometry.y_polarity;
    let dt = scene.dt;
    let from_eff = scene.stats_from - 0.25 * dt;
    let mut acfg = analysis_config(scene, scene.stats_from, segment, false);
    acfg.spectra = spectra;
    acfg.windows = false;
    acfg.breakaway_jump_m_s2 = jump_m_s2;
    let mut analyzer = Analyzer::new(acfg);
    let mut samples = 0u64;
    for i in 0..run::planned_steps(scene) {
        if let Err(halt) = motion.advance() {
            let o = Outcome::halted(scene, halt);
            return Err(IdealRunError::Outcome(o.keyword(), o.halt_time()));
        }
        let a = sensed_accelerations(&motion, arm_trail, arm_lead, y_polarity);
        let t = (i + 1) as f64 * dt;
        analyzer.push(i + 2, t, 0.0, &a).map_err(|m| input(format!("virtual rig of {}: {m}", ns.origin_label())))?;
        if t >= from_eff {
            samples += 1;
        }
    }
    match analyzer.finish() {
        Ok(a) if samples > 0 => Ok(Some(a)),
        Ok(_) => Ok(None),
        Err(m) => Err(input(format!("virtual rig of {}: {m}", ns.origin_label()))),
    }
}

/// Why [`ideal_model2_statistics`] gives no statistics.
#[derive(Debug)]
pub enum IdealRunError {
    /// The run does not complete: its outcome's keyword and the halt's time.
    Outcome(&'static str, Option<f64>),
    /// A bad scene or analysis.
    Input(String),
}
