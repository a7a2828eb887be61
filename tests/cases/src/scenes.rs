//! The scenes of the on-target cross-check and the digest of a run.
//!
//! Run by the Cortex-M4F test binary (`tests/on-target/src/bin/digest.rs`) and by the
//! host-side test `tests/tests/on_target.rs`, so the emulated M4F and x86-64 compute the digest
//! with the same code. It uses nothing but `core` and `stickslip_model`.
//!
//! The digest ([`run`]) is an FNV-1a 64 ([`stickslip_model::digest`]) over, for every step:
//! the tag [`TAG_STEP`], the regime at the end of the step (u8), the four state values
//! x, x', phi, phi' (bit patterns of `T`), the number of transitions the step returned (u32),
//! and for each transition the stepper kept: [`TAG_TRANSITION`], from and to regimes (u8),
//! its time (f64 bits) and the entry state (4 x `T`). A halt adds [`TAG_HALT`], its kind (u8)
//! and its time (f64) and ends the run. The run closes with [`TAG_END`], the step count,
//! the transition count and the dropped-transition count (u64 each).

use core::fmt;

use stickslip_model::digest::{DigestBits, Fnv1a64};
use stickslip_model::model2::{Composition, Model2Stepper, Model2Observer, Model2Transition};
use stickslip_model::{Caliper, ExactStepper, FrictionLaw, Halt, Real, Scene, SceneError};

pub const TAG_STEP: u8 = b'S';
pub const TAG_TRANSITION: u8 = b'T';
pub const TAG_HALT: u8 = b'H';
pub const TAG_END: u8 = b'E';

/// The rig's step: dt = 1/25 600 s.
pub const DT: f64 = 1.0 / 25_600.0;
/// Run length of the two-DOF cross-check scenes [s].
pub const DURATION: f64 = 1.0;
/// Run length of the 1-DOF oracle scene [s]: its first breakaway comes at
/// x_s / V = 0.06 m / 0.05 m/s = 1.2 s, so a 1 s run would have no transition at all; 3 s holds
/// the first stick, slip, stick and slip (transitions near 1.2, 1.56, 2.36 and 2.73 s).
pub const ORACLE_DURATION: f64 = 3.0;

/// One cross-check scene: a name (as printed) and how to build it.
#[derive(Clone, Copy)]
pub struct Case {
    pub name: &'static str,
    pub scene: fn() -> Scene,
}

/// The scenes run on the target and recomputed on the host, in print order.
pub const CASES: [Case; 3] = [
    Case { name: "pull_center", scene: pull_center },
    Case { name: "push_center", scene: push_center },
    Case { name: "oracle_1dof", scene: oracle_1dof },
];

fn with_run_settings(mut s: Scene, duration: f64) -> Scene {
    s.dt = DT;
    s.duration = duration;
    s.stats_from = 0.5 * duration;
    s
}

/// Pull caliper, load at the pad centre (beta = 0.040 m): settles into a periodic cycle.
pub fn pull_center() -> Scene {
    with_run_settings(Scene::case(Caliper::Pull, 0.040), DURATION)
}

/// Push caliper, load at the pad centre: the default scene (irregular event timing).
pub fn push_center() -> Scene {
    with_run_settings(Scene::case(Caliper::Push, 0.040), DURATION)
}

/// The 1-DOF mass on a moving belt of the closed-form oracle: no rotation, m = 1 kg,
/// k_g = 100 N/m, V = 0.05 m/s, mu_s = 0.6, mu_k = 0.4, and F_N such that
/// N0 = c_N F_N a_N / K = 10 N; run for [`ORACLE_DURATION`].
pub fn oracle_1dof() -> Scene {
    let s = Scene::oracle_1dof();
    with_run_settings(s, ORACLE_DURATION)
}

/// What a run produced: its digest and counts, and the halt that ended it early, if any.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunDigest {
    pub digest: u64,
    pub steps: u64,
    pub transitions: u64,
    pub halt: Option<Halt>,
}

fn halt_kind(h: &Halt) -> (u8, &'static str) {
    match h {
        Halt::NonFinite { .. } => (1, "non_finite"),
        Halt::Diverged { .. } => (2, "diverged"),
        Halt::ContactLoss { .. } => (3, "contact_loss"),
        Halt::TransitionStorm { .. } => (4, "transition_storm"),
    }
}

/// Steps in a run of `scene` (duration / dt, rounded to the nearest whole step).
pub fn step_count(scene: &Scene) -> u64 {
    (scene.duration / scene.dt + 0.5) as u64
}

/// Runs `scene` from the default initial state with `ExactStepper<T>` and digests every step.
pub fn run<T: Real + DigestBits>(scene: &Scene) -> Result<RunDigest, SceneError> {
    let mut stepper = ExactStepper::<T>::new(scene)?;
    let n = step_count(scene);
    let mut d = Fnv1a64::new();
    let mut transitions = 0u64;
    let mut halt = None;
    for _ in 0..n {
        match stepper.step() {
            Ok(k) => {
                transitions += k as u64;
                d.write_u8(TAG_STEP);
                d.write_u8(stepper.regime().index() as u8);
                for v in stepper.state().to_array() {
                    d.write(v);
                }
                d.write_u32(k as u32);
                for tr in stepper.transitions() {
                    d.write_u8(TAG_TRANSITION);
                    d.write_u8(tr.from.index() as u8);
                    d.write_u8(tr.to.index() as u8);
                    d.write_f64(tr.t);
                    for v in tr.state.to_array() {
                        d.write(v);
                    }
                }
            }
            Err(h) => {
                d.write_u8(TAG_HALT);
                d.write_u8(halt_kind(&h).0);
                d.write_f64(h.time());
                halt = Some(h);
                break;
            }
        }
    }
    d.write_u8(TAG_END);
    d.write_u64(stepper.steps());
    d.write_u64(transitions);
    d.write_u64(stepper.transitions_dropped());
    Ok(RunDigest { digest: d.finish(), steps: stepper.steps(), transitions, halt })
}

/// The report line of one run, as printed by the target and rebuilt by the host:
/// `digest <scene> <f32|f64> <16 hex digits> steps=<n> transitions=<n>`, followed by
/// ` halt=<kind>` when the run stopped early.
pub struct Report<'a> {
    pub scene: &'a str,
    pub real: &'a str,
    pub run: &'a RunDigest,
}

impl fmt::Display for Report<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "digest {} {} {:016x} steps={} transitions={}",
            self.scene, self.real, self.run.digest, self.run.steps, self.run.transitions
        )?;
        if let Some(h) = &self.run.halt {
            write!(f, " halt={}", halt_kind(h).1)?;
        }
        Ok(())
    }
}

/// Run length of the model-2 cross-check runs [s] (about 60 transitions each).
pub const MODEL2_DURATION: f64 = 0.5;

/// The rig set's push_center as it was before its Table 3.1 fit
/// (`stickslip_model::rig_set::pre_fit_rig_scene`: a friction drop of 0.10, vigorous
/// stick-slip in every composition; the fitted drop of 0.010 leaves the Coulomb compositions
/// sliding after one breakaway) with the options of composition `C` (band or not; Stribeck or
/// Coulomb friction), at the rig's step, for [`MODEL2_DURATION`].
pub fn model2_scene<C: Composition>() -> Scene {
    let mut s = stickslip_model::rig_set::pre_fit_rig_scene(Caliper::Push, 0.040);
    s.band = C::BAND;
    if !C::STRIBECK {
        s.friction = FrictionLaw::Coulomb;
    }
    with_run_settings(s, MODEL2_DURATION)
}

/// Feeds each transition of a model-2 step into the digest.
struct DigestTransitions<'a, T> {
    d: &'a mut Fnv1a64,
    _t: core::marker::PhantomData<T>,
}

impl<T: Real + DigestBits> Model2Observer<T> for DigestTransitions<'_, T> {
    const DERIVATIVES: bool = false;
    fn transition(&mut self, tr: &Model2Transition<T>) {
        self.d.write_u8(TAG_TRANSITION);
        self.d.write_u8(tr.from.index() as u8);
        self.d.write_u8(tr.to.index() as u8);
        self.d.write_f64(tr.t);
        for v in tr.z {
            self.d.write(v);
        }
    }
}

/// Runs `scene` with `Model2Stepper<T, C>` and digests every step as [`run`] does, with the
/// six state values x, x', phi, phi', u, u' and each transition as the step reports it
/// (dropped transitions: 0, the model-2 stepper keeps none). The stepper is built in place in
/// a slot on this frame (its tables are 13 to 20 KB in f32).
pub fn run_model2<T: Real + DigestBits, C: Composition>(scene: &Scene) -> Result<RunDigest, SceneError> {
    let mut slot = None;
    let stepper = Model2Stepper::<T, C>::init_in(&mut slot, scene)?;
    let n = step_count(scene);
    let mut d = Fnv1a64::new();
    let mut transitions = 0u64;
    let mut halt = None;
    for _ in 0..n {
        d.write_u8(TAG_STEP);
        let step = stepper.step_observed(&mut DigestTransitions { d: &mut d, _t: core::marker::PhantomData });
        match step {
            Ok(k) => {
                transitions += k as u64;
                d.write_u8(stepper.regime().index() as u8);
                for v in stepper.state() {
                    d.write(v);
                }
                d.write_u32(k as u32);
            }
            Err(h) => {
                d.write_u8(TAG_HALT);
                d.write_u8(halt_kind(&h).0);
                d.write_f64(h.time());
                halt = Some(h);
                break;
            }
        }
    }
    d.write_u8(TAG_END);
    d.write_u64(stepper.steps());
    d.write_u64(transitions);
    d.write_u64(0);
    Ok(RunDigest { digest: d.finish(), steps: stepper.steps(), transitions, halt })
}

/// The report line of one model-2 run: `digest2 <composition> <f32|f64> <16 hex digits>
/// steps=<n> transitions=<n>` (and ` halt=<kind>`).
pub struct Report2<'a> {
    pub composition: &'a str,
    pub real: &'a str,
    pub run: &'a RunDigest,
}

impl fmt::Display for Report2<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "digest2 {} {} {:016x} steps={} transitions={}",
            self.composition, self.real, self.run.digest, self.run.steps, self.run.transitions
        )?;
        if let Some(h) = &self.run.halt {
            write!(f, " halt={}", halt_kind(h).1)?;
        }
        Ok(())
    }
}
