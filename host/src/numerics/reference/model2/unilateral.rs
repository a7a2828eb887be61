//! The reference of model 3, part 1 (docs/model.md, "unilateral contact"): the floating pad
//! whose edge springs push and never pull, independent of `stickslip_model`'s event runner and
//! its edge systems.
//!
//! Each contact state (both edges closed, the lead open, the trail open, both open) is model 2's
//! reference right-hand side ([`Phys`], written from docs/model.md) with the open spring's
//! stiffness taken out of `N`, `K`, `c_N` and the y equation: `F_i = k_i max(0, y + d_i phi)`.
//! The driver watches three guards in every regime ([`Hybrid::guard_count`]): the friction's
//! (model 2's), and each edge's compression `d_i = y + d_i phi` (a closed edge opens where it
//! falls through zero, an open one closes where it rises through zero), crests inside a step
//! included (their rates `y' + d_i phi'` are exact). At an edge's crossing its force is zero on
//! both sides: the state is kept, only the contact state changes. Both edges open is the pad in
//! the air: the run ends with an error naming `contact_loss`.
//!
//! The statistics are taken along the run's main path: the DOP853 step ends and the extrema
//! inside a step (bisected on the rate's sign), the edges' open time and openings over the
//! window [stats_from, duration] (an edge open at the window's start counts one opening, as the
//! product counts them).
//!
//! Slow and allocating: a yardstick for the accuracy report and the tests.

use super::driver::{self, arr, Bracket, Hybrid, Plan};
use super::*;

/// An edge's index in `[lead, trail]`.
const LEAD: usize = 0;
const TRAIL: usize = 1;

/// The regime: the friction's and which edges are open (`[lead, trail]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Contact {
    pub friction: Regime,
    pub open: [bool; 2],
}

impl Contact {
    fn index(self) -> usize {
        self.open[LEAD] as usize + 2 * self.open[TRAIL] as usize
    }
    /// Both edges open: the pad is in the air.
    pub fn lost(self) -> bool {
        self.open[LEAD] && self.open[TRAIL]
    }
}

/// The four contact states' constants (index: lead open + 2 trail open).
struct Edges {
    phys: [Phys; 4],
}

impl Edges {
    fn of(scene: &Scene) -> Edges {
        let closed = Phys::of(scene);
        let [k_l, k_t] = scene.contact_stiffnesses();
        let (d_l, d_t) = (closed.pad.d_l, closed.pad.d_t);
        let with = |kl: f64, kt: f64| {
            let mut p = closed;
            p.pad.k_rot = kl * d_l * d_l + kt * d_t * d_t;
            p.pad.c_n = kl * d_l + kt * d_t;
            p.k_s = kl + kt;
            p
        };
        Edges { phys: [closed, with(0.0, k_t), with(k_l, 0.0), with(0.0, 0.0)] }
    }
    fn phys(&self, r: Contact) -> &Phys {
        &self.phys[r.index()]
    }
    /// The compression of edge `e`, y + d_e phi [m], and its rate.
    fn compression(&self, z: &Z, e: usize) -> (f64, f64) {
        let d = if e == LEAD { self.phys[0].pad.d_l } else { self.phys[0].pad.d_t };
        (z[6] + d * z[2], z[7] + d * z[3])
    }
}

impl Hybrid<8> for Edges {
    type Regime = Contact;
    const NAME: &'static str = "unilateral-contact reference";

    fn rhs(&self, r: Contact, z: &Z) -> Z {
        self.phys(r).rhs(r.friction, z)
    }
    /// The friction's guard (the regime's guard is the first of the three).
    fn guard(&self, r: Contact, z: &Z) -> f64 {
        self.phys(r).guard(r.friction, z)
    }
    fn transition(&self, r: Contact, z: &mut Z) -> Contact {
        Contact { friction: self.phys(r).transition(r.friction, z), open: r.open }
    }
    fn fastest_rate(&self) -> f64 {
        self.phys[0].fastest_rate()
    }
    fn guard_count(&self) -> usize {
        3
    }
    fn guard_k(&self, r: Contact, z: &Z, k: usize) -> f64 {
        match k {
            0 => self.guard(r, z),
            _ => {
                let (d, _) = self.compression(z, k - 1);
                if r.open[k - 1] {
                    d
                } else {
                    -d
                }
            }
        }
    }
    fn guard_rate_k(&self, r: Contact, z: &Z, k: usize) -> Option<f64> {
        match k {
            0 => self.phys(r).guard_rate(r.friction, z),
            _ => {
                let (_, rate) = self.compression(z, k - 1);
                Some(if r.open[k - 1] { rate } else { -rate })
            }
        }
    }
    fn armed_k(&self, r: Contact, z: &Z, k: usize) -> bool {
        k > 0 || self.phys(r).armed(r.friction, z)
    }
    fn transition_k(&self, r: Contact, z: &mut Z, k: usize) -> Contact {
        match k {
            0 => self.transition(r, z),
            _ => {
                let mut open = r.open;
                open[k - 1] = !open[k - 1];
                Contact { friction: r.friction, open }
            }
        }
    }
}

/// A reference run with unilateral contact: what the accuracy report compares.
#[derive(Clone, Debug)]
pub struct UnilateralRun {
    /// Every transition: time, from, to (friction and edges).
    pub transitions: Vec<(f64, Contact, Contact)>,
    /// Slip onsets (stick to slip) in the window [s].
    pub onsets: Vec<f64>,
    /// The window's extremes of [x, x', phi, phi'].
    pub min: [f64; 4],
    pub max: [f64; 4],
    /// The fraction of the window spent in stick.
    pub stick_fraction: f64,
    /// The state `[x, x', phi, phi', u, u', y, y']` at the end.
    pub final_state: [f64; 8],
    /// Each edge's (`[lead, trail]`) open time in the window [s] and openings there.
    pub open_s: [f64; 2],
    pub openings: [u64; 2],
    pub window_s: f64,
    /// DOP853 steps accepted on the main path.
    pub accepted_steps: u64,
}

/// Runs a unilateral scene (a floating pad, `contact = "unilateral"`) from model 2's start (the
/// static state under the load; an edge in tension there opens at once) to its duration.
pub fn simulate_unilateral(scene: &Scene, tol: Tolerances) -> Result<UnilateralRun, String> {
    scene.validate().map_err(|e| format!("invalid scene: {e}"))?;
    if !scene.floating() {
        return Err("unilateral-contact reference: the pad must float (finite k_pivot)".into());
    }
    let sys = Edges::of(scene);
    let start = Start::default_of(scene);
    let mut z = Z::from_row_slice(&start.state);
    let open = [sys.compression(&z, LEAD).0 < 0.0, sys.compression(&z, TRAIL).0 < 0.0];
    let regime = Contact { friction: start.regime, open };
    if regime.lost() {
        return Err("contact_loss at t = 0 s: both edges in tension under the load".into());
    }
    sys.phys(regime).project_stick(&mut z);
    let from = scene.stats_from;
    let mut lo = [f64::INFINITY; 4];
    let mut hi = [f64::NEG_INFINITY; 4];
    let (mut stick_s, mut open_s) = (0.0, [0.0; 2]);
    let quantities = |r: Contact, y: &Z| {
        let d = sys.rhs(r, y);
        ([y[0], y[1], y[2], y[3]], [y[1], d[1], y[3], d[3]])
    };
    let observe = |piece: &driver::Piece<Contact, 8>| -> Result<(), String> {
        let r = piece.regime;
        if r.lost() {
            return Err(format!("contact_loss at t = {:.9} s: both edges open", piece.t0));
        }
        if piece.t0 < from {
            return Ok(());
        }
        if r.friction == Regime::Stick {
            stick_s += piece.t1 - piece.t0;
        }
        for e in 0..2 {
            if r.open[e] {
                open_s[e] += piece.t1 - piece.t0;
            }
        }
        let mut include = |q: [f64; 4]| {
            for c in 0..4 {
                lo[c] = lo[c].min(q[c]);
                hi[c] = hi[c].max(q[c]);
            }
        };
        include(quantities(r, piece.y0).0);
        include(quantities(r, piece.y1).0);
        // the steps up to the event (the last one cut at it)
        let last = piece.fired.unwrap_or(piece.ys.len() - 1);
        for k in 1..=last {
            let (t_b, y_b) = if Some(k) == piece.fired { (piece.t1, *piece.y1) } else { (piece.ts[k], piece.ys[k]) };
            include(quantities(r, &y_b).0);
            let (_, ra) = quantities(r, &piece.ys[k - 1]);
            let (_, rb) = quantities(r, &y_b);
            for c in 0..4 {
                if ra[c] * rb[c] < 0.0 {
                    let up = ra[c] > 0.0;
                    let step = Bracket { t_a: piece.ts[k - 1], y_a: piece.ys[k - 1], lo: piece.ts[k - 1], hi: t_b, y_hi: y_b };
                    let found = driver::bisect(&sys, r, step, piece.h_max, &tol, |y| (quantities(r, y).1[c] > 0.0) != up)?;
                    include(quantities(r, &found.state).0);
                }
            }
        }
        Ok(())
    };
    let plan = Plan { stop_at: (from > 0.0).then_some(from), chunk_steps: Some(CHUNK_STEPS) };
    let path = driver::run(&sys, z, regime, scene.duration, plan, &tol, observe)?;
    if path.final_regime.lost() {
        return Err(format!("contact_loss by t = {} s: both edges open", scene.duration));
    }
    // an edge open at the window's start counts one opening (not one made before it)
    let at_from = path.transitions.iter().take_while(|tr| tr.t < from).last().map_or(regime, |tr| tr.to);
    let mut openings = [at_from.open[LEAD] as u64, at_from.open[TRAIL] as u64];
    let mut onsets = Vec::new();
    for tr in &path.transitions {
        if tr.t < from {
            continue;
        }
        if tr.from.friction == Regime::Stick && tr.to.friction != Regime::Stick {
            onsets.push(tr.t);
        }
        for e in 0..2 {
            if !tr.from.open[e] && tr.to.open[e] {
                openings[e] += 1;
            }
        }
    }
    let window_s = scene.duration - from;
    Ok(UnilateralRun {
        transitions: path.transitions.iter().map(|tr| (tr.t, tr.from, tr.to)).collect(),
        onsets,
        min: lo,
        max: hi,
        stick_fraction: stick_s / window_s,
        final_state: arr(&path.final_state),
        open_s,
        openings,
        window_s,
        accepted_steps: path.accepted_steps,
    })
}
