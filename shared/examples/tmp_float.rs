use stickslip_model::model2::AnyModel2Stepper;
use stickslip_model::{Caliper, Scene};
fn main() {
    let mut h = Scene::case(Caliper::Pull, 0.040);
    h.face = true; h.c_x = 10.0; h.c_phi = 0.03; h.duration = 0.1; h.stats_from = 0.05;
    let mut f = h; f.k_pivot = 1e10;
    let mut a = AnyModel2Stepper::<f64>::new(&h).unwrap();
    let mut b = AnyModel2Stepper::<f64>::new(&f).unwrap();
    println!("subs {} {}", a.substeps(), b.substeps());
    for i in 0..2560 {
        let ra = a.step(); let rb = b.step();
        if i % 128 == 0 || ra.is_err() || rb.is_err() {
            println!("{i} {:?} {:?} {:?}\n   {:?}\n   {:?}", a.regime(), b.regime(), (ra, rb), a.state(), b.state());
        }
        if ra.is_err() || rb.is_err() { break; }
    }
}
