//! Model 2's runs at event speed on the host (a map's cells, f64): the wide chunks' tables
//! ([`WideChunks`]) and steps by precision (f64 takes them, f32 never), the transitions' located
//! level, and the donors of slip tables each thread keeps for the next cells.

use stickslip_model::model2::{AnyModel2Stepper, Model2Observer, Shared, WideChunks, WideSamples};
use stickslip_model::{Coefficients, Real, Scene, SceneError};

/// The level below which a run at event speed locates a transition on the guard's quadratic
/// Taylor polynomial: 2^44 units of 2^-53 of a substep (f64), 2^-9 of it.
pub(crate) const LOCATE_BELOW_LEVEL: usize = 44;

/// Steps per wide chunk in a map's runs ([`WideChunks`]): 8 was slower (more chunks not
/// taken) and 4 times less accurate, 2 was 1.3 times slower (measured on a 20 x 20 rig map).
pub const WIDE_STEPS: usize = 4;

/// Model 2's wide chunks of Stribeck slip ([`WideChunks`]): taken in f64, never in f32 (whose
/// runs keep the firmware's arithmetic).
pub(crate) trait WideReal: Real {
    /// The stepper of `scene`, its slip tables from this thread's last one where they are the
    /// same ([`AnyModel2Stepper::new_reusing`]; f64).
    fn stepper_reusing(scene: &Scene) -> std::result::Result<AnyModel2Stepper<Self>, SceneError> {
        AnyModel2Stepper::new(scene)
    }
    /// Keeps `st`, the stepper of `scene`, as one of this thread's donors of slip tables.
    fn keep_donor(_scene: &Scene, _st: AnyModel2Stepper<Self>) {}
    fn wide_chunks(st: &AnyModel2Stepper<Self>, scene: &Scene, m: usize) -> Option<WideChunks>;
    fn wide_step<O: Model2Observer<Self>>(st: &mut AnyModel2Stepper<Self, Shared<'_>>, w: &WideChunks, obs: &mut O, samples: bool, out: &mut WideSamples) -> bool;
}

impl WideReal for f32 {
    fn wide_chunks(_: &AnyModel2Stepper<f32>, _: &Scene, _: usize) -> Option<WideChunks> {
        None
    }
    fn wide_step<O: Model2Observer<f32>>(_: &mut AnyModel2Stepper<f32, Shared<'_>>, _: &WideChunks, _: &mut O, _: bool, _: &mut WideSamples) -> bool {
        false
    }
}

thread_local! {
    /// This thread's last map cells' model-2 steppers by [`slip_key`]: donors of slip tables
    /// to the next cells (at most [`DONORS_KEPT`], the oldest dropped first).
    static DONORS: std::cell::RefCell<Vec<(u64, AnyModel2Stepper<f64>)>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Donors kept per thread (a map's distinct slip tables: e.g. one per beta of a beta x V map).
const DONORS_KEPT: usize = 128;

/// A hash of what a Stribeck slip's kinetic tables depend on (the slips' A, b and the step;
/// the composition's flags): the donor to try. The stepper's set-up checks the values
/// themselves, bit for bit, before it takes any table.
fn slip_key(scene: &Scene) -> u64 {
    use stickslip_model::model2::system::System;
    let co = Coefficients::of(scene);
    let sys = if scene.floating() { System::floating_pad(scene, &co) } else { System::hinged(scene, &co) };
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |x: u64| {
        h ^= x;
        h = h.wrapping_mul(0x0100_0000_01b3);
    };
    for v in sys.a[1].iter().chain(sys.a[2].iter()).flatten().chain(sys.b.iter()) {
        eat(v.to_bits());
    }
    eat(scene.dt.to_bits());
    eat(u64::from(scene.floating()) | u64::from(scene.band) << 1 | u64::from(scene.face) << 2);
    h
}

impl WideReal for f64 {
    fn stepper_reusing(scene: &Scene) -> std::result::Result<AnyModel2Stepper<f64>, SceneError> {
        let key = slip_key(scene);
        DONORS.with(|d| match d.borrow().iter().find(|(k, _)| *k == key) {
            Some((_, donor)) => AnyModel2Stepper::new_reusing(scene, donor),
            None => AnyModel2Stepper::new(scene),
        })
    }
    fn keep_donor(scene: &Scene, st: AnyModel2Stepper<f64>) {
        let key = slip_key(scene);
        DONORS.with(|d| {
            let mut d = d.borrow_mut();
            if d.iter().any(|(k, _)| *k == key) {
                return;
            }
            if d.len() >= DONORS_KEPT {
                d.remove(0);
            }
            d.push((key, st));
        });
    }
    fn wide_chunks(st: &AnyModel2Stepper<f64>, scene: &Scene, m: usize) -> Option<WideChunks> {
        st.wide_chunks(scene, m)
    }
    #[inline(always)]
    fn wide_step<O: Model2Observer<f64>>(st: &mut AnyModel2Stepper<f64, Shared<'_>>, w: &WideChunks, obs: &mut O, samples: bool, out: &mut WideSamples) -> bool {
        st.wide_step(w, obs, samples, out)
    }
}

