//! What the commands print: the human summary and the JSON of `simulate`, the Markdown table
//! and the JSON of `cases`. No NaN or infinity is ever printed: a missing value is `n/a` in
//! text and `null` in JSON.

use serde::Serialize;
use stickslip_model::{Coefficients, Halt};

use super::format::{num, pm, sci, sig4};
use crate::scenes::run::{Outcome, RunReport};
use crate::scenes::scene_source::NamedScene;




fn finite(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}

/// One line on how the run ended.
pub fn outcome_line(o: &Outcome) -> String {
    match o {
        Outcome::Completed => "completed".into(),
        Outcome::Budget(b) => format!("halted, budget: {}", b.cause()),
        Outcome::Stalled { t } => format!(
            "halted, stalled: at t = {t:.6} s the error-controlled steps had used up their budget (1,000 a sample, plus a million, \
             or a pace that would have): a scene too stiff for the event runner's steps (a throttle that fills the chamber in far \
             under a sample, a very light band) or a state it cannot leave"
        ),
        Outcome::Halted { halt, self_locked } => {
            let kw = o.keyword();
            let what = match *halt {
                Halt::Diverged { t, regime: stickslip_model::Regime::Stick, .. } if *self_locked => format!(
                    "at t = {t:.6} s the state left the plausible range (|x| > 1 m or |phi| > 0.5 rad) in stick: \
                     the pad self-locks (K - s mu_s w c_N <= 0), the friction limit grows faster than the \
                     guide force and it never slips"
                ),
                Halt::ContactLoss { t, n } if n == 0.0 => format!(
                    "at t = {t:.6} s the pad lost its contact with unilateral edges: both edges open (the pad \
                     leaves the band), or one open and the pad tipping over about the other (the state left \
                     the plausible range)"
                ),
                Halt::ContactLoss { t, n } => format!(
                    "at t = {t:.6} s the normal force went negative (N = {} N): the pad lifts off and the \
                     model no longer applies",
                    sci(finite(n), 4)
                ),
                Halt::Diverged { t, regime, stiffness_margin } if stiffness_margin <= 0.0 => format!(
                    "at t = {t:.6} s phi diverged in {} with rotational stiffness K_eff = {} N m/rad <= 0: \
                     the pad sprags (self-locks)",
                    regime.name(),
                    sci(finite(stiffness_margin), 4)
                ),
                Halt::Diverged { t, regime, stiffness_margin } => format!(
                    "at t = {t:.6} s the state left the plausible range (|x| > 1 m or |phi| > 0.5 rad) in {} \
                     (K_eff = {} N m/rad)",
                    regime.name(),
                    sci(finite(stiffness_margin), 4)
                ),
                Halt::NonFinite { t } => format!("at t = {t:.6} s a state value stopped being a finite number"),
                Halt::TransitionStorm { t } => {
                    format!("at t = {t:.6} s more than 64 regime changes fell inside one substep")
                }
            };
            format!("halted, {kw}: {what}")
        }
    }
}

/// The human summary of `simulate`.
pub fn summary(ns: &NamedScene, r: &RunReport) -> String {
    let s = &ns.scene;
    let co = Coefficients::of(s);
    let mut out = String::new();
    let mut line = |k: &str, v: String| out.push_str(&format!("{k:<22}{v}\n"));
    line("scene", format!("{} ({})", ns.name, ns.origin_short()));
    if !ns.description.is_empty() {
        line("description", ns.description.clone());
    }
    let guide = match s.caliper {
        stickslip_model::Caliper::Push => "guide and pivot at the trailing edge",
        stickslip_model::Caliper::Pull => "guide and pivot at the leading edge",
    };
    line("caliper", format!("{} ({guide})", s.caliper.name()));
    line(
        "beta",
        format!(
            "{} m from the trailing edge (pad length 2 l = {} m)",
            s.beta,
            2.0 * s.l
        ),
    );
    if !s.rotation {
        line(
            "rotation",
            format!("off: phi held at {:.6e} rad, N = {:.6} N", co.phi0, co.n0),
        );
    }
    if s.friction == stickslip_model::FrictionLaw::Stribeck {
        line(
            "friction",
            format!(
                "Stribeck: mu(v) = {} + {} exp(-(|v| / {} m/s)^{})",
                s.mu_k,
                s.mu_s - s.mu_k,
                s.v_s,
                s.stribeck_exponent
            ),
        );
    }
    if s.band {
        line(
            "band",
            if s.pneumatic() {
                // k_b does nothing there: the air column is the band's spring (its stiffness below)
                format!("a mass m_b = {} kg pushed by the pneumatic drive (its air column below), c_b = {} N s/m", s.m_b, s.c_b)
            } else {
                format!("a mass m_b = {} kg driven at V through k_b = {} N/m, c_b = {} N s/m", s.m_b, s.k_b, s.c_b)
            },
        );
    }
    if s.floating() {
        line(
            "pad support",
            format!(
                "not hinged: pivot spring k_pivot = {} N/m normal to the band, c_y = {} N s/m (the pad translates in y)",
                s.k_pivot, s.c_y
            ),
        );
    }
    if s.face {
        line(
            "kinematics",
            "friction face: sliding velocity x' + s w phi' - band velocity; stick holds the face".into(),
        );
    }
    if s.c_x != 0.0 || s.c_phi != 0.0 {
        line(
            "damping",
            format!("c_x = {} N s/m, c_phi = {} N m s/rad", s.c_x, s.c_phi),
        );
    }
    line("precision", r.precision.name().into());
    let rate = 1.0 / s.dt;
    line(
        "dt",
        format!(
            "{:?} s ({} steps/s)",
            s.dt,
            if rate.fract() == 0.0 {
                format!("{rate}")
            } else {
                format!("{rate:.3}")
            }
        ),
    );
    let simulated = r.steps_planned as f64 * s.dt;
    let mut dur_note = if (simulated - s.duration).abs() > 1e-9 * s.duration {
        format!(", {simulated} s simulated")
    } else {
        String::new()
    };
    if r.steps_done < r.steps_planned {
        dur_note.push_str(&format!(", {} completed before the halt", r.steps_done));
    }
    line(
        "duration",
        format!("{} s ({} steps{dur_note})", s.duration, r.steps_planned),
    );
    line(
        "window",
        format!(
            "t in [{}, {}] s for the statistics ({:.6} s covered)",
            r.window_start, simulated, r.stats.window_s
        ),
    );
    line("outcome", outcome_line(&r.outcome));
    for (i, (k, unit)) in [
        ("x pp", "m"),
        ("x' pp", "m/s"),
        ("phi pp", "rad"),
        ("phi' pp", "rad/s"),
    ]
    .iter()
    .enumerate()
    {
        match r.pp(i) {
            Some(v) => line(k, format!("{} {unit}", sci(Some(v), 5))),
            None => line(k, "n/a (the run halted before the window)".into()),
        }
    }
    if let (Some(e), true) = (&r.edges, r.has_window()) {
        use stickslip_model::model2::event_run::edges::{LEAD, TRAIL};
        for (name, i) in [("trail edge open", TRAIL), ("lead edge open", LEAD)] {
            line(name, format!("{:.4} of the window, {} openings (unilateral contact)", e.open_fraction(i), e.openings[i]));
        }
    }
    if let (Some(d), true) = (&r.drive, r.has_window()) {
        line("band mean speed", format!("{} m/s (pneumatic drive)", sci(Some(d.mean_speed()), 5)));
        line("band stuck", format!("{:.4} of the window, {} breakaways at the seal", d.stuck_fraction(), d.breakaways));
        line(
            "chamber pressure",
            format!("mean {} Pa, {} to {} Pa (absolute)", sci(Some(d.p_mean), 5), sci(Some(d.p_min), 5), sci(Some(d.p_max), 5)),
        );
        line(
            "air column",
            format!(
                "{} N/m at the mean pressure; throttle C = {} m^3/(s Pa){}",
                sci(Some(d.column_stiffness), 4),
                sci(Some(d.conductance), 4),
                if d.conductance_solved { " (solved from v)" } else { "" }
            ),
        );
    }
    if let (Some(m2), true) = (&r.model2, r.has_window()) {
        line("pad x'' pp", format!("{} m/s^2 (the rig's pad_x)", sci(Some(m2.pad_acc_pp), 5)));
        if s.band {
            line("band x_b' pp", format!("{} m/s", sci(Some(m2.band_v_pp), 5)));
            line(
                "band x_b'' pp",
                format!("{} m/s^2 (the rig's disc_x)", sci(Some(m2.band_acc_pp), 5)),
            );
        }
    }
    let c = &r.cycles;
    if r.has_window() {
        let per_cycle = match (c.stick_fraction.mean(), c.stick_fraction.sd()) {
            (Some(m), Some(sd)) => format!(
                "; per cycle {} ({} complete cycles, mean ± sd)",
                pm(m, sd),
                c.stick_fraction.n
            ),
            (Some(m), None) => format!("; the one complete cycle: {}", num(m)),
            _ => String::new(),
        };
        line(
            "stick fraction",
            format!("{:.4} over the window{per_cycle}", r.stats.stick_fraction),
        );
        let hz = if r.stats.slip_onsets >= 2 {
            let period = match (c.period.mean(), c.period.sd()) {
                (Some(m), Some(sd)) => format!(
                    "; period {} ms ({} cycles, mean ± sd)",
                    pm(m * 1e3, sd * 1e3),
                    c.period.n
                ),
                (Some(m), None) => format!("; period {} ms (one cycle)", num(m * 1e3)),
                _ => String::new(),
            };
            format!("{:.4} Hz = 1 / mean period{period}", r.stats.stick_slip_hz)
        } else {
            "0 Hz (fewer than two slip onsets in the window: no sustained stick-slip)".to_string()
        };
        line("stick-slip frequency", hz);
    } else {
        line(
            "stick fraction",
            "n/a (the run halted before the window)".into(),
        );
        line(
            "stick-slip frequency",
            "n/a (the run halted before the window)".into(),
        );
    }
    line(
        "transitions",
        format!(
            "{} in the run, {} in the window ({} slip onsets)",
            r.transitions, r.stats.transitions, r.stats.slip_onsets
        ),
    );
    // The model crate's quasi-static estimate assumes the rotation is on.
    let qs = if s.rotation {
        let t1 = co.quasi_static_first_slip(s);
        if t1.is_finite() {
            format!(" (quasi-static estimate {t1:.6} s)")
        } else {
            " (quasi-static estimate: none, the pad self-locks)".into()
        }
    } else {
        String::new()
    };
    line(
        "first slip",
        match r.first_slip {
            Some(t) => format!("{t:.6} s{qs}"),
            None => format!("none{qs}"),
        },
    );
    if s.uses_model2() {
        let lin = crate::scenes::sliding::sliding_stability(s);
        line("steady sliding", sliding_line(&lin));
        if s.floating() {
            let threshold = crate::scenes::sliding::instability_threshold_mu(s, 0.0, 2.0, 1e-6);
            line(
                "mode coupling",
                match threshold {
                    Some(mu) => format!(
                        "steady Coulomb sliding of this pad turns unstable (flutter) at mu_k = {mu:.4} (the model's linearisation; this scene: mu = {:.4} at V)",
                        crate::scenes::sliding::friction_at(s, s.v).0
                    ),
                    None => "no flutter threshold for mu_k in [0, 2]".into(),
                },
            );
        }
    }
    out
}

/// The linear stability of steady sliding as one line of the summary.
pub fn sliding_line(lin: &crate::scenes::sliding::SlidingStability) -> String {
    if let Some((_, why)) = &lin.invalid {
        return format!("does not exist ({why})");
    }
    let mode = |hz: f64| if hz == 0.0 { "a non-oscillating mode".to_string() } else { format!("the {} Hz mode", sig4(hz)) };
    match lin.unstable_mode() {
        Some(m) => format!(
            "unstable: a perturbation grows at {} 1/s in {} (the model's linearisation)",
            sig4(m.growth_rate),
            mode(m.frequency_hz)
        ),
        None if lin.max_growth_rate() >= 0.0 => {
            "neutral: the slowest modes neither grow nor decay (undamped; the model's linearisation)".into()
        }
        None => format!(
            "stable: the slowest mode decays at {} 1/s (the model's linearisation)",
            sig4(-lin.max_growth_rate())
        ),
    }
}

/// The keys shared by `simulate --json` and each case of `cases --json`.
#[derive(Serialize)]
pub struct CaseJson {
    pub name: String,
    pub caliper: &'static str,
    pub beta: f64,
    pub x_pp: Option<f64>,
    pub xdot_pp: Option<f64>,
    pub phi_pp: Option<f64>,
    pub phidot_pp: Option<f64>,
    pub stick_fraction: Option<f64>,
    pub stick_slip_hz: Option<f64>,
    /// Only when the run halted (documented in `cases --help`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub outcome: Option<&'static str>,
    /// Unilateral contact only: each edge's open fraction and openings over the window.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub edges: Option<EdgesJson>,
    /// Pneumatic band drive only: the band and the air column over the window.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drive: Option<DriveJson>,
}

/// `"drive": {...}` of a pneumatic-drive run (SI units, absolute pressures).
#[derive(Serialize)]
pub struct DriveJson {
    /// The band's mean speed over the window [m/s].
    pub mean_speed: f64,
    /// The fraction of the window the band was stuck at its seal, and its breakaways there.
    pub stuck_fraction: f64,
    pub breakaways: u64,
    pub p_mean: f64,
    pub p_min: f64,
    pub p_max: f64,
    /// n p A^2 / V at the mean pressure and position [N/m].
    pub column_stiffness: f64,
    /// The throttle's sonic conductance [m^3/(s Pa)] and whether it was solved from v.
    pub throttle_conductance: f64,
    pub throttle_solved: bool,
}

impl DriveJson {
    pub fn of(r: &RunReport) -> Option<DriveJson> {
        let d = r.drive?;
        if !r.has_window() {
            return None;
        }
        Some(DriveJson {
            mean_speed: d.mean_speed(),
            stuck_fraction: d.stuck_fraction(),
            breakaways: d.breakaways,
            p_mean: d.p_mean,
            p_min: d.p_min,
            p_max: d.p_max,
            column_stiffness: d.column_stiffness,
            throttle_conductance: d.conductance,
            throttle_solved: d.conductance_solved,
        })
    }
}

/// `"edges": {"trail": {...}, "lead": {...}}` of a unilateral-contact run.
#[derive(Serialize)]
pub struct EdgesJson {
    pub trail: EdgeJson,
    pub lead: EdgeJson,
}

/// One edge: the fraction of the statistics window it was open, and its openings there (an
/// edge open as the window starts counts one).
#[derive(Serialize)]
pub struct EdgeJson {
    pub open_fraction: f64,
    pub openings: u64,
}

impl EdgesJson {
    pub fn of(r: &RunReport) -> Option<EdgesJson> {
        use stickslip_model::model2::event_run::edges::{LEAD, TRAIL};
        let e = r.edges?;
        let one = |i: usize| EdgeJson { open_fraction: e.open_fraction(i), openings: e.openings[i] };
        Some(EdgesJson { trail: one(TRAIL), lead: one(LEAD) })
    }
}

impl CaseJson {
    pub fn new(ns: &NamedScene, r: &RunReport) -> Self {
        let w = r.has_window();
        CaseJson {
            name: ns.name.clone(),
            caliper: ns.scene.caliper.name(),
            beta: ns.scene.beta,
            x_pp: r.pp(0),
            xdot_pp: r.pp(1),
            phi_pp: r.pp(2),
            phidot_pp: r.pp(3),
            stick_fraction: if w {
                finite(r.stats.stick_fraction)
            } else {
                None
            },
            stick_slip_hz: if w {
                finite(r.stats.stick_slip_hz)
            } else {
                None
            },
            outcome: match r.outcome {
                Outcome::Completed => None,
                o => Some(o.keyword()),
            },
            edges: EdgesJson::of(r),
            drive: DriveJson::of(r),
        }
    }
}

/// `simulate --json`: the keys of [`CaseJson`] (its `outcome` left out: this one always has
/// it, below), then the run's.
#[derive(Serialize)]
pub struct SimulateJson {
    #[serde(flatten)]
    pub case: CaseJson,
    pub precision: &'static str,
    pub dt: f64,
    pub duration: f64,
    pub steps: u64,
    pub stats_from: f64,
    pub outcome: &'static str,
    pub halt_t_s: Option<f64>,
    pub first_slip_s: Option<f64>,
    pub transitions: u64,
    pub slip_onsets: u64,
    pub cycles: u64,
    pub period_mean_s: Option<f64>,
    pub period_sd_s: Option<f64>,
    pub cycle_stick_fraction_mean: Option<f64>,
    pub cycle_stick_fraction_sd: Option<f64>,
    /// Model-2 scenes with a statistics window: the pad's x'' peak-to-peak [m/s^2] (the rig's
    /// pad_x), and with the band its x_b'' peak-to-peak [m/s^2] (the rig's disc_x), as the
    /// summary's lines give them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pad_x_pp: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub disc_x_pp: Option<f64>,
    /// Model-2 scenes: the linear stability of steady sliding (`stickslip::scenes::sliding`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub linear: Option<LinearJson>,
}

/// The linear stability of steady sliding in JSON.
#[derive(Serialize)]
pub struct LinearJson {
    pub stable: bool,
    /// Largest real part of the linearisation's eigenvalues [1/s].
    pub max_growth_rate: f64,
    /// Frequency of the fastest-growing mode [Hz] (null when stable).
    pub unstable_hz: Option<f64>,
    /// Why steady sliding does not exist, if it does not (sprag, contact loss).
    pub invalid: Option<String>,
    /// The floating pad: the kinetic friction at which steady Coulomb sliding turns unstable.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flutter_mu_k: Option<f64>,
}

impl LinearJson {
    pub fn of(s: &stickslip_model::Scene) -> Option<LinearJson> {
        if !s.uses_model2() {
            return None;
        }
        let lin = crate::scenes::sliding::sliding_stability(s);
        Some(LinearJson {
            stable: lin.stable(),
            max_growth_rate: lin.max_growth_rate(),
            unstable_hz: lin.unstable_mode().map(|m| m.frequency_hz),
            invalid: lin.invalid.as_ref().map(|(_, why)| why.clone()),
            flutter_mu_k: if s.floating() { crate::scenes::sliding::instability_threshold_mu(s, 0.0, 2.0, 1e-6) } else { None },
        })
    }
}

impl SimulateJson {
    pub fn new(ns: &NamedScene, r: &RunReport) -> Self {
        let case = CaseJson { outcome: None, ..CaseJson::new(ns, r) };
        SimulateJson {
            case,
            precision: r.precision.name(),
            dt: ns.scene.dt,
            duration: ns.scene.duration,
            steps: r.steps_planned,
            stats_from: r.window_start,
            outcome: r.outcome.keyword(),
            halt_t_s: r.outcome.halt_time(),
            first_slip_s: r.first_slip,
            transitions: r.transitions,
            slip_onsets: r.stats.slip_onsets,
            cycles: r.cycles.period.n,
            period_mean_s: r.cycles.period.mean(),
            period_sd_s: r.cycles.period.sd(),
            cycle_stick_fraction_mean: r.cycles.stick_fraction.mean(),
            cycle_stick_fraction_sd: r.cycles.stick_fraction.sd(),
            pad_x_pp: r.model2.as_ref().filter(|_| r.has_window()).map(|m2| m2.pad_acc_pp),
            disc_x_pp: r.model2.as_ref().filter(|_| r.has_window() && ns.scene.band).map(|m2| m2.band_acc_pp),
            linear: LinearJson::of(&ns.scene),
        }
    }
}

/// `cases --json`.
#[derive(Serialize)]
pub struct CasesJson {
    pub precision: &'static str,
    pub dt: f64,
    pub duration: f64,
    pub stats_from: f64,
    pub cases: Vec<CaseJson>,
}


/// The Markdown tables of `cases`: the values (in the manner of the thesis's Table 2.1) and
/// their cycle-to-cycle spread, with a caption and notes.
pub fn cases_table(runs: &[(NamedScene, RunReport)]) -> String {
    let mut out = String::new();
    if let Some((ns, r)) = runs.first() {
        out.push_str(&format!(
            "Six cases over the statistics window t in [{}, {}] s ({}, dt = {:?} s). Peak-to-peak values are \
             the extremes of the exact continuous motion, not of the samples.\n\n",
            r.window_start,
            r.steps_planned as f64 * ns.scene.dt,
            r.precision.name(),
            ns.scene.dt
        ));
    }
    out.push_str(
        "| case | caliper | beta [m] | x pp [m] | x' pp [m/s] | phi pp [rad] | phi' pp [rad/s] | stick fraction [-] | stick-slip frequency [Hz] |\n",
    );
    out.push_str("|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
    let mut notes = Vec::new();
    for (ns, r) in runs {
        let (sf, hz) = if r.has_window() {
            (
                format!("{:.4}", r.stats.stick_fraction),
                sig4(r.stats.stick_slip_hz),
            )
        } else {
            ("n/a".into(), "n/a".into())
        };
        out.push_str(&format!(
            "| {} | {} | {:.3} | {} | {} | {} | {} | {} | {} |\n",
            ns.name,
            ns.scene.caliper.name(),
            ns.scene.beta,
            sci(r.pp(0), 4),
            sci(r.pp(1), 4),
            sci(r.pp(2), 4),
            sci(r.pp(3), 4),
            sf,
            hz
        ));
        if r.outcome != Outcome::Completed {
            notes.push(format!("- {}: {}", ns.name, outcome_line(&r.outcome)));
        }
    }
    if runs.iter().any(|(_, r)| r.model2.is_some()) {
        out.push_str(
            "\nModel 2 accelerations (peak-to-peak over the window, at every substep end and transition):\n\n\
             | case | friction | band | pad x'' pp [m/s^2] | band x_b' pp [m/s] | band x_b'' pp [m/s^2] |\n\
             |---|---|---|---:|---:|---:|\n",
        );
        for (ns, r) in runs {
            let Some(m2) = &r.model2 else { continue };
            let ok = r.has_window();
            let v = |x: f64| if ok { sci(Some(x), 4) } else { "n/a".into() };
            out.push_str(&format!(
                "| {} | {} | {} | {} | {} | {} |\n",
                ns.name,
                ns.scene.friction.name(),
                if ns.scene.band { "mass" } else { "constant V" },
                v(m2.pad_acc_pp),
                v(m2.band_v_pp),
                v(m2.band_acc_pp)
            ));
        }
    }
    out.push_str(
        "\nStick fraction = time in stick / window length; stick-slip frequency = 1 / mean interval between \
         slip onsets (stick-to-slip transitions) in the window.\n",
    );
    for n in &notes {
        out.push_str(n);
        out.push('\n');
    }
    out.push_str(
        "\nCycle-to-cycle spread: a cycle runs from one slip onset to the next; complete cycles in the window \
         only; mean ± sample standard deviation.\n\n\
         | case | cycles | period [ms] | stick fraction per cycle [-] |\n\
         |---|---:|---:|---:|\n",
    );
    for (ns, r) in runs {
        let c = &r.cycles;
        let cell = |w: &crate::scenes::cycles::Welford, scale: f64| match (w.mean(), w.sd()) {
            (Some(m), Some(sd)) => pm(m * scale, sd * scale),
            (Some(m), None) => num(m * scale),
            _ => "n/a".into(),
        };
        out.push_str(&format!(
            "| {} | {} | {} | {} |\n",
            ns.name,
            c.period.n,
            cell(&c.period, 1e3),
            cell(&c.stick_fraction, 1.0)
        ));
    }
    out
}
