//! A contact that stiffens with load (`contact_exponent` p > 1; issue 34, option 3): each edge
//! spring's stiffness is the tangent of F = k0 d^p at the static load it carries,
//! k (F / F_ref)^((p - 1) / p) (`Scene::contact_stiffnesses`). Checked against independent
//! statics: the floating pad's lever rule, the fixed point of the hinged pad's; and that beta
//! now acts on the floating set, where linear springs under a dead load leave it blind.

use stickslip::scenes::run::{self, Precision};
use stickslip::scenes::series::NoSink;
use stickslip::scenes::sliding::instability_threshold_mu;
use stickslip_model::{rig_set, Caliper, Scene};

fn levers(s: &Scene) -> (f64, f64, f64) {
    match s.caliper {
        Caliper::Push => (s.l + s.l_cl, s.l - s.l_ct, s.beta),
        Caliper::Pull => (s.l - s.l_cl, s.l + s.l_ct, 2.0 * s.l - s.beta),
    }
}

#[test]
fn linear_springs_are_the_scene_s_own_stiffnesses() {
    for s in [rig_set::rig_float_scene(Caliper::Push, 0.025), Scene::case(Caliper::Pull, 0.055)] {
        assert_eq!(s.contact_exponent, 1.0);
        assert_eq!(s.contact_stiffnesses(), [s.k_l, s.k_t]);
        assert_eq!(s.linearised_contact(), s);
    }
}

#[test]
fn the_floating_pad_s_stiffnesses_follow_the_lever_rule() {
    for caliper in [Caliper::Push, Caliper::Pull] {
        for beta in [0.025, 0.04, 0.055] {
            for p in [1.5, 2.0, 3.0] {
                let mut s = rig_set::rig_float_scene(caliper, beta);
                assert_eq!(s.k_pivot, 0.0);
                s.contact_exponent = p;
                s.contact_ref_load = 60.0;
                s.validate().unwrap();
                // k_pivot = 0 under a dead load: the springs' loads by the lever rule about each
                // other, whatever their stiffness
                let (d_l, d_t, a_n) = levers(&s);
                let f_l = s.f_n * (a_n - d_t) / (d_l - d_t);
                let f_t = s.f_n - f_l;
                let q = (p - 1.0) / p;
                let want = [s.k_l * (f_l / 60.0).powf(q), s.k_t * (f_t / 60.0).powf(q)];
                let got = s.contact_stiffnesses();
                for i in 0..2 {
                    assert!((got[i] - want[i]).abs() <= 1e-12 * want[i], "{caliper:?} {beta} p {p}: {got:?} vs {want:?}");
                }
            }
        }
    }
}

#[test]
fn the_hinged_pad_s_stiffnesses_are_the_tangents_at_the_loads_they_carry() {
    for caliper in [Caliper::Push, Caliper::Pull] {
        for beta in [0.025, 0.055] {
            let mut s = Scene::case(caliper, beta);
            s.contact_exponent = 1.5;
            s.contact_ref_load = 75.0;
            let k = s.contact_stiffnesses();
            // the hinge: phi0 = F_N a_N / K, each spring carries k_i d_i phi0
            let (d_l, d_t, a_n) = levers(&s);
            let phi0 = s.f_n * a_n / (k[0] * d_l * d_l + k[1] * d_t * d_t);
            let loads = [k[0] * d_l * phi0, k[1] * d_t * phi0];
            for i in 0..2 {
                let tangent = [s.k_l, s.k_t][i] * (loads[i] / 75.0).powf(1.0 / 3.0);
                assert!((tangent - k[i]).abs() <= 1e-12 * k[i], "{caliper:?} {beta}: {k:?}, loads {loads:?}");
            }
        }
    }
}

#[test]
fn beta_acts_on_the_floating_set_through_a_load_dependent_contact() {
    let thresholds = |p: f64| -> Vec<f64> {
        [0.025, 0.04, 0.055]
            .iter()
            .map(|&beta| {
                let mut s = rig_set::rig_float_scene(Caliper::Push, beta);
                s.contact_exponent = p;
                s.contact_ref_load = 75.0;
                instability_threshold_mu(&s, 0.0, 2.0, 1e-6).unwrap_or(f64::INFINITY)
            })
            .collect()
    };
    let linear = thresholds(1.0);
    let stiffening = thresholds(3.0);
    eprintln!("push flutter threshold mu_k over beta 25, 40, 55 mm: linear {linear:?}, p = 3 {stiffening:?}");
    assert!((linear[0] - linear[2]).abs() < 1e-5, "linear springs under a dead load: beta-blind {linear:?}");
    assert!((stiffening[0] - stiffening[2]).abs() > 0.05 * stiffening[1].min(1.0), "{stiffening:?}");
    // and the runs differ with beta
    let pp = |beta: f64| {
        let mut s = rig_set::rig_float_scene(Caliper::Push, beta);
        s.contact_exponent = 3.0;
        s.contact_ref_load = 75.0;
        let r = run::run(&s, Precision::F64, &mut NoSink).unwrap();
        r.model2.unwrap().pad_acc_pp
    };
    let (trail, lead) = (pp(0.025), pp(0.055));
    eprintln!("pad x'' pp with p = 3: trail {trail:.4}, lead {lead:.4} m/s^2");
    assert!((trail - lead).abs() > 0.01 * trail.max(lead), "{trail} {lead}");
}
