//! The noise floor: each accelerometer's bias and noise, and those of the relative
//! acceleration the contact decision uses, measured while nothing moves (the sequencer's
//! clamped, band-still phase, or a quiet stretch of a recording).
//!
//! Per sample only additions and multiplications (f32): each value is taken relative to the
//! first sample (so the squares do not cancel a large offset), and the sums are folded every
//! 256 samples as in [`super::window`]. [`NoiseFloor::report`] takes the divisions and square
//! roots, once.
//!
//! From the report, [`super::contact::ContactThresholds::from_noise_floor`] designs the
//! contact thresholds (onset 6 sigma of a_rel, at least 2 quanta) and the bias of a_rel starts
//! the contact estimator's bias tracker. A channel whose floor has no spread at all (max =
//! min) is *flat*: dead, or quieter than one count of its converter; which one, only a moving
//! signal can tell (the window's peak-to-peak).

use super::ACCEL_CHANNELS;

/// Values per sample: the four accelerometers, then a_rel.
pub const FLOOR_VALUES: usize = ACCEL_CHANNELS + 1;
/// Index of a_rel in a [`FloorReport`].
pub const A_REL: usize = ACCEL_CHANNELS;
/// The fewest samples a floor is designed from (10 ms at 25.6 kHz).
pub const MIN_FLOOR_SAMPLES: u32 = 256;
const BLOCK: u32 = 256;

/// The floor of each value: the four accelerometers and a_rel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FloorReport {
    pub samples: u32,
    /// Mean [m/s^2] (a bias: the accelerometers are AC-coupled, so ideally 0).
    pub mean_m_s2: [f32; FLOOR_VALUES],
    /// Standard deviation about the mean [m/s^2].
    pub sigma_m_s2: [f32; FLOOR_VALUES],
    /// max - min [m/s^2]; 0: flat.
    pub pp_m_s2: [f32; FLOOR_VALUES],
}

/// Accumulates a noise floor (see the module documentation).
#[derive(Clone, Copy, Debug)]
pub struct NoiseFloor {
    n: u32,
    first: [f32; FLOOR_VALUES],
    block: [[f32; FLOOR_VALUES]; 2],
    total: [[f32; FLOOR_VALUES]; 2],
    block_n: u32,
    min: [f32; FLOOR_VALUES],
    max: [f32; FLOOR_VALUES],
}

impl Default for NoiseFloor {
    fn default() -> Self {
        Self::new()
    }
}

impl NoiseFloor {
    pub const fn new() -> Self {
        NoiseFloor {
            n: 0,
            first: [0.0; FLOOR_VALUES],
            block: [[0.0; FLOOR_VALUES]; 2],
            total: [[0.0; FLOOR_VALUES]; 2],
            block_n: 0,
            min: [f32::INFINITY; FLOOR_VALUES],
            max: [f32::NEG_INFINITY; FLOOR_VALUES],
        }
    }

    /// Samples so far.
    pub fn samples(&self) -> u32 {
        self.n
    }

    /// One sample: the four accelerations and a_rel [m/s^2] (finite: the caller checks).
    /// Never inlined: it runs only in the clamped phase, and inlined into the per-sample path
    /// it would be a second copy of its code in flash (the builds' sizes:
    /// `scripts/build-firmware.sh`).
    #[inline(never)]
    #[allow(clippy::needless_range_loop)] // parallel per-value arrays
    pub fn add(&mut self, accel_m_s2: &[f32; ACCEL_CHANNELS], a_rel_m_s2: f32) {
        let v = [accel_m_s2[0], accel_m_s2[1], accel_m_s2[2], accel_m_s2[3], a_rel_m_s2];
        if self.n == 0 {
            self.first = v;
        }
        for k in 0..FLOOR_VALUES {
            let d = v[k] - self.first[k];
            self.block[0][k] += d;
            self.block[1][k] += d * d;
            if v[k] < self.min[k] {
                self.min[k] = v[k];
            }
            if v[k] > self.max[k] {
                self.max[k] = v[k];
            }
        }
        self.n = self.n.saturating_add(1);
        self.block_n += 1;
        if self.block_n >= BLOCK {
            self.fold();
        }
    }

    fn fold(&mut self) {
        for j in 0..2 {
            for k in 0..FLOOR_VALUES {
                self.total[j][k] += self.block[j][k];
                self.block[j][k] = 0.0;
            }
        }
        self.block_n = 0;
    }

    /// The floor so far (zeros without samples).
    pub fn report(&self) -> FloorReport {
        let mut c = *self;
        c.fold();
        let mut r = FloorReport { samples: c.n, ..FloorReport::default() };
        if c.n == 0 {
            return r;
        }
        let n = c.n as f32;
        for k in 0..FLOOR_VALUES {
            let m = c.total[0][k] / n;
            let var = (c.total[1][k] / n - m * m).max(0.0);
            r.mean_m_s2[k] = c.first[k] + m;
            r.sigma_m_s2[k] = libm::sqrtf(var);
            r.pp_m_s2[k] = c.max[k] - c.min[k];
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_sigma_and_flat_against_a_two_pass_computation() {
        let mut f = NoiseFloor::new();
        let mut xs = [[0.0f64; FLOOR_VALUES]; 1000];
        for (i, x) in xs.iter_mut().enumerate() {
            // an offset, a deterministic +-1 pattern of 0.01, one flat channel
            let e = if (i * 7919) % 13 < 6 { 0.01 } else { -0.012 };
            *x = [100.0 + e, e * 2.0, 0.0, -3.0 + e, e];
            f.add(&[x[0] as f32, x[1] as f32, x[2] as f32, x[3] as f32], x[4] as f32);
        }
        let r = f.report();
        assert_eq!(r.samples, 1000);
        for k in 0..FLOOR_VALUES {
            let m = xs.iter().map(|x| x[k]).sum::<f64>() / 1000.0;
            let s = (xs.iter().map(|x| (x[k] - m).powi(2)).sum::<f64>() / 1000.0).sqrt();
            assert!((r.mean_m_s2[k] as f64 - m).abs() < 1e-5 * m.abs().max(1.0), "mean {k}: {} vs {m}", r.mean_m_s2[k]);
            assert!((r.sigma_m_s2[k] as f64 - s).abs() < 1e-3 * s.max(1e-3), "sigma {k}: {} vs {s}", r.sigma_m_s2[k]);
        }
        assert!(r.pp_m_s2[2] == 0.0 && r.pp_m_s2[0] > 0.0 && r.pp_m_s2[4] > 0.0, "flat: pad_trail only");
    }
}
