//! WAV recordings (RIFF/WAVE as many data acquisition systems and recorders write them), read
//! with the `hound` crate: integer PCM of 8 to 32 bits and 32-bit float, any number of
//! channels, streamed one frame at a time.
//!
//! A WAV file holds no units and no channel names: each channel used is mapped with
//! `--channel KEY=#N*SCALE` (N from 1). Integer samples are read as fractions of full scale
//! (sample / 2^(bits - 1), -1 to 1), so SCALE is the acceleration at full scale [m/s^2];
//! float samples are read as written, and SCALE multiplies them. A float file without SCALE is
//! taken to be in m/s^2 (the report says so); an integer file without SCALE is refused.
//! Time: sample i (from 0) at i / rate.

use std::io::Read;

use super::channels::{key_name, ChannelMap, ChannelSource};
use super::csv_in::{Row, PLAUSIBLE_ACCEL_M_S2};
use crate::error::{HostError, Result};

enum Samples<R: Read> {
    Int(hound::WavIntoSamples<R, i32>, f64),
    Float(hound::WavIntoSamples<R, f32>),
}

/// The rows of a WAV file.
pub struct WavRows<R: Read> {
    label: String,
    samples: Samples<R>,
    channels: usize,
    /// Per key: (channel index from 0, scale).
    map: [Option<(usize, f64)>; 4],
    frame: Vec<f64>,
    i: u64,
    rate: f64,
    pub notes: Vec<String>,
}

impl<R: Read> WavRows<R> {
    pub fn open(label: &str, input: R, map: &ChannelMap) -> Result<Self> {
        let bad = |m: String| HostError::Input(format!("{label}: {m}"));
        let rd = hound::WavReader::new(input).map_err(|e| bad(format!("not a readable WAV file: {e}")))?;
        let spec = rd.spec();
        let channels = spec.channels as usize;
        let int = spec.sample_format == hound::SampleFormat::Int;
        let what = if int { format!("{}-bit integer PCM", spec.bits_per_sample) } else { format!("{}-bit float", spec.bits_per_sample) };
        if !int && spec.bits_per_sample != 32 {
            return Err(bad(format!("{what}: only 32-bit float or 8- to 32-bit integer samples are read")));
        }
        if channels == 0 || spec.sample_rate == 0 {
            return Err(bad(format!("{channels} channels at {} Hz: nothing to read", spec.sample_rate)));
        }
        let mut m: [Option<(usize, f64)>; 4] = [None; 4];
        let mut notes = Vec::new();
        for sp in &map.specs {
            let n = match &sp.source {
                ChannelSource::Index(n) => *n,
                ChannelSource::Name(_) => {
                    return Err(bad(format!("--channel {}: a WAV file's channels have no names: map them by number, #N (1 to {channels})", sp.arg)))
                }
            };
            if n > channels {
                return Err(bad(format!("--channel {}: the file has {channels} channel{}", sp.arg, if channels == 1 { "" } else { "s" })));
            }
            let scale = match sp.scale {
                Some(s) => s,
                None if int => {
                    return Err(bad(format!(
                        "--channel {}: the file is {what}, which holds no units: give the acceleration at full scale, --channel {}=#{n}*SCALE (m/s^2; only a float WAV in m/s^2 needs none)",
                        sp.arg,
                        key_name(sp.key)
                    )))
                }
                None => {
                    notes.push(format!("{} (#{n}): float samples without SCALE, taken as m/s^2", key_name(sp.key)));
                    1.0
                }
            };
            m[sp.key] = Some((n - 1, scale));
        }
        if m[1].is_none() {
            return Err(super::channels::pad_x_needed(
                label,
                &format!("{what}, {channels} channels, no names"),
                "map pad_x by number, e.g. --channel pad_x=#1*SCALE",
            ));
        }
        let rate = spec.sample_rate as f64;
        let samples = if int {
            Samples::Int(rd.into_samples::<i32>(), (2f64).powi(spec.bits_per_sample as i32 - 1))
        } else {
            Samples::Float(rd.into_samples::<f32>())
        };
        Ok(WavRows { label: label.to_string(), samples, channels, map: m, frame: vec![0.0; channels], i: 0, rate, notes })
    }

    pub fn present(&self) -> [bool; 4] {
        self.map.map(|m| m.is_some())
    }

    /// The next frame as a row (its `line` is the frame's number, from 1).
    pub fn next_row(&mut self) -> Result<Option<Row>> {
        for k in 0..self.channels {
            let v = match &mut self.samples {
                Samples::Int(it, full) => it.next().map(|r| r.map(|v| v as f64 / *full)),
                Samples::Float(it) => it.next().map(|r| r.map(|v| v as f64)),
            };
            match v {
                None if k == 0 => return Ok(None),
                None => {
                    return Err(HostError::Input(format!(
                        "{}: sample {}: the data end within a frame (channel {} of {})",
                        self.label,
                        self.i + 1,
                        k + 1,
                        self.channels
                    )))
                }
                Some(Err(e)) => return Err(HostError::Input(format!("{}: sample {}: cannot read: {e}", self.label, self.i + 1))),
                Some(Ok(v)) => self.frame[k] = v,
            }
        }
        let mut accel = [0.0; 4];
        for (c, m) in self.map.iter().enumerate() {
            if let Some((ch, scale)) = m {
                let v = self.frame[*ch] * scale;
                if !(v.abs() <= PLAUSIBLE_ACCEL_M_S2) {
                    return Err(HostError::Input(format!(
                        "{}: sample {}, channel {}: {v:.4e} m/s^2 is not a finite acceleration within +-{PLAUSIBLE_ACCEL_M_S2:e} m/s^2",
                        self.label,
                        self.i + 1,
                        ch + 1
                    )));
                }
                accel[c] = v;
            }
        }
        let t = self.i as f64 / self.rate;
        self.i += 1;
        Ok(Some(Row { line: self.i, t, t_resolution: 0.0, accel }))
    }
}
