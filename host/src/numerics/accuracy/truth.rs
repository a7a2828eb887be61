//! The references a method is measured against (the closed form of `oracle_1dof`, the exact
//! propagator in f64 at the rig's rate) and the errors against them.

use super::*;

/// The reference against which a scene's runs are measured.
#[derive(Clone, Debug)]
pub(super) enum Truth {
    Periodic { period: f64, amplitude: f64, final_state: [f64; 4], scale: [f64; 4] },
    Statistics { pp: [f64; 4], stick_fraction: f64, hz: f64 },
}

/// The closed form of the mass on a moving belt (docs/model.md), N = ORACLE_N0.
pub(super) fn oracle_truth(scene: &Scene) -> Truth {
    let (m, k, n, v) = (scene.m, scene.k_g, builtin::ORACLE_N0, scene.v);
    let (mu_s, mu_k) = (scene.mu_s, scene.mu_k);
    let omega = (k / m).sqrt();
    let delta = (mu_s - mu_k) * n / k;
    let x_k = mu_k * n / k;
    let x_r = (2.0 * mu_k - mu_s) * n / k;
    let r = (delta * delta + (v / omega).powi(2)).sqrt();
    let t_stick = 2.0 * delta / v;
    let t_slip = (2.0 * std::f64::consts::PI - 2.0 * (omega * delta / v).atan()) / omega;
    let period = t_stick + t_slip;
    // from rest the pad sticks until k x = mu_s N: t_b = mu_s N / (k V); then periodic
    let t_b = mu_s * n / (k * v);
    let tau = (scene.duration - t_b).rem_euclid(period);
    let (x, xd) = if tau < t_slip {
        let (s, c) = (omega * tau).sin_cos();
        (x_k + delta * c + v / omega * s, -delta * omega * s + v * c)
    } else {
        (x_r + v * (tau - t_slip), v)
    };
    let v_min = -((omega * delta).powi(2) + v * v).sqrt();
    Truth::Periodic { period, amplitude: 2.0 * r, final_state: [x, xd, 0.0, 0.0], scale: [2.0 * r, v - v_min, 0.0, 0.0] }
}

pub(super) fn exact_truth(scene: &Scene, periodic: bool) -> Result<Truth> {
    let mut s = *scene;
    s.dt = RIG_DT;
    let o = observe::<f64>(MethodKind::Exact, &s)?;
    if let Some(h) = o.halt {
        return Err(HostError::Input(format!("the reference run of the scene halted: {h:?}")));
    }
    Ok(if periodic {
        Truth::Periodic {
            period: o.period().unwrap_or(f64::NAN),
            amplitude: o.pp(0),
            final_state: o.final_state,
            scale: [o.pp(0), o.pp(1), o.pp(2), o.pp(3)],
        }
    } else {
        let hz = o.period().map_or(0.0, |p| 1.0 / p);
        Truth::Statistics { pp: [o.pp(0), o.pp(1), o.pp(2), o.pp(3)], stick_fraction: o.stick_fraction, hz }
    })
}

pub(super) fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

/// (error, period error, amplitude error, final-state error) of an observed run.
pub(super) fn measure(truth: &Truth, o: &Observed) -> (Option<f64>, Option<f64>, Option<f64>, Option<f64>) {
    if o.halt.is_some() {
        return (None, None, None, None);
    }
    match truth {
        Truth::Periodic { period, amplitude, final_state, scale } => {
            let pe = o.period().map_or(1.0, |p| rel(p, *period));
            let ae = rel(o.pp(0), *amplitude);
            let mut fe: f64 = 0.0;
            for i in 0..4 {
                if scale[i] > 0.0 {
                    fe = fe.max((o.final_state[i] - final_state[i]).abs() / scale[i]);
                }
            }
            (Some(pe.max(ae)), Some(pe), Some(ae), Some(fe))
        }
        Truth::Statistics { pp, stick_fraction, hz } => {
            let mut e: f64 = (o.stick_fraction - stick_fraction).abs();
            for (i, p) in pp.iter().enumerate() {
                e = e.max(rel(o.pp(i), *p));
            }
            let h = o.period().map_or(0.0, |p| 1.0 / p);
            e = e.max(if *hz > 0.0 { rel(h, *hz) } else { h });
            (Some(e), None, None, None)
        }
    }
}
