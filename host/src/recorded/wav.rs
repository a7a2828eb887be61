//! WAV recordings (RIFF/WAVE as many data acquisition systems and recorders write them), read
//! by this module's own RIFF reader: integer PCM in containers of 1 to 4 bytes and 32- or 64-bit float,
//! plain (`WAVE_FORMAT_PCM`, `WAVE_FORMAT_IEEE_FLOAT`) or `WAVE_FORMAT_EXTENSIBLE`, any number
//! of channels, streamed one frame at a time.
//!
//! A WAV file holds no units and no channel names: each channel used is mapped with
//! `--channel KEY=#N*SCALE` (N from 1). Integer samples are read as fractions of full scale
//! (sample / 2^(container bits - 1), -1 to 1; 8-bit samples are unsigned, offset 128), so SCALE
//! is the acceleration at full scale [m/s^2]; float samples are read as written, and SCALE
//! multiplies them. A float file without SCALE is taken to be in m/s^2 (the report says so);
//! an integer file without SCALE is refused. Time: sample i (from 0) at i / rate.
//!
//! **Containers.** A sample takes block_align / channels bytes (its container), and is decoded
//! by that size: the valid bits (`wBitsPerSample` of a plain header, `wValidBitsPerSample` of an
//! extensible one) are its most significant bits (left-justified, as the format specifies), so
//! 24 valid bits in a 32-bit container, 20 in 24 or 12 in 16 read as the container's fraction of
//! full scale. Valid bits above the container's are refused.
//!
//! **Chunks.** RIFF chunks are word-aligned: a chunk of odd size is followed by one pad byte,
//! which is skipped. Chunks other than `fmt ` and `data` are skipped; the samples end at the
//! `data` chunk's declared size, which must be a whole number of frames.
//!
//! **Full scale.** An integer sample at the extreme codes of its valid bits (the largest, or
//! either of the two most negative: -32768 or -32767 and 32767 for 16 bits; a symmetric writer
//! clips at +-32767) is at the format's full scale, and is marked in [`Row::full_scale`]: the
//! analysis calls the channel clipped from [`FULL_SCALE_MIN_SAMPLES`] such samples on.

use std::io::{BufReader, Read};

use super::channels::{key_name, ChannelMap, ChannelSource};
use super::csv_in::{Row, PLAUSIBLE_ACCEL_M_S2};
use crate::error::{HostError, Result};

/// Samples of a channel at its integer format's extreme codes from which the channel is
/// called clipped (saturated). One is not enough: a recording normalised to full scale (its
/// largest sample made the largest code) holds one legitimately; a clipped waveform stays at
/// the rail for several samples, and two extreme samples in one record are taken as clipping.
pub const FULL_SCALE_MIN_SAMPLES: u64 = 2;

/// The standard GUID's last 14 bytes (`xxxxxxxx-0000-0010-8000-00aa00389b71`) of an extensible
/// header's subformat; its first two bytes are the format code.
const SUBFORMAT_TAIL: [u8; 14] = [0x00, 0x00, 0x00, 0x00, 0x10, 0x00, 0x80, 0x00, 0x00, 0xaa, 0x00, 0x38, 0x9b, 0x71];

/// How a sample is stored.
#[derive(Clone, Copy, Debug)]
enum Coding {
    /// Integer PCM: container bytes (1: unsigned, offset 128), valid bits (the most
    /// significant of the container's).
    Int { bytes: usize, valid: u32 },
    /// 32-bit IEEE float.
    Float,
    /// 64-bit IEEE float.
    Float64,
}

/// The rows of a WAV file.
pub struct WavRows<R: Read> {
    label: String,
    input: BufReader<R>,
    coding: Coding,
    channels: usize,
    /// Bytes per channel sample and per frame.
    container: usize,
    block: Vec<u8>,
    /// Frames the data chunk declares.
    frames: u64,
    /// Per key: (channel index from 0, scale).
    map: [Option<(usize, f64)>; 4],
    i: u64,
    rate: f64,
    /// What the integer format's full scale is, in words (`None` for float).
    pub full_scale: Option<String>,
    pub notes: Vec<String>,
}

fn u16_at(b: &[u8], i: usize) -> u16 {
    u16::from_le_bytes([b[i], b[i + 1]])
}

fn u32_at(b: &[u8], i: usize) -> u32 {
    u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]])
}

/// Reads exactly `buf.len()` bytes; `Ok(false)` at the end of the input before the first byte
/// or within them.
fn read_full<R: Read>(r: &mut R, buf: &mut [u8]) -> std::io::Result<bool> {
    match r.read_exact(buf) {
        Ok(()) => Ok(true),
        Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => Ok(false),
        Err(e) => Err(e),
    }
}

impl<R: Read> WavRows<R> {
    pub fn open(label: &str, input: R, map: &ChannelMap) -> Result<Self> {
        let bad = |m: String| HostError::Input(format!("{label}: {m}"));
        let io = |e: std::io::Error| HostError::Input(format!("{label}: cannot read: {e}"));
        let mut input = BufReader::new(input);
        let mut head = [0u8; 12];
        if !read_full(&mut input, &mut head).map_err(io)? || &head[..4] != b"RIFF" || &head[8..12] != b"WAVE" {
            return Err(bad("not a readable WAV file: no RIFF/WAVE header".into()));
        }
        // the chunks up to `data`
        let mut fmt: Option<Vec<u8>> = None;
        let mut offset = 12u64;
        let data_len = loop {
            let mut ch = [0u8; 8];
            if !read_full(&mut input, &mut ch).map_err(io)? {
                let what = if fmt.is_none() { "fmt " } else { "data" };
                return Err(bad(format!("not a readable WAV file: the file ends at byte {offset} without a `{what}` chunk")));
            }
            let id = String::from_utf8_lossy(&ch[..4]).into_owned();
            let size = u32_at(&ch, 4) as u64;
            if &ch[..4] == b"data" {
                if fmt.is_none() {
                    return Err(bad(format!("not a readable WAV file: the `data` chunk at byte {offset} comes before a `fmt ` chunk")));
                }
                break size;
            }
            // a chunk of odd size is followed by one pad byte (RIFF chunks are word-aligned)
            let padded = size + (size & 1);
            if &ch[..4] == b"fmt " {
                if !(16..=1024).contains(&size) {
                    return Err(bad(format!("not a readable WAV file: the `fmt ` chunk at byte {offset} has {size} bytes (16 to 1024 expected)")));
                }
                let mut b = vec![0u8; padded as usize];
                if !read_full(&mut input, &mut b).map_err(io)? {
                    return Err(bad(format!("not a readable WAV file: the file ends within the `fmt ` chunk at byte {offset}")));
                }
                b.truncate(size as usize);
                fmt = Some(b);
            } else {
                let skipped = std::io::copy(&mut (&mut input).take(padded), &mut std::io::sink()).map_err(io)?;
                if skipped < padded {
                    return Err(bad(format!("not a readable WAV file: the file ends within the `{id}` chunk at byte {offset} ({size} bytes declared)")));
                }
            }
            offset += 8 + padded;
        };
        let f = fmt.unwrap_or_default();
        let (mut tag, channels, rate, block_align, bits) = (u16_at(&f, 0), u16_at(&f, 2) as usize, u32_at(&f, 4), u16_at(&f, 12) as usize, u16_at(&f, 14) as u32);
        let mut valid = bits;
        if tag == 0xFFFE {
            if f.len() < 40 || u16_at(&f, 16) < 22 {
                return Err(bad(format!("not a readable WAV file: WAVE_FORMAT_EXTENSIBLE with a {}-byte `fmt ` chunk (40 needed)", f.len())));
            }
            if f[26..40] != SUBFORMAT_TAIL {
                return Err(bad("WAVE_FORMAT_EXTENSIBLE with a subformat GUID that is not PCM or IEEE float: not read".into()));
            }
            tag = u16_at(&f, 24);
            let v = u16_at(&f, 18) as u32;
            // 0: not given (the container's bits are valid)
            if v != 0 {
                if v > bits {
                    return Err(bad(format!("WAVE_FORMAT_EXTENSIBLE: {v} valid bits per sample in {bits}-bit samples: more valid bits than the sample holds")));
                }
                valid = v;
            }
        }
        if channels == 0 || rate == 0 {
            return Err(bad(format!("{channels} channels at {rate} Hz: nothing to read")));
        }
        if block_align == 0 || block_align % channels != 0 {
            return Err(bad(format!("block align {block_align} bytes for {channels} channels: not a whole number of bytes per sample")));
        }
        let container = block_align / channels;
        let coding = match tag {
            1 => {
                if !(1..=4).contains(&container) || !(2..=8 * container as u32).contains(&valid) || bits > 8 * container as u32 {
                    return Err(bad(format!(
                        "integer PCM of {valid} bits in {container}-byte samples (block align {block_align}, {channels} channels): only 2 to 32 bits in 1 to 4 bytes are read"
                    )));
                }
                Coding::Int { bytes: container, valid }
            }
            3 => {
                match (container, bits) {
                    (4, 32) => Coding::Float,
                    (8, 64) => Coding::Float64,
                    _ => {
                        return Err(bad(format!(
                            "{bits}-bit float in {container}-byte samples: only 32- or 64-bit float or 8- to 32-bit integer samples are read"
                        )))
                    }
                }
            }
            t => return Err(bad(format!("format code {t:#06x}: only integer PCM (1) and IEEE float (3) are read"))),
        };
        let int = matches!(coding, Coding::Int { .. });
        let what = match coding {
            Coding::Int { bytes, valid } if valid == 8 * bytes as u32 => format!("{valid}-bit integer PCM"),
            Coding::Int { bytes, valid } => format!("{valid}-bit integer PCM in {}-bit samples", 8 * bytes),
            Coding::Float => "32-bit float".to_string(),
            Coding::Float64 => "64-bit float".to_string(),
        };
        if data_len % block_align as u64 != 0 {
            return Err(bad(format!(
                "not a readable WAV file: the `data` chunk declares {data_len} bytes, not a whole number of {block_align}-byte frames"
            )));
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
        let full_scale = int.then(|| {
            let top = (1i64 << (valid - 1)) - 1;
            if valid == 8 * container as u32 && container == 1 {
                format!("{what}: codes 0, 1 and 255 (unsigned)")
            } else {
                format!("{what}: codes -{}, -{top} and {top}", top + 1)
            }
        });
        Ok(WavRows {
            label: label.to_string(),
            input,
            coding,
            channels,
            container,
            block: vec![0; block_align],
            frames: data_len / block_align as u64,
            map: m,
            i: 0,
            rate: rate as f64,
            full_scale,
            notes,
        })
    }

    pub fn present(&self) -> [bool; 4] {
        self.map.map(|m| m.is_some())
    }

    /// Channel `ch`'s sample of the frame read: its value (a fraction of full scale for an
    /// integer format) and whether it is at the format's extreme codes.
    fn sample(&self, ch: usize) -> (f64, bool) {
        let b = &self.block[ch * self.container..(ch + 1) * self.container];
        match self.coding {
            Coding::Float => (f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64, false),
            Coding::Float64 => (f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]), false),
            Coding::Int { bytes, valid } => {
                // the container's bits, sign-extended (8 bits: unsigned, offset 128)
                let raw: i64 = if bytes == 1 {
                    b[0] as i64 - 128
                } else {
                    let mut v = 0i64;
                    for (k, &x) in b.iter().enumerate() {
                        v |= (x as i64) << (8 * k);
                    }
                    let sh = 64 - 8 * bytes as u32;
                    (v << sh) >> sh
                };
                let cbits = 8 * bytes as u32;
                let code = raw >> (cbits - valid);
                let top = (1i64 << (valid - 1)) - 1;
                (raw as f64 / (1i64 << (cbits - 1)) as f64, code >= top || code <= -top)
            }
        }
    }

    /// The next frame as a row (its `line` is the frame's number, from 1).
    pub fn next_row(&mut self) -> Result<Option<Row>> {
        if self.i >= self.frames {
            return Ok(None);
        }
        let mut got = 0;
        while got < self.block.len() {
            match self.input.read(&mut self.block[got..]) {
                Ok(0) => break,
                Ok(n) => got += n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(HostError::Input(format!("{}: sample {}: cannot read: {e}", self.label, self.i + 1))),
            }
        }
        if got < self.block.len() {
            let within = if got == 0 { String::new() } else { format!(", within a frame (channel {} of {})", got / self.container + 1, self.channels) };
            return Err(HostError::Input(format!(
                "{}: sample {}: the file ends before the `data` chunk's {} frames{within}",
                self.label,
                self.i + 1,
                self.frames
            )));
        }
        let mut accel = [0.0; 4];
        let mut full_scale = 0u8;
        for (c, m) in self.map.iter().enumerate() {
            if let Some((ch, scale)) = m {
                let (s, at_full_scale) = self.sample(*ch);
                let v = s * scale;
                if !(v.abs() <= PLAUSIBLE_ACCEL_M_S2) {
                    return Err(HostError::Input(format!(
                        "{}: sample {}, channel {}: {v:.4e} m/s^2 is not a finite acceleration within +-{PLAUSIBLE_ACCEL_M_S2:e} m/s^2",
                        self.label,
                        self.i + 1,
                        ch + 1
                    )));
                }
                accel[c] = v;
                if at_full_scale {
                    full_scale |= 1 << c;
                }
            }
        }
        let t = self.i as f64 / self.rate;
        self.i += 1;
        Ok(Some(Row { line: self.i, t, t_resolution: 0.0, accel, full_scale }))
    }
}
