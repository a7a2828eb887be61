//! Unilateral contact (`contact = "unilateral"`; issue 34, option 2): the edges of the floating
//! pad open and close again. Checked here:
//! - where no edge opens, a unilateral run is the bilateral run (the fixed-step stepper's, an
//!   independent method) within the event runner's tolerance, and the hinged limit (a stiff
//!   pivot) the same;
//! - a scene whose lead edge opens and closes many times completes with its open fraction and
//!   openings reported, and its energy balance closes, with the power integrated along each
//!   segment by RK4 on a right-hand side written here from docs/model.md's equations with the
//!   springs' F_i = k_i max(0, d_i) (not the model crate's matrices);
//! - the edge events are found whatever the grid: the same openings and open time at every
//!   step from 1e-5 to 2e-3 s (at the runs' tolerance, 1e-12: at 1e-10 a step of 1e-3 s lost 3
//!   of 42 openings of this scene, near-grazing dips whose depth is the state's error);
//! - the fixed-step stepper (and so the firmware's chain) refuses such a scene, and a hinged
//!   pad with unilateral contact is a bad scene.

use stickslip::scenes::run::{self, Precision, RunReport};
use stickslip::scenes::series::NoSink;
use stickslip_model::model2::event_run::edges::{LEAD, TRAIL};
use stickslip::scenes::unilateral::UNILATERAL_RTOL;
use stickslip_model::model2::event_run::{EventRunner, GridSample};
use stickslip_model::model2::{AnyModel2Stepper, Model2Observer, Model2Segment, NS, Y};
use stickslip_model::{rig_set, Caliper, Coefficients, ContactLaw, Regime, Scene};

/// The floating rig scene `rig_float_push_center` turned to the pull caliper with the load
/// 11.5 mm from the trailing edge: its lead edge opens and closes about 160 times in the
/// window (found by a scan of beta, both calipers).
fn chattering() -> Scene {
    let mut s = rig_set::rig_float_scene(Caliper::Push, 0.04);
    s.caliper = Caliper::Pull;
    s.beta = 0.0115;
    s.contact = ContactLaw::Unilateral;
    s
}

fn report(s: &Scene) -> RunReport {
    run::run(s, Precision::F64, &mut NoSink).expect("the run")
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-300)
}

#[test]
fn where_no_edge_opens_unilateral_contact_is_the_bilateral_run() {
    let mut cases = vec![];
    for (caliper, beta) in [(Caliper::Push, 0.04), (Caliper::Pull, 0.025), (Caliper::Push, 0.055)] {
        cases.push(rig_set::rig_float_scene(caliper, beta));
        // the hinged limit: a stiff pivot (damped at 0.1 of critical) holds y near 0
        let mut stiff = rig_set::rig_float_scene(caliper, beta);
        stiff.k_pivot = 1e9;
        stiff.c_y = 2.0 * 0.1 * (stiff.k_pivot * stiff.m).sqrt();
        cases.push(stiff);
    }
    for bilateral in cases {
        let mut uni = bilateral;
        uni.contact = ContactLaw::Unilateral;
        let (a, b) = (report(&bilateral), report(&uni));
        let edges = b.edges.expect("a unilateral run reports its edges");
        assert_eq!(edges.openings_run, [0, 0], "{:?} beta {}: an edge opened", uni.caliper, uni.beta);
        assert_eq!(a.outcome.keyword(), "completed");
        assert_eq!(b.outcome.keyword(), "completed");
        assert_eq!(a.stats.slip_onsets, b.stats.slip_onsets, "{:?} beta {} k_pivot {}", uni.caliper, uni.beta, uni.k_pivot);
        for i in 0..4 {
            let (pa, pb) = (a.pp(i).unwrap(), b.pp(i).unwrap());
            // the stepper's own error and the event runner's (rtol 1e-10) over 1 s of stick-slip
            assert!(close(pa, pb, 1e-5), "pp[{i}]: bilateral {pa:e}, unilateral {pb:e}");
        }
        assert!(close(a.stats.stick_slip_hz, b.stats.stick_slip_hz, 1e-6));
        assert!((a.stats.stick_fraction - b.stats.stick_fraction).abs() < 1e-5);
        let (ma, mb) = (a.model2.unwrap(), b.model2.unwrap());
        // the stepper takes x'' at its substeps' ends, the event runner at its located extremes
        assert!(close(ma.pad_acc_pp, mb.pad_acc_pp, 2e-4), "pad x'' pp {} vs {}", ma.pad_acc_pp, mb.pad_acc_pp);
    }
}

#[test]
fn an_edge_that_opens_and_closes_is_a_regime_reported_per_edge() {
    let s = chattering();
    let r = report(&s);
    assert_eq!(r.outcome.keyword(), "completed");
    let e = r.edges.unwrap();
    eprintln!("lead open {:.4} ({} openings), trail open {:.4} ({} openings)", e.open_fraction(LEAD), e.openings[LEAD], e.open_fraction(TRAIL), e.openings[TRAIL]);
    assert!(e.openings[LEAD] >= 50, "{e:?}");
    assert!(e.open_fraction(LEAD) > 0.01 && e.open_fraction(LEAD) < 0.9, "{e:?}");
    assert!((e.window_s - (s.duration - s.stats_from)).abs() < 1e-9);
    // the bilateral model halts there
    let mut bi = s;
    bi.contact = ContactLaw::Bilateral;
    assert_eq!(report(&bi).outcome.keyword(), "contact_loss");
}

/// The floating pad's equations with unilateral springs, written from docs/model.md
/// ("The floating pad"), independent of the model crate's matrices.
struct Pad {
    s: Scene,
    co: Coefficients,
}

impl Pad {
    fn compressions(&self, z: &[f64; NS]) -> [f64; 2] {
        [z[Y] + self.co.d_l * z[2], z[Y] + self.co.d_t * z[2]]
    }

    /// z' and the friction force on the pad F in `regime` (stick: the force that holds the
    /// face on the band; slip: sigma mu(|v|) N).
    fn rhs(&self, regime: Regime, z: &[f64; NS]) -> ([f64; NS], f64) {
        let (s, co) = (&self.s, &self.co);
        let d = self.compressions(z);
        let [k_l, k_t] = s.contact_stiffnesses();
        let f_l = k_l * d[0].max(0.0);
        let f_t = k_t * d[1].max(0.0);
        let n = f_l + f_t;
        let sw = co.s * s.w;
        let qx = -s.k_g * z[0] - s.c_x * z[1];
        let qphi = s.f_n * co.a_n - f_l * co.d_l - f_t * co.d_t - s.c_phi * z[3];
        let qy = s.f_n - n - s.k_pivot * z[Y] - s.c_y * z[Y + 1];
        let qu = if s.band { -s.k_b * z[4] - s.c_b * z[5] } else { 0.0 };
        let ml = s.m * s.l;
        let det = s.inertia * s.m - ml * ml;
        let (ipp, ipy, iyy) = (s.m / det, -ml / det, s.inertia / det);
        let acc = |f: f64| {
            let ax = (qx + f) / s.m;
            let aphi = ipp * (qphi + sw * f) + ipy * qy;
            let ay = ipy * (qphi + sw * f) + iyy * qy;
            let au = if s.band { (qu - f) / s.m_b } else { 0.0 };
            (ax, aphi, ay, au)
        };
        let f = match regime {
            Regime::Stick => {
                let (ax, aphi, _, au) = acc(0.0);
                let inv = 1.0 / s.m + sw * ipp * sw + if s.band { 1.0 / s.m_b } else { 0.0 };
                -(ax + sw * aphi - au) / inv
            }
            _ => {
                let v = z[1] + sw * z[3] - s.v - z[5];
                let mu = s.mu_k + (s.mu_s - s.mu_k) * (-(v.abs() / s.v_s).powf(s.stribeck_exponent)).exp();
                regime.friction_sign() * mu * n
            }
        };
        let (ax, aphi, ay, au) = acc(f);
        ([z[1], ax, z[3], aphi, z[5], au, z[Y + 1], ay], f)
    }

    fn energy(&self, z: &[f64; NS]) -> f64 {
        let (s, co) = (&self.s, &self.co);
        let d = self.compressions(z);
        let [k_l, k_t] = s.contact_stiffnesses();
        let xb_dot = s.v + z[5];
        0.5 * s.m * z[1] * z[1]
            + 0.5 * s.inertia * z[3] * z[3]
            + s.m * s.l * z[Y + 1] * z[3]
            + 0.5 * s.m * z[Y + 1] * z[Y + 1]
            + 0.5 * s.k_g * z[0] * z[0]
            + 0.5 * k_l * d[0].max(0.0).powi(2)
            + 0.5 * k_t * d[1].max(0.0).powi(2)
            + 0.5 * s.k_pivot * z[Y] * z[Y]
            - s.f_n * (z[Y] + co.a_n * z[2])
            + 0.5 * s.m_b * xb_dot * xb_dot
            + 0.5 * s.k_b * z[4] * z[4]
    }

    /// [drive, friction dissipation, damping dissipation] [W].
    fn powers(&self, z: &[f64; NS], f: f64) -> [f64; 3] {
        let s = &self.s;
        let band_v = s.v + z[5];
        let drive = s.v * (-s.k_b * z[4] - s.c_b * z[5]);
        let face_v = z[1] + self.co.s * s.w * z[3];
        let friction = -f * (face_v - band_v);
        let damping = s.c_x * z[1] * z[1] + s.c_phi * z[3] * z[3] + s.c_b * z[5] * z[5] + s.c_y * z[Y + 1] * z[Y + 1];
        [drive, friction, damping]
    }
}

struct Segments(Vec<(Regime, f64, f64, [f64; NS], [f64; NS])>);

impl Model2Observer<f64> for Segments {
    fn segment(&mut self, seg: &Model2Segment<f64>) {
        self.0.push((seg.regime, seg.t0, seg.t1, seg.z0, seg.z1));
    }
}

/// The energy balance of a unilateral run of `s` over [stats_from, duration]: the power
/// integrated by RK4 along each of the event runner's segments on [`Pad`]'s right-hand side.
/// Returns (residual relative to the largest term, the largest RK4 end error over the state's
/// scale, segments, openings over the run [lead, trail], each edge's load swing over the window:
/// peak-to-peak over the segments' ends relative to its mid-range load [lead, trail]).
fn energy_balance(s: Scene) -> (f64, f64, usize, [u64; 2], [f64; 2]) {
    let mut runner = EventRunner::new(&s, UNILATERAL_RTOL).unwrap();
    let mut segs = Segments(Vec::new());
    runner.run(s.stats_from, s.duration, &mut segs).expect("the run completes");
    let openings = runner.edges().unwrap().openings_run;
    let pad = Pad { s, co: Coefficients::of(&s) };
    let (mut work, mut stored, mut end_error) = ([0.0; 3], 0.0, 0.0f64);
    for &(regime, t0, t1, z0, z1) in &segs.0 {
        const PIECES: usize = 16;
        let h = (t1 - t0) / PIECES as f64;
        let mut z = z0;
        let axpy = |z: &[f64; NS], d: &[f64; NS], a: f64| -> [f64; NS] { core::array::from_fn(|r| z[r] + a * d[r]) };
        let f = |z: &[f64; NS]| {
            let (zd, force) = pad.rhs(regime, z);
            (zd, pad.powers(z, force))
        };
        for _ in 0..PIECES {
            let (k1, p1) = f(&z);
            let (k2, p2) = f(&axpy(&z, &k1, h / 2.0));
            let (k3, p3) = f(&axpy(&z, &k2, h / 2.0));
            let (k4, p4) = f(&axpy(&z, &k3, h));
            for r in 0..NS {
                z[r] += h / 6.0 * (k1[r] + 2.0 * k2[r] + 2.0 * k3[r] + k4[r]);
            }
            for c in 0..3 {
                work[c] += h / 6.0 * (p1[c] + 2.0 * p2[c] + 2.0 * p3[c] + p4[c]);
            }
        }
        stored += pad.energy(&z1) - pad.energy(&z0);
        let scale = [1e-3, 0.1, 1e-3, 10.0, 1e-3, 0.1, 1e-3, 0.1];
        for r in 0..NS {
            end_error = end_error.max((z[r] - z1[r]).abs() / scale[r]);
        }
    }
    let [drive, friction, damping] = work;
    let residual = (drive - (friction + damping + stored)).abs() / drive.abs().max(friction.abs()).max(damping.abs());
    let k = s.contact_stiffnesses();
    let swing: [f64; 2] = core::array::from_fn(|e| {
        let loads = segs.0.iter().filter(|seg| seg.1 >= s.stats_from).flat_map(|seg| [pad.compressions(&seg.3)[e], pad.compressions(&seg.4)[e]]).map(|d| k[e] * d.max(0.0));
        let (lo, hi) = loads.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), f| (lo.min(f), hi.max(f)));
        (hi - lo) / (0.5 * (hi + lo))
    });
    eprintln!(
        "caliper {:?} beta {}: {} segments, {openings:?} openings: drive {drive:.4e} J, friction {friction:.4e} J, damping {damping:.4e} J, stored {stored:.4e} J; residual {residual:.2e}, largest RK4 end error {end_error:.1e}",
        s.caliper,
        s.beta,
        segs.0.len()
    );
    (residual, end_error, segs.0.len(), openings, swing)
}

#[test]
fn the_energy_balance_closes_where_an_edge_opens_and_closes() {
    let mut s = chattering();
    s.duration = 0.7;
    s.stats_from = 0.5;
    assert!(s.band, "the rig scene drives the band through its spring");
    let (residual, end_error, _, openings, _) = energy_balance(s);
    assert!(openings[LEAD] >= 20, "{openings:?}");
    assert!(end_error < 1e-6, "the event runner's segments leave the independent equations: {end_error:e}");
    assert!(residual <= 1e-8, "energy balance off by {residual:e}");
}

#[test]
fn the_energy_balance_closes_on_the_rig_built_set() {
    // the built-in set `rig-built` (unilateral edges, contact exponent 1.5, the soft band):
    // 0.3 s of each case's run from 1.2 s, where its stick-slip has built up
    for (caliper, pos) in [(Caliper::Push, "trail"), (Caliper::Push, "center"), (Caliper::Push, "lead"), (Caliper::Pull, "trail"), (Caliper::Pull, "center"), (Caliper::Pull, "lead")] {
        let name = format!("rig_built_{}_{pos}", if caliper == Caliper::Push { "push" } else { "pull" });
        let mut s = stickslip::scenes::builtin::find(&name).expect("a built-in scene").scene;
        assert_eq!(s.contact, ContactLaw::Unilateral, "{name}");
        assert!(s.contact_exponent > 1.0, "{name}");
        s.duration = 1.5;
        s.stats_from = 1.2;
        let (residual, end_error, segments, _, swing) = energy_balance(s);
        assert!(segments > 100, "{name}: {segments} segments");
        // the contact law enters linearised about each edge's static load (docs/model.md, "Model
        // 3, part 2"); F = k0 d^p's second-order term is (p - 1) / (2 p) of the load's swing
        // amplitude over its load, relative to the linear term: held below 1e-3 here
        let p = s.contact_exponent;
        let second_order = (p - 1.0) / (2.0 * p) * 0.5 * swing[0].max(swing[1]);
        eprintln!("{name}: edge loads swing {:.3} % (lead), {:.3} % (trail) peak-to-peak; the law's second-order term {:.4} % of the dynamic force", 100.0 * swing[0], 100.0 * swing[1], 100.0 * second_order);
        assert!(second_order < 1e-3, "{name}: the linearised contact law is off by {second_order:e} of the dynamic force");
        assert!(end_error < 1e-6, "{name}: the event runner's segments leave the independent equations: {end_error:e}");
        assert!(residual <= 1e-8, "{name}: energy balance off by {residual:e}");
    }
}

#[test]
fn edge_events_are_found_at_every_step() {
    let mut base = chattering();
    base.duration = 0.7;
    base.stats_from = 0.5;
    let mut results = vec![];
    for dt in [1e-5, 1e-4, 1e-3, 2e-3] {
        let mut s = base;
        s.dt = dt;
        let mut runner = EventRunner::new(&s, UNILATERAL_RTOL).unwrap();
        let mut n = 0u64;
        let mut on = |_: &GridSample| {
            n += 1;
            true
        };
        // the grid's end as the runs take it: round(duration / dt) steps of dt
        let t_end = (s.duration / dt).round() * dt;
        runner.run_sampled(s.stats_from, t_end, s.dt, &mut (), &mut on).expect("completes");
        let e = runner.edges().unwrap();
        eprintln!("dt {dt:e}: {n} samples, openings {:?}, lead open {:.9} s", e.openings_run, e.open_s[LEAD]);
        assert_eq!(n, (s.duration / dt).round() as u64);
        results.push(e);
    }
    assert!(results[0].openings_run[LEAD] >= 20);
    for e in &results[1..] {
        assert_eq!(e.openings_run, results[0].openings_run, "another number of openings");
        assert!((e.open_s[LEAD] - results[0].open_s[LEAD]).abs() < 1e-9, "open time {} vs {}", e.open_s[LEAD], results[0].open_s[LEAD]);
    }
}

#[test]
fn the_fixed_step_stepper_refuses_unilateral_contact_and_a_hinge_cannot_have_it() {
    let err = AnyModel2Stepper::<f32>::new(&chattering()).err().expect("refused");
    assert_eq!(err.field, "contact");
    let mut hinged = rig_set::rig_scene(Caliper::Push, 0.04);
    hinged.contact = ContactLaw::Unilateral;
    let err = hinged.validate().err().expect("a hinged pad with unilateral contact is refused");
    assert_eq!(err.field, "contact");
    assert!(run::run(&chattering(), Precision::F32, &mut NoSink).is_err(), "f32 is refused with a message");
}

/// A run that settles into steady Stribeck sliding ends: there phi'' is round-off alternating
/// in sign (1e-13 rad/s^2), and before the extremes' noise floor every such sign change was an
/// event, 1e-14 s apart, a run that never ended (rig_built_push_center at beta 65 mm, v 50
/// mm/s: 0.48 s took 0.08 s, 0.49 s never finished). Now the run completes with a finite
/// number of events, and every run has a step budget besides.
#[test]
fn a_run_settling_into_steady_sliding_ends() {
    let mut s = rig_set::rig_built_scene(Caliper::Push, 0.04);
    s.beta = 0.065;
    s.v = 0.05;
    s.stats_from = 0.0;
    let mut runner = EventRunner::new(&s, UNILATERAL_RTOL).expect("runner");
    runner.run_sampled(0.0, s.duration, s.dt, &mut (), &mut |_: &GridSample| true).expect("the run completes");
    let c = runner.counts();
    assert!(runner.time() >= s.duration - s.dt, "t {}", runner.time());
    assert!(c.events < 20_000, "{c:?}");
    assert_eq!(runner.regime(), Regime::SlipSlower, "settled into steady sliding");
}
