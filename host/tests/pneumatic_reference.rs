//! The pneumatic drive's runner (`stickslip_model::model3::pneumatic_run::PneumaticRunner`,
//! Dormand-Prince 5(4) with Illinois event location, run as the host runs it at rtol 1e-10)
//! against the independent reference (`stickslip::numerics::reference::pneumatic`: its own
//! right-hand side from docs/model.md, DOP853 with bisected events, rtol 1e-12): the same pad
//! and band transitions at the same times, the same final state and drive statistics, on
//! three scenes. And the reference against itself at half its tolerance.
//!
//! `cargo test --release -p stickslip --test pneumatic_reference -- --nocapture` prints the
//! measured differences.

use std::time::Instant;
use stickslip::numerics::reference::pneumatic::{self as reference, Band, PadRegime, Run, Tolerances, P, XB};
use stickslip::scenes::pneumatic::PNEUMATIC_RTOL;
use stickslip_model::model2::stepper::{Model2Observer, Model2Segment, Model2Transition};
use stickslip_model::model3::pneumatic_run::{self as product, DriveStats, PneumaticRunner, PneumaticSample};
use stickslip_model::{rig_set, BandDrive, Caliper, Regime, Scene};

/// A band event: its time and whether it is a breakaway (true) or a stop (false).
type BandEvent = (f64, bool);

/// What the product's run gave.
struct ProductRun {
    pad: Vec<(f64, PadRegime, PadRegime)>,
    band: Vec<BandEvent>,
    /// x, x', phi, phi', x_b, x_b', p at the end.
    last: [f64; 7],
    drive: DriveStats,
    steps: u64,
    band_changes: u64,
    secs: f64,
}

/// The product's transitions (pad: as reported; band: from its segments, a stuck band's
/// segment having u' = -V and u'' = 0 at both ends exactly).
struct Watch {
    v: f64,
    pad: Vec<(f64, PadRegime, PadRegime)>,
    band: Vec<BandEvent>,
    /// The previous segment: whether the band was stuck in it.
    prev_stuck: Option<bool>,
}

fn pad_of(r: Regime) -> PadRegime {
    match r {
        Regime::Stick => PadRegime::Stick,
        Regime::SlipSlower => PadRegime::Slower,
        Regime::SlipFaster => PadRegime::Faster,
    }
}

impl Model2Observer<f64> for Watch {
    fn segment(&mut self, s: &Model2Segment<f64>) {
        let at_rest = |u_dot: f64| u_dot == -self.v;
        let stuck = at_rest(s.z0[5]) && at_rest(s.z1[5]) && s.zd0[5] == 0.0 && s.zd1[5] == 0.0;
        match self.prev_stuck {
            Some(false) if at_rest(s.z0[5]) => self.band.push((s.t0, false)),
            Some(true) if !stuck => self.band.push((s.t0, true)),
            _ => {}
        }
        self.prev_stuck = Some(stuck);
    }
    fn transition(&mut self, tr: &Model2Transition<f64>) {
        self.pad.push((tr.t, pad_of(tr.from), pad_of(tr.to)));
    }
}

fn run_product(s: &Scene) -> ProductRun {
    let clock = Instant::now();
    let mut runner = PneumaticRunner::new(s, PNEUMATIC_RTOL).expect("the product's runner");
    let mut watch = Watch { v: s.v, pad: vec![], band: vec![], prev_stuck: None };
    runner.run_sampled(s.stats_from, s.duration, s.dt, &mut watch, &mut |_: &PneumaticSample| true).expect("the product's run completes");
    let secs = clock.elapsed().as_secs_f64();
    let w = runner.state();
    ProductRun {
        pad: watch.pad,
        band: watch.band,
        last: [w[0], w[1], w[2], w[3], w[product::XB], s.v + w[5], w[product::P]],
        drive: runner.drive_stats(),
        steps: runner.counts().steps,
        band_changes: runner.counts().band_changes,
        secs,
    }
}

fn run_reference(s: &Scene, tol: Tolerances) -> (Run, f64) {
    let clock = Instant::now();
    let r = reference::simulate(s, tol).expect("the reference run completes");
    (r, clock.elapsed().as_secs_f64())
}

fn ref_band(r: &Run) -> Vec<BandEvent> {
    r.band_transitions().iter().map(|&(t, from, _)| (t, from == Band::Stuck)).collect()
}

/// The largest time difference between two lists of events of the same kinds (None: the
/// counts or the kinds differ).
fn worst_dt<K: PartialEq + Copy>(a: &[(f64, K)], b: &[(f64, K)]) -> Option<f64> {
    if a.len() != b.len() || a.iter().zip(b).any(|(x, y)| x.1 != y.1) {
        return None;
    }
    Some(a.iter().zip(b).map(|(x, y)| (x.0 - y.0).abs()).fold(0.0, f64::max))
}

fn pad_kinds(v: &[(f64, PadRegime, PadRegime)]) -> Vec<(f64, (PadRegime, PadRegime))> {
    v.iter().map(|&(t, f, to)| (t, (f, to))).collect()
}

/// The rig scene (push, centre) driven by the cylinder.
fn rig_pneumatic() -> Scene {
    let mut s = rig_set::rig_scene(Caliper::Push, 0.04);
    s.drive = BandDrive::Pneumatic;
    s.duration = 0.6;
    s.stats_from = 0.1;
    s
}

fn one_dof_seal_stick_slip() -> Scene {
    let mut s = rig_set::rig_scene(Caliper::Push, 0.04);
    s.k_b = 2.0e4;
    s.m_b = 0.5;
    s.rotation = false;
    s.drive = BandDrive::Pneumatic;
    s.c_b = 5.0;
    s.column_length = 0.01;
    s.seal_static = 30.0;
    s.seal_kinetic = 25.0;
    s.seal_v_s = 0.005;
    s.duration = 0.8;
    s.stats_from = 0.1;
    s.dt = 1e-4;
    s
}

fn floating_no_drop() -> Scene {
    let mut s = rig_set::rig_built_scene(Caliper::Push, 0.04);
    s.contact = stickslip_model::ContactLaw::Bilateral;
    s.drive = BandDrive::Pneumatic;
    s.column_length = 0.015;
    s.seal_kinetic = s.seal_static;
    s.duration = 0.3;
    s.stats_from = 0.1;
    s.throttle_conductance = 2.0e-11;
    s
}

fn rig_small_seal() -> Scene {
    let mut s = rig_pneumatic();
    s.column_length = 0.015;
    s.seal_static = 40.0;
    s.seal_kinetic = 30.0;
    s
}

#[test]
fn explore() {
    let mut hinged_nodrop = rig_pneumatic();
    hinged_nodrop.column_length = 0.015;
    hinged_nodrop.seal_kinetic = hinged_nodrop.seal_static;
    hinged_nodrop.duration = 0.3;
    let mut face = hinged_nodrop;
    face.face = true;
    let mut fl_nodamp = floating_no_drop();
    fl_nodamp.c_b = 0.0;
    let mut fl_lin = floating_no_drop();
    fl_lin.contact_exponent = 1.0;
    for (name, s) in [("hinged no drop", hinged_nodrop), ("hinged face no drop", face), ("floating", floating_no_drop()), ("floating c_b 0", fl_nodamp), ("floating linear", fl_lin)] {
        eprintln!("start product {:?}", PneumaticRunner::new(&s, 1e-10).unwrap().state());
        let p = run_product(&s);
        let (r, secs) = run_reference(&s, Tolerances::default());
        eprintln!("== {name}: product {} steps {:.3} s, reference {} steps {:.3} s", p.steps, p.secs, r.accepted_steps, secs);
        eprintln!("pad counts {} {} dt {:?}", p.pad.len(), r.pad_transitions().len(), worst_dt(&pad_kinds(&p.pad), &pad_kinds(&r.pad_transitions())));
        eprintln!("band counts {} ({}) {} dt {:?}", p.band.len(), p.band_changes, ref_band(&r).len(), worst_dt(&p.band, &ref_band(&r)));
        if p.pad.len() < 12 { eprintln!("product pad {:?}\nref pad {:?}", p.pad, r.pad_transitions()); }
        if p.band.len() < 12 { eprintln!("product band {:?}\nref band {:?}", p.band, r.band_transitions()); }
        eprintln!("product last {:?}\nref final {:?}\nref start {:?}", p.last, r.final_state, r.start);
        eprintln!("product drive {:?}\nref stats {:?}", p.drive, r.stats);
    }
    let _ = (P, XB);
}

#[test]
fn derivative_probe() {
    let s = floating_no_drop();
    let mut runner = PneumaticRunner::new(&s, 1e-10).unwrap();
    let mut first: Option<PneumaticSample> = None;
    runner.run_sampled(0.0, 1e-5, 1e-5, &mut (), &mut |g: &PneumaticSample| { first = Some(*g); false }).unwrap();
    let g = first.unwrap();
    let w = g.w;
    let y = [w[0], w[1], w[2], w[3], w[product::XB], s.v + w[5], w[6], w[7], w[product::P], 0.0];
    let r = reference::Regime { pad: PadRegime::Stick, band: Band::Forward, pad_armed: true, band_armed: true };
    let d = reference::rhs(&s, r, &y).unwrap();
    eprintln!("product d {:?}\nref     d {:?}", g.d, d);
    let (_, secs) = (0, 0);
    let _ = secs;
    let co = stickslip_model::Coefficients::of(&s.linearised_contact());
    let rr = reference::simulate(&{ let mut q = s; q.duration = 1e-4; q.stats_from = 0.0; q }, Tolerances::default()).unwrap();
    eprintln!("C product {:e} ref {:e}; Coefficients n0 {} F_N {} steady_pad_friction {}", runner.drive_stats().conductance, rr.conductance, co.n0, s.f_n, stickslip_model::model3::cylinder::steady_pad_friction(&s));
}
