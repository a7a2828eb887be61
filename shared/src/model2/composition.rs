//! Which options of model 2 a stepper carries, fixed at compile time.
//!
//! A [`Composition`] is a type whose constants say which degrees of freedom and which friction
//! law the stepper is built for. [`super::Model2Stepper`] is generic over it, so what a
//! composition leaves out is not in the code or the tables:
//!
//! Every table has one entry per dyadic level, `T::DYADIC_LEVELS + 1` of them (25 in f32, 54
//! in f64).
//!
//! | composition | state rows moved | flow table entries per level | ETDRK4 vectors |
//! |---|---|---|---|
//! | [`Coulomb`] (no band) | 4 | 4 x 5 | none |
//! | [`Band`] (Coulomb, band) | 6 (x, x', phi, phi', u, u') | 6 x 7 | none |
//! | [`Stribeck`] (no band) | 4 (x, x', phi, phi') | 4 x 5 | 2 slip regimes (+ near) |
//! | [`StribeckBand`] | 6 | 6 x 7 | 2 slip regimes (+ near) |
//!
//! Each has a friction-face twin ([`CoulombFace`], [`BandFace`], [`StribeckFace`],
//! [`StribeckBandFace`]) with the same tables: face kinematics changes rows and the stick flows'
//! entries, not their sizes.
//!
//! With Stribeck friction each slip regime also has near operators: flows and ETDRK4 vectors
//! about part of the falling slope at v = 0 (A + b g_k, k = 1 .. [`NEAR_OPS`]), on the top
//! [`NEAR_LEVELS`] levels only (`Model2Stepper` documents why).
//!
//! Damping needs no composition of its own (it is part of every exact flow); the thesis model
//! with or without damping runs on [`crate::ExactStepper`] ([`Coulomb`] is that model in
//! model 2's matrices: a cross-check of them, not a production path). [`super::AnyModel2Stepper`] picks
//! the composition from a scene at run time (the host); the firmware names its composition.
//! Part 2 adds face kinematics here ([`Composition::FACE`]).

use core::fmt::Debug;

use crate::real::Real;
use crate::scene::{FrictionLaw, Scene, SceneError};

/// Near operators of Stribeck slip: the falling slope at v = 0 in fractions k / NEAR_OPS,
/// k = 1 .. NEAR_OPS (k = 0 is the kinetic operator).
pub const NEAR_OPS: usize = 3;
/// Levels the near operators are tabulated on: the top ones, L - NEAR_LEVELS + 1 ..= L (a chunk
/// of 2^j units reads levels j - 1 and j, so chunks of the top NEAR_LEVELS - 1 levels).
pub const NEAR_LEVELS: usize = 4;
/// Levels the near operators' flows are tabulated on: those levels but the highest, L - NEAR_LEVELS
/// + 1 ..= L - 1 (a chunk of 2^j units applies only the flow of level j - 1: the whole chunk's
/// flow is folded into its ETDRK4 weights).
pub const NEAR_FLOW_LEVELS: usize = NEAR_LEVELS - 1;

/// The ETDRK4 vectors of one dyadic level: h phi_1(hA) b and the three weights of the final
/// combination, h (phi_1 - 3 phi_2 + 4 phi_3) b, h (2 phi_2 - 4 phi_3) b, h (4 phi_3 - phi_2) b.
/// `V` is a composition's [`Composition::Row`]: one entry per moved state entry (6, or 8 with
/// the floating pad).
#[derive(Clone, Copy, Debug)]
pub struct EtdVectors<V> {
    pub phi1: V,
    pub w0: V,
    pub wab: V,
    pub wc: V,
}

impl<V: Copy> EtdVectors<V> {
    pub fn splat(v: V) -> Self {
        EtdVectors { phi1: v, w0: v, wab: v, wc: v }
    }
}

/// The options a model-2 stepper is compiled for.
pub trait Composition: Copy + Debug + 'static {
    /// The band degree of freedom (u, u').
    const BAND: bool;
    /// Stribeck friction (ETDRK4 in slip); Coulomb otherwise.
    const STRIBECK: bool;
    /// The floating pad (docs/model.md, "Model 2, part 2"): the pad's translation y normal to the
    /// band and its pivot spring k_pivot. Its compositions carry the band's rows too (u, u'
    /// stay 0 for a scene without the band) and friction-face kinematics (the floating pad's
    /// energy balance needs them).
    const FLOAT: bool = false;
    /// Friction-face kinematics: the sliding velocity carries s w phi', stick holds the face
    /// (x and phi coupled). The tables' sizes are those of the same composition without it;
    /// what it changes is in the rows, the stick flows and three small functions of the
    /// stepper (the sliding velocity, the entry to stick, the stick anchor).
    const FACE: bool;
    /// Name in reports.
    const NAME: &'static str;
    /// State entries a flow moves, the first ROWS of the state: 8 with the floating pad (x, x',
    /// phi, phi', u, u', y, y'), 6 with the band, 4 without (u = u' = 0 for good).
    const ROWS: usize = if Self::FLOAT {
        8
    } else if Self::BAND {
        6
    } else {
        4
    };
    /// Columns of a flow row: the moved entries and the constant 1.
    const COLS: usize = Self::ROWS + 1;
    /// One flow, ROWS x COLS entries by columns, entry (r, c) at c ROWS + r (increment form:
    /// z(t + h) - z(t) = F (z, 1)).
    type Flow<T: Real>: Copy + Debug + AsRef<[T]> + AsMut<[T]>;
    /// A vector over the moved entries as the ETDRK4 tables store it: 6 entries (the first 4 or
    /// 6 used), 8 with the floating pad.
    type Row<T: Real>: Copy + Debug + core::ops::Index<usize, Output = T> + core::ops::IndexMut<usize>;
    /// The ETDRK4 vectors per slip regime and level: two regimes with Stribeck friction, none
    /// with Coulomb friction.
    type Etd<T: Real>: Copy
        + Debug
        + AsRef<[T::PerLevel<EtdVectors<Self::Row<T>>>]>
        + AsMut<[T::PerLevel<EtdVectors<Self::Row<T>>>]>;
    /// The slip flows of the near operators (Stribeck slip near v = 0, see
    /// [`super::Model2Stepper`]) on [`NEAR_FLOW_LEVELS`] levels, per operator and slip
    /// regime ([`NEAR_OPS`] x 2 with Stribeck friction, none with Coulomb friction).
    /// Entry (k - 1) 2 NEAR_FLOW_LEVELS + (slip regime - 1) NEAR_FLOW_LEVELS + level offset.
    type NearFlows<T: Real>: Copy + Debug + AsRef<[Self::Flow<T>]> + AsMut<[Self::Flow<T>]>;
    /// Their ETDRK4 vectors on the top [`NEAR_LEVELS`] levels, laid out in the same way.
    type NearEtd<T: Real>: Copy + Debug + AsRef<[EtdVectors<Self::Row<T>>]> + AsMut<[EtdVectors<Self::Row<T>>]>;
    fn zero_flow<T: Real>() -> Self::Flow<T>;
    fn zero_row<T: Real>() -> Self::Row<T>;
    fn zero_etd<T: Real>() -> Self::Etd<T>;
    fn zero_near<T: Real>() -> Self::NearFlows<T>;
    fn zero_near_etd<T: Real>() -> Self::NearEtd<T>;

    /// Whether `scene` asks for exactly this composition.
    fn matches(scene: &Scene) -> Result<(), SceneError> {
        let stribeck = scene.friction == FrictionLaw::Stribeck;
        if stribeck != Self::STRIBECK {
            return Err(SceneError {
                field: "friction",
                rule: "is not the friction law this model-2 stepper was compiled for",
                value: if stribeck { 1.0 } else { 0.0 },
            });
        }
        if scene.pneumatic() {
            return Err(SceneError {
                field: "drive",
                rule: "the pneumatic band drive runs on the host's event-driven path (f64), not on the fixed-step model-2 stepper, whose band is driven at V",
                value: 1.0,
            });
        }
        if scene.unilateral() {
            return Err(SceneError {
                field: "contact",
                rule: "unilateral contact runs on the host's event-driven path (f64), not on the fixed-step model-2 stepper, whose edge springs are bilateral",
                value: 1.0,
            });
        }
        let floating = scene.k_pivot.is_finite();
        if floating != Self::FLOAT {
            return Err(SceneError {
                field: "k_pivot",
                rule: "is not what this model-2 stepper was compiled for (finite: the floating pad)",
                value: scene.k_pivot,
            });
        }
        if scene.band != Self::BAND && !Self::FLOAT {
            return Err(SceneError {
                field: "band",
                rule: "is not what this model-2 stepper was compiled for",
                value: if scene.band { 1.0 } else { 0.0 },
            });
        }
        if scene.face != Self::FACE {
            return Err(SceneError {
                field: "face",
                rule: "is not what this model-2 stepper was compiled for",
                value: if scene.face { 1.0 } else { 0.0 },
            });
        }
        Ok(())
    }
}

/// Defines a composition: its type, its options, and the sizes that follow from them (flow
/// entries per level: 4 x 5 without the band, 6 x 7 with it; ETDRK4 tables for the two slip
/// regimes with Stribeck friction, none with Coulomb).
macro_rules! composition {
    ($(#[$doc:meta])* $name:ident, band: $band:expr, stribeck: $stribeck:expr, face: $face:expr, float: $float:expr, $label:expr, flow: $flow:expr, row: $row:expr, etd: $etd:expr) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug)]
        pub struct $name;

        impl Composition for $name {
            const BAND: bool = $band;
            const STRIBECK: bool = $stribeck;
            const FACE: bool = $face;
            const FLOAT: bool = $float;
            const NAME: &'static str = $label;
            type Flow<T: Real> = [T; $flow];
            type Row<T: Real> = [T; $row];
            type Etd<T: Real> = [T::PerLevel<EtdVectors<[T; $row]>>; $etd];
            type NearFlows<T: Real> = [[T; $flow]; $etd * NEAR_OPS * NEAR_FLOW_LEVELS];
            type NearEtd<T: Real> = [EtdVectors<[T; $row]>; $etd * NEAR_OPS * NEAR_LEVELS];
            fn zero_flow<T: Real>() -> [T; $flow] {
                [T::zero(); $flow]
            }
            fn zero_row<T: Real>() -> [T; $row] {
                [T::zero(); $row]
            }
            fn zero_etd<T: Real>() -> Self::Etd<T> {
                core::array::from_fn(|_| T::per_level(EtdVectors::splat([T::zero(); $row])))
            }
            // inlined, so that a stepper built in place (`init_in`) gets its zeros in place too
            #[inline(always)]
            fn zero_near<T: Real>() -> Self::NearFlows<T> {
                [[T::zero(); $flow]; $etd * NEAR_OPS * NEAR_FLOW_LEVELS]
            }
            #[inline(always)]
            fn zero_near_etd<T: Real>() -> Self::NearEtd<T> {
                [EtdVectors::splat([T::zero(); $row]); $etd * NEAR_OPS * NEAR_LEVELS]
            }
        }
        const _: () = assert!($flow == <$name as Composition>::ROWS * <$name as Composition>::COLS);
        const _: () = assert!($row >= <$name as Composition>::ROWS && $row <= 8);
        const _: () = assert!(!$float || ($band && $face));
        const _: () = assert!(($etd == 2) == $stribeck);
    };
}

composition!(
    /// Coulomb friction, no band: the thesis model in model 2's matrices.
    Coulomb, band: false, stribeck: false, face: false, float: false, "coulomb", flow: 20, row: 6, etd: 0
);
composition!(
    /// Coulomb friction and the band.
    Band, band: true, stribeck: false, face: false, float: false, "band", flow: 42, row: 6, etd: 0
);
composition!(
    /// Stribeck friction, no band.
    Stribeck, band: false, stribeck: true, face: false, float: false, "stribeck", flow: 20, row: 6, etd: 2
);
composition!(
    /// Stribeck friction and the band.
    StribeckBand, band: true, stribeck: true, face: false, float: false, "stribeck+band", flow: 42, row: 6, etd: 2
);
composition!(
    /// Coulomb friction, friction-face kinematics, no band.
    CoulombFace, band: false, stribeck: false, face: true, float: false, "coulomb+face", flow: 20, row: 6, etd: 0
);
composition!(
    /// Coulomb friction, the band, friction-face kinematics.
    BandFace, band: true, stribeck: false, face: true, float: false, "band+face", flow: 42, row: 6, etd: 0
);
composition!(
    /// Stribeck friction, friction-face kinematics, no band.
    StribeckFace, band: false, stribeck: true, face: true, float: false, "stribeck+face", flow: 20, row: 6, etd: 2
);
composition!(
    /// Stribeck friction, the band, friction-face kinematics.
    StribeckBandFace, band: true, stribeck: true, face: true, float: false, "stribeck+band+face", flow: 42, row: 6, etd: 2
);
composition!(
    /// The floating pad, Coulomb friction (with the band's rows and the face).
    FloatFace, band: true, stribeck: false, face: true, float: true, "float+face", flow: 72, row: 8, etd: 0
);
composition!(
    /// The floating pad, Stribeck friction (with the band's rows and the face): the rig set.
    StribeckFloatFace, band: true, stribeck: true, face: true, float: true, "stribeck+float+face", flow: 72, row: 8, etd: 2
);
