//! Model 2's regression anchor, beside the thesis set's (`thesis_anchor.rs`): every composition
//! of model 2 (Coulomb, the moving band, Stribeck, both, the floating pad with face kinematics)
//! on the rig's scenes, stepped to the end in f32 and f64 at the rig's step (1/25600 s) and at
//! 1 ms; every step's state and regime and the running transition count are fed to an FNV-1a
//! digest (`stickslip_model::digest`).
//!
//! The pinned values were computed by this same test on commit c7da98c (model 2 after its
//! stepper was split into files and restarted in place; those changes had been checked against
//! the commit before them by a throwaway probe over the same kind of runs). A change that alters
//! one bit of one step fails here: re-pin only for a change that is meant to alter model 2's
//! arithmetic, and say so in the commit and in CHANGELOG.md.

#[path = "common/pinned.rs"]
mod pinned;
use pinned::PinnedRow;
use stickslip_model::catalogue::CASE_BETAS;
use stickslip_model::digest::{DigestBits, Fnv1a64};
use stickslip_model::model2::AnyModel2Stepper;
use stickslip_model::rig_set::{pre_fit_rig_scene, rig_float_scene, rig_quiet_scene, rig_scene};
use stickslip_model::{Caliper, FrictionLaw, Real, Scene};

/// The 1-DOF Stribeck oracle (as the host's built-in `oracle_stribeck` builds it).
fn oracle_stribeck() -> Scene {
    let mut s = Scene::oracle_1dof();
    s.friction = FrictionLaw::Stribeck;
    s.v_s = 0.01;
    s.c_x = Scene::ORACLE_N0 * (s.mu_s - s.mu_k) / s.v_s * (-0.03f64 / s.v_s).exp();
    s.v = 0.02;
    s
}

fn model2_set() -> Vec<(String, Scene)> {
    let mut v = Vec::new();
    for caliper in [Caliper::Push, Caliper::Pull] {
        for (tag, beta) in CASE_BETAS {
            v.push((format!("rig_{}_{}", caliper.name(), tag), rig_scene(caliper, beta)));
            v.push((format!("rig_float_{}_{}", caliper.name(), tag), rig_float_scene(caliper, beta)));
        }
    }
    let centre = CASE_BETAS[1].1;
    v.push(("pre_fit_push_center".into(), pre_fit_rig_scene(Caliper::Push, centre)));
    v.push(("quiet_push_center".into(), rig_quiet_scene(Caliper::Push, centre)));
    let mut stribeck = pre_fit_rig_scene(Caliper::Pull, centre);
    stribeck.band = false;
    v.push(("stribeck_pull_center".into(), stribeck));
    let mut band = pre_fit_rig_scene(Caliper::Push, centre);
    band.friction = FrictionLaw::Coulomb;
    v.push(("band_push_center".into(), band));
    let mut coulomb = Scene::case(Caliper::Pull, centre);
    coulomb.friction = FrictionLaw::Coulomb;
    coulomb.c_x = 5.0;
    v.push(("coulomb_damped_pull_center".into(), coulomb));
    v.push(("oracle_stribeck".into(), oracle_stribeck()));
    v
}

fn digest<T: Real + DigestBits>(scene: &Scene) -> u64 {
    let mut s = AnyModel2Stepper::<T>::new(scene).unwrap();
    let steps = (scene.duration / scene.dt).round() as u64;
    let mut d = Fnv1a64::new();
    for _ in 0..steps {
        if s.step().is_err() {
            d.write_u8(0xff);
            break;
        }
        for v in s.state() {
            d.write(v);
        }
        d.write_u8(s.regime() as u8);
        d.write_u64(s.transitions());
    }
    d.finish()
}

/// (scene, dt, f32 digest, f64 digest), pinned on c7da98c.
const PINNED: &[PinnedRow] = &[
    ("rig_push_trail", 3.90625e-5, 0x5aca6e85c7ad5d9d, 0x40ed1b1fa8eae74b),
    ("rig_push_trail", 0.001, 0xeb1dcd3c9a67d68e, 0x0b00caecd04f4cd5),
    ("rig_float_push_trail", 3.90625e-5, 0x2d228b096d1c6d4f, 0x0d1b6a76563c7fbd),
    ("rig_float_push_trail", 0.001, 0xb76bc32b9f061a8a, 0x6ed01e1c2c680b07),
    ("rig_push_center", 3.90625e-5, 0xfbb234a19d2ca667, 0xb0d74acf86cb19e8),
    ("rig_push_center", 0.001, 0xcd59ca1ad945121a, 0x19eb0d25e113d0f8),
    ("rig_float_push_center", 3.90625e-5, 0xbb1c8c58e330254a, 0x504ce951b86134c7),
    ("rig_float_push_center", 0.001, 0x8cb3822a774a84ea, 0xe05f0f45ac55b34c),
    ("rig_push_lead", 3.90625e-5, 0xab3f546b005cb2b3, 0x030e2630dd455bc0),
    ("rig_push_lead", 0.001, 0xf5774032a999844d, 0x648256ead04011b6),
    ("rig_float_push_lead", 3.90625e-5, 0xd30ec984f1ad7bcd, 0xe85685ba1a7db0cc),
    ("rig_float_push_lead", 0.001, 0x1b9652cff6d5c4d5, 0xfd9a33e539861073),
    ("rig_pull_trail", 3.90625e-5, 0xbb17fff7255cd3dc, 0x3035288232e9f523),
    ("rig_pull_trail", 0.001, 0x618ad531c24636e5, 0x28c494339da2b1ef),
    ("rig_float_pull_trail", 3.90625e-5, 0x2678f3f51db8cf23, 0xca1599f318fed7c5),
    ("rig_float_pull_trail", 0.001, 0x19ef4e6701369cfa, 0x542d87ad2c00787e),
    ("rig_pull_center", 3.90625e-5, 0x91a0e8ed2e7a36eb, 0x7e1e502fd2f43b3d),
    ("rig_pull_center", 0.001, 0xe35399c707706897, 0x1eefeef9f7701ad8),
    ("rig_float_pull_center", 3.90625e-5, 0xe08b3c3a79a36e85, 0x349db18d3474bc9a),
    ("rig_float_pull_center", 0.001, 0x0fa4c629c4986aa3, 0xdff5f552358f3ad6),
    ("rig_pull_lead", 3.90625e-5, 0xf28823d66d558857, 0xdd39de06e157cea3),
    ("rig_pull_lead", 0.001, 0xb7e673cf6bebed42, 0x0d88634d98a8f58c),
    ("rig_float_pull_lead", 3.90625e-5, 0xad53b0a6134e145a, 0xd95722779f7d9cde),
    ("rig_float_pull_lead", 0.001, 0xc3df0076b18330db, 0x27c55e90a9786cf7),
    ("pre_fit_push_center", 3.90625e-5, 0x4f978cc29c73764e, 0x53e2b2ce22dae785),
    ("pre_fit_push_center", 0.001, 0x6a9bb30e15b5b571, 0x0326890f578e96c6),
    ("quiet_push_center", 3.90625e-5, 0x2cbd5c676a5e7248, 0xce0eb6ddbd2e7eff),
    ("quiet_push_center", 0.001, 0x0686ee18b8ad040b, 0xbf0d137f39a9ea9b),
    ("stribeck_pull_center", 3.90625e-5, 0x2889e34b1d745c03, 0xab406c2c87cb322c),
    ("stribeck_pull_center", 0.001, 0xdea65074a0bf1bcd, 0xb2aea3d30af3b7e8),
    ("band_push_center", 3.90625e-5, 0x53d9fb6494d7ebee, 0x392e364d8fc4787e),
    ("band_push_center", 0.001, 0x3925a438940ca0ae, 0xe91301d2d7d260ee),
    ("coulomb_damped_pull_center", 3.90625e-5, 0x8a449091a95849f9, 0x11e487b0e0853c3a),
    ("coulomb_damped_pull_center", 0.001, 0x9d8d63efe67c8e7c, 0x2fb2acb774f1a141),
    ("oracle_stribeck", 3.90625e-5, 0xac44c1e6e9cb1481, 0x5a3ed01ddaef08e9),
    ("oracle_stribeck", 0.001, 0x32f358bbb22e5103, 0x817190847d5190f5),
];

#[test]
fn model_2s_set_is_bit_identical_to_its_pinned_digests() {
    pinned::assert_pinned(model2_set(), PINNED, |s| (digest::<f32>(s), digest::<f64>(s)));
}
