//! The pneumatic band drive (`drive = "pneumatic"`; issue 34, option 1). Checked here:
//! - its small-signal limit is today's band on a spring k_b = n p A^2 / V: with the column
//!   made long and wide (L_0 -> inf at a fixed n p A / L_0, no seal friction) a pneumatic run
//!   tends to the velocity-driven run of model 2 (the event runner, another code path) at rate
//!   1 / L_0;
//! - the seal's stick-slip alone (no normal load: the pad exerts no friction) has its linear
//!   threshold where the 1-DOF Stribeck oracle puts it, V_cr = v_ss ln((F_ss - F_sk) / (v_ss c)),
//!   found here by bisection on the growth of a small perturbation of steady sliding;
//! - the energy balance closes: the air's work on the piston, the integral of (p - p_atm) A
//!   dx_b from the run's own p and x_b, equals the mechanical energy's change and the
//!   dissipation (pad friction, seal friction, dampers), each from the sampled state;
//! - the chamber's pressure with the band held follows the throttle's and the column's closed
//!   form (choked, then ISO 6358's elliptic flow);
//! - the fixed-step stepper (and so the firmware's chain) refuses such a scene, f32 is refused,
//!   and bad cylinder keys are bad scenes naming their field.

use stickslip::scenes::run::{self, Precision};
use stickslip::scenes::series::NoSink;
use stickslip_model::model2::event_run::{EventRunner, GridSample};
use stickslip_model::model2::{AnyModel2Stepper, NS};
use stickslip_model::model3::pneumatic_run::{PneumaticRunner, PneumaticSample, P, XB};
use stickslip_model::scene::ATMOSPHERE_PA;
use stickslip_model::{rig_set, BandDrive, Caliper, FrictionLaw, Regime, Scene};

/// The rig scene (push, centre) with a soft band (k_b 2e4 N/m, m_b 0.5 kg, undamped drive).
fn soft_band() -> Scene {
    let mut s = rig_set::rig_scene(Caliper::Push, 0.04);
    s.k_b = 2.0e4;
    s.m_b = 0.5;
    s.c_b = 0.0;
    s.duration = 1.5;
    s.stats_from = 0.5;
    s.dt = 1e-4;
    s
}

/// `s` driven by a cylinder whose column at atmospheric pressure has the stiffness k_b with a
/// column of length `l0`, no seal friction, the throttle solved from V.
fn pneumatic_equivalent(s: &Scene, l0: f64) -> Scene {
    let mut p = *s;
    p.drive = BandDrive::Pneumatic;
    p.polytropic_exponent = 1.0;
    p.column_length = l0;
    let area = s.k_b * l0 / (p.polytropic_exponent * ATMOSPHERE_PA);
    p.bore = (4.0 * area / std::f64::consts::PI).sqrt();
    p.seal_static = 0.0;
    p.seal_kinetic = 0.0;
    p.throttle_conductance = 0.0;
    p
}

#[test]
fn the_small_signal_limit_is_the_band_on_its_spring() {
    let s = soft_band();
    // the velocity-driven band: model 2's event runner, samples on the grid
    let mut reference: Vec<[f64; NS]> = vec![];
    let mut er = EventRunner::new(&s, 1e-12).expect("event runner");
    er.run_sampled(0.0, s.duration, s.dt, &mut (), &mut |g: &GridSample| {
        reference.push(g.z);
        true
    })
    .expect("the reference run completes");
    let x_range = reference.iter().map(|z| z[0]).fold(f64::NEG_INFINITY, f64::max) - reference.iter().map(|z| z[0]).fold(f64::INFINITY, f64::min);
    let u_range = reference.iter().map(|z| z[4]).fold(f64::NEG_INFINITY, f64::max) - reference.iter().map(|z| z[4]).fold(f64::INFINITY, f64::min);
    let mut errors = vec![];
    for l0 in [1.0, 10.0, 100.0] {
        let p = pneumatic_equivalent(&s, l0);
        let mut runner = PneumaticRunner::new(&p, 1e-12).expect("pneumatic runner");
        // model 2's start: the band at V, the pad stuck on it, no force in the drive yet
        let mut w0 = runner.state();
        w0[1] = s.v;
        w0[5] = 0.0;
        w0[P] = ATMOSPHERE_PA;
        runner.set_state(w0, Regime::Stick, 1);
        let mut k = 0;
        let mut worst: f64 = 0.0;
        let mut slips = 0;
        let mut last = Regime::Stick;
        runner
            .run_sampled(0.0, s.duration, s.dt, &mut (), &mut |g: &PneumaticSample| {
                let z = &reference[k];
                worst = worst.max((g.w[0] - z[0]).abs() / x_range).max((g.w[4] - z[4]).abs() / u_range);
                if last == Regime::Stick && g.regime != Regime::Stick {
                    slips += 1;
                }
                last = g.regime;
                k += 1;
                true
            })
            .expect("the pneumatic run completes");
        assert_eq!(k, reference.len());
        assert!(slips >= 3, "L0 {l0}: the run should stick-slip ({slips} slips)");
        errors.push(worst);
    }
    eprintln!("small-signal limit: max deviation of x and u relative to their ranges at L0 = 1, 10, 100 m: {errors:?}");
    assert!(errors[0] / errors[1] > 5.0 && errors[1] / errors[2] > 5.0, "not converging at rate 1 / L0: {errors:?}");
    assert!(errors[2] < 2e-3, "{errors:?}");
}

/// The band alone (no normal load), sliding steadily at `v` with a small kick: the growth
/// rate [1/s] of its velocity's oscillation (log of the late window's amplitude over the
/// early one's, over the time between them); +inf if the band stops.
fn seal_growth(base: &Scene, v: f64) -> f64 {
    let mut s = *base;
    s.v = v;
    let mut runner = PneumaticRunner::new(&s, 1e-12).expect("runner");
    let mut z = [0.0; NS];
    z[5] = 1e-9; // the kick: the band 1e-9 m/s faster than V
    runner.set_sliding(z);
    let (mut early, mut late, mut stopped) = (0.0f64, 0.0f64, false);
    runner
        .run_sampled(0.0, s.duration, s.dt, &mut (), &mut |g: &PneumaticSample| {
            let dv = g.w[5].abs();
            if g.t < 0.5 {
                early = early.max(dv);
            } else if g.t >= s.duration - 0.5 {
                late = late.max(dv);
            }
            stopped |= g.band != 1;
            true
        })
        .expect("the run completes");
    if stopped {
        return f64::INFINITY;
    }
    (late / early).ln() / (s.duration - 0.5)
}

#[test]
fn the_seal_alone_loses_stability_at_the_oracles_critical_speed() {
    let mut s = soft_band();
    s.f_n = 0.0;
    s.friction = FrictionLaw::Coulomb;
    s.drive = BandDrive::Pneumatic;
    s.m_b = 1.0;
    s.bore = 0.04;
    s.column_length = 0.1;
    s.polytropic_exponent = 1.2;
    s.seal_static = 30.0;
    s.seal_kinetic = 20.0;
    s.seal_v_s = 0.01;
    s.duration = 2.0;
    s.stats_from = 1.0;
    s.dt = 1e-3;
    // the oracle's damping for V_cr = 0.03 m/s (host/src/scenes/builtin.rs oracle_stribeck)
    let v_cr = 0.03;
    s.c_b = (s.seal_static - s.seal_kinetic) / s.seal_v_s * (-v_cr / s.seal_v_s).exp();
    let (mut lo, mut hi) = (0.9 * v_cr, 1.1 * v_cr);
    assert!(seal_growth(&s, lo) > 0.0, "below V_cr steady sliding must be unstable");
    assert!(seal_growth(&s, hi) < 0.0, "above V_cr steady sliding must be stable");
    for _ in 0..12 {
        let mid = 0.5 * (lo + hi);
        if seal_growth(&s, mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let found = 0.5 * (lo + hi);
    eprintln!("seal alone: V_cr found {found:.6} m/s against the oracle's {v_cr} m/s ({:+.3} %)", 100.0 * (found / v_cr - 1.0));
    assert!((found / v_cr - 1.0).abs() < 0.01, "V_cr {found} against {v_cr}");
}

#[test]
fn the_energy_balance_closes_with_the_air_columns_work() {
    // the 1-DOF pad (rotation held: N constant) on the pneumatic band, seal stick-slip on
    let mut s = soft_band();
    s.rotation = false;
    s.drive = BandDrive::Pneumatic;
    s.c_b = 5.0;
    s.column_length = 0.01;
    s.seal_static = 30.0;
    s.seal_kinetic = 25.0;
    s.seal_v_s = 0.005;
    s.duration = 0.8;
    s.stats_from = 0.1;
    s.dt = 2e-6;
    let mut runner = PneumaticRunner::new(&s, 1e-12).expect("runner");
    let area = runner.cylinder().area;
    let energy = |w: &[f64]| {
        let vb = s.v + w[5];
        0.5 * s.m * w[1] * w[1] + 0.5 * s.k_g * w[0] * w[0] + 0.5 * s.m_b * vb * vb
    };
    let mut prev: Option<PneumaticSample> = None;
    let (mut work, mut dissipated, mut e0, mut e1, mut scale) = (0.0, 0.0, f64::NAN, 0.0, 0.0f64);
    let cyl = *runner.cylinder();
    let power_lost = |g: &PneumaticSample| {
        let w = &g.w;
        let vb = s.v + w[5];
        let seal = if g.band == 0 { 0.0 } else { cyl.seal_friction(vb) * vb.abs() };
        s.c_x * w[1] * w[1] + s.c_b * vb * vb + seal - g.f_f * g.v_slide
    };
    runner
        .run_sampled(0.0, s.duration, s.dt, &mut (), &mut |g: &PneumaticSample| {
            match &prev {
                None => e0 = energy(&g.w),
                Some(a) => {
                    // the air's work from the run's p and x_b; the losses from the state
                    work += 0.5 * ((a.w[P] - ATMOSPHERE_PA) + (g.w[P] - ATMOSPHERE_PA)) * area * (g.w[XB] - a.w[XB]);
                    dissipated += 0.5 * (power_lost(a) + power_lost(g)) * (g.t - a.t);
                }
            }
            scale = scale.max(work.abs());
            e1 = energy(&g.w);
            prev = Some(*g);
            true
        })
        .expect("the run completes");
    let residual = (work - (e1 - e0) - dissipated) / scale;
    eprintln!(
        "energy balance: air work {work:.9e} J, energy change {:.9e} J, dissipated {dissipated:.9e} J, residual {residual:.2e} of the work; {:?}",
        e1 - e0,
        runner.counts()
    );
    assert!(runner.counts().transitions >= 4, "the pad should stick-slip: {:?}", runner.counts());
    assert!(runner.counts().band_changes >= 4, "the band should stick and slip at its seal: {:?}", runner.counts());
    assert!(residual.abs() < 1e-8, "residual {residual:e}");
}

#[test]
fn a_pneumatic_scene_runs_on_the_event_path_only_and_bad_keys_are_named() {
    let mut s = soft_band();
    s.drive = BandDrive::Pneumatic;
    let e = AnyModel2Stepper::<f64>::new(&s).err().expect("the fixed-step stepper refuses it");
    assert_eq!(e.field, "drive");
    assert!(run::run(&s, Precision::F32, &mut NoSink).is_err(), "f32 is refused");
    let r = run::run(&s, Precision::F64, &mut NoSink).expect("f64 runs");
    let d = r.drive.expect("a pneumatic run reports its drive");
    assert!(d.conductance_solved && d.conductance > 0.0);
    assert!(d.p_min > ATMOSPHERE_PA && d.p_max < s.supply_pressure);
    for (field, set) in [
        ("bore", (|s: &mut Scene| s.bore = -0.01) as fn(&mut Scene)),
        ("supply_pressure", |s: &mut Scene| s.supply_pressure = 9e4),
        ("polytropic_exponent", |s: &mut Scene| s.polytropic_exponent = 1.6),
        ("seal_static", |s: &mut Scene| s.seal_static = 10.0),
        ("seal_v_s", |s: &mut Scene| s.seal_v_s = 0.0),
        ("column_length", |s: &mut Scene| s.column_length = f64::NAN),
        ("throttle_critical_ratio", |s: &mut Scene| s.throttle_critical_ratio = 1.0),
    ] {
        let mut b = s;
        set(&mut b);
        assert_eq!(b.validate().err().map(|e| e.field), Some(field));
    }
    let mut no_band = s;
    no_band.band = false;
    assert_eq!(no_band.validate().err().map(|e| e.field), Some("drive"));
    // a supply that cannot push the load at V
    let mut weak = s;
    weak.supply_pressure = 1.2e5;
    assert_eq!(PneumaticRunner::new(&weak, 1e-10).err().map(|e| e.field), Some("supply_pressure"));
}

/// The air column fed by the throttle with the band held (a seal it cannot break): the chamber
/// pressure has a closed form, linear while the throttle is choked (p <= b p_s) and then, with
/// ISO 6358's elliptic flow, s = (p / p_s - b) / (1 - b) = sin(K (t - t_b)), K = n Q / (V_c p_s
/// (1 - b)), Q = p_ref C p_s, until p reaches the supply.
#[test]
fn the_chamber_fills_as_the_throttle_law_says() {
    let mut s = soft_band();
    s.f_n = 0.0;
    s.drive = BandDrive::Pneumatic;
    s.seal_static = 1e4;
    s.seal_kinetic = 1e4;
    s.throttle_conductance = 1e-10;
    s.throttle_critical_ratio = 0.4;
    s.polytropic_exponent = 1.3;
    s.duration = 8.0;
    s.stats_from = 1.0;
    s.dt = 1e-3;
    let mut runner = PneumaticRunner::new(&s, 1e-12).expect("runner");
    let cyl = *runner.cylinder();
    assert!(!cyl.solved);
    let mut w = runner.state();
    w[P] = ATMOSPHERE_PA;
    w[1] = 0.0;
    w[5] = -s.v;
    runner.set_state(w, Regime::SlipSlower, 0);
    let v_c = cyl.area * cyl.l0;
    let q = stickslip_model::model3::cylinder::P_REF * cyl.conductance * cyl.p_s;
    let rate = cyl.n * q / v_c; // dp/dt while choked [Pa/s]
    let t_b = (cyl.b * cyl.p_s - ATMOSPHERE_PA) / rate;
    let k = rate / (cyl.p_s * (1.0 - cyl.b));
    let t_full = t_b + std::f64::consts::FRAC_PI_2 / k;
    assert!(t_b > 1.0 && t_full < s.duration - 1.0, "both phases in the run: t_b {t_b}, t_full {t_full}");
    let mut worst: f64 = 0.0;
    runner
        .run_sampled(0.0, s.duration, s.dt, &mut (), &mut |g: &PneumaticSample| {
            let t = g.t;
            let p = if t <= t_b {
                ATMOSPHERE_PA + rate * t
            } else if t < t_full {
                cyl.p_s * (cyl.b + (1.0 - cyl.b) * (k * (t - t_b)).sin())
            } else {
                cyl.p_s
            };
            assert_eq!(g.band, 0, "the band stays stuck");
            assert_eq!(g.w[XB], 0.0);
            worst = worst.max((g.w[P] - p).abs() / cyl.p_s);
            true
        })
        .expect("the run completes");
    eprintln!("chamber fill: largest deviation from the closed form {worst:.2e} of p_s (t_b {t_b:.4} s, full at {t_full:.4} s)");
    assert!(worst < 1e-8, "{worst:e}");
}

/// A map over the supply pressure: cells whose supply cannot push their load at v are invalid
/// cells naming `supply_pressure`, the others run (the map does not fail as a whole).
#[test]
fn a_map_marks_a_supply_too_low_for_its_load_invalid() {
    let dir = std::env::temp_dir().join(format!("stickslip-pneumatic-map-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("pn.toml");
    std::fs::write(
        &file,
        "name = \"pn\"\nfriction = \"stribeck\"\nv_s = 0.00044\nmu_k = 0.4398\nband = true\nm_b = 2.0\nc_b = 0.0\n\
         drive = \"pneumatic\"\nduration = 0.3\nstats_from = 0.15\n",
    )
    .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_stickslip"))
        .args(["map", file.to_str().unwrap(), "--sweep", "beta=0.02:0.06:3", "--sweep", "supply_pressure=1.9e5:6e5:2", "--json", "--jobs", "1"])
        .output()
        .expect("the binary runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let cells = v["cells"].as_array().expect("cells");
    assert_eq!(cells.len(), 6);
    let invalid: Vec<&serde_json::Value> = cells.iter().filter(|c| !c["invalid"].is_null()).collect();
    assert!(!invalid.is_empty() && invalid.len() < 3, "{invalid:?}");
    for c in &invalid {
        assert_eq!(c["params"]["supply_pressure"], 1.9e5);
        assert!(c["invalid"].as_str().unwrap().contains("supply_pressure"), "{c}");
    }
    assert!(cells.iter().filter(|c| c["params"]["supply_pressure"] == 6e5).all(|c| c["invalid"].is_null()));
    std::fs::remove_dir_all(&dir).ok();
}

/// At every sample the regimes hold their laws: a stuck band's net force (but the seal's) is
/// within the seal's static friction, a stuck pad's friction within mu_s N. A guard that a
/// change leaves above zero must fire at once: the pad sticking on a stuck band raised the net
/// force on the band past F_ss in one jump, and the band stayed stuck for good (the rig-built
/// twin with the pneumatic drive and a seal without drop: stuck 1.0 of the window, 0
/// breakaways, the pressure climbing to 3.9 bar).
#[test]
fn every_sample_holds_the_stuck_regimes_laws() {
    let mut seen_stuck_band = 0;
    for (seal_kinetic, column) in [(80.0, 0.015), (60.0, 0.015), (78.0, 0.05), (60.0, 0.05)] {
        let mut s = rig_set::rig_built_scene(Caliper::Push, 0.04);
        s.contact = stickslip_model::ContactLaw::Bilateral;
        s.drive = BandDrive::Pneumatic;
        s.column_length = column;
        s.seal_kinetic = seal_kinetic;
        s.duration = 2.0;
        let mut runner = PneumaticRunner::new(&s, 1e-10).expect("runner");
        let probe = runner.clone();
        let cyl = *runner.cylinder();
        let (mut worst_band, mut worst_pad) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
        runner
            .run_sampled(0.0, s.duration, s.dt, &mut (), &mut |g: &PneumaticSample| {
                if g.band == 0 {
                    seen_stuck_band += 1;
                    let net = cyl.force(g.w[P]) - probe.friction_force(g.regime, 0, &g.w);
                    worst_band = worst_band.max(net.abs() - cyl.f_ss);
                }
                if g.regime == Regime::Stick && g.n > 0.0 {
                    worst_pad = worst_pad.max(g.f_f.abs() - s.mu_s * g.n);
                }
                true
            })
            .expect("the run completes");
        eprintln!("seal {seal_kinetic} N, column {column} m: stuck band's |net| - F_ss at most {worst_band:.3e} N, stuck pad's |F| - mu_s N at most {worst_pad:.3e} N; {:?}", runner.counts());
        assert!(worst_band <= 1e-6 * cyl.f_ss, "the band stayed stuck past its seal's static friction by {worst_band} N");
        assert!(worst_pad <= 1e-6 * s.f_n, "the pad stayed stuck past mu_s N by {worst_pad} N");
    }
    assert!(seen_stuck_band > 0, "some run has the band stuck at its seal");
}
