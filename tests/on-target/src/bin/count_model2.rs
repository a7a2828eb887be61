//! Instruction counts of single f32 steps on the Cortex-M4F for each composition of model 2,
//! and of single calls of the two f32 exponentials, for `scripts/count-model2.sh`.
//!
//! Same machinery as `count` (see its documentation and scripts/count-instructions.sh): every
//! measured call sits between [`stickslip_mark_begin`] and [`stickslip_mark_end`]; right
//! after the end marker a class marker `count_class_<class>` names what the window measured
//! (the script counts the trace lines between the two markers and groups them by class).
//! Window 0 is empty (the markers' calling glue, subtracted from the others).
//!
//! Compositions (push_center, beta = 0.040 m, dt = 1/25 600 s, each started fresh):
//! - `thesis`: `ExactStepper<f32>`, the default scene;
//! - `damping`: `ExactStepper<f32>`, c_x and c_phi at 2 % of critical;
//! - `band`: `Model2Stepper<f32, Band>`, Coulomb, the band (m_b = 2 kg, k_b = 1e6 N/m, 5 % of
//!   critical in c_b);
//! - `stribeck`: `Model2Stepper<f32, Stribeck>`, Stribeck friction v_s = 0.002 m/s
//!   (delta = 1), no band;
//! - `all`: `Model2Stepper<f32, StribeckBand>`, Stribeck + band + damping;
//! - `face`: `Model2Stepper<f32, StribeckBandFace>`, `all` with friction-face kinematics;
//! - `float`: `Model2Stepper<f32, StribeckFloatFace>`, `face` with the floating pad
//!   (k_pivot = 0, c_y at 2 % of critical on k_L + k_T): every option of model 2.
//!
//! Each composition is its own compile-time specialised stepper (model2::composition), as the
//! firmware would build it.
//!
//! Every step of each run is measured, from the first step until the end of the second slip
//! phase (at most [`MAX_STEPS`]), and classed by the regime it starts in and whether it had a
//! transition: `<composition>_stick`, `<composition>_slip`, `<composition>_transition`.
//! Then [`EXP_ARGS`] are each passed once to the model's `expf::expf` (`expf_model`, the
//! default f32 `Real::exp`), to `libm::expf` (`expf_libm`) and to micromath's `F32Ext::exp`
//! (`exp_micromath`).
//!
//! The steppers live in a static arena, one at a time (a `Model2Stepper<f32, _>` is 14 to 38 KB:
//! its dyadic tables of 25 levels in f32); the stack is painted at boot and its high-water mark printed after each
//! composition. Printed (semihosting), one line each:
//! `comp <name> stepper=<type> size=<bytes> tables=<bytes> n_sub=<n> steps=<k> transitions=<n> stack_used=<bytes> stack_size=<bytes>`
//!
//! Built with the environment variable `COUNT_MODEL2_MAX_STEPS=<k>`, each composition stops
//! after k steps (a quick look; the script's figures use the default, [`MAX_STEPS`]).
//! and at the end `done count_model2`.
#![no_std]
#![no_main]

use core::hint::black_box;
use core::mem::MaybeUninit;
use core::ptr::addr_of_mut;

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use panic_semihosting as _;
use stickslip_model::model2::{Band, Composition, Model2Stepper, Stribeck, StribeckBand, StribeckBandFace, StribeckFloatFace};
use stickslip_model::{Coefficients, ExactStepper, FrictionLaw, Halt, Regime, Scene, SceneError};
use stickslip_on_target::{scenes, stack};

/// Cap on the steps of one composition (0.2 s).
const MAX_STEPS: u64 = 5_120;

/// The cap in force: [`MAX_STEPS`], or `COUNT_MODEL2_MAX_STEPS` at build time.
const fn max_steps() -> u64 {
    match option_env!("COUNT_MODEL2_MAX_STEPS") {
        None => MAX_STEPS,
        Some(s) => {
            let b = s.as_bytes();
            let mut v = 0u64;
            let mut i = 0;
            while i < b.len() {
                assert!(b[i].is_ascii_digit(), "COUNT_MODEL2_MAX_STEPS: not a number");
                v = v * 10 + (b[i] - b'0') as u64;
                i += 1;
            }
            v
        }
    }
}

/// Arguments of the exponential calls: exp(-y) for y in [0, 20], the range of the Stribeck law.
const EXP_ARGS: [f32; 9] = [0.0, -0.01, -0.3, -1.0, -2.5, -5.0, -9.7, -15.0, -20.0];

/// Start of a measured window.
#[inline(never)]
#[no_mangle]
pub extern "C" fn stickslip_mark_begin() {
    cortex_m::asm::nop();
}

/// End of a measured window (a body unlike the begin marker's, so that they stay two
/// functions).
#[inline(never)]
#[no_mangle]
pub extern "C" fn stickslip_mark_end() {
    cortex_m::asm::nop();
    cortex_m::asm::nop();
}

/// Written by the class markers (each with its own value, so that no two markers have the same
/// body and are merged into one function).
static mut CLASS: u32 = 0;

macro_rules! class_markers {
    ($($name:ident = $k:expr),* $(,)?) => {
        $(
            #[inline(never)]
            #[no_mangle]
            pub extern "C" fn $name() {
                // SAFETY: single-threaded program; a plain volatile store.
                unsafe { addr_of_mut!(CLASS).write_volatile($k) }
            }
        )*
    };
}

class_markers!(
    count_class_baseline = 1,
    count_class_thesis_stick = 2,
    count_class_thesis_slip = 3,
    count_class_thesis_transition = 4,
    count_class_damping_stick = 5,
    count_class_damping_slip = 6,
    count_class_damping_transition = 7,
    count_class_band_stick = 8,
    count_class_band_slip = 9,
    count_class_band_transition = 10,
    count_class_stribeck_stick = 11,
    count_class_stribeck_slip = 12,
    count_class_stribeck_transition = 13,
    count_class_all_stick = 14,
    count_class_all_slip = 15,
    count_class_all_transition = 16,
    count_class_expf_libm = 17,
    count_class_exp_micromath = 18,
    count_class_expf_model = 19,
    count_class_face_stick = 20,
    count_class_face_slip = 21,
    count_class_face_transition = 22,
    count_class_float_stick = 23,
    count_class_float_slip = 24,
    count_class_float_transition = 25,
);

/// The three class markers of one composition: stick, slip, transition.
type Classes = [extern "C" fn(); 3];

fn fail(msg: &str) -> ! {
    hprintln!("error {}", msg);
    debug::exit(debug::EXIT_FAILURE);
    #[allow(clippy::empty_loop)]
    loop {}
}

/// What the measurement needs of a stepper.
trait Steps {
    fn regime_now(&self) -> Regime;
    fn one_step(&mut self) -> Result<usize, Halt>;
    fn n_sub(&self) -> u32;
}

impl Steps for ExactStepper<f32> {
    fn regime_now(&self) -> Regime {
        self.regime()
    }
    #[inline(always)]
    fn one_step(&mut self) -> Result<usize, Halt> {
        self.step()
    }
    fn n_sub(&self) -> u32 {
        1
    }
}

impl<C: Composition> Steps for Model2Stepper<f32, C> {
    fn regime_now(&self) -> Regime {
        self.regime()
    }
    #[inline(always)]
    fn one_step(&mut self) -> Result<usize, Halt> {
        self.step()
    }
    fn n_sub(&self) -> u32 {
        self.substeps()
    }
}

/// Runs `st` from its start, every step in a window, until the second slip phase has ended.
/// Returns (steps, transitions).
fn measure<S: Steps>(st: &mut S, classes: &Classes) -> (u64, u64) {
    // The stepper is reached through a pointer the optimiser must assume the markers can see,
    // so no part of a measured step moves out of its window.
    let st: &mut S = black_box(st);
    let mut slip_ends = 0;
    let mut transitions = 0u64;
    let mut k = 0;
    while k < max_steps() {
        let from = st.regime_now();
        stickslip_mark_begin();
        let result = st.one_step();
        stickslip_mark_end();
        let n = match black_box(result) {
            Ok(n) => n,
            Err(_) => fail("halted in a measured step"),
        };
        k += 1;
        transitions += n as u64;
        if n > 0 {
            classes[2]();
        } else if from == Regime::Stick {
            classes[0]();
        } else {
            classes[1]();
        }
        if n > 0 && from != Regime::Stick && st.regime_now() == Regime::Stick {
            slip_ends += 1;
            if slip_ends == 2 {
                break;
            }
        }
    }
    (k, transitions)
}

fn report(name: &str, stepper: &str, size: usize, tables: usize, n_sub: u32, (steps, transitions): (u64, u64)) {
    let (used, total) = stack::used();
    hprintln!(
        "comp {} stepper={} size={} tables={} n_sub={} steps={} transitions={} stack_used={} stack_size={}",
        name,
        stepper,
        size,
        tables,
        n_sub,
        steps,
        transitions,
        used,
        total
    );
}

fn damped(mut s: Scene) -> Scene {
    let co = Coefficients::of(&s);
    s.c_x = 0.02 * 2.0 * libm::sqrt(s.k_g * s.m);
    s.c_phi = 0.02 * 2.0 * libm::sqrt(co.k_rot * s.inertia);
    s
}

fn banded(mut s: Scene) -> Scene {
    s.band = true;
    s.m_b = 2.0;
    s.k_b = 1e6;
    s.c_b = 2.0 * 0.05 * libm::sqrt(s.k_b * s.m_b);
    s
}

fn stribeck(mut s: Scene) -> Scene {
    s.friction = FrictionLaw::Stribeck;
    s.v_s = 0.002;
    s.stribeck_exponent = 1.0;
    s
}

/// The static homes of the steppers (one composition at a time), as `Result`s so that `new`
/// can build its value in the static itself rather than on the stack and then move it there.
static mut EXACT: MaybeUninit<Result<ExactStepper<f32>, SceneError>> = MaybeUninit::uninit();
/// `Model2Stepper::init_in` fills its tables in place: one static arena that each composition
/// takes in turn (five steppers of 14 to 38 KB would not fit the F405's 128 KB side by side).
const ARENA_BYTES: usize = 40 * 1024;
#[repr(C, align(8))]
struct Arena([u8; ARENA_BYTES]);
static mut ARENA: MaybeUninit<Arena> = MaybeUninit::uninit();

/// The arena as an empty slot for a stepper of composition `C` (the previous one is over:
/// steppers hold no resources, nothing to drop).
fn slot<C: Composition>() -> &'static mut Option<Model2Stepper<f32, C>> {
    const {
        assert!(core::mem::size_of::<Option<Model2Stepper<f32, C>>>() <= ARENA_BYTES);
        assert!(core::mem::align_of::<Option<Model2Stepper<f32, C>>>() <= 8);
    }
    let p = addr_of_mut!(ARENA).cast::<Option<Model2Stepper<f32, C>>>();
    // SAFETY: the arena is large and aligned enough (checked above); single-threaded program,
    // and the slot of the previous composition is no longer referenced when the next is taken.
    unsafe {
        p.write(None);
        &mut *p
    }
}

fn run_exact(name: &str, scene: &Scene, classes: &Classes) {
    stack::paint();
    // SAFETY: the only reference made to EXACT at a time; single-threaded program.
    let slot = unsafe { &mut *addr_of_mut!(EXACT) };
    let Ok(st) = slot.write(ExactStepper::<f32>::new(scene)) else {
        fail("scene rejected (ExactStepper)");
    };
    let r = measure(st, classes);
    let size = core::mem::size_of::<ExactStepper<f32>>();
    report(name, "ExactStepper<f32>", size, size, 1, r);
}

fn run_model2<C: Composition>(name: &str, slot: &mut Option<Model2Stepper<f32, C>>, scene: &Scene, classes: &Classes) {
    stack::paint();
    let Ok(st) = Model2Stepper::<f32, C>::init_in(slot, scene) else {
        fail("scene rejected (Model2Stepper)");
    };
    let n_sub = st.n_sub();
    let tables = st.table_bytes();
    let r = measure(st, classes);
    report(name, C::NAME, core::mem::size_of::<Model2Stepper<f32, C>>(), tables, n_sub, r);
}

#[inline(never)]
fn exp_libm(x: f32) -> f32 {
    libm::expf(x)
}

#[inline(never)]
fn exp_model(x: f32) -> f32 {
    stickslip_model::expf::expf(x)
}

#[inline(never)]
fn exp_micromath(x: f32) -> f32 {
    micromath::F32Ext::exp(x)
}

#[entry]
fn main() -> ! {
    stack::paint();

    // Window 0: nothing between the markers.
    stickslip_mark_begin();
    stickslip_mark_end();
    count_class_baseline();

    let thesis = scenes::push_center();
    run_exact(
        "thesis",
        &thesis,
        &[count_class_thesis_stick, count_class_thesis_slip, count_class_thesis_transition],
    );
    run_exact(
        "damping",
        &damped(thesis),
        &[count_class_damping_stick, count_class_damping_slip, count_class_damping_transition],
    );
    run_model2(
        "band",
        slot::<Band>(),
        &banded(thesis),
        &[count_class_band_stick, count_class_band_slip, count_class_band_transition],
    );
    run_model2(
        "stribeck",
        slot::<Stribeck>(),
        &stribeck(thesis),
        &[count_class_stribeck_stick, count_class_stribeck_slip, count_class_stribeck_transition],
    );
    run_model2(
        "all",
        slot::<StribeckBand>(),
        &damped(banded(stribeck(thesis))),
        &[count_class_all_stick, count_class_all_slip, count_class_all_transition],
    );
    let all_on = damped(banded(stribeck(thesis)));
    let mut with_face = all_on;
    with_face.face = true;
    let mut floating = with_face;
    floating.k_pivot = 0.0;
    floating.c_y = 0.02 * 2.0 * libm::sqrt((floating.k_l + floating.k_t) * floating.m);
    run_model2(
        "face",
        slot::<StribeckBandFace>(),
        &with_face,
        &[count_class_face_stick, count_class_face_slip, count_class_face_transition],
    );
    run_model2(
        "float",
        slot::<StribeckFloatFace>(),
        &floating,
        &[count_class_float_stick, count_class_float_slip, count_class_float_transition],
    );

    // The exponentials, one call per window (the call's glue is inside the window: the three
    // functions are called the same way).
    let mut sink = 0.0f32;
    for &x in EXP_ARGS.iter() {
        let x = black_box(x);
        stickslip_mark_begin();
        let r = exp_model(x);
        stickslip_mark_end();
        count_class_expf_model();
        sink += black_box(r);
        stickslip_mark_begin();
        let r = exp_libm(x);
        stickslip_mark_end();
        count_class_expf_libm();
        sink += black_box(r);
        stickslip_mark_begin();
        let r = exp_micromath(x);
        stickslip_mark_end();
        count_class_exp_micromath();
        sink += black_box(r);
    }
    black_box(sink);
    let (used, total) = stack::used();
    hprintln!("done count_model2 stack_used={} stack_size={}", used, total);
    debug::exit(debug::EXIT_SUCCESS);
    #[allow(clippy::empty_loop)]
    loop {}
}
