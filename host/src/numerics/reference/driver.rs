//! The event-driven driver shared by the references: DOP853 stepping (the `ode_solvers` crate,
//! Hairer-Wanner, order 8 with step-size control), event location by bisection on
//! re-integrated sub-intervals, and the restart in the regime a fired guard leads to.
//!
//! It knows no model: a model is a [`Hybrid`] system (a right-hand side per regime, each
//! regime's guard, the transition a fired guard makes), written in its own file from
//! docs/model.md ([`super::thesis`], [`super::model2`]).
//!
//! Event location, in [`run`]:
//! - a regime's guard `g(y)` is negative while the regime holds; it is checked at every
//!   accepted step end, and the first step end where `g >= 0` is bisected, re-integrating from
//!   the step's start, to `t_tol`;
//! - a system that gives the guard's rate ([`Hybrid::guard_rate`]) also has every crest of `g`
//!   inside a step (negative at both ends, its rate turning from + to -) located by bisection
//!   and the guard tested there, so that a graze inside a step is not missed;
//! - a system may hold a regime's guard unarmed ([`Hybrid::armed`]): until it arms, the regime
//!   cannot end;
//! - steps are capped at `h_max = h_max_factor / fastest rate`, so no guard or extremum is
//!   stepped over.

use ode_solvers::dop853::Dop853;
use ode_solvers::{OutputType, SVector, System};
use std::fmt::Debug;

/// A state of N components.
pub type State<const N: usize> = SVector<f64, N>;

/// A run with more transitions than this stops with an error (a chattering contact).
const MAX_TRANSITIONS: usize = 10_000_000;

/// Tolerances of a reference run.
#[derive(Clone, Copy, Debug)]
pub struct Tolerances {
    /// Relative tolerance of DOP853's step-size control.
    pub rtol: f64,
    /// Absolute tolerance [state units: m, m/s, rad, rad/s].
    pub atol: f64,
    /// Width to which transitions and extrema are bisected [s].
    pub t_tol: f64,
    /// Largest step, as a fraction of 1 / omega_max (the fastest mode's period over 2 pi).
    pub h_max_factor: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances { rtol: 1e-12, atol: 1e-16, t_tol: 1e-13, h_max_factor: 0.05 }
    }
}

impl Tolerances {
    /// A looser run for the work-precision baseline: atol scaled with rtol, transitions to
    /// max(1e-13 s, rtol x 1e-3 s), steps up to 1/12 of the fastest period (the step-size
    /// control, not a cap, sets them).
    pub fn loose(rtol: f64) -> Self {
        Tolerances { rtol, atol: rtol * 1e-4, t_tol: (rtol * 1e-3).max(1e-13), h_max_factor: 0.5 }
    }

    fn check(&self, name: &str) -> Result<(), String> {
        if self.rtol > 0.0 && self.atol > 0.0 && self.t_tol > 0.0 && self.h_max_factor > 0.0 {
            Ok(())
        } else {
            Err(format!("{name}: tolerances must be > 0: {self:?}"))
        }
    }
}

/// A hybrid system of N states: what a model gives the driver.
pub trait Hybrid<const N: usize> {
    /// The contact's regime (stick, slip one way, slip the other).
    type Regime: Copy + Eq + Debug;
    /// The reference's name in error messages.
    const NAME: &'static str;

    /// The right-hand side y' in `regime`.
    fn rhs(&self, regime: Self::Regime, y: &State<N>) -> State<N>;
    /// The regime holds while its guard is negative.
    fn guard(&self, regime: Self::Regime, y: &State<N>) -> f64;
    /// The guard's rate along the motion, when the system wants crests inside a step located.
    fn guard_rate(&self, _regime: Self::Regime, _y: &State<N>) -> Option<f64> {
        None
    }
    /// Whether the guard of `regime` may end it at y (a regime that starts on its own guard
    /// arms once it has moved away from it).
    fn armed(&self, _regime: Self::Regime, _y: &State<N>) -> bool {
        true
    }
    /// The regime entered when the guard of `regime` fired at y; y is made consistent with it
    /// (the projection on entering stick).
    fn transition(&self, regime: Self::Regime, y: &mut State<N>) -> Self::Regime;

    /// How many guards every regime has (default 1: [`Hybrid::guard`] alone). A system with
    /// several (the friction's and each contact edge's) gives them by index in
    /// [`Hybrid::guard_k`], [`Hybrid::guard_rate_k`], [`Hybrid::armed_k`] and
    /// [`Hybrid::transition_k`]; the driver locates each one's first crossing in a step (crests
    /// included) and makes the earliest.
    fn guard_count(&self) -> usize {
        1
    }
    /// Guard `k` of `regime` (negative while the regime holds).
    fn guard_k(&self, regime: Self::Regime, y: &State<N>, _k: usize) -> f64 {
        self.guard(regime, y)
    }
    /// Rate of guard `k` along the motion.
    fn guard_rate_k(&self, regime: Self::Regime, y: &State<N>, _k: usize) -> Option<f64> {
        self.guard_rate(regime, y)
    }
    /// Whether guard `k` of `regime` may end it at y.
    fn armed_k(&self, regime: Self::Regime, y: &State<N>, _k: usize) -> bool {
        self.armed(regime, y)
    }
    /// The regime entered when guard `k` of `regime` fired at y.
    fn transition_k(&self, regime: Self::Regime, y: &mut State<N>, _k: usize) -> Self::Regime {
        self.transition(regime, y)
    }
    /// The fastest rate of the system [1/s]; steps are capped at `h_max_factor` over it.
    fn fastest_rate(&self) -> f64;
}

/// Right-hand side of one regime, as `ode_solvers` calls it.
struct Flow<'a, H: Hybrid<N>, const N: usize> {
    sys: &'a H,
    regime: H::Regime,
}

impl<H: Hybrid<N>, const N: usize> System<f64, State<N>> for Flow<'_, H, N> {
    fn system(&self, _t: f64, y: &State<N>, dy: &mut State<N>) {
        *dy = self.sys.rhs(self.regime, y);
    }
}

/// Step-end times and states of one DOP853 run in `regime` from (t0, y0) to t1, and the steps
/// accepted.
pub type Steps<const N: usize> = (Vec<f64>, Vec<State<N>>, u64);

/// One DOP853 run in `regime` from (t0, y0) to t1, steps up to `h_max`: the step ends.
pub fn integrate<H: Hybrid<N>, const N: usize>(
    sys: &H,
    regime: H::Regime,
    t0: f64,
    y0: State<N>,
    t1: f64,
    h_max: f64,
    tol: &Tolerances,
) -> Result<Steps<N>, String> {
    if t1 <= t0 {
        return Ok((vec![t0], vec![y0], 0));
    }
    let mut solver = Dop853::from_param(
        Flow { sys, regime },
        t0,
        t1,
        t1 - t0,
        y0,
        tol.rtol,
        tol.atol,
        0.9,
        0.0,
        0.333,
        6.0,
        h_max.min(t1 - t0),
        0.0,
        10_000_000,
        1000,
        OutputType::Sparse,
    );
    let stats = solver
        .integrate()
        .map_err(|e| format!("{} DOP853 failed from t = {t0} s in {regime:?}: {e:?}", H::NAME))?;
    let (ts, ys) = (solver.x_out().clone(), solver.y_out().clone());
    if ys.iter().any(|y| !y.iter().all(|v| v.is_finite())) {
        return Err(format!("{} DOP853 produced a non-finite state after t = {t0} s in {regime:?}", H::NAME));
    }
    Ok((ts, ys, stats.accepted_steps as u64))
}

/// The state at t, integrated in `regime` from (t0, y0).
pub fn state_at<H: Hybrid<N>, const N: usize>(
    sys: &H,
    regime: H::Regime,
    t0: f64,
    y0: State<N>,
    t: f64,
    h_max: f64,
    tol: &Tolerances,
) -> Result<State<N>, String> {
    let (_, ys, _) = integrate(sys, regime, t0, y0, t, h_max, tol)?;
    Ok(*ys.last().expect("DOP853 output holds the start"))
}

/// What a bisection found: the bracket's upper end, the state there, and the state at the last
/// midpoint tried (`None` when the bracket was narrow enough from the start).
#[derive(Clone, Copy, Debug)]
pub struct Bisected<const N: usize> {
    pub t: f64,
    pub state: State<N>,
    pub last: Option<State<N>>,
}

/// Where in a step a test turns true.
#[derive(Clone, Copy, Debug)]
pub struct Bracket<const N: usize> {
    /// Start of the re-integrations (at or before `lo`): time and state.
    pub t_a: f64,
    pub y_a: State<N>,
    /// The test is false at lo, true at hi; `y_hi` the state at hi.
    pub lo: f64,
    pub hi: f64,
    pub y_hi: State<N>,
}

/// Bisects `bracket` to `t_tol` for the time where `test(state)` turns true, re-integrating in
/// `regime` from the bracket's start.
pub fn bisect<H: Hybrid<N>, const N: usize, F: Fn(&State<N>) -> bool>(
    sys: &H,
    regime: H::Regime,
    bracket: Bracket<N>,
    h_max: f64,
    tol: &Tolerances,
    test: F,
) -> Result<Bisected<N>, String> {
    let Bracket { t_a, y_a, mut lo, mut hi, mut y_hi } = bracket;
    let mut last = None;
    while hi - lo > tol.t_tol {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        let ym = state_at(sys, regime, t_a, y_a, mid, h_max, tol)?;
        if test(&ym) {
            hi = mid;
            y_hi = ym;
        } else {
            lo = mid;
        }
        last = Some(ym);
    }
    Ok(Bisected { t: hi, state: y_hi, last })
}

/// One transition: at `t` the regime changed from `from` to `to` (possibly the same regime);
/// `state` is the state the new regime starts from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transition<R, const N: usize> {
    pub t: f64,
    pub from: R,
    pub to: R,
    pub state: [f64; N],
}

/// How a run is cut into DOP853 runs: at `stop_at` (if ahead), and in chunks of
/// `chunk_steps` largest steps (so an early event does not pay for integrating to the end).
/// The cuts change where DOP853 restarts, hence the last digits of a run.
#[derive(Clone, Copy, Debug, Default)]
pub struct Plan {
    pub stop_at: Option<f64>,
    pub chunk_steps: Option<f64>,
}

/// One DOP853 run of the main path, handed to the observer of [`run`]: it starts at (t0, y0)
/// in `regime`, its step ends are `ts`, `ys`; it ends at (t1, y1), at an event located inside
/// step `fired` (between step ends fired - 1 and fired) or at a stop.
pub struct Piece<'a, R, const N: usize> {
    pub regime: R,
    pub t0: f64,
    pub y0: &'a State<N>,
    pub ts: &'a [f64],
    pub ys: &'a [State<N>],
    pub fired: Option<usize>,
    pub t1: f64,
    pub y1: &'a State<N>,
    /// The run's largest step (for re-integrations).
    pub h_max: f64,
}

/// The main path of a run.
#[derive(Clone, Debug)]
pub struct Path<R, const N: usize> {
    /// The start state and regime, after the projection on entering stick.
    pub start: ([f64; N], R),
    pub transitions: Vec<Transition<R, N>>,
    pub final_state: State<N>,
    pub final_regime: R,
    /// DOP853 steps accepted on the main path (not counting the bisections' re-integrations).
    pub accepted_steps: u64,
    pub h_max: f64,
}

/// The array of a state.
pub fn arr<const N: usize>(y: &State<N>) -> [f64; N] {
    let mut a = [0.0; N];
    a.copy_from_slice(y.as_slice());
    a
}

/// Runs `sys` from (0, y0) in `regime` to `t_end`: DOP853 runs cut as `plan` says, each one's
/// first event located, the run restarted in the regime the transition leads to. `observe` sees
/// every DOP853 run of the main path before its transition is made.
pub fn run<H: Hybrid<N>, const N: usize>(
    sys: &H,
    y0: State<N>,
    regime: H::Regime,
    t_end: f64,
    plan: Plan,
    tol: &Tolerances,
    mut observe: impl FnMut(&Piece<H::Regime, N>) -> Result<(), String>,
) -> Result<Path<H::Regime, N>, String> {
    tol.check(H::NAME)?;
    if !y0.iter().all(|v| v.is_finite()) {
        return Err(format!("{}: non-finite start state {:?}", H::NAME, arr(&y0)));
    }
    let h_max = tol.h_max_factor / sys.fastest_rate();
    let chunk = plan.chunk_steps.map(|c| c * h_max);
    let mut y = y0;
    let mut regime = regime;
    let mut t = 0.0;
    let guards = sys.guard_count();
    let mut armed: Vec<bool> = (0..guards).map(|g| sys.armed_k(regime, &y, g)).collect();
    let mut transitions = Vec::new();
    let mut accepted = 0u64;
    let start = (arr(&y), regime);
    while t < t_end {
        let target = match plan.stop_at {
            Some(s) if t < s => s,
            _ => t_end,
        };
        let stop = match chunk {
            Some(c) if target - t > 1.5 * c => t + c,
            _ => target,
        };
        let (ts, ys, acc) = integrate(sys, regime, t, y, stop, h_max, tol)?;
        accepted += acc;
        // (step index, time, state, guard) of the earliest guard crossing
        let mut event: Option<(usize, f64, State<N>, usize)> = None;
        for k in 1..ys.len() {
            let step = Bracket { t_a: ts[k - 1], y_a: ys[k - 1], lo: ts[k - 1], hi: ts[k], y_hi: ys[k] };
            for g in 0..guards {
                if !armed[g] {
                    armed[g] = sys.armed_k(regime, &ys[k], g);
                    continue;
                }
                let found = first_crossing(sys, regime, step, h_max, tol, g)?;
                if let Some((te, ye)) = found {
                    if event.is_none_or(|e| te < e.1) {
                        event = Some((k, te, ye, g));
                    }
                }
            }
            if event.is_some() {
                break;
            }
        }
        let (t1, y1) = match event {
            None => {
                let t_last = *ts.last().expect("DOP853 output holds the start");
                if (t_last - stop).abs() > 1e-9 * stop.abs().max(1e-9) {
                    return Err(format!("{}: DOP853 stopped at t = {t_last} s before {stop} s", H::NAME));
                }
                (stop, *ys.last().expect("DOP853 output holds the start"))
            }
            Some((_, te, ye, _)) => (te, ye),
        };
        observe(&Piece { regime, t0: t, y0: &y, ts: &ts, ys: &ys, fired: event.map(|e| e.0), t1, y1: &y1, h_max })?;
        t = t1;
        y = y1;
        if let Some((_, _, _, g)) = event {
            let next = sys.transition_k(regime, &mut y, g);
            transitions.push(Transition { t, from: regime, to: next, state: arr(&y) });
            if transitions.len() > MAX_TRANSITIONS {
                return Err(format!("{}: more than {MAX_TRANSITIONS} transitions by t = {t} s (chattering)", H::NAME));
            }
            regime = next;
            for (g, a) in armed.iter_mut().enumerate() {
                *a = sys.armed_k(regime, &y, g);
            }
        }
    }
    Ok(Path { start, transitions, final_state: y, final_regime: regime, accepted_steps: accepted, h_max })
}

/// Where guard `g` of `regime` first turns non-negative inside `step` (its end, or a crest
/// inside it: negative at both ends, its rate turning from + to -), bisected to `t_tol`.
fn first_crossing<H: Hybrid<N>, const N: usize>(
    sys: &H,
    regime: H::Regime,
    step: Bracket<N>,
    h_max: f64,
    tol: &Tolerances,
    g: usize,
) -> Result<Option<(f64, State<N>)>, String> {
    if sys.guard_k(regime, &step.y_hi, g) >= 0.0 {
        let ev = bisect(sys, regime, step, h_max, tol, |y| sys.guard_k(regime, y, g) >= 0.0)?;
        return Ok(Some((ev.t, ev.state)));
    }
    let rising = |y: &State<N>| sys.guard_rate_k(regime, y, g).is_some_and(|r| r > 0.0);
    let falling = |y: &State<N>| sys.guard_rate_k(regime, y, g).is_some_and(|r| r < 0.0);
    if rising(&step.y_a) && falling(&step.y_hi) {
        let crest = bisect(sys, regime, step, h_max, tol, |y| sys.guard_rate_k(regime, y, g).is_some_and(|r| r <= 0.0))?;
        if sys.guard_k(regime, &crest.state, g) >= 0.0 {
            let to_crest = Bracket { hi: crest.t, y_hi: crest.state, ..step };
            let ev = bisect(sys, regime, to_crest, h_max, tol, |y| sys.guard_k(regime, y, g) >= 0.0)?;
            return Ok(Some((ev.t, ev.state)));
        }
    }
    Ok(None)
}
