//! A small seeded pseudo-random generator for deterministic measurement noise.
//!
//! Marsaglia's xorshift32 (shifts 13, 17, 5; period 2^32 - 1): integer operations only, so
//! the same seed gives the same sequence on every platform. Not for cryptography, and not a
//! high-quality generator: it only has to make repeatable, roughly white noise.
//!
//! [`XorShift32::unit_noise`] is the Irwin-Hall sum of four uniforms, centred and scaled to unit
//! variance: bell-shaped, bounded to +-2 sqrt(3) = +-3.46 (so a test can state a hard bound on
//! the noise it added), computed in integers and rounded once.

use crate::real::Real;

/// The bound of [`XorShift32::unit_noise`]: |noise| <= 2 sqrt(3).
pub const UNIT_NOISE_BOUND: f64 = 3.464_101_615_137_754_6;

/// The xorshift32 generator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct XorShift32 {
    state: u32,
}

impl XorShift32 {
    /// A generator from `seed`; seed 0 (a fixed point of xorshift) is replaced by 0x9E3779B9.
    pub const fn new(seed: u32) -> Self {
        XorShift32 { state: if seed == 0 { 0x9E37_79B9 } else { seed } }
    }

    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let mut x = self.state;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.state = x;
        x
    }

    /// Zero-mean, unit-variance noise bounded by [`UNIT_NOISE_BOUND`]: the sum of four 23-bit
    /// uniforms minus its mean (an integer with |i| <= 2^24, exact in f32), times sqrt(3) 2^-23.
    /// (Each uniform has variance 1/12 in units of 2^23; four have 1/3.)
    #[inline]
    pub fn unit_noise<T: Real>(&mut self) -> T {
        let mut sum: i32 = 0;
        for _ in 0..4 {
            sum += (self.next_u32() >> 9) as i32;
        }
        let centred = sum - (1 << 24) + 2; // mean of four uniforms on 0..=2^23-1 is 2 (2^23 - 1)
        T::from_f64(centred as f64) * T::from_f64(1.732_050_807_568_877_2 / 8_388_608.0)
    }
}
