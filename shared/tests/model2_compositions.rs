//! Model 2's compile-time compositions: a stepper refuses a scene of another composition
//! (naming the field), leaves out what its composition does not use (table sizes from the
//! dimensions, not from the code), and runs as the rig's lockstep model.

use stickslip_model::model2::{AnyModel2Stepper, Band, Coulomb, Model2Stepper, Model2Observer, Model2Segment, Stribeck, StribeckBand, Model2Transition};
use stickslip_model::rig::lockstep::LockstepModel;
// The rig set as guessed before its Table 3.1 fit (a friction drop of 0.10): vigorous
// stick-slip on every composition, the scenes these tests were written for; the fitted set's
// drop of 0.010 leaves the Coulomb compositions sliding after one breakaway.
use stickslip_model::rig_set::pre_fit_rig_scene as rig_scene;
use stickslip_model::{Caliper, FrictionLaw, Real, Regime, Scene};

fn stribeck_no_band() -> Scene {
    let mut s = rig_scene(Caliper::Push, 0.040);
    s.band = false;
    s
}

#[test]
fn a_stepper_refuses_a_scene_of_another_composition() {
    let rig = rig_scene(Caliper::Push, 0.040);
    let e = Model2Stepper::<f32, Stribeck>::new(&rig).unwrap_err();
    assert_eq!(e.field, "band");
    let e = Model2Stepper::<f32, Band>::new(&rig).unwrap_err();
    assert_eq!(e.field, "friction");
    let mut coulomb_band = rig;
    coulomb_band.friction = FrictionLaw::Coulomb;
    assert!(Model2Stepper::<f32, Band>::new(&coulomb_band).is_ok());
    assert!(Model2Stepper::<f32, StribeckBand>::new(&rig).is_ok());
    assert!(Model2Stepper::<f32, Stribeck>::new(&stribeck_no_band()).is_ok());
    // validation still comes first
    let mut bad = rig;
    bad.m_b = -1.0;
    assert_eq!(Model2Stepper::<f32, StribeckBand>::new(&bad).unwrap_err().field, "m_b");
}

/// Tables per composition from the dimensions: 3 regimes x 25 levels (f32: a substep of 2^24
/// units, levels 0 to 24) x (rows x columns) flow entries, plus, with Stribeck friction, 2 slip
/// regimes x 25 levels x 4 vectors of 6.
#[test]
fn a_composition_carries_only_its_tables() {
    let f = core::mem::size_of::<f32>();
    let flows = |rows: usize, cols: usize| 3 * 25 * rows * cols * f;
    let etd = 2 * 25 * 4 * 6 * f;
    // Stribeck slip near v = 0: three near operators per slip regime, ETDRK4 vectors on the
    // top four levels and flows on the three below the top (a chunk applies only its half
    // chunk's flow)
    let near = |rows: usize, cols: usize| 3 * 2 * (3 * rows * cols + 4 * 4 * 6) * f;
    let mut coulomb = Scene::case(Caliper::Pull, 0.040);
    coulomb.friction = FrictionLaw::Coulomb;
    let mut band = rig_scene(Caliper::Push, 0.040);
    band.friction = FrictionLaw::Coulomb;
    assert_eq!(Model2Stepper::<f32, Coulomb>::new(&coulomb).unwrap().table_bytes(), flows(4, 5));
    assert_eq!(Model2Stepper::<f32, Band>::new(&band).unwrap().table_bytes(), flows(6, 7));
    assert_eq!(Model2Stepper::<f32, Stribeck>::new(&stribeck_no_band()).unwrap().table_bytes(), flows(4, 5) + etd + near(4, 5));
    let all = Model2Stepper::<f32, StribeckBand>::new(&rig_scene(Caliper::Push, 0.040)).unwrap();
    assert_eq!(all.table_bytes(), flows(6, 7) + etd + near(6, 7));
    // and the stepper's size is its tables plus a small remainder (< 3 KB: rows, state and the f64 equations)
    assert!(core::mem::size_of::<Model2Stepper<f32, Stribeck>>() < flows(4, 5) + etd + near(4, 5) + 3072);
    assert!(core::mem::size_of::<Model2Stepper<f32, Band>>() < flows(6, 7) + 3072);
    // slip's block structure (the rotation on its own; x and u driven by it) is exact in the
    // rounded tables, so the slip step skips those zeros
    assert!(all.slip_flows_are_block_sparse());
    assert!(Model2Stepper::<f64, StribeckBand>::new(&rig_scene(Caliper::Pull, 0.055)).unwrap().slip_flows_are_block_sparse());
    assert!(Model2Stepper::<f32, Stribeck>::new(&stribeck_no_band()).unwrap().slip_flows_are_block_sparse());
}

/// The run-time dispatch is the specialised stepper: the same states, bit for bit.
#[test]
fn the_run_time_choice_is_the_compiled_composition() {
    let scene = stribeck_no_band();
    let mut a = AnyModel2Stepper::<f32>::new(&scene).unwrap();
    let mut b = Model2Stepper::<f32, Stribeck>::new(&scene).unwrap();
    assert_eq!(a.composition(), "stribeck");
    for _ in 0..4000 {
        a.step().unwrap();
        b.step().unwrap();
        assert_eq!(a.state().map(f32::to_bits), b.state().map(f32::to_bits));
    }
}

/// The rig's lockstep model on a model-2 stepper: its x'' agrees with the central difference
/// of the model's own velocity (an independent estimate, to O(dt^2)), and it flags exactly the
/// steps whose regime went from stick to slip.
#[test]
fn the_lockstep_model_runs_model_2() {
    let template = rig_scene(Caliper::Push, 0.040);
    let fs = 25_600.0;
    // 5 bar on the rig's piston gives the scene's F_N of about 0.5 kN: any positive load runs
    let mut m = LockstepModel::<Model2Stepper<f32, StribeckBand>>::stopped();
    m.start(&template, 5.0, 1e-3, template.v, fs).unwrap();
    let mut v = Vec::new();
    let mut xdd = Vec::new();
    let mut onsets = 0;
    let mut regime_onsets = 0;
    let mut last = Regime::Stick;
    for _ in 0..25_600 {
        let s = m.step(0.0).expect("running");
        assert!(!s.halted);
        let st = m.stepper().unwrap();
        v.push(st.state()[1] as f64);
        xdd.push(s.xdd_m_s2 as f64);
        if s.slip_onset {
            onsets += 1;
        }
        if last == Regime::Stick && s.regime != Regime::Stick {
            regime_onsets += 1;
        }
        last = s.regime;
    }
    assert!(onsets > 5, "stick-slip expected: {onsets} onsets");
    assert_eq!(onsets, regime_onsets);
    // central differences away from the transitions (where x'' jumps)
    let dt = 1.0 / fs;
    let scale = xdd.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
    let mut compared = 0;
    for k in 1..v.len() - 1 {
        let cd = (v[k + 1] - v[k - 1]) / (2.0 * dt);
        let smooth = (xdd[k + 1] - 2.0 * xdd[k] + xdd[k - 1]).abs() < 0.01 * scale;
        if smooth {
            compared += 1;
            assert!((cd - xdd[k]).abs() < 0.02 * scale, "step {k}: {cd} vs {}", xdd[k]);
        }
    }
    assert!(compared > 20_000, "{compared} steps compared");
    m.stop();
    assert!(m.step(0.0).is_none());
}

/// Counts, per step, the segments (one per chunk) and the transitions.
#[derive(Default)]
struct ChunkCount {
    segments: u32,
    slip_segments: u32,
    transitions: u32,
}

impl<T: stickslip_model::Real> Model2Observer<T> for ChunkCount {
    const DERIVATIVES: bool = false;
    fn segment(&mut self, seg: &Model2Segment<T>) {
        self.segments += 1;
        if seg.regime != Regime::Stick {
            self.slip_segments += 1;
        }
    }
    fn transition(&mut self, _tr: &Model2Transition<T>) {
        self.transitions += 1;
    }
}

/// Steps of Stribeck slip without a transition that the stepper walks in more than one chunk
/// per substep, out of all such steps, over `seconds` at the scene's step.
fn multi_chunk_slip_steps<T: stickslip_model::Real>(scene: &Scene, seconds: f64) -> (u32, u32) {
    let mut s = AnyModel2Stepper::<T>::new(scene).unwrap();
    let n_sub = s.substeps();
    let (mut multi, mut all) = (0, 0);
    for _ in 0..(seconds / scene.dt).round() as u64 {
        let mut c = ChunkCount::default();
        s.step_observed(&mut c).unwrap();
        if c.transitions == 0 && c.slip_segments == c.segments {
            all += 1;
            if c.segments > n_sub {
                multi += 1;
            }
        }
    }
    (multi, all)
}

/// Stribeck slip near v = 0 takes the near operator (the friction's slope at v = 0 in the
/// exponential), so the steep falling slope does not split a step: at the rig's step every
/// Stribeck slip step without a transition is one ETDRK4 chunk per substep, in the six rig
/// cases with and without the band, in f32 and f64. (With the kinetic operator alone, up to 7 % of
/// the slip steps took 2 to 4 chunks: the 1,000-instruction bound of the M4F's slip
/// step rests on this.)
#[test]
fn stribeck_slip_near_v0_is_one_chunk_per_substep() {
    for caliper in [Caliper::Push, Caliper::Pull] {
        for beta in [0.025, 0.040, 0.055] {
            for band in [true, false] {
                let mut scene = rig_scene(caliper, beta);
                scene.band = band;
                let (m32, a32) = multi_chunk_slip_steps::<f32>(&scene, 0.3);
                let (m64, a64) = multi_chunk_slip_steps::<f64>(&scene, 0.3);
                eprintln!("{caliper:?} beta {beta} band {band}: f32 {m32} of {a32}, f64 {m64} of {a64}");
                assert!(a32 > 100 && a64 > 100, "{caliper:?} {beta} {band}: too few slip steps ({a32}, {a64})");
                assert_eq!((m32, m64), (0, 0), "{caliper:?} beta {beta} band {band}: slip steps in more than one chunk");
            }
        }
    }
}

/// Records every segment and transition a stepper reports, as bits.
#[derive(Default)]
struct Record {
    events: Vec<(u8, u64, Vec<u64>)>,
}

impl<T: stickslip_model::Real> Model2Observer<T> for Record {
    fn segment(&mut self, seg: &Model2Segment<T>) {
        let mut v: Vec<u64> = seg.z0.iter().chain(&seg.z1).chain(&seg.zd0).chain(&seg.zd1).map(|x| x.to_f64().to_bits()).collect();
        v.push(seg.t1.to_bits());
        self.events.push((seg.regime as u8, seg.t0.to_bits(), v));
    }
    fn transition(&mut self, tr: &Model2Transition<T>) {
        self.events.push((10 + tr.to as u8, tr.t.to_bits(), tr.z.iter().map(|x| x.to_f64().to_bits()).collect()));
    }
}

/// Runs `scene` for `steps` steps on the short path (as `step_observed` does) and on the
/// general path only, with an observer on each: the same states, regimes, segments and
/// transitions, bit for bit, and the same halt. Returns the number of stick and slip steps.
fn short_and_general_agree<T: stickslip_model::Real, C: stickslip_model::model2::Composition>(scene: &Scene, steps: usize) -> (usize, usize) {
    let mut short = Model2Stepper::<T, C>::new(scene).unwrap();
    let mut general = Model2Stepper::<T, C>::new(scene).unwrap();
    let (mut rs, mut rg) = (Record::default(), Record::default());
    let (mut stick, mut slip) = (0, 0);
    for n in 0..steps {
        if short.regime() == Regime::Stick {
            stick += 1;
        } else {
            slip += 1;
        }
        let a = short.step_observed(&mut rs);
        let b = general.step_observed_general(&mut rg);
        assert_eq!(a, b, "step {n}: {}", C::NAME);
        assert_eq!(short.state().map(|x| x.to_f64().to_bits()), general.state().map(|x| x.to_f64().to_bits()), "step {n}: {}", C::NAME);
        assert_eq!(short.regime(), general.regime(), "step {n}");
        assert_eq!(short.substeps(), general.substeps(), "step {n}");
        assert!(rs.events == rg.events, "step {n}: {}: the observers saw different segments or transitions", C::NAME);
        rs.events.clear();
        rg.events.clear();
        if a.is_err() {
            break;
        }
    }
    // and without an observer (`step`), the same states
    let mut short = Model2Stepper::<T, C>::new(scene).unwrap();
    let mut general = Model2Stepper::<T, C>::new(scene).unwrap();
    for n in 0..steps {
        let a = short.step();
        let b = general.step_observed_general(&mut ());
        assert_eq!(a, b, "step {n}");
        assert_eq!(short.state().map(|x| x.to_f64().to_bits()), general.state().map(|x| x.to_f64().to_bits()), "step {n}");
        if a.is_err() {
            break;
        }
    }
    (stick, slip)
}

/// A substep whose one chunk neither fires nor crests a guard takes a short path
/// (`short_substep`): it must do exactly what the general path does. Every composition, f32 and
/// f64, push and pull, 0.25 s of the rig set (both regimes, the near operators and transitions).
#[test]
fn the_short_substep_is_the_general_one_bit_for_bit() {
    let steps = 6_400;
    for (caliper, beta) in [(Caliper::Push, 0.040), (Caliper::Pull, 0.055), (Caliper::Push, 0.025)] {
        let all = rig_scene(caliper, beta);
        let mut strib = all;
        strib.band = false;
        let mut band = all;
        band.friction = FrictionLaw::Coulomb;
        let mut coulomb = strib;
        coulomb.friction = FrictionLaw::Coulomb;
        let counts = [
            short_and_general_agree::<f32, StribeckBand>(&all, steps),
            short_and_general_agree::<f64, StribeckBand>(&all, steps),
            short_and_general_agree::<f32, Stribeck>(&strib, steps),
            short_and_general_agree::<f64, Stribeck>(&strib, steps),
            short_and_general_agree::<f32, Band>(&band, steps),
            short_and_general_agree::<f64, Band>(&band, steps),
            short_and_general_agree::<f32, Coulomb>(&coulomb, steps),
        ];
        // the runs cover both regimes
        for (stick, slip) in counts {
            assert!(stick > 100 && slip > 100, "{caliper:?} {beta}: {stick} stick and {slip} slip steps");
        }
    }
}

/// Steps `scene` for `steps` steps and checks, after each, that `pad_acceleration` (which
/// takes the friction's falling part the stepper carries) is bit for bit row 1 of
/// `derivative` (which evaluates it afresh). Returns the steps ending in stick and in slip.
fn pad_acceleration_is_the_derivative<T: Real>(scene: &Scene, steps: u64) -> (u64, u64) {
    let mut s = AnyModel2Stepper::<T>::new(scene).unwrap();
    let (mut stick, mut slip) = (0, 0);
    for k in 0..steps {
        if s.step().is_err() {
            break;
        }
        let want = s.derivative(s.regime(), &s.state())[1];
        let got = s.pad_acceleration();
        assert_eq!(got.to_f64().to_bits(), want.to_f64().to_bits(), "{}: step {k}: {:?}", s.composition(), s.regime());
        if s.regime() == Regime::Stick {
            stick += 1;
        } else {
            slip += 1;
        }
    }
    (stick, slip)
}

#[test]
fn the_pad_acceleration_is_the_derivatives_row_bit_for_bit() {
    use stickslip_model::rig_set::{rig_float_scene, rig_scene as fitted};
    let mut scenes = vec![rig_scene(Caliper::Push, 0.040), stribeck_no_band(), fitted(Caliper::Pull, 0.055)];
    for v in [0.001, 0.004] {
        let mut f = rig_float_scene(Caliper::Push, 0.040);
        f.v = v;
        scenes.push(f);
    }
    let (mut slipped, mut stuck) = (0, 0);
    for scene in &scenes {
        let steps = (0.5 / scene.dt).round() as u64;
        for (stick, slip) in [pad_acceleration_is_the_derivative::<f64>(scene, steps), pad_acceleration_is_the_derivative::<f32>(scene, steps)] {
            slipped += usize::from(slip > 0);
            stuck += usize::from(stick > 0);
        }
    }
    // the check covers both regimes (slip: the carried falling part) in most runs
    assert!(slipped >= 6 && stuck >= 6, "{slipped} of 10 runs slip, {stuck} stick");
}
