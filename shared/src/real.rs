//! The floating-point types the model runs in.
//!
//! Every stepper is generic over [`Real`], implemented for `f32` (the Cortex-M4F's FPU type) and
//! `f64` (the desktop reference). Set-up work (matrix exponentials, coefficients) is always done
//! in `f64` and rounded once to `T`; the per-step arithmetic is plain `+ - * /` in `T`, so the
//! same source gives bit-identical results on x86-64 and on the Cortex-M4F (no fused
//! multiply-add is ever formed implicitly by rustc).

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

/// A floating-point scalar the model can step in.
pub trait Real:
    Copy
    + Debug
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + Default
    + 'static
{
    /// Number of significand bits (24 for f32, 53 for f64). Sets the resolution of the
    /// in-step transition search: a step is divided into `2^DYADIC_LEVELS` units.
    const DYADIC_LEVELS: usize;
    /// Storage for the dyadic propagator table: `DYADIC_LEVELS + 1` matrices of 4 x 5 entries
    /// (row-major), see [`crate::propagator`].
    type DyadicTable: Copy + Debug + AsRef<[[Self; 20]]> + AsMut<[[Self; 20]]>;
    /// A table filled with zeros.
    fn empty_table() -> Self::DyadicTable;
    /// One value per dyadic level: `DYADIC_LEVELS + 1` entries (25 in f32, 54 in f64), for
    /// the model-2 stepper's tables.
    type PerLevel<X: Copy + Debug>: Copy + Debug + AsRef<[X]> + AsMut<[X]>;
    /// Every level holding `x`.
    fn per_level<X: Copy + Debug>(x: X) -> Self::PerLevel<X>;
    /// Short name used in reports ("f32", "f64").
    const NAME: &'static str;
    fn zero() -> Self;
    fn one() -> Self;
    /// Rounds an f64 to this type (round to nearest, ties to even).
    fn from_f64(v: f64) -> Self;
    fn to_f64(self) -> f64;
    /// Exact for integers below 2^24 (f32) or 2^53 (f64).
    fn from_u64(v: u64) -> Self;
    /// Exact below 2^24 (f32); always exact in f64. One instruction on the Cortex-M4F.
    fn from_u32(v: u32) -> Self;
    fn abs(self) -> Self;
    fn is_finite(self) -> bool;
    fn sqrt(self) -> Self;
    /// e^self: the same software routine on the host and the Cortex-M4F. f64: libm. f32:
    /// [`crate::expf::expf`] (Cody-Waite and a degree-5 polynomial, about one ulp); with the
    /// cargo feature `libm-exp` libm's `expf`, with `micromath` micromath's approximation.
    fn exp(self) -> Self;
    /// self^e for self > 0 (libm).
    fn powf(self, e: Self) -> Self;
    fn max(self, other: Self) -> Self {
        if other > self {
            other
        } else {
            self
        }
    }
    fn min(self, other: Self) -> Self {
        if other < self {
            other
        } else {
            self
        }
    }
}

macro_rules! impl_real {
    ($t:ty, $levels:expr, $name:expr, $sqrt:path, $exp:path, $pow:path) => {
        impl Real for $t {
            const DYADIC_LEVELS: usize = $levels;
            const NAME: &'static str = $name;
            type DyadicTable = [[$t; 20]; $levels + 1];
            fn empty_table() -> Self::DyadicTable {
                [[0.0; 20]; $levels + 1]
            }
            type PerLevel<X: Copy + Debug> = [X; $levels + 1];
            fn per_level<X: Copy + Debug>(x: X) -> [X; $levels + 1] {
                [x; $levels + 1]
            }
            #[inline(always)]
            fn zero() -> Self {
                0.0
            }
            #[inline(always)]
            fn one() -> Self {
                1.0
            }
            #[inline(always)]
            fn from_f64(v: f64) -> Self {
                v as $t
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn from_u64(v: u64) -> Self {
                v as $t
            }
            #[inline(always)]
            fn from_u32(v: u32) -> Self {
                v as $t
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                $sqrt(self)
            }
            #[inline(always)]
            fn exp(self) -> Self {
                $exp(self)
            }
            #[inline(always)]
            fn powf(self, e: Self) -> Self {
                $pow(self, e)
            }
        }
    };
}

/// e^x in f32 with the feature `micromath`: micromath's `F32Ext::exp` (called by path, so that
/// no inherent `f32::exp` can shadow it).
#[cfg(feature = "micromath")]
#[inline(always)]
fn expf_micromath(x: f32) -> f32 {
    micromath::F32Ext::exp(x)
}

#[cfg(all(feature = "micromath", feature = "libm-exp"))]
compile_error!("stickslip-model: the features `micromath` and `libm-exp` each choose the f32 exp; enable at most one");

#[cfg(not(any(feature = "micromath", feature = "libm-exp")))]
impl_real!(f32, 24, "f32", libm::sqrtf, crate::expf::expf, libm::powf);
#[cfg(all(feature = "libm-exp", not(feature = "micromath")))]
impl_real!(f32, 24, "f32", libm::sqrtf, libm::expf, libm::powf);
#[cfg(all(feature = "micromath", not(feature = "libm-exp")))]
impl_real!(f32, 24, "f32", libm::sqrtf, expf_micromath, libm::powf);
impl_real!(f64, 53, "f64", libm::sqrt, crate::exp64::exp, libm::pow);
