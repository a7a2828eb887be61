//! The inverse of the measurement: the model's motion to the frames the rig's ADC would return.
//! For tests (signals whose truth is known) and for the virtual rig.
//!
//! Per sample, after one step of the exact stepper (so frame `i` shows the state at
//! t = (i + 1) dt, and the transitions of that step are those the frame is the first to see):
//!
//! - `disc_x` = the band's acceleration along x: 0 when the band runs at constant V (the thesis
//!   model); the band's x_b'' with model 2's band degree of freedom ([`Model2Motion`]).
//! - `pad_x` = x'' of the pad, from [`Plant::accelerations`] in the stepper's regime (exactly
//!   0 in stick, a jump of about -(mu_s - mu_k) N / m at breakaway).
//! - `pad_trail`, `pad_lead` = the y accelerations of two points of the pad, from the rotation:
//!   see [`SensorGeometry`].
//! - actuator line pressure = F_N / A (the scene's F_N, the piston area A); band line pressure =
//!   a configured constant (the band starts moving near 0.6 to 0.7 bar).
//!
//! Then, in this order: optional noise (white, from the seeded [`XorShift32`], Irwin-Hall
//! shaped, bounded by 3.46 sigma), clipping at the accelerometers' measuring range (+-700
//! m/s^2: the sensor saturates), and the ADC (nearest count, clamped to the rails) through the
//! inverse of the [`Calibration`]. The noise-free physical values of the last frame are kept in
//! [`SensorModel::truth`].
//!
//! The model is open loop: its band moves from the first frame and its pressures do not follow
//! the valves.

use crate::rig::calibration::{Calibration, Frame};
use crate::rig::pneumatics::{actuator_bar_for, RIG_PISTON_AREA_M2};
use super::prng::XorShift32;
pub use crate::rig::geometry::SensorGeometry;
use crate::rig::{
    check, ConfigError, ACCEL_CHANNELS, ACTUATOR, BAND, CHANNELS, DISC_X, PAD_LEAD, PAD_TRAIL, PAD_X, PRESSURE_CHANNELS,
};
use crate::coefficients::Coefficients;
use crate::exact::{ExactStepper, Halt};
use crate::methods::plant::Plant;
use crate::real::Real;
use crate::scene::{Scene, SceneError};
use crate::model2::{AnyModel2Stepper, Model2Observer, Model2Transition};
use crate::stickslip::Regime;

/// What the sensor model samples: a stepper, and the accelerations its sensors see.
pub trait Motion<T: Real> {
    /// One step of the model.
    fn advance(&mut self) -> Result<(), Halt>;
    fn regime(&self) -> Regime;
    /// (pad x'' [m/s^2], pad phi'' [rad/s^2], band x_b'' [m/s^2]) at the current state.
    fn accelerations(&self) -> (T, T, T);
    /// The pivot's acceleration normal to the band y'' [m/s^2], toward the band, for a pad that
    /// is not hinged (`None`: the hinge, y'' = 0).
    fn normal_acceleration(&self) -> Option<T> {
        None
    }
    /// Times [s] of the stick-to-slip transitions of the last step.
    fn slip_onsets(&self) -> &[f64];
}

/// The four accelerometers' true accelerations [m/s^2] at `motion`'s current state, in the
/// channel order (disc_x = the band's x_b'', pad_x = x'', pad_trail and pad_lead = their lever
/// arms [m] times phi'', plus `y_polarity` times the pivot's y'' for a pad that is not hinged).
pub fn sensed_accelerations<T: Real, M: Motion<T>>(motion: &M, arm_trail: T, arm_lead: T, y_polarity: T) -> [T; ACCEL_CHANNELS] {
    let (xdd, phidd, band) = motion.accelerations();
    let mut accel = [T::zero(); ACCEL_CHANNELS];
    accel[DISC_X] = band;
    accel[PAD_X] = xdd;
    accel[PAD_TRAIL] = arm_trail * phidd;
    accel[PAD_LEAD] = arm_lead * phidd;
    if let Some(ydd) = motion.normal_acceleration() {
        // a pad that is not hinged: the pivot's own y'' adds to every point's
        accel[PAD_TRAIL] = accel[PAD_TRAIL] + y_polarity * ydd;
        accel[PAD_LEAD] = accel[PAD_LEAD] + y_polarity * ydd;
    }
    accel
}

/// The thesis model: the exact stepper, the band at constant speed (x_b'' = 0).
#[derive(Clone, Debug)]
pub struct ThesisMotion<T: Real> {
    stepper: ExactStepper<T>,
    plant: Plant<T>,
    onsets: [f64; crate::exact::TRANSITIONS_PER_STEP],
    n_onsets: usize,
}

impl<T: Real> ThesisMotion<T> {
    pub fn new(scene: &Scene) -> Result<Self, SceneError> {
        Ok(ThesisMotion {
            stepper: ExactStepper::<T>::new(scene)?,
            plant: Plant::new(scene, &Coefficients::of(scene)),
            onsets: [0.0; crate::exact::TRANSITIONS_PER_STEP],
            n_onsets: 0,
        })
    }
    pub fn stepper(&self) -> &ExactStepper<T> {
        &self.stepper
    }
}

impl<T: Real> Motion<T> for ThesisMotion<T> {
    #[inline]
    fn advance(&mut self) -> Result<(), Halt> {
        self.stepper.step()?;
        self.n_onsets = 0;
        for tr in self.stepper.transitions() {
            if tr.from == Regime::Stick {
                self.onsets[self.n_onsets] = tr.t;
                self.n_onsets += 1;
            }
        }
        Ok(())
    }
    fn regime(&self) -> Regime {
        self.stepper.regime()
    }
    #[inline]
    fn accelerations(&self) -> (T, T, T) {
        let z = self.stepper.state().to_array();
        let (xdd, phidd) = self.plant.accelerations(self.stepper.regime(), &z);
        (xdd, phidd, T::zero())
    }
    fn slip_onsets(&self) -> &[f64] {
        &self.onsets[..self.n_onsets]
    }
}

/// Model 2 (Stribeck friction, the band): disc_x is the band's acceleration.
#[derive(Clone, Debug)]
pub struct Model2Motion<T: Real> {
    stepper: AnyModel2Stepper<T>,
    onsets: OnsetLog,
}

/// The slip onsets of one step (at most 8 kept).
#[derive(Clone, Copy, Debug, Default)]
struct OnsetLog {
    t: [f64; 8],
    n: usize,
}

impl<T: Real> Model2Observer<T> for OnsetLog {
    const DERIVATIVES: bool = false;
    fn transition(&mut self, tr: &Model2Transition<T>) {
        if tr.from == Regime::Stick && self.n < self.t.len() {
            self.t[self.n] = tr.t;
            self.n += 1;
        }
    }
}

impl<T: Real> Model2Motion<T> {
    pub fn new(scene: &Scene) -> Result<Self, SceneError> {
        Ok(Model2Motion { stepper: AnyModel2Stepper::<T>::new(scene)?, onsets: OnsetLog::default() })
    }
    pub fn stepper(&self) -> &AnyModel2Stepper<T> {
        &self.stepper
    }
}

impl<T: Real> Motion<T> for Model2Motion<T> {
    fn advance(&mut self) -> Result<(), Halt> {
        self.onsets.n = 0;
        self.stepper.step_observed(&mut self.onsets).map(|_| ())
    }
    fn regime(&self) -> Regime {
        self.stepper.regime()
    }
    fn accelerations(&self) -> (T, T, T) {
        let d = self.stepper.derivative(self.stepper.regime(), &self.stepper.state());
        (d[1], d[3], d[5])
    }
    fn normal_acceleration(&self) -> Option<T> {
        if self.stepper.floating() {
            Some(self.stepper.derivative(self.stepper.regime(), &self.stepper.state())[crate::model2::Y + 1])
        } else {
            None
        }
    }
    fn slip_onsets(&self) -> &[f64] {
        &self.onsets.t[..self.onsets.n]
    }
}

/// Noise added to the physical signals before clipping and quantisation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Noise {
    /// Standard deviation on each accelerometer [m/s^2] (0: none).
    pub accel_rms_m_s2: f64,
    /// Standard deviation on each pressure [bar] (0: none).
    pub pressure_rms_bar: f64,
    /// Seed of the generator.
    pub seed: u32,
    /// The converter's own noise on each conversion [counts rms] (0: none): independent from
    /// one conversion to the next, unlike the sensors' noise, which is drawn once per frame
    /// (band-limited to 8 kHz, it is nearly the same in the conversions of one frame). With
    /// [`super::calibration::Adc::oversample`] N > 1 it dithers the N conversions a frame sums.
    pub adc_rms_counts: f64,
}

impl Noise {
    pub const NONE: Noise = Noise { accel_rms_m_s2: 0.0, pressure_rms_bar: 0.0, seed: 1, adc_rms_counts: 0.0 };
}

/// Everything the sensor model needs besides the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorModelConfig {
    /// The calibration whose inverse makes the counts.
    pub calibration: Calibration,
    pub geometry: SensorGeometry,
    /// Actuator piston area [m^2] (F_N = p A).
    pub piston_area_m2: f64,
    /// Band-drive cylinder line pressure [bar].
    pub band_line_bar: f64,
    pub noise: Noise,
}

impl SensorModelConfig {
    /// The rig's nominal set-up, noise-free, band line at 0.65 bar.
    pub const RIG: SensorModelConfig = SensorModelConfig {
        calibration: crate::rig::calibration::RIG_CALIBRATION,
        geometry: SensorGeometry::RIG,
        piston_area_m2: RIG_PISTON_AREA_M2,
        band_line_bar: 0.65,
        noise: Noise::NONE,
    };
}

impl Default for SensorModelConfig {
    fn default() -> Self {
        Self::RIG
    }
}

/// Why a sensor model cannot be built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SensorModelError {
    Scene(SceneError),
    Config(ConfigError),
}

impl From<SceneError> for SensorModelError {
    fn from(e: SceneError) -> Self {
        SensorModelError::Scene(e)
    }
}
impl From<ConfigError> for SensorModelError {
    fn from(e: ConfigError) -> Self {
        SensorModelError::Config(e)
    }
}

/// The noise-free physical values behind the last frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Truth<T> {
    /// `disc_x`, `pad_x`, `pad_trail`, `pad_lead` [m/s^2], before noise and clipping.
    pub accel_m_s2: [T; ACCEL_CHANNELS],
    /// Actuator line, band line [bar].
    pub pressure_bar: [T; PRESSURE_CHANNELS],
    /// The model's regime at the sample instant.
    pub regime: Option<Regime>,
}

/// Per-channel constants of the physical-value-to-count map, in `T`.
#[derive(Clone, Copy, Debug)]
struct ToCounts<T> {
    /// count = offset + value * gain, per frame channel.
    offset: [T; CHANNELS],
    gain: [T; CHANNELS],
    /// Sensor range of each accelerometer [m/s^2].
    range: [T; ACCEL_CHANNELS],
    max_count: T,
}

/// Makes one frame per call from a model's motion (the thesis model's exact stepper by default).
#[derive(Clone, Debug)]
pub struct SensorModel<T: Real, M: Motion<T> = ThesisMotion<T>> {
    motion: M,
    arm_trail: T,
    arm_lead: T,
    /// +1 or -1: the y accelerometers' reading of a motion toward the band.
    y_polarity: T,
    pressure: [T; PRESSURE_CHANNELS],
    accel_sigma: T,
    pressure_sigma: T,
    /// The converter's noise per conversion [counts], and the conversions per frame.
    adc_sigma: T,
    oversample: u32,
    rng: XorShift32,
    to_counts: ToCounts<T>,
    truth: Truth<T>,
    /// What reached the converter in the last frame: the accelerations with the sensors' noise,
    /// clipped at their range [m/s^2].
    converter_input: [T; ACCEL_CHANNELS],
}

impl<T: Real> SensorModel<T> {
    /// The thesis model's motion.
    pub fn new(scene: &Scene, cfg: &SensorModelConfig) -> Result<Self, SensorModelError> {
        let motion = ThesisMotion::<T>::new(scene)?;
        Self::with_motion(motion, scene, cfg)
    }

    /// The stepper behind the frames (its state, regime and the transitions of the last step
    /// are the truth of the last frame).
    pub fn stepper(&self) -> &ExactStepper<T> {
        self.motion.stepper()
    }
}

impl<T: Real, M: Motion<T>> SensorModel<T, M> {
    /// Any motion; `scene` gives the geometry and the load (validated by the motion's stepper).
    pub fn with_motion(motion: M, scene: &Scene, cfg: &SensorModelConfig) -> Result<Self, SensorModelError> {
        let cal = &cfg.calibration;
        cal.validate()?;
        let (arm_trail, arm_lead) = cfg.geometry.arms(scene)?;
        check(
            cfg.piston_area_m2.is_finite() && cfg.piston_area_m2 > 0.0,
            "piston_area_m2",
            "must be > 0 m^2",
            cfg.piston_area_m2,
        )?;
        check(cfg.band_line_bar.is_finite(), "band_line_bar", "must be a finite pressure", cfg.band_line_bar)?;
        let n = &cfg.noise;
        check(
            n.accel_rms_m_s2.is_finite() && n.accel_rms_m_s2 >= 0.0,
            "noise.accel_rms_m_s2",
            "must be >= 0",
            n.accel_rms_m_s2,
        )?;
        check(
            n.pressure_rms_bar.is_finite() && n.pressure_rms_bar >= 0.0,
            "noise.pressure_rms_bar",
            "must be >= 0",
            n.pressure_rms_bar,
        )?;
        check(
            n.adc_rms_counts.is_finite() && n.adc_rms_counts >= 0.0,
            "noise.adc_rms_counts",
            "must be >= 0",
            n.adc_rms_counts,
        )?;
        let t = T::from_f64;
        let adc = &cal.adc;
        let mut offset = [T::zero(); CHANNELS];
        let mut gain = [T::zero(); CHANNELS];
        let mut range = [T::zero(); ACCEL_CHANNELS];
        for (i, a) in cal.accel.iter().enumerate() {
            offset[i] = t(a.offset_counts);
            gain[i] = t(a.counts_per_m_s2(adc));
            range[i] = t(a.range_m_s2);
        }
        for (j, p) in cal.pressure.iter().enumerate() {
            offset[ACCEL_CHANNELS + j] = t(p.zero_counts(adc));
            gain[ACCEL_CHANNELS + j] = t(p.pin_volts_per_bar() / adc.volts_per_count());
        }
        let mut pressure = [T::zero(); PRESSURE_CHANNELS];
        pressure[ACTUATOR] = t(actuator_bar_for(scene.f_n, cfg.piston_area_m2));
        pressure[BAND] = t(cfg.band_line_bar);
        Ok(SensorModel {
            motion,
            arm_trail: t(arm_trail),
            arm_lead: t(arm_lead),
            y_polarity: t(cfg.geometry.y_polarity),
            pressure,
            accel_sigma: t(n.accel_rms_m_s2),
            pressure_sigma: t(n.pressure_rms_bar),
            adc_sigma: t(n.adc_rms_counts),
            oversample: adc.oversample,
            rng: XorShift32::new(n.seed),
            to_counts: ToCounts { offset, gain, range, max_count: t(adc.max_count() as f64) },
            truth: Truth::default(),
            converter_input: [T::zero(); ACCEL_CHANNELS],
        })
    }

    /// The motion behind the frames.
    pub fn motion(&self) -> &M {
        &self.motion
    }

    /// The noise-free physical values of the last frame.
    pub fn truth(&self) -> &Truth<T> {
        &self.truth
    }

    /// The accelerations the converter was given in the last frame [m/s^2]: the truth with
    /// the sensors' noise, clipped at their range (what a perfect converter would report; the
    /// difference from the calibrated frame is the converter's error: quantisation and its own
    /// noise, after the oversampling's sum).
    pub fn converter_input_m_s2(&self) -> &[T; ACCEL_CHANNELS] {
        &self.converter_input
    }

    /// Steps the model once and returns the frame of the new state. A halted model (a finding
    /// such as sprag or contact loss, see [`Halt`]) yields no more frames.
    #[allow(clippy::needless_range_loop)] // parallel per-channel arrays
    pub fn next_frame(&mut self) -> Result<Frame, Halt> {
        self.motion.advance()?;
        let regime = self.motion.regime();
        let accel = sensed_accelerations(&self.motion, self.arm_trail, self.arm_lead, self.y_polarity);
        self.truth = Truth { accel_m_s2: accel, pressure_bar: self.pressure, regime: Some(regime) };
        Ok(self.counts_of_truth())
    }

    /// A frame of the clamped, band-still phase before the run: nothing moves (accelerations
    /// 0, the model not stepped, regime stick), the sensors' noise and the converter as in
    /// [`Self::next_frame`] (the noise stream goes on, so a run after quiet frames sees other
    /// noise than one without).
    pub fn quiet_frame(&mut self) -> Frame {
        self.truth = Truth { accel_m_s2: [T::zero(); ACCEL_CHANNELS], pressure_bar: self.pressure, regime: Some(Regime::Stick) };
        self.counts_of_truth()
    }

    /// The frame of `self.truth`: noise, the sensors' range, the converter.
    #[allow(clippy::needless_range_loop)] // parallel per-channel arrays
    fn counts_of_truth(&mut self) -> Frame {
        let accel = self.truth.accel_m_s2;
        let k = self.to_counts;
        let mut frame = Frame::default();
        for i in 0..ACCEL_CHANNELS {
            let mut a = accel[i];
            if self.accel_sigma > T::zero() {
                a += self.accel_sigma * self.rng.unit_noise::<T>();
            }
            // the sensor saturates at its measuring range
            a = a.min(k.range[i]).max(-k.range[i]);
            self.converter_input[i] = a;
            frame.counts[i] = self.convert(k.offset[i] + a * k.gain[i], k.max_count);
        }
        for j in 0..PRESSURE_CHANNELS {
            let mut p = self.pressure[j];
            if self.pressure_sigma > T::zero() {
                p += self.pressure_sigma * self.rng.unit_noise::<T>();
            }
            let c = ACCEL_CHANNELS + j;
            frame.counts[c] = self.convert(k.offset[c] + p * k.gain[c], k.max_count);
        }
        frame
    }

    /// The frame count of a channel whose pin holds `c` counts: `oversample` conversions, each
    /// with the converter's noise and rounded, summed (one plain rounding without either).
    #[inline(always)]
    fn convert(&mut self, c: T, max: T) -> u16 {
        if self.oversample <= 1 && !(self.adc_sigma > T::zero()) {
            return Self::count(c, max);
        }
        let mut sum = 0u32;
        for _ in 0..self.oversample.max(1) {
            let ci = if self.adc_sigma > T::zero() { c + self.adc_sigma * self.rng.unit_noise::<T>() } else { c };
            sum += Self::count(ci, max) as u32;
        }
        sum.min(u16::MAX as u32) as u16
    }

    /// Nearest count (half up), clamped to [0, max].
    #[inline(always)]
    fn count(c: T, max: T) -> u16 {
        let c = c.min(max);
        if !(c > T::zero()) {
            return 0;
        }
        (c + T::from_f64(0.5)).to_f64() as u16
    }
}
