//! The three f32 exponentials side by side in one binary, for `stickslip accuracy`.
//!
//! The model crate chooses its f32 `Real::exp` at compile time (its own `expf::expf` by default,
//! libm's or micromath's behind cargo features), so one host binary runs only one of them as
//! `f32`. [`F32Exp<E>`] is f32 with the exponential `E`: every other operation is f32's own, so
//! `F32Exp<ModelExp>` steps bit for bit as `f32` (tested in `host/tests/exp_variants.rs`), and
//! `F32Exp<LibmExp>` / `F32Exp<MicromathExp>` are the firmware's alternatives, run by the same
//! stepper code.

use std::fmt::Debug;
use std::marker::PhantomData;
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

use stickslip_model::Real;

/// An f32 exponential.
pub trait ExpF32: Copy + Debug + Default + PartialEq + PartialOrd + 'static {
    /// The precision label of rows run with it.
    const NAME: &'static str;
    /// What it is, for the report.
    const WHAT: &'static str;
    fn exp(x: f32) -> f32;
}

/// The model's own (`stickslip_model::expf::expf`, the default f32 `Real::exp`).
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct ModelExp;
/// libm's `expf` (the model crate's feature `libm-exp`).
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct LibmExp;
/// micromath 2.1's `F32Ext::exp` (the model crate's feature `micromath`).
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct MicromathExp;

impl ExpF32 for ModelExp {
    const NAME: &'static str = "f32 model exp";
    const WHAT: &'static str = "model expf (default)";
    fn exp(x: f32) -> f32 {
        stickslip_model::expf::expf(x)
    }
}

impl ExpF32 for LibmExp {
    const NAME: &'static str = "f32 libm exp";
    const WHAT: &'static str = "libm expf (feature libm-exp)";
    fn exp(x: f32) -> f32 {
        libm::expf(x)
    }
}

impl ExpF32 for MicromathExp {
    const NAME: &'static str = "f32 micromath exp";
    const WHAT: &'static str = "micromath 2.1 exp (feature micromath)";
    fn exp(x: f32) -> f32 {
        micromath::F32Ext::exp(x)
    }
}

/// f32 whose `Real::exp` is `E`'s.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct F32Exp<E: ExpF32>(pub f32, PhantomData<E>);

impl<E: ExpF32> F32Exp<E> {
    #[inline(always)]
    pub fn new(v: f32) -> Self {
        Self(v, PhantomData)
    }
}

macro_rules! binary_op {
    ($tr:ident, $f:ident, $op:tt) => {
        impl<E: ExpF32> $tr for F32Exp<E> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                Self::new(self.0 $op o.0)
            }
        }
    };
}
binary_op!(Add, add, +);
binary_op!(Sub, sub, -);
binary_op!(Mul, mul, *);
binary_op!(Div, div, /);

impl<E: ExpF32> Neg for F32Exp<E> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self::new(-self.0)
    }
}

impl<E: ExpF32> AddAssign for F32Exp<E> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        self.0 += o.0;
    }
}

impl<E: ExpF32> Real for F32Exp<E> {
    const DYADIC_LEVELS: usize = <f32 as Real>::DYADIC_LEVELS;
    type DyadicTable = [[Self; 20]; 25];
    fn empty_table() -> Self::DyadicTable {
        [[Self::zero(); 20]; 25]
    }
    type PerLevel<X: Copy + Debug> = [X; 25];
    fn per_level<X: Copy + Debug>(x: X) -> [X; 25] {
        [x; 25]
    }
    const NAME: &'static str = E::NAME;
    #[inline(always)]
    fn zero() -> Self {
        Self::new(0.0)
    }
    #[inline(always)]
    fn one() -> Self {
        Self::new(1.0)
    }
    #[inline(always)]
    fn from_f64(v: f64) -> Self {
        Self::new(v as f32)
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self.0 as f64
    }
    #[inline(always)]
    fn from_u64(v: u64) -> Self {
        Self::new(v as f32)
    }
    #[inline(always)]
    fn from_u32(v: u32) -> Self {
        Self::new(v as f32)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Self::new(self.0.abs())
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        self.0.is_finite()
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Self::new(libm::sqrtf(self.0))
    }
    #[inline(always)]
    fn exp(self) -> Self {
        Self::new(E::exp(self.0))
    }
    #[inline(always)]
    fn powf(self, e: Self) -> Self {
        Self::new(libm::powf(self.0, e.0))
    }
}

/// Max relative error of `exp(-y)` against f64 libm::exp over the Stribeck law's range: `n + 1`
/// evenly spaced y in [0, 20]. Returns (error, y where it is largest).
pub fn max_rel_error_stribeck_range<E: ExpF32>(n: u32) -> (f64, f32) {
    let mut worst = (0.0f64, 0.0f32);
    for i in 0..=n {
        let y = (20.0 * i as f64 / n as f64) as f32;
        let exact = libm::exp(-(y as f64));
        let e = ((E::exp(-y) as f64 - exact) / exact).abs();
        if e > worst.0 {
            worst = (e, y);
        }
    }
    worst
}
