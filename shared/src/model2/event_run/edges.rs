//! Unilateral contact (model 3, option 2; issue 34; docs/model.md "Model 3: unilateral
//! contact"): the floating pad's two edge springs push and never pull,
//! F_i = k_i max(0, d_i) with d_i = y + d_i phi the compression at edge i.
//!
//! An open edge is a contact state with its own linear flow: the same equations with that
//! spring's stiffness set to zero (its force is zero while it is open), so each of the three
//! contact states (both closed, the lead open, the trail open) is a [`System`] of its own.
//! Both edges open is the pad in the air: the run halts with `contact_loss` there.
//!
//! Guards, watched by the event runner beside the friction's:
//! - a closed edge opens where its compression d_i (and so its force) falls through zero;
//! - an open edge closes where d_i rises through zero.
//!
//! At either crossing the spring's force is zero on both sides, so the state is continuous
//! and nothing is gained or lost on re-contact (no impact: a spring that closes starts at
//! zero force); the new state is chosen by the compression's rate at the crossing (its
//! second derivative on a graze), so a graze that touches zero and turns back keeps the state.

use crate::coefficients::Coefficients;
use crate::model2::system::{System, NA, NS, ONE, Y};
use crate::scene::Scene;

/// Index of the lead and the trail edge in `[lead, trail]` pairs.
pub const LEAD: usize = 0;
pub const TRAIL: usize = 1;

/// The contact state's index into [`systems`]: 0 both closed, 1 the lead open, 2 the trail
/// open; None with both open (no contact).
pub fn state_index(open: [bool; 2]) -> Option<usize> {
    match open {
        [false, false] => Some(0),
        [true, false] => Some(1),
        [false, true] => Some(2),
        [true, true] => None,
    }
}

/// The systems of the three contact states of `scene` (a pad that is not hinged): both
/// closed (model 2's own [`System::floating_pad`]), the lead spring open (k_L = 0), the trail
/// spring open (k_T = 0). The static start (phi_0, y_0, N_0) stays the closed pad's in all three.
pub fn systems(scene: &Scene) -> [System; 3] {
    let scene = &scene.linearised_contact();
    let co = Coefficients::of(scene);
    let closed = System::floating_pad(scene, &co);
    let open = |lead: bool| {
        let mut s = *scene;
        if lead {
            s.k_l = 0.0;
        } else {
            s.k_t = 0.0;
        }
        let mut sys = System::floating_pad(&s, &Coefficients::of(&s));
        sys.phi0 = closed.phi0;
        sys.y0 = closed.y0;
        sys.n0 = closed.n0;
        // the edges' lever arms and stiffnesses stay the scene's (the compressions' rows)
        sys.k_l = closed.k_l;
        sys.k_t = closed.k_t;
        sys
    };
    [closed, open(true), open(false)]
}

/// The compression rows d_L = y + d_L phi and d_T = y + d_T phi [m].
pub fn compression_rows(sys: &System) -> [[f64; NA]; 2] {
    let row = |d: f64| {
        let mut r = [0.0; NA];
        r[Y] = 1.0;
        r[2] = d;
        r
    };
    [row(sys.d_l), row(sys.d_t)]
}

/// The compression of row `r` at `z` [m].
pub fn compression(r: &[f64; NA], z: &[f64; NS]) -> f64 {
    let mut s = r[ONE];
    for i in 0..NS {
        s += r[i] * z[i];
    }
    s
}

/// Each edge's time open and openings over the statistics window.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EdgeStats {
    /// Time each edge ([lead, trail]) was open inside the window [s].
    pub open_s: [f64; 2],
    /// Openings of each edge inside the window (an edge open at the window's start counts
    /// one).
    pub openings: [u64; 2],
    /// Openings over the whole run.
    pub openings_run: [u64; 2],
    /// The window's length covered [s].
    pub window_s: f64,
}

impl EdgeStats {
    /// The fraction of the window edge `i` was open (0 without a window).
    pub fn open_fraction(&self, i: usize) -> f64 {
        if self.window_s > 0.0 {
            self.open_s[i] / self.window_s
        } else {
            0.0
        }
    }
}
