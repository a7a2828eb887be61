//! The per-step time series of a run and where it goes: a CSV file (`simulate --csv`) or
//! memory (the figures of `cases --plots`).

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use stickslip_model::rig::bandpass::{BandPass, CascadeState, GROAN_SECTIONS};
use stickslip_model::Regime;

use crate::error::{HostError, Result};

/// The state at the end of one step (SI units).
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    /// Time [s].
    pub t: f64,
    /// x [m], x' [m/s], phi [rad], phi' [rad/s].
    pub z: [f64; 4],
    /// Normal contact force N [N] (NaN unless the sink [`Sink::wants_forces`]).
    pub n: f64,
    /// Friction force on the pad F_f [N] (along +x, the band's direction; NaN unless the sink
    /// [`Sink::wants_forces`]).
    pub f_f: f64,
    /// Pad acceleration x'' [m/s^2] (the rig's pad_x); NaN unless the sink
    /// [`Sink::wants_kinematics`].
    pub pad_acc: f64,
    /// Sliding velocity of the friction contact against the band [m/s] (x' - V for the
    /// thesis model; 0 in stick); NaN unless the sink [`Sink::wants_kinematics`].
    pub v_slide: f64,
    pub regime: Regime,
}

/// Receives the state after every completed step of a run.
pub trait Sink {
    fn sample(&mut self, s: &Sample) -> Result<()>;
    /// Whether the sink reads the forces n and f_f (false: the run leaves them NaN and saves
    /// their cost).
    fn wants_forces(&self) -> bool {
        true
    }
    /// Whether the sink reads pad_acc and v_slide (false, the default: the run leaves them
    /// NaN and saves their cost).
    fn wants_kinematics(&self) -> bool {
        false
    }
    /// The first time [s] whose sample the sink reads: the run builds no sample (and computes
    /// none of its forces and kinematics) at a step end t below it. The default: every sample.
    fn samples_from(&self) -> f64 {
        f64::NEG_INFINITY
    }
    /// Whether the sink takes the steps of a stick phase as one run ([`Sink::stick_samples`])
    /// instead of one sample each: a thesis-model run of [`crate::scenes::run::Detail::Events`]
    /// then jumps over stick at event speed ([`stickslip_model::ExactTables::jump_stick`]).
    /// The default: no, every step is sampled.
    fn takes_stick_runs(&self) -> bool {
        false
    }
    /// The samples at the ends of steps `first_step .. first_step + n` (times k dt [s], k the
    /// step's number, as the run forms them), all in stick: the pad moves with the band, so
    /// x'' = 0 and the sliding velocity is 0; the state between is not given. Called only
    /// when [`Sink::takes_stick_runs`] says yes, for every step the run jumped, whatever
    /// [`Sink::samples_from`] says.
    fn stick_samples(&mut self, _first_step: u64, _n: u64, _dt: f64) -> Result<()> {
        Ok(())
    }
    /// The sample at the end of a quiet step (one without a transition) of a run that takes
    /// stick runs ([`Sink::takes_stick_runs`]): the step's number `k` (it ends at k dt [s], at
    /// or after [`Sink::samples_from`]), the pad's x'' [m/s^2], the sliding velocity [m/s] and
    /// the regime; the state itself is not given. Such runs hand every step without a
    /// transition here instead of to [`Sink::sample`]; the default forwards it there with the
    /// state and forces NaN.
    #[inline]
    fn quiet_sample(&mut self, k: u64, dt: f64, pad_acc: f64, v_slide: f64, regime: Regime) -> Result<()> {
        self.sample(&Sample { t: k as f64 * dt, z: [f64::NAN; 4], n: f64::NAN, f_f: f64::NAN, pad_acc, v_slide, regime })
    }
    /// The window statistics of quiet samples, handed to the run by value for a stretch of
    /// quiet steps (kept in registers there) and back with [`Sink::put_window`]; `None` (the
    /// default): the run hands each quiet sample to [`Sink::quiet_sample`].
    fn take_window(&mut self) -> Option<QuietWindow> {
        None
    }
    /// The window statistics [`Sink::take_window`] handed out, with the quiet samples since.
    fn put_window(&mut self, _w: QuietWindow) {}
    /// The state at a transition inside a step, one side of it (`regime`: the regime left,
    /// then the one entered; x'' jumps there), for a sink that keeps extremes of the
    /// continuous motion: not a sample of the step grid (no filter takes it). Called only
    /// where the sink [`Sink::wants_kinematics`], for transitions at or after
    /// [`Sink::samples_from`]. The default ignores it.
    fn between(&mut self, _s: &Sample) -> Result<()> {
        Ok(())
    }
}

/// A map cell's window statistics of the pad's x'' and the sliding velocity: the groan
/// band-pass (f32; `None` where it cannot be designed at the run's rate) from step `filter_k`
/// on, and from step `window_k` on the extremes, the band's sum of squares and the count. A
/// quiet stretch of a run takes them by value ([`Sink::take_window`]).
#[derive(Clone, Copy, Debug)]
pub struct QuietWindow {
    pub groan: Option<BandPass<GROAN_SECTIONS>>,
    pub groan_state: CascadeState<GROAN_SECTIONS>,
    pub filter_k: u64,
    pub window_k: u64,
    /// (min, max) of x'' [m/s^2] and of the sliding velocity [m/s].
    pub acc: (f64, f64),
    pub v: (f64, f64),
    pub groan_sq: f64,
    pub n: u64,
}

impl QuietWindow {
    /// The sample at the end of step `k`.
    #[inline(always)]
    pub fn take(&mut self, k: u64, pad_acc: f64, v_slide: f64) {
        if k >= self.filter_k {
            self.sample(pad_acc, v_slide, k >= self.window_k);
        }
    }

    /// A sample through the groan filter, and into the window's statistics if `in_window`
    /// (and both values finite).
    #[inline(always)]
    pub fn sample(&mut self, pad_acc: f64, v_slide: f64, in_window: bool) {
        let g = match &self.groan {
            Some(bp) => bp.run(&mut self.groan_state, pad_acc as f32) as f64,
            None => 0.0,
        };
        if in_window && pad_acc.is_finite() && v_slide.is_finite() {
            // (both finite: plain comparisons are the extremes)
            if pad_acc < self.acc.0 {
                self.acc.0 = pad_acc;
            }
            if pad_acc > self.acc.1 {
                self.acc.1 = pad_acc;
            }
            if v_slide < self.v.0 {
                self.v.0 = v_slide;
            }
            if v_slide > self.v.1 {
                self.v.1 = v_slide;
            }
            self.groan_sq += g * g;
            self.n += 1;
        }
    }
}

/// Takes nothing.
pub struct NoSink;

impl Sink for NoSink {
    fn sample(&mut self, _s: &Sample) -> Result<()> {
        Ok(())
    }
    fn wants_forces(&self) -> bool {
        false
    }
    fn samples_from(&self) -> f64 {
        f64::INFINITY
    }
}

/// The CSV header: one column per quantity, unit in the name.
pub const CSV_HEADER: [&str; 8] = [
    "t_s",
    "x_m",
    "xdot_m_per_s",
    "phi_rad",
    "phidot_rad_per_s",
    "n_N",
    "f_f_N",
    "regime",
];

/// Writes one row per step. In f32 runs the state is written with f32's shortest digits.
pub struct CsvSink {
    path: PathBuf,
    writer: csv::Writer<BufWriter<File>>,
    f32_values: bool,
}

impl CsvSink {
    pub fn create(path: &Path, f32_values: bool) -> Result<Self> {
        let file = File::create(path).map_err(|e| {
            HostError::Output(format!(
                "{}: cannot create the CSV file: {e}",
                path.display()
            ))
        })?;
        let mut writer = csv::WriterBuilder::new()
            .has_headers(false)
            .from_writer(BufWriter::new(file));
        writer.write_record(CSV_HEADER).map_err(|e| {
            HostError::Output(format!(
                "{}: cannot write the CSV file: {e}",
                path.display()
            ))
        })?;
        Ok(CsvSink {
            path: path.to_path_buf(),
            writer,
            f32_values,
        })
    }

    fn err(&self, e: impl std::fmt::Display) -> HostError {
        HostError::Output(format!(
            "{}: cannot write the CSV file: {e}",
            self.path.display()
        ))
    }

    /// Flushes the file; call once after the run.
    pub fn finish(mut self) -> Result<()> {
        self.writer.flush().map_err(|e| self.err(e))
    }
}

impl Sink for CsvSink {
    fn sample(&mut self, s: &Sample) -> Result<()> {
        let r = s.regime.name();
        let res = if self.f32_values {
            let f = |v: f64| v as f32;
            self.writer.serialize((
                s.t,
                f(s.z[0]),
                f(s.z[1]),
                f(s.z[2]),
                f(s.z[3]),
                f(s.n),
                f(s.f_f),
                r,
            ))
        } else {
            self.writer
                .serialize((s.t, s.z[0], s.z[1], s.z[2], s.z[3], s.n, s.f_f, r))
        };
        res.map_err(|e| self.err(e))
    }
}

/// Keeps the samples with t in [from, to] [s] (for the figures).
pub struct Recorder {
    pub from: f64,
    pub to: f64,
    pub samples: Vec<(f64, [f64; 4])>,
}

impl Recorder {
    pub fn new(from: f64, to: f64) -> Self {
        Recorder {
            from,
            to,
            samples: Vec::new(),
        }
    }
}

impl Sink for Recorder {
    fn sample(&mut self, s: &Sample) -> Result<()> {
        // A little slack: the window ends are usually step boundaries.
        if s.t >= self.from - 1e-12 && s.t <= self.to + 1e-12 {
            self.samples.push((s.t, s.z));
        }
        Ok(())
    }
}
