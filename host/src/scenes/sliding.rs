//! Steady sliding and its linear stability: the model's own linearisation (docs/model.md,
//! "Steady sliding and its stability").
//!
//! Steady sliding at the band speed is slip with the pad slower than the band (sigma = +1), the
//! pad at rest (x' = phi' = y' = 0, sliding velocity v = -V) and the band at its drive speed.
//! It is the fixed point of the slip regime's equations with the friction mu(V) N. Its
//! Jacobian is the model's slip matrix A (the kinetic friction sigma mu_k N) plus, with
//! Stribeck friction, the falling curve's terms: the excess (mu(V) - mu_k) along the normal
//! force, and N mu'(V) along the sliding velocity (negative damping where the curve falls):
//!
//! ```text
//! J = A + b [ (mu(V) - mu_k) r_N - N mu'(V) r_v ]        (sigma = +1, |v| = -v)
//! ```
//!
//! with b, r_N, r_v the model's friction direction and rows ([`stickslip_model::model2::System`]).
//! With the floating pad the friction couples bounce (y) and pitch (phi) through a
//! non-symmetric stiffness: past a threshold in mu the two modes merge into a growing pair
//! (flutter, the mode-coupling groan mechanism). Eigenvalues by nalgebra (real Schur form).

use nalgebra::DMatrix;
use stickslip_model::model2::{System, NA, NS, Y};
use stickslip_model::{Coefficients, FrictionLaw, Scene};

/// One mode of the linearisation: eigenvalue lambda = growth + i 2 pi frequency.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mode {
    /// Real part [1/s]: > 0 grows.
    pub growth_rate: f64,
    /// |Im| / (2 pi) [Hz] (0 for a real eigenvalue).
    pub frequency_hz: f64,
}

/// The linear stability of steady sliding of a scene.
#[derive(Clone, Debug)]
pub struct SlidingStability {
    /// The fixed point (state [x, x', phi, phi', u, u', y, y']).
    pub state: [f64; NS],
    /// Normal force there [N].
    pub normal_force: f64,
    /// Every mode of the degrees of freedom the scene moves, one per complex pair, fastest
    /// growth first.
    pub modes: Vec<Mode>,
    /// Where steady sliding does not exist as a valid state, why: sprag (no static
    /// equilibrium under the sliding friction) or contact loss (N or a contact spring's
    /// compression below 0 at the fixed point).
    pub invalid: Option<(NoSteadySliding, String)>,
}

/// Why a scene has no steady sliding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoSteadySliding {
    /// The friction's moment beats the rotational stiffness: the pad self-locks (the static
    /// stiffness under sliding friction is <= 0, so there is no fixed point, or only an
    /// unstable one beyond a real divergence).
    Sprag,
    /// The fixed point has N < 0 or a contact spring in tension.
    ContactLoss,
}

impl NoSteadySliding {
    /// The keyword of the map and the JSON: `sprag`, `contact_loss`.
    pub fn keyword(self) -> &'static str {
        match self {
            NoSteadySliding::Sprag => "sprag",
            NoSteadySliding::ContactLoss => "contact_loss",
        }
    }
}

impl SlidingStability {
    /// The largest growth rate [1/s].
    pub fn max_growth_rate(&self) -> f64 {
        self.modes.first().map_or(f64::NEG_INFINITY, |m| m.growth_rate)
    }
    /// Stable: every mode decays, to a relative round-off of 1e-9 of the fastest rate (an
    /// undamped mode, growth 0, counts as stable).
    pub fn stable(&self) -> bool {
        self.max_growth_rate() <= self.tolerance()
    }
    /// The most unstable mode, if any mode grows beyond round-off.
    pub fn unstable_mode(&self) -> Option<Mode> {
        let m = *self.modes.first()?;
        (m.growth_rate > self.tolerance()).then_some(m)
    }
    fn tolerance(&self) -> f64 {
        let scale = self.modes.iter().map(|m| m.growth_rate.abs().max(2.0 * std::f64::consts::PI * m.frequency_hz)).fold(0.0, f64::max);
        1e-9 * scale
    }
}

/// The state entries a scene moves (x always; phi with rotation; u with the band; y with the
/// floating pad).
fn active(scene: &Scene) -> Vec<usize> {
    let mut idx = vec![0, 1];
    if scene.rotation {
        idx.extend([2, 3]);
    }
    if scene.band {
        idx.extend([4, 5]);
    }
    if scene.floating() {
        idx.extend([Y, Y + 1]);
    }
    idx
}

/// mu(V) and mu'(V) of the scene's friction law at sliding speed `speed` [m/s].
pub fn friction_at(scene: &Scene, speed: f64) -> (f64, f64) {
    match scene.friction {
        FrictionLaw::Coulomb => (scene.mu_k, 0.0),
        FrictionLaw::Stribeck => {
            let d = scene.stribeck_exponent;
            let r = speed / scene.v_s;
            let e = (-r.powf(d)).exp();
            let mu = scene.mu_k + (scene.mu_s - scene.mu_k) * e;
            let slope = -(scene.mu_s - scene.mu_k) * e * d * r.powf(d - 1.0) / scene.v_s;
            (mu, slope)
        }
    }
}

/// The fixed point of steady sliding at the band speed, without its modes.
#[derive(Clone, Debug)]
pub struct SteadySliding {
    /// The state [x, x', phi, phi', u, u', y, y'].
    pub state: [f64; NS],
    /// Normal force there [N].
    pub normal_force: f64,
    /// Why it does not exist as a valid state, if it does not (as in [`SlidingStability`]).
    pub invalid: Option<(NoSteadySliding, String)>,
}

/// The scene whose steady sliding is linearised: a pneumatic drive's small-signal equivalent
/// (the band on the air column's stiffness at the steady pressure, the seal's friction slope
/// with the guides' damping: `model3::cylinder::small_signal_scene`), else the scene. A supply
/// too low to slide at V keeps the scene as it is (its runs report that).
fn small_signal(scene: &Scene) -> Scene {
    stickslip_model::model3::cylinder::small_signal_scene(scene).unwrap_or(*scene)
}

/// The fixed point of steady sliding of `scene` (the start of [`crate::scenes::run::Start::Sliding`]).
/// The scene must be valid.
pub fn steady_sliding(scene: &Scene) -> SteadySliding {
    let equivalent = small_signal(scene);
    let scene = &equivalent;
    let co = Coefficients::of(scene);
    let sys = System::of(scene, &co);
    fixed_point(scene, &co, &sys)
}

/// A x + b (mu(V) - mu_k) N(x) = 0 at zero velocity, and whether it exists (sprag, contact).
fn fixed_point(scene: &Scene, co: &Coefficients, sys: &System) -> SteadySliding {
    let a = &sys.a[stickslip_model::Regime::SlipSlower.index()];
    let (mu_v, _) = friction_at(scene, scene.v);
    // fixed point: A z + b (mu(V) - mu_k) N(z) = 0 with x' = phi' = y' = u' = 0
    let excess = mu_v - scene.mu_k;
    let a_eff = |r: usize, c: usize| a[r][c] + sys.b[r] * excess * sys.r_n[c];
    let pos: Vec<usize> = active(scene).into_iter().filter(|i| i % 2 == 0).collect();
    // the velocity rows (odd) at zero velocity: sum over positions of a_eff(row, pos) q = -a_eff(row, ONE)
    let n = pos.len();
    let m = DMatrix::from_fn(n, n, |r, c| a_eff(pos[r] + 1, pos[c]));
    let rhs = nalgebra::DVector::from_fn(n, |r, _| -a_eff(pos[r] + 1, NA - 1));
    let mut state = [0.0; NS];
    if let Some(q) = m.lu().solve(&rhs) {
        for (k, &p) in pos.iter().enumerate() {
            state[p] = q[k];
        }
    }
    // (without rotation phi stays phi_0; the model's rows carry N_0 as a constant)
    if !scene.rotation {
        state[2] = co.phi0;
    }
    let normal_force: f64 = (0..NS).map(|c| sys.r_n[c] * state[c]).sum::<f64>() + sys.r_n[NA - 1];
    let mut invalid = None;
    // sprag: the static stiffness under the sliding friction mu(V) (forward: sigma = +1)
    let static_stiffness = if !scene.rotation {
        f64::INFINITY
    } else if scene.floating() {
        let (_, _, c) = System::floating_mode_quadratic(scene, co, mu_v);
        c
    } else {
        co.effective_rotational_stiffness(scene, 1.0, mu_v)
    };
    if static_stiffness <= 0.0 {
        invalid = Some((
            NoSteadySliding::Sprag,
            format!("sprag: the pad's static stiffness under the sliding friction mu(V) = {mu_v:.4} is {static_stiffness:.4e} <= 0 (it self-locks)"),
        ));
    } else if normal_force < 0.0 {
        invalid = Some((NoSteadySliding::ContactLoss, format!("contact loss: N = {normal_force:.4e} N < 0 in steady sliding")));
    } else if scene.floating() {
        for (name, d) in [("leading", sys.d_l), ("trailing", sys.d_t)] {
            let compression = state[Y] + d * state[2];
            if compression < 0.0 {
                invalid = Some((
                    NoSteadySliding::ContactLoss,
                    format!("contact loss: the {name} spring lifts off in steady sliding (compression {compression:.3e} m)"),
                ));
            }
        }
    }
    SteadySliding { state, normal_force, invalid }
}

/// Steady sliding of `scene` and its modes. The scene must be valid
/// ([`Scene::validate`]).
pub fn sliding_stability(scene: &Scene) -> SlidingStability {
    let equivalent = small_signal(scene);
    let scene = &equivalent;
    let co = Coefficients::of(scene);
    let sys = System::of(scene, &co);
    let SteadySliding { state, normal_force, invalid } = fixed_point(scene, &co, &sys);
    let a = &sys.a[stickslip_model::Regime::SlipSlower.index()];
    let (mu_v, mu_slope) = friction_at(scene, scene.v);
    let excess = mu_v - scene.mu_k;
    // J = A + b [excess r_N - N mu'(V) r_v] on the active entries
    let idx = active(scene);
    let k = idx.len();
    let j = DMatrix::from_fn(k, k, |r, c| {
        let (r, c) = (idx[r], idx[c]);
        a[r][c] + sys.b[r] * (excess * sys.r_n[c] - normal_force * mu_slope * sys.r_v[c])
    });
    let eig = eigenvalues(j);
    let mut modes: Vec<Mode> = eig
        .iter()
        .filter(|l| l.im >= 0.0)
        .map(|l| Mode { growth_rate: l.re, frequency_hz: l.im / (2.0 * std::f64::consts::PI) })
        .collect();
    modes.sort_by(|p, q| q.growth_rate.total_cmp(&p.growth_rate));
    SlidingStability { state, normal_force, modes, invalid }
}

/// Eigenvalues of a real matrix: balanced first (the model's entries span ten decades: a
/// stiffness over an inertia beside 1), then nalgebra's real Schur form with a bounded
/// iteration count, shifted where it stalls (NaN eigenvalues if no shift converges, never a
/// hang).
fn eigenvalues(mut j: DMatrix<f64>) -> Vec<nalgebra::Complex<f64>> {
    let n = j.nrows();
    // Parlett-Reinsch balancing by powers of two (exact: the eigenvalues are unchanged)
    for _ in 0..32 {
        let mut done = true;
        for i in 0..n {
            let c: f64 = (0..n).filter(|&k| k != i).map(|k| j[(k, i)].abs()).sum();
            let r: f64 = (0..n).filter(|&k| k != i).map(|k| j[(i, k)].abs()).sum();
            // (a row or column that sums to inf or NaN is left as it is: halving inf never ends)
            if c == 0.0 || r == 0.0 || !(c + r).is_finite() {
                continue;
            }
            let mut f = 1.0;
            let (mut cc, s) = (c, c + r);
            while cc < r / 2.0 {
                cc *= 2.0;
                f *= 2.0;
            }
            while cc > r * 2.0 {
                cc /= 2.0;
                f /= 2.0;
            }
            if (cc + r / f) < 0.95 * s {
                done = false;
                for k in 0..n {
                    j[(i, k)] /= f;
                    j[(k, i)] *= f;
                }
            }
        }
        if done {
            break;
        }
    }
    // nalgebra's real Schur iteration stalls on spectra symmetric about 0 (an undamped
    // system's +-a +-ib, exactly the flutter case): a real shift sigma breaks the symmetry, and
    // the eigenvalues of J + sigma I less sigma are J's (to round-off of sigma's size)
    let scale = j.norm() / (n as f64).sqrt();
    for shift in [0.0, 0.137, -0.291, 0.613] {
        let sigma = shift * scale;
        let shifted = &j + DMatrix::identity(n, n) * sigma;
        if let Some(schur) = nalgebra::linalg::Schur::try_new(shifted, f64::EPSILON, 10_000) {
            return schur.complex_eigenvalues().iter().map(|l| l - sigma).collect();
        }
    }
    vec![nalgebra::Complex::new(f64::NAN, f64::NAN); n]
}

/// The smallest kinetic friction coefficient mu_k in [lo, hi] at which steady sliding (Coulomb
/// friction) is unstable, by bisection to `tol`; `None` if it is stable at `hi` or unstable at
/// `lo`. For the floating pad this is the mode-coupling (flutter) threshold.
pub fn instability_threshold_mu(scene: &Scene, lo: f64, hi: f64, tol: f64) -> Option<f64> {
    let unstable = |mu: f64| {
        let mut s = *scene;
        s.friction = FrictionLaw::Coulomb;
        s.mu_k = mu;
        s.mu_s = s.mu_s.max(mu);
        !sliding_stability(&s).stable()
    };
    if unstable(lo) || !unstable(hi) {
        return None;
    }
    let (mut a, mut b) = (lo, hi);
    while b - a > tol {
        let mid = 0.5 * (a + b);
        if unstable(mid) {
            b = mid;
        } else {
            a = mid;
        }
    }
    Some(b)
}
