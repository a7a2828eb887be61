//! The friction law at the pad-band contact: Coulomb with a static coefficient mu_s for
//! sticking and a kinetic coefficient mu_k <= mu_s for sliding (docs/model.md).
//!
//! Sign convention: the friction force F_f acts on the pad along +x (the band's direction of
//! motion). Relative velocity V_r = x' - V (pad minus band).

/// Coulomb friction with distinct static and kinetic coefficients.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coulomb {
    pub mu_s: f64,
    pub mu_k: f64,
}

impl Coulomb {
    /// Friction force on the pad while sliding [N]: +mu_k N when the pad is slower than the
    /// band (V_r < 0, the band drags it forward), -mu_k N when faster (V_r > 0).
    #[inline]
    pub fn sliding_force(&self, v_r_sign: f64, n: f64) -> f64 {
        -v_r_sign * self.mu_k * n
    }

    /// Largest friction force the contact can hold while sticking [N].
    #[inline]
    pub fn static_limit(&self, n: f64) -> f64 {
        self.mu_s * n
    }
}
