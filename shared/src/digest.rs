//! A 64-bit FNV-1a digest over the exact bit patterns of floating-point values and small tags,
//! for comparing two runs bit for bit (the same model on the desktop and on the Cortex-M4F,
//! or before and after a change that must not alter the arithmetic).
//!
//! What is hashed, byte by byte with FNV-1a (offset basis `0xcbf29ce484222325`, prime
//! `0x100000001b3`):
//!
//! - [`Fnv1a64::write_f32`]: the 4 bytes of `f32::to_bits`, little-endian;
//! - [`Fnv1a64::write_f64`]: the 8 bytes of `f64::to_bits`, little-endian;
//! - [`Fnv1a64::write_u8`]: the byte itself (use it for tags: regimes, record kinds);
//! - [`Fnv1a64::write_u32`] / [`Fnv1a64::write_u64`]: 4 / 8 bytes, little-endian.
//!
//! Bit patterns, not values: `0.0` and `-0.0` differ, and so do NaNs with different payloads.
//! The byte order is fixed, so the digest of the same values is the same on every platform.
//! FNV-1a is not cryptographic: it detects accidental differences, not forged ones.

/// FNV-1a 64-bit offset basis.
pub const FNV64_OFFSET_BASIS: u64 = 0xcbf2_9ce4_8422_2325;
/// FNV-1a 64-bit prime.
pub const FNV64_PRIME: u64 = 0x0000_0100_0000_01b3;

/// A running FNV-1a 64-bit digest.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fnv1a64 {
    state: u64,
}

impl Default for Fnv1a64 {
    fn default() -> Self {
        Self::new()
    }
}

impl Fnv1a64 {
    /// A digest of nothing (the offset basis).
    pub const fn new() -> Self {
        Fnv1a64 { state: FNV64_OFFSET_BASIS }
    }

    /// Feeds raw bytes.
    #[inline]
    pub fn write_bytes(&mut self, bytes: &[u8]) {
        let mut h = self.state;
        for &b in bytes {
            h ^= b as u64;
            h = h.wrapping_mul(FNV64_PRIME);
        }
        self.state = h;
    }

    /// Feeds one byte (a tag).
    #[inline]
    pub fn write_u8(&mut self, v: u8) {
        self.write_bytes(&[v]);
    }

    /// Feeds a `u32`, little-endian.
    #[inline]
    pub fn write_u32(&mut self, v: u32) {
        self.write_bytes(&v.to_le_bytes());
    }

    /// Feeds a `u64`, little-endian.
    #[inline]
    pub fn write_u64(&mut self, v: u64) {
        self.write_bytes(&v.to_le_bytes());
    }

    /// Feeds the bit pattern of an `f32` (4 bytes, little-endian).
    #[inline]
    pub fn write_f32(&mut self, v: f32) {
        self.write_u32(v.to_bits());
    }

    /// Feeds the bit pattern of an `f64` (8 bytes, little-endian).
    #[inline]
    pub fn write_f64(&mut self, v: f64) {
        self.write_u64(v.to_bits());
    }

    /// Feeds any value that knows its bit pattern ([`DigestBits`]).
    #[inline]
    pub fn write<V: DigestBits>(&mut self, v: V) {
        v.digest_into(self);
    }

    /// The digest of everything fed so far.
    pub const fn finish(&self) -> u64 {
        self.state
    }
}

/// Values with a defined byte representation for [`Fnv1a64`]: lets code generic over
/// [`crate::Real`] feed `T` values as their own type's bits (`T: Real + DigestBits`).
pub trait DigestBits: Copy {
    fn digest_into(self, d: &mut Fnv1a64);
}

impl DigestBits for f32 {
    #[inline]
    fn digest_into(self, d: &mut Fnv1a64) {
        d.write_f32(self);
    }
}

impl DigestBits for f64 {
    #[inline]
    fn digest_into(self, d: &mut Fnv1a64) {
        d.write_f64(self);
    }
}

impl DigestBits for u8 {
    #[inline]
    fn digest_into(self, d: &mut Fnv1a64) {
        d.write_u8(self);
    }
}

impl DigestBits for u32 {
    #[inline]
    fn digest_into(self, d: &mut Fnv1a64) {
        d.write_u32(self);
    }
}

impl DigestBits for u64 {
    #[inline]
    fn digest_into(self, d: &mut Fnv1a64) {
        d.write_u64(self);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn of(bytes: &[u8]) -> u64 {
        let mut d = Fnv1a64::new();
        d.write_bytes(bytes);
        d.finish()
    }

    /// Published FNV-1a 64-bit test vectors (the FNV reference test suite).
    #[test]
    fn reference_vectors() {
        assert_eq!(of(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(of(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(of(b"foobar"), 0x8594_4171_f739_67e8);
    }

    /// Floats are fed as their IEEE-754 bit patterns, little-endian (bytes written out by hand).
    #[test]
    fn floats_are_fed_as_little_endian_bits() {
        let mut d = Fnv1a64::new();
        d.write_f32(1.0); // 0x3f800000
        d.write_f64(-2.0); // 0xc000000000000000
        d.write_u8(7);
        let bytes = [0x00, 0x00, 0x80, 0x3f, 0, 0, 0, 0, 0, 0, 0x00, 0xc0, 7];
        assert_eq!(d.finish(), of(&bytes));
    }

    #[test]
    fn bit_patterns_not_values() {
        let mut a = Fnv1a64::new();
        a.write_f32(0.0);
        let mut b = Fnv1a64::new();
        b.write_f32(-0.0);
        assert_ne!(a.finish(), b.finish());
        // the same value as f32 and as f64 is a different record
        let mut c = Fnv1a64::new();
        c.write_f64(0.0);
        assert_ne!(a.finish(), c.finish());
    }

    #[test]
    fn generic_write_matches_typed_writes() {
        let mut a = Fnv1a64::new();
        a.write(1.5f32);
        a.write(2.5f64);
        a.write(3u8);
        a.write(4u32);
        a.write(5u64);
        let mut b = Fnv1a64::new();
        b.write_f32(1.5);
        b.write_f64(2.5);
        b.write_u8(3);
        b.write_u32(4);
        b.write_u64(5);
        assert_eq!(a.finish(), b.finish());
    }
}
