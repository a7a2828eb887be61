use stickslip_model::model2::AnyModel2Stepper;
use stickslip_model::rig_set::rig_scene;
use stickslip_model::{Caliper, FrictionLaw, Real, Scene};
fn run<T: Real>(s: &Scene) -> u64 {
    let mut st = AnyModel2Stepper::<T>::new(s).unwrap();
    let mut h: u64 = 1469598103934665603;
    for _ in 0..6000 {
        let _ = st.step();
        for v in st.state().iter().take(6) {
            h = (h ^ v.to_f64().to_bits()).wrapping_mul(1099511628211);
        }
    }
    h
}
fn main() {
    for cal in [Caliper::Push, Caliper::Pull] {
        for beta in [0.025, 0.055] {
            for face in [false, true] {
                for (fr, band) in [(FrictionLaw::Coulomb, false), (FrictionLaw::Coulomb, true), (FrictionLaw::Stribeck, false), (FrictionLaw::Stribeck, true)] {
                    let mut s = rig_scene(cal, beta);
                    s.friction = fr;
                    s.band = band;
                    s.face = face;
                    println!("{cal:?} {beta} face {face} {fr:?} band {band}: {:016x} {:016x}", run::<f32>(&s), run::<f64>(&s));
                }
            }
        }
    }
}
