//! The equations of model 2 as matrices (docs/model.md, "Model 2").
//!
//! State z = [x, x', phi, phi', u, u', y, y'] with u = x_b - V t (the band's offset from its
//! drive point) and y the pivot's translation normal to the band (the floating pad, part 2),
//! augmented with a constant 1 (index [`ONE`]). Every regime's Coulomb part is linear,
//! z' = A z; Stribeck friction adds a scalar forcing along one fixed direction,
//!
//! ```text
//! z' = A_sigma z + b q(z),   q(z) = sigma (mu(|v|) - mu_k) N(z)
//! ```
//!
//! where b = [0, 1/m, 0, s w / I, 0, -1/m_b] is where a unit friction force on the pad acts
//! (the pad's x, its moment arm s w, and the band's reaction) and A_sigma carries the kinetic
//! part sigma mu_k N. The sliding velocity v, the normal force N and the stick's required force
//! F_req are linear rows of z. Rows of a degree of freedom the scene leaves out are zero, and
//! its coordinates keep their initial values for good.

use crate::coefficients::Coefficients;
use crate::linalg::MatN;
use crate::scene::{FrictionLaw, Scene};
use crate::stickslip::Regime;

/// State size: x, x', phi, phi', u, u', y, y'.
pub const NS: usize = 8;
/// Augmented size (the constant 1 last).
pub const NA: usize = 9;
/// Index of the constant 1 in the augmented state.
pub const ONE: usize = 8;
/// Index of y, the floating pad's pivot translation normal to the band [m] (positive toward
/// the band: compressing the contact springs); y' is `Y + 1`.
pub const Y: usize = 6;
/// An augmented matrix of model 2 (f64, set-up only).
pub type Mat9 = MatN<NA>;

/// The regimes' matrices and rows, in f64.
#[derive(Clone, Copy, Debug)]
pub struct System {
    /// A of stick, slip slower, slip faster (slip: the kinetic part sigma mu_k N).
    pub a: [Mat9; 3],
    /// Direction of a unit friction force on the pad, per unit of force [1/kg, 1/(kg m)].
    pub b: [f64; NA],
    /// Sliding velocity v = x' (+ s w phi' with the face) - V - u' [m/s].
    pub r_v: [f64; NA],
    /// Normal force N [N]: c_N phi, or N_0 without rotation.
    pub r_n: [f64; NA],
    /// Required friction force in stick F_req [N].
    pub r_freq: [f64; NA],
    pub stribeck: bool,
    pub band: bool,
    pub rotation: bool,
    /// Friction-face kinematics (with rotation: without it phi' = 0 and the face is the pivot).
    pub face: bool,
    /// s w [m]: the friction's moment arm about the pivot, and with `face` the face velocity's
    /// phi' coefficient.
    pub s_w: f64,
    /// Inverse effective mass of the sliding velocity, dv/dt per newton of friction on the pad,
    /// r_v . b = 1/m (+ (s w)^2 / I with the face, + 1/m_b with the band) [1/kg].
    pub inv_mass_v: f64,
    /// mu_s - mu_k.
    pub d_mu: f64,
    pub mu_s: f64,
    pub mu_k: f64,
    pub v_s: f64,
    pub delta: f64,
    pub v: f64,
    pub m: f64,
    pub m_b: f64,
    /// The floating pad (finite k_pivot): y and y' move.
    pub floating: bool,
    /// The start: phi_0 [rad] and y_0 [m] (y_0 = 0 with the hinge), the static state under
    /// the load with no friction.
    pub phi0: f64,
    pub y0: f64,
    /// The normal force at the start, N_0 [N].
    pub n0: f64,
    /// Contact spring compressions y + d phi: the lever arms d_L, d_T [m] and stiffnesses
    /// k_L, k_T [N/m] (the floating pad's per-spring contact check).
    pub d_l: f64,
    pub d_t: f64,
    pub k_l: f64,
    pub k_t: f64,
}

impl System {
    /// The equations of `scene`: [`Self::floating_pad`] for a finite k_pivot, else
    /// [`Self::hinged`]. (A stepper compiled for one kind calls that one directly, so the
    /// other's set-up code is not in its build.)
    pub fn of(scene: &Scene, co: &Coefficients) -> System {
        if scene.floating() {
            Self::floating_pad(scene, co)
        } else {
            Self::hinged(scene, co)
        }
    }

    /// How a force G [N] on the band (along x) enters each regime's equations, per newton: z'
    /// gains `g[regime] G` and stick's required friction F_req gains `f_req G` (model 3's
    /// pneumatic drive, whose cylinder force is not linear in z). In slip G moves only the
    /// band, g = e_u' / m_b; in stick it moves the stuck pad-band pair and shares out through
    /// the constraint. Each is the difference of the augmented columns of the equations with a
    /// unit constant band force and without (the equations are linear in that column).
    #[cfg(feature = "model3")]
    pub fn band_force_response(scene: &Scene, co: &Coefficients) -> ([[f64; NS]; 3], f64) {
        let (with, without) = if scene.floating() {
            (Self::floating_forced(scene, co, 1.0), Self::floating_forced(scene, co, 0.0))
        } else {
            (Self::hinged_forced(scene, co, 1.0), Self::hinged_forced(scene, co, 0.0))
        };
        let g = core::array::from_fn(|r| core::array::from_fn(|i| with.a[r][i][ONE] - without.a[r][i][ONE]));
        (g, with.r_freq[ONE] - without.r_freq[ONE])
    }

    /// The hinged pad (the thesis's pivot, y = 0 for good): part 1 and the face.
    #[inline(always)]
    pub fn hinged(scene: &Scene, co: &Coefficients) -> System {
        Self::hinged_forced(scene, co, 0.0)
    }

    /// [`Self::hinged`] with a constant force `band_force` [N] on the band (along x), carried
    /// in the augmented column: the pneumatic drive's response ([`Self::band_force_response`]).
    #[inline(always)]
    fn hinged_forced(scene: &Scene, co: &Coefficients, band_force: f64) -> System {
        let band = scene.band;
        let rot = scene.rotation;
        let (m, i) = (scene.m, scene.inertia);
        let s_w = co.s * scene.w;
        let mut r_n = [0.0; NA];
        if rot {
            r_n[2] = co.c_n;
        } else {
            r_n[ONE] = co.n0;
        }
        let face = scene.face;
        let mut r_v = [0.0; NA];
        r_v[1] = 1.0;
        r_v[ONE] = -scene.v;
        if band {
            r_v[5] = -1.0;
        }
        if face && rot {
            // the face, w from the pivot line, moves at x' + s w phi'
            r_v[3] = s_w;
        }
        // the pad's and the band's restoring rows (no friction)
        let mut pad_x = [0.0; NA]; // m x'' without friction
        pad_x[0] = -scene.k_g;
        pad_x[1] = -scene.c_x;
        let mut band_u = [0.0; NA]; // m_b u'' without friction
        if band {
            band_u[4] = -scene.k_b;
            band_u[5] = -scene.c_b;
            band_u[ONE] = band_force;
        }
        let mut rot_row = [0.0; NA]; // I phi'' without friction
        if rot {
            rot_row[2] = -co.k_rot;
            rot_row[3] = -scene.c_phi;
            rot_row[ONE] = scene.f_n * co.a_n;
        }
        // stick: F_req and the common acceleration
        let mut r_freq = [0.0; NA];
        let mut stick_acc = [0.0; NA]; // x'' (= u'' with the band)
        // face kinematics: the stick constraint x'' + s w phi'' = u'' (band) or 0 with the
        // friction F on the pad, m x'' = P_x + F, I phi'' = P_phi + s w F, m_b u'' = P_u - F:
        //   F = (-P_x - (m s w / I) P_phi + (m / m_b) P_u) / (1 + m (s w)^2 / I + m / m_b)
        // (the band's terms only with the band). Scaled by m, so that w = 0 without the band
        // gives F = -P_x exactly.
        let s_w_face = if face && rot { s_w } else { 0.0 };
        if face {
            let den = 1.0 + m * s_w_face * s_w_face / i + if band { m / scene.m_b } else { 0.0 };
            for c in 0..NA {
                let mut num = -pad_x[c] - m * s_w_face / i * rot_row[c];
                if band {
                    num += m / scene.m_b * band_u[c];
                }
                r_freq[c] = num / den;
            }
        } else if band {
            let mt = m + scene.m_b;
            for c in 0..NA {
                stick_acc[c] = (pad_x[c] + band_u[c]) / mt;
                r_freq[c] = m * stick_acc[c] - pad_x[c];
            }
        } else {
            // x' = V, x'' = 0: F_req = k_g x + c_x V
            r_freq[0] = scene.k_g;
            r_freq[ONE] = scene.c_x * scene.v;
        }
        let mut a = [[[0.0; NA]; NA]; 3];
        for regime in Regime::ALL {
            let ar = &mut a[regime.index()];
            ar[0][1] = 1.0;
            if rot {
                ar[2][3] = 1.0;
            }
            if band {
                ar[4][5] = 1.0;
            }
            match regime {
                Regime::Stick if face => {
                    for c in 0..NA {
                        ar[1][c] = (pad_x[c] + r_freq[c]) / m;
                        if rot {
                            ar[3][c] = (rot_row[c] + s_w * r_freq[c]) / i;
                        }
                        if band {
                            ar[5][c] = (band_u[c] - r_freq[c]) / scene.m_b;
                        }
                    }
                }
                Regime::Stick => {
                    if band {
                        ar[1] = stick_acc;
                        ar[5] = stick_acc;
                    }
                    if rot {
                        for c in 0..NA {
                            ar[3][c] = (rot_row[c] + s_w * r_freq[c]) / i;
                        }
                    }
                }
                Regime::SlipSlower | Regime::SlipFaster => {
                    let f = regime.friction_sign() * scene.mu_k; // F_f = f N
                    for c in 0..NA {
                        let ff = f * r_n[c];
                        ar[1][c] = (pad_x[c] + ff) / m;
                        if rot {
                            ar[3][c] = (rot_row[c] + s_w * ff) / i;
                        }
                        if band {
                            ar[5][c] = (band_u[c] - ff) / scene.m_b;
                        }
                    }
                }
            }
        }
        let mut b = [0.0; NA];
        b[1] = 1.0 / m;
        if rot {
            b[3] = s_w / i;
        }
        if band {
            b[5] = -1.0 / scene.m_b;
        }
        System {
            a,
            b,
            r_v,
            r_n,
            r_freq,
            stribeck: scene.friction == FrictionLaw::Stribeck,
            band,
            rotation: rot,
            face,
            s_w,
            inv_mass_v: (0..NA).map(|c| r_v[c] * b[c]).sum(),
            d_mu: scene.mu_s - scene.mu_k,
            mu_s: scene.mu_s,
            mu_k: scene.mu_k,
            v_s: scene.v_s,
            delta: scene.stribeck_exponent,
            v: scene.v,
            m,
            m_b: scene.m_b,
            floating: false,
            phi0: co.phi0,
            y0: 0.0,
            n0: co.n0,
            d_l: co.d_l,
            d_t: co.d_t,
            k_l: scene.contact_stiffnesses()[0],
            k_t: scene.contact_stiffnesses()[1],
        }
    }

    /// The floating pad (docs/model.md, "Model 2, part 2"): generalized coordinates x, phi, u
    /// (with the band) and y, the pivot's translation normal to the band. The reference point is
    /// the pivot (the supported edge at mid-thickness), so that y = 0 is the thesis's hinge; the
    /// centre of gravity lies l from it along the pad, which couples y and phi in the mass
    /// matrix:
    ///
    /// ```text
    /// m x''                 = -k_g x - c_x x'                              + F
    /// I phi'' + m l y''     = F_N a_N - K phi - c_N y - c_phi phi'         + s w F
    /// m l phi'' + m y''     = F_N - (k_L + k_T + k_pivot) y - c_N phi - c_y y'
    /// m_b u''               = -k_b u - c_b u'                              - F   (band)
    /// N = (k_L + k_T) y + c_N phi = k_L (y + d_L phi) + k_T (y + d_T phi)
    /// ```
    ///
    /// with the friction F at the face, whose velocity is x' + s w phi' (face kinematics).
    /// Stick holds x'' + s w phi'' - u'' = 0, which gives F_req as a linear row of z.
    #[allow(clippy::needless_range_loop)] // matrix code: indices read as the formulas
    #[inline(always)]
    pub fn floating_pad(scene: &Scene, co: &Coefficients) -> System {
        Self::floating_forced(scene, co, 0.0)
    }

    /// [`Self::floating_pad`] with a constant force `band_force` [N] on the band.
    #[inline(always)]
    fn floating_forced(scene: &Scene, co: &Coefficients, band_force: f64) -> System {
        let band = scene.band;
        let (m, i) = (scene.m, scene.inertia);
        let s_w = co.s * scene.w;
        let k_s = { let [k_l, k_t] = scene.contact_stiffnesses(); k_l + k_t };
        let k_y = k_s + scene.k_pivot;
        let ml = m * scene.l;
        // inverse of the (phi, y) mass block [[I, m l], [m l, m]]
        let det = i * m - ml * ml;
        let (inv_pp, inv_py, inv_yy) = (m / det, -ml / det, i / det);
        // generalized forces without friction, as rows of (z, 1)
        let mut q_x = [0.0; NA];
        q_x[0] = -scene.k_g;
        q_x[1] = -scene.c_x;
        let mut q_phi = [0.0; NA];
        q_phi[2] = -co.k_rot;
        q_phi[3] = -scene.c_phi;
        q_phi[Y] = -co.c_n;
        q_phi[ONE] = scene.f_n * co.a_n;
        let mut q_y = [0.0; NA];
        q_y[2] = -co.c_n;
        q_y[Y] = -k_y;
        q_y[Y + 1] = -scene.c_y;
        q_y[ONE] = scene.f_n;
        let mut q_u = [0.0; NA];
        if band {
            q_u[4] = -scene.k_b;
            q_u[5] = -scene.c_b;
            q_u[ONE] = band_force;
        }
        // accelerations without friction
        let acc_x: [f64; NA] = core::array::from_fn(|c| q_x[c] / m);
        let acc_phi: [f64; NA] = core::array::from_fn(|c| inv_pp * q_phi[c] + inv_py * q_y[c]);
        let acc_y: [f64; NA] = core::array::from_fn(|c| inv_py * q_phi[c] + inv_yy * q_y[c]);
        let acc_u: [f64; NA] = core::array::from_fn(|c| if band { q_u[c] / scene.m_b } else { 0.0 });
        // a unit friction force: generalized force (1, s w, -1, 0) on (x, phi, u, y)
        let mut b = [0.0; NA];
        b[1] = 1.0 / m;
        b[3] = inv_pp * s_w;
        b[Y + 1] = inv_py * s_w;
        if band {
            b[5] = -1.0 / scene.m_b;
        }
        let mut r_v = [0.0; NA];
        r_v[1] = 1.0;
        r_v[3] = s_w;
        if band {
            r_v[5] = -1.0;
        }
        r_v[ONE] = -scene.v;
        let mut r_n = [0.0; NA];
        r_n[2] = co.c_n;
        r_n[Y] = k_s;
        let inv_mass_v: f64 = (0..NA).map(|c| r_v[c] * b[c]).sum();
        // stick: x'' + s w phi'' - u'' = 0 with the friction F_req
        let r_freq: [f64; NA] = core::array::from_fn(|c| -(acc_x[c] + s_w * acc_phi[c] - acc_u[c]) / inv_mass_v);
        let mut a = [[[0.0; NA]; NA]; 3];
        for regime in Regime::ALL {
            let f: [f64; NA] = match regime {
                Regime::Stick => r_freq,
                _ => core::array::from_fn(|c| regime.friction_sign() * scene.mu_k * r_n[c]),
            };
            let ar = &mut a[regime.index()];
            ar[0][1] = 1.0;
            ar[2][3] = 1.0;
            ar[Y][Y + 1] = 1.0;
            if band {
                ar[4][5] = 1.0;
            }
            for c in 0..NA {
                ar[1][c] = acc_x[c] + b[1] * f[c];
                ar[3][c] = acc_phi[c] + b[3] * f[c];
                ar[Y + 1][c] = acc_y[c] + b[Y + 1] * f[c];
                if band {
                    ar[5][c] = acc_u[c] + b[5] * f[c];
                }
            }
        }
        // the start: static under the load, no friction (x = 0)
        let (y0, phi0) = co.floating_rest(scene);
        System {
            a,
            b,
            r_v,
            r_n,
            r_freq,
            stribeck: scene.friction == FrictionLaw::Stribeck,
            band,
            rotation: true,
            face: true,
            s_w,
            inv_mass_v,
            d_mu: scene.mu_s - scene.mu_k,
            mu_s: scene.mu_s,
            mu_k: scene.mu_k,
            v_s: scene.v_s,
            delta: scene.stribeck_exponent,
            v: scene.v,
            m,
            m_b: scene.m_b,
            floating: true,
            phi0,
            y0,
            n0: k_s * y0 + co.c_n * phi0,
            d_l: co.d_l,
            d_t: co.d_t,
            k_l: scene.contact_stiffnesses()[0],
            k_t: scene.contact_stiffnesses()[1],
        }
    }

    /// The floating pad's (phi, y) modes with friction sigma mu N acting in the moment:
    /// det(K_f - lambda M) = 0 with M = [[I, m l], [m l, m]] and the friction-coupled,
    /// non-symmetric stiffness K_f = [[K - s w sigma mu c_N, c_N - s w sigma mu (k_L + k_T)],
    /// [c_N, k_L + k_T + k_pivot]]: lambda = omega^2 as (a, b, c) of a lambda^2 + b lambda + c.
    /// A negative discriminant b^2 - 4 a c is flutter (the two modes merged).
    pub fn floating_mode_quadratic(scene: &Scene, co: &Coefficients, sigma_mu: f64) -> (f64, f64, f64) {
        let s_w = co.s * scene.w;
        let k_s = { let [k_l, k_t] = scene.contact_stiffnesses(); k_l + k_t };
        let (m11, m12, m21, m22) = (scene.inertia, scene.m * scene.l, scene.m * scene.l, scene.m);
        let k11 = co.k_rot - s_w * sigma_mu * co.c_n;
        let k12 = co.c_n - s_w * sigma_mu * k_s;
        let (k21, k22) = (co.c_n, k_s + scene.k_pivot);
        let a = m11 * m22 - m12 * m21;
        let b = -(k11 * m22 + k22 * m11 - k12 * m21 - k21 * m12);
        let c = k11 * k22 - k12 * k21;
        (a, b, c)
    }

    /// Largest |eigenvalue| of the regimes' linear parts [1/s] (from the 2 x 2 blocks of each
    /// degree of freedom and of the stuck pad-band pair; an upper estimate, not a bound).
    pub fn linear_rate(&self, scene: &Scene, co: &Coefficients) -> f64 {
        if self.floating {
            self.floating_rate(scene, co)
        } else {
            self.hinged_rate(scene, co)
        }
    }

    /// [`Self::linear_rate`] of the floating pad.
    pub fn floating_rate(&self, scene: &Scene, co: &Coefficients) -> f64 {
        let mut rate = quad_max_root(scene.m, scene.c_x, scene.k_g);
        {
            // the (phi, y) modes with the friction's coupling (|omega^2| of the larger root; a
            // complex pair: its modulus), and the damping rates over the smaller inertia
            for sigma_mu in [scene.mu_s, -scene.mu_s, scene.mu_k, -scene.mu_k, 0.0] {
                let (a, b, c) = Self::floating_mode_quadratic(scene, co, sigma_mu);
                let disc = b * b - 4.0 * a * c;
                let lam = if disc < 0.0 {
                    libm::sqrt(libm::fabs(c / a))
                } else {
                    libm::fabs((-b - libm::sqrt(disc)) / (2.0 * a)).max(libm::fabs((-b + libm::sqrt(disc)) / (2.0 * a)))
                };
                rate = rate.max(libm::sqrt(lam));
            }
            let i_g = scene.inertia - scene.m * scene.l * scene.l;
            rate = rate.max(scene.c_y / scene.m).max(scene.c_phi / i_g);
            if self.band {
                // the band's mode, and its coupling through the friction (bounded by the sum)
                rate += quad_max_root(scene.m_b, scene.c_b, scene.k_b);
            }
            rate
        }
    }

    /// [`Self::linear_rate`] of the hinged pad.
    pub fn hinged_rate(&self, scene: &Scene, co: &Coefficients) -> f64 {
        let mut rate = quad_max_root(scene.m, scene.c_x, scene.k_g);
        if self.rotation {
            for sigma in [1.0, -1.0, 0.0] {
                for mu in [scene.mu_s, scene.mu_k] {
                    let k = co.k_rot - co.s * scene.w * sigma * mu * co.c_n;
                    rate = rate.max(quad_max_root(scene.inertia, scene.c_phi, k));
                }
            }
        }
        if self.face && self.rotation {
            // stick holds the face: x = x_face - s w phi, one rotational mode about the face,
            // (I + m w^2) phi'' = -(K + k_g w^2) phi - (c_phi + c_x w^2) phi' + ...
            let w2 = scene.w * scene.w;
            let face_rate =
                quad_max_root(scene.inertia + scene.m * w2, scene.c_phi + scene.c_x * w2, co.k_rot + scene.k_g * w2);
            rate = rate.max(face_rate);
            if self.band {
                rate = rate.max(face_rate + quad_max_root(scene.m_b, scene.c_b, scene.k_b));
            }
        }
        if self.band {
            rate = rate.max(quad_max_root(scene.m_b, scene.c_b, scene.k_b));
            rate = rate.max(quad_max_root(scene.m + scene.m_b, scene.c_x + scene.c_b, scene.k_g + scene.k_b));
            // the pad-band pair in slip: relative mode through the friction's mu_k coupling
            // is bounded by the sum of the two rates
            rate = rate.max(
                quad_max_root(scene.m, scene.c_x, scene.k_g) + quad_max_root(scene.m_b, scene.c_b, scene.k_b),
            );
        }
        rate
    }
}

/// The largest |root| of a x^2 + b x + c (a mode's rate for m, c, k), or sqrt(|c / a|) for a
/// complex pair.
fn quad_max_root(a: f64, b: f64, c: f64) -> f64 {
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        libm::sqrt(libm::fabs(c / a))
    } else {
        let r = libm::sqrt(disc);
        libm::fabs((-b - r) / (2.0 * a)).max(libm::fabs((-b + r) / (2.0 * a)))
    }
}

/// Dot product of a row with an augmented state (z, 1).
#[inline(always)]
pub fn row_dot<T: crate::Real>(r: &[T; NA], z: &[T; NS]) -> T {
    r[0] * z[0] + r[1] * z[1] + r[2] * z[2] + r[3] * z[3] + r[4] * z[4] + r[5] * z[5] + r[ONE]
}

/// [`row_dot`] over every entry, y and y' included (the floating pad).
#[inline(always)]
pub fn row_dot_all<T: crate::Real>(r: &[T; NA], z: &[T; NS]) -> T {
    r[0] * z[0] + r[1] * z[1] + r[2] * z[2] + r[3] * z[3] + r[4] * z[4] + r[5] * z[5] + r[6] * z[6] + r[7] * z[7] + r[ONE]
}
