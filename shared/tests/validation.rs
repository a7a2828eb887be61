//! Every validation rule of a scene names its field.

use stickslip_model::{ExactStepper, Scene, DEFAULT_SCENE};

fn field_of(edit: impl Fn(&mut Scene)) -> &'static str {
    let mut s = DEFAULT_SCENE;
    edit(&mut s);
    let err = s.validate().expect_err("the edited scene must be rejected");
    // the stepper refuses it too, with the same error
    let again = ExactStepper::<f32>::new(&s).unwrap_err();
    assert_eq!((again.field, again.rule), (err.field, err.rule));
    err.field
}

#[test]
fn the_default_scene_is_valid() {
    DEFAULT_SCENE.validate().unwrap();
}

#[test]
fn non_finite_values_are_rejected_by_name() {
    type Setter = fn(&mut Scene, f64);
    let cases: [(&str, Setter); 19] = [
        ("m", |s, v| s.m = v),
        ("inertia", |s, v| s.inertia = v),
        ("l", |s, v| s.l = v),
        ("w", |s, v| s.w = v),
        ("l_cl", |s, v| s.l_cl = v),
        ("l_ct", |s, v| s.l_ct = v),
        ("k_l", |s, v| s.k_l = v),
        ("k_t", |s, v| s.k_t = v),
        ("k_g", |s, v| s.k_g = v),
        ("f_n", |s, v| s.f_n = v),
        ("beta", |s, v| s.beta = v),
        ("v", |s, v| s.v = v),
        ("mu_s", |s, v| s.mu_s = v),
        ("mu_k", |s, v| s.mu_k = v),
        ("c_x", |s, v| s.c_x = v),
        ("c_phi", |s, v| s.c_phi = v),
        ("dt", |s, v| s.dt = v),
        ("duration", |s, v| s.duration = v),
        ("stats_from", |s, v| s.stats_from = v),
    ];
    for (name, set) in cases {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(field_of(|s| set(s, bad)), name, "{name} = {bad}");
        }
    }
}

#[test]
fn out_of_range_values_are_rejected_by_name() {
    assert_eq!(field_of(|s| s.m = 0.0), "m");
    assert_eq!(field_of(|s| s.m = -0.3), "m");
    assert_eq!(field_of(|s| s.inertia = 0.0), "inertia");
    assert_eq!(field_of(|s| s.l = 0.0), "l");
    assert_eq!(field_of(|s| s.w = -0.001), "w");
    assert_eq!(field_of(|s| s.l_cl = -0.01), "l_cl");
    assert_eq!(field_of(|s| s.l_cl = 0.04), "l_cl");
    assert_eq!(field_of(|s| s.l_ct = -0.01), "l_ct");
    assert_eq!(field_of(|s| s.l_ct = 0.04), "l_ct");
    assert_eq!(field_of(|s| s.l_ct = 0.05), "l_ct");
    assert_eq!(field_of(|s| s.k_l = -1.0), "k_l");
    assert_eq!(field_of(|s| s.k_t = -1.0), "k_t");
    assert_eq!(field_of(|s| { s.k_l = 0.0; s.k_t = 0.0 }), "k_l");
    assert_eq!(field_of(|s| s.k_g = 0.0), "k_g");
    assert_eq!(field_of(|s| s.f_n = -1.0), "f_n");
    assert_eq!(field_of(|s| s.beta = -1e-9), "beta");
    assert_eq!(field_of(|s| s.beta = 0.0800001), "beta");
    assert_eq!(field_of(|s| s.v = 0.0), "v");
    assert_eq!(field_of(|s| s.v = -0.005), "v");
    assert_eq!(field_of(|s| s.mu_s = -0.1), "mu_s");
    assert_eq!(field_of(|s| s.mu_k = -0.1), "mu_k");
    assert_eq!(field_of(|s| s.mu_k = 0.46), "mu_k");
    assert_eq!(field_of(|s| s.c_x = -1.0), "c_x");
    assert_eq!(field_of(|s| s.c_phi = -1.0), "c_phi");
    assert_eq!(field_of(|s| s.dt = 0.0), "dt");
    assert_eq!(field_of(|s| s.dt = -1e-5), "dt");
    assert_eq!(field_of(|s| s.dt = 2.0), "dt");
    assert_eq!(field_of(|s| s.dt = 1e-12), "dt");
    assert_eq!(field_of(|s| s.duration = 0.0), "duration");
    assert_eq!(field_of(|s| s.stats_from = -0.1), "stats_from");
    assert_eq!(field_of(|s| s.stats_from = 1.0), "stats_from");
}

#[test]
fn boundary_values_are_accepted() {
    for edit in [
        (|s: &mut Scene| s.beta = 0.0) as fn(&mut Scene),
        |s| s.beta = 0.08,
        |s| s.f_n = 0.0,
        |s| s.mu_k = s.mu_s,
        |s| s.w = 0.0,
        |s| s.k_l = 0.0,
        |s| s.dt = s.duration,
    ] {
        let mut s = DEFAULT_SCENE;
        edit(&mut s);
        s.validate().unwrap();
    }
}

#[test]
fn error_message_names_field_value_and_rule() {
    let mut s = DEFAULT_SCENE;
    s.m = -1.0;
    let msg = s.validate().unwrap_err().to_string();
    assert!(msg.contains("`m`") && msg.contains("-1") && msg.contains("> 0"), "{msg}");
}

#[test]
fn an_error_about_a_word_field_shows_no_number_for_it() {
    use stickslip_model::SceneError;
    // a switch or a word has no number to show: the value a check carries for it is a code
    let word = SceneError { field: "contact", rule: "needs a pad that is not hinged", value: f64::INFINITY };
    assert_eq!(word.to_string(), "field `contact`: needs a pad that is not hinged");
    let number = SceneError { field: "m", rule: "pad mass must be > 0 kg", value: -1.0 };
    assert_eq!(number.to_string(), "field `m` = -1: pad mass must be > 0 kg");
}
