//! The pneumatic drive's runner (`stickslip_model::model3::pneumatic_run::PneumaticRunner`,
//! Dormand-Prince 5(4) with Illinois event location, run as the host runs it at rtol 1e-10)
//! against the independent reference (`stickslip::numerics::reference::pneumatic`: its own
//! right-hand side from docs/model.md, DOP853 with bisected events, rtol 1e-12): the same pad
//! and band transitions at the same times, the same final state and drive statistics, on
//! three scenes; the two right-hand sides at every sample of the product's run; the throttle
//! solved from V; and the reference against itself at half its tolerance.
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

/// The 1-DOF pad (rotation held) on a soft pneumatic band whose seal stick-slips (the energy
/// balance's scene of tests/pneumatic.rs): 10 pad transitions, 19 band stops and breakaways.
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

/// The rig-built set's bilateral twin (floating pad, friction face, contact law p = 1.5; push,
/// centre) on a 15 mm column with no drop in the seal's friction: the band slides most of the
/// window and the pad stick-slips near 55 Hz. The throttle is given (2e-11 m^3/(s Pa)): the
/// product solves it from the hinged pad's N_0 (see `the_throttle_is_solved_from_the_static_normal_force`).
fn floating_no_drop() -> Scene {
    let mut s = rig_set::rig_built_scene(Caliper::Push, 0.04);
    s.contact = stickslip_model::ContactLaw::Bilateral;
    s.drive = BandDrive::Pneumatic;
    s.column_length = 0.015;
    s.seal_kinetic = s.seal_static;
    s.duration = 1.0;
    s.stats_from = 0.5;
    s.throttle_conductance = 2.0e-11;
    s
}

/// `rig_push_center` (the hinged rig set, push, beta 40 mm) with the pneumatic drive on a
/// 15 mm column and a seal of 40 / 30 N (the default 80 / 60 N breaks away only every 1.5 to
/// 2 s): the band breaks away 6 times in 1 s, the pad slips once per breakaway.
fn rig_small_seal() -> Scene {
    // the accuracy report's pneumatic scene
    stickslip::numerics::accuracy::pneumatic_scene()
}

/// Largest differences between a product run and a reference run.
#[derive(Debug, Default)]
struct Diff {
    pad_dt: f64,
    band_dt: f64,
    /// Final x, x', phi, phi', x_b, x_b', p, each relative to its range over the window.
    state: [f64; 7],
    mean_speed: f64,
    stuck_fraction: f64,
    /// p's least, greatest and mean, relative to its range.
    p: [f64; 3],
}

impl Diff {
    fn line(&self) -> String {
        let e = |v: &[f64]| v.iter().map(|x| format!("{x:.1e}")).collect::<Vec<_>>().join(" ");
        format!(
            "pad transitions {:.1e} s, band events {:.1e} s; final x x' phi phi' x_b x_b' p / range: {}; band mean speed {:.1e}, stuck fraction {:.1e}; p min max mean / range: {}",
            self.pad_dt,
            self.band_dt,
            e(&self.state),
            self.mean_speed,
            self.stuck_fraction,
            e(&self.p)
        )
    }
}

fn compare(name: &str, p: &ProductRun, r: &Run, r_secs: f64) -> Diff {
    let pad_dt = worst_dt(&pad_kinds(&p.pad), &pad_kinds(&r.pad_transitions()))
        .unwrap_or_else(|| panic!("{name}: pad transitions differ:\nproduct {:?}\nreference {:?}", p.pad, r.pad_transitions()));
    let rb = ref_band(r);
    let band_dt = worst_dt(&p.band, &rb).unwrap_or_else(|| panic!("{name}: band events differ:\nproduct {:?}\nreference {:?}", p.band, rb));
    assert_eq!(p.band.len() as u64, p.band_changes, "{name}: the product's band events as read from its segments");
    let st = &r.stats;
    let f = &r.final_state;
    let ours = [f[0], f[1], f[2], f[3], f[XB], f[XB + 1], f[P]];
    let p_range = st.p_max - st.p_min;
    let ranges = [st.pad.pp(0), st.pad.pp(1), st.pad.pp(2), st.pad.pp(3), f[XB].abs(), st.band_speed_max - st.band_speed_min, p_range];
    let state = std::array::from_fn(|i| {
        let d = (p.last[i] - ours[i]).abs();
        if d == 0.0 {
            0.0
        } else {
            d / ranges[i]
        }
    });
    let d = &p.drive;
    let diff = Diff {
        pad_dt,
        band_dt,
        state,
        mean_speed: (d.mean_speed() / st.band_mean_speed - 1.0).abs(),
        stuck_fraction: (d.stuck_fraction() - st.band_stuck_fraction).abs(),
        p: [(d.p_min - st.p_min).abs() / p_range, (d.p_max - st.p_max).abs() / p_range, (d.p_mean - st.p_mean).abs() / p_range],
    };
    assert_eq!(d.breakaways as usize, st.band_breakaways, "{name}: band breakaways in the window");
    eprintln!(
        "{name}: {} pad transitions, {} band events ({} breakaways in the window, stuck {:.4}, mean speed {:.4e} m/s, p {:.0} to {:.0} Pa); \
         product {} steps in {:.3} s, reference {} steps in {:.3} s\n  differences: {}",
        p.pad.len(),
        p.band.len(),
        st.band_breakaways,
        st.band_stuck_fraction,
        st.band_mean_speed,
        st.p_min,
        st.p_max,
        p.steps,
        p.secs,
        r.accepted_steps,
        r_secs,
        diff.line(),
    );
    diff
}

/// Transition times agree within this [s] (measured: at most 7.7e-11 s, the 1-DOF scene's).
const T_BOUND: f64 = 1e-9;
/// The final state, each quantity relative to its range over the window (measured: at most
/// 8.2e-10, the floating pad's x').
const STATE_BOUND: f64 = 1e-8;
/// The band's mean speed (relative), stuck fraction (absolute), and p's least, greatest and mean
/// relative to its range (measured: at most 1.7e-8, p's greatest on the hinged rig: the product
/// takes it at its step ends, the reference bisects the crest).
const STATS_BOUND: f64 = 2e-7;

fn check(name: &str, s: &Scene, min_pad: usize, min_breakaways: usize) -> Diff {
    let p = run_product(s);
    let (r, secs) = run_reference(s, Tolerances::default());
    let d = compare(name, &p, &r, secs);
    assert!(p.pad.len() >= min_pad, "{name}: the pad should slip: {} transitions", p.pad.len());
    assert!(r.stats.band_breakaways >= min_breakaways, "{name}: the band should stick and break away: {:?}", r.stats);
    assert!(r.stats.band_stuck_fraction < 1.0 && r.stats.band_mean_speed > 0.0, "{name}: the band should slide: {:?}", r.stats);
    assert!(d.pad_dt <= T_BOUND && d.band_dt <= T_BOUND, "{name}: transition times differ: {d:?}");
    assert!(d.state.iter().all(|e| *e <= STATE_BOUND), "{name}: final states differ: {d:?}");
    assert!(d.mean_speed <= STATS_BOUND && d.stuck_fraction <= STATS_BOUND && d.p.iter().all(|e| *e <= STATS_BOUND), "{name}: drive statistics differ: {d:?}");
    d
}

#[test]
fn the_hinged_rig_pad_agrees_with_the_reference() {
    check("rig_push_center, pneumatic, 15 mm column, seal 40 / 30 N, 1 s", &rig_small_seal(), 6, 4);
}

#[test]
fn the_one_dof_pad_on_a_stick_slipping_seal_agrees_with_the_reference() {
    check("1-DOF pad, soft band, seal 30 / 25 N, 0.8 s", &one_dof_seal_stick_slip(), 10, 5);
}

#[test]
fn the_floating_pad_with_a_seal_without_drop_agrees_with_the_reference() {
    check("rig_built_push_center bilateral, pneumatic, seal without drop, 1 s", &floating_no_drop(), 20, 5);
}

/// The reference against itself at half its tolerance (rtol 2e-12 against 1e-12): its
/// transitions move by far less than `T_BOUND`.
#[test]
fn the_reference_converges() {
    for (name, s) in [("rig", rig_small_seal()), ("1-DOF", one_dof_seal_stick_slip()), ("floating", floating_no_drop())] {
        let (fine, _) = run_reference(&s, Tolerances::default());
        let (coarse, _) = run_reference(&s, Tolerances { rtol: 2e-12, ..Tolerances::default() });
        let pad = worst_dt(&pad_kinds(&fine.pad_transitions()), &pad_kinds(&coarse.pad_transitions())).expect("the same pad transitions");
        let band = worst_dt(&ref_band(&fine), &ref_band(&coarse)).expect("the same band events");
        let f = &fine.stats;
        let c = &coarse.stats;
        let p = (f.p_max - c.p_max).abs().max((f.p_min - c.p_min).abs()) / (f.p_max - f.p_min);
        eprintln!("reference at rtol 1e-12 against 2e-12, {name}: pad transitions within {pad:.2e} s, band events within {band:.2e} s, p extremes within {p:.2e} of the range");
        assert!(pad < T_BOUND / 10.0 && band < T_BOUND / 10.0 && p < STATS_BOUND / 10.0, "{name}: the reference moves with its tolerance");
    }
}

/// The throttle solved from V (`throttle_conductance = 0`): p_0 = p_atm + (F_seal(V) + mu(V) N_0
/// + c_b V) / A, C = p_0 A V / (p_ref p_s phi(p_0 / p_s)), N_0 the pad's static normal force
/// (written out here once more). The product and the reference agree on the hinged pad; on the
/// floating pad (N_0 = F_N with k_pivot = 0) the product takes the hinged pad's c_N F_N a_N / K
/// (printed; `the_product_solves_the_floating_pads_throttle_from_its_static_normal_force`).
#[test]
fn the_throttle_is_solved_from_the_static_normal_force() {
    let closed_form = |s: &Scene, n0: f64| {
        let area = std::f64::consts::PI * s.bore * s.bore / 4.0;
        let mu = s.mu_k + (s.mu_s - s.mu_k) * (-(s.v / s.v_s).powf(s.stribeck_exponent)).exp();
        let seal = s.seal_kinetic + (s.seal_static - s.seal_kinetic) * (-s.v / s.seal_v_s).exp();
        let p0 = stickslip_model::scene::ATMOSPHERE_PA + (seal + mu * n0 + s.c_b * s.v) / area;
        let r = p0 / s.supply_pressure;
        let b = s.throttle_critical_ratio;
        let phi = if r <= b { 1.0 } else { (1.0 - ((r - b) / (1.0 - b)).powi(2)).sqrt() };
        p0 * area * s.v / (1e5 * s.supply_pressure * phi)
    };
    let short = |s: &Scene| {
        let mut q = *s;
        q.throttle_conductance = 0.0;
        q.duration = 1e-3;
        q.stats_from = 0.0;
        q
    };
    let hinged = short(&rig_small_seal());
    let r = reference::simulate(&hinged, Tolerances::default()).unwrap();
    let product = PneumaticRunner::new(&hinged, PNEUMATIC_RTOL).unwrap().cylinder().conductance;
    let co = stickslip_model::Coefficients::of(&hinged);
    let expect = closed_form(&hinged, co.c_n * hinged.f_n * co.a_n / co.k_rot);
    eprintln!("throttle, hinged: reference {:.15e}, product {product:.15e}, closed form {expect:.15e}", r.conductance);
    assert!((r.conductance / expect - 1.0).abs() < 1e-13 && (product / expect - 1.0).abs() < 1e-13);
    let floating = short(&floating_no_drop());
    let r = reference::simulate(&floating, Tolerances::default()).unwrap();
    let product = PneumaticRunner::new(&floating, PNEUMATIC_RTOL).unwrap().cylinder().conductance;
    assert_eq!(floating.k_pivot, 0.0);
    let expect = closed_form(&floating, floating.f_n);
    eprintln!(
        "throttle, floating: reference {:.15e}, closed form with N_0 = F_N {expect:.15e}, product {product:.15e} ({:+.2} %)",
        r.conductance,
        100.0 * (product / expect - 1.0)
    );
    assert!((r.conductance / expect - 1.0).abs() < 1e-13);
    // the product's solve takes the floating pad's static normal force too (it took the hinged
    // pad's c_N F_N a_N / K before: 8.1 % too little conductance on this twin)
    assert!((product / expect - 1.0).abs() < 1e-12, "product {product:e}, closed form {expect:e}");
}

/// The two right-hand sides at every grid sample of the product's run (the product's state and
/// regimes, its own derivative against the reference's `rhs`): x', x'', phi', phi'', x_b'',
/// y', y'', p', each relative to its largest magnitude over the run.
#[test]
fn the_right_hand_sides_agree_at_every_sample() {
    for (name, s) in [("rig", rig_small_seal()), ("1-DOF", one_dof_seal_stick_slip()), ("floating", floating_no_drop())] {
        let mut runner = PneumaticRunner::new(&s, PNEUMATIC_RTOL).expect("runner");
        let mut pairs: Vec<([f64; 8], [f64; 8])> = vec![];
        let mut failure: Option<String> = None;
        runner
            .run_sampled(0.0, s.duration, s.dt, &mut (), &mut |g: &PneumaticSample| {
                let w = &g.w;
                let y = [w[0], w[1], w[2], w[3], w[product::XB], s.v + w[5], w[6], w[7], w[product::P], 0.0];
                let band = match g.band {
                    0 => Band::Stuck,
                    1 => Band::Forward,
                    _ => Band::Back,
                };
                let r = reference::Regime { pad: pad_of(g.regime), band, pad_armed: true, band_armed: true };
                match reference::rhs(&s, r, &y) {
                    Ok(d) => {
                        let ours = [d[0], d[1], d[2], d[3], d[5], d[6], d[7], d[P]];
                        let theirs = [g.d[0], g.d[1], g.d[2], g.d[3], g.d[5], g.d[6], g.d[7], g.d[product::P]];
                        pairs.push((theirs, ours));
                        true
                    }
                    Err(e) => {
                        failure = Some(e);
                        false
                    }
                }
            })
            .expect("the product's run completes");
        assert!(failure.is_none(), "{failure:?}");
        let mut worst = [0.0f64; 8];
        for i in 0..8 {
            let scale = pairs.iter().map(|(a, _)| a[i].abs()).fold(0.0, f64::max);
            if scale > 0.0 {
                worst[i] = pairs.iter().map(|(a, b)| (a[i] - b[i]).abs()).fold(0.0, f64::max) / scale;
            }
        }
        eprintln!("right-hand sides, {name}, {} samples: x' x'' phi' phi'' x_b'' y' y'' p' differ by at most {} of their largest magnitudes", pairs.len(), worst.iter().map(|e| format!("{e:.1e}")).collect::<Vec<_>>().join(" "));
        assert!(worst.iter().all(|e| *e < 1e-10), "{name}: {worst:?}");
    }
}
