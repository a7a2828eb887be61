//! A map as Markdown (the summary) and CSV (one row per cell).

use std::path::Path;

use super::cell::{CellJson, RunCell};
use super::MapJson;
use crate::error::{HostError, Result};
use crate::output::format::sig4;

/// The regimes in the order the summary lists them, with their letter in the text grid.
pub const REGIMES: [(&str, char); 10] = [
    ("steady_sliding", 's'),
    ("stick_slip", 'x'),
    ("edge_open", 'e'),
    ("sliding_oscillation", 'o'),
    ("stuck", 't'),
    ("sprag", 'p'),
    ("contact_loss", 'c'),
    ("method_unstable", 'm'),
    ("invalid", '?'),
    // not run: over the work budget (listed in the grid's legend only where a cell has it)
    ("budget", 'b'),
];

fn letter(regime: &str) -> char {
    REGIMES.iter().find(|(r, _)| *r == regime).map_or('?', |(_, c)| *c)
}

fn regime_of(run: Option<&RunCell>) -> &str {
    run.map_or("invalid", |r| r.regime.as_str())
}

fn opt(v: Option<f64>) -> String {
    v.map_or("-".into(), sig4)
}

/// Whether the cell is linearly unstable (None: invalid).
fn unstable(c: &CellJson) -> Option<bool> {
    c.linear.as_ref().map(|l| !l.stable)
}

/// The linear boundary along the first sweep: for each pair of neighbouring cells whose
/// stability differs, (index of the first cell, index of the second).
pub fn boundary_pairs(m: &MapJson) -> Vec<(usize, usize)> {
    let n1 = m.sweeps[0].n;
    let by_index = by_index(m);
    let mut out = Vec::new();
    for c in &m.cells {
        let i = c.index;
        if i % n1 + 1 < n1 {
            let next = by_index.get(i + 1).copied().flatten();
            if let (Some(a), Some(b)) = (unstable(c), next.and_then(unstable)) {
                if a != b {
                    out.push((i, i + 1));
                }
            }
        }
    }
    out
}

/// The cells by index (None: not in this shard).
pub fn by_index(m: &MapJson) -> Vec<Option<&CellJson>> {
    let mut v = vec![None; m.cells_total];
    for c in &m.cells {
        if let Some(slot) = v.get_mut(c.index) {
            *slot = Some(c);
        }
    }
    v
}

/// Cells whose two runs disagree in the way a subcritical Hopf bifurcation does: steady
/// sliding stays steady, the run from rest keeps stick-slipping.
pub fn bistable(c: &CellJson) -> bool {
    regime_of(c.from_sliding.as_ref()) == "steady_sliding" && regime_of(c.from_rest.as_ref()) == "stick_slip"
}

/// The cell's swept values in the map's sweep order (a cell's `params` is a JSON object, whose
/// keys serde_json keeps sorted: never read it in its own order).
pub fn swept_values(m: &MapJson, c: &CellJson) -> Vec<(String, Option<f64>)> {
    m.sweeps.iter().map(|w| (w.key.clone(), c.params.get(&w.key).and_then(|v| v.as_f64()))).collect()
}

fn params_text(m: &MapJson, c: &CellJson) -> String {
    swept_values(m, c).iter().map(|(k, v)| format!("{k} = {}", v.map_or("?".into(), sig4))).collect::<Vec<_>>().join(", ")
}

/// The Markdown summary.
pub fn markdown(m: &MapJson) -> String {
    let mut s = String::new();
    let sweeps: Vec<String> = m.sweeps.iter().map(|w| w.spec()).collect();
    s.push_str(&format!("# Regime map of `{}`: {}\n\n", m.scene, sweeps.join(" x ")));
    let shard = m.shard.map_or(String::new(), |sh| format!(" (shard {}/{}: {} of them)", sh.k, sh.n, m.cells.len()));
    // a swept run setting is the cell's, not the base scene's
    let setting = |key: &str, v: String| if m.sweeps.iter().any(|w| w.key == key) { format!("{key} swept") } else { v };
    s.push_str(&format!(
        "{} cells{shard}; each: the linear stability of steady sliding, a run from steady sliding with a velocity kick of {} V, and a run from the stuck start; runs of {} (dt {}, {}), statistics from {}.\n\n",
        m.cells_total,
        m.kick,
        setting("duration", format!("{} s", m.duration_s)),
        setting("dt", format!("{} s", sig4(m.dt_s))),
        m.precision,
        setting("stats_from", format!("{} s", m.stats_from_s))
    ));
    // linear
    let count = |f: &dyn Fn(&CellJson) -> bool| m.cells.iter().filter(|c| f(c)).count();
    let stable = count(&|c| c.linear.as_ref().is_some_and(|l| l.stable));
    let no_sliding = |k: &'static str| move |c: &CellJson| c.linear.as_ref().is_some_and(|l| l.no_steady_sliding.as_deref() == Some(k));
    let sprag = count(&no_sliding("sprag"));
    let lost = count(&no_sliding("contact_loss"));
    let invalid = count(&|c| c.invalid.is_some());
    let unstable_n = m.cells.len() - stable - sprag - lost - invalid;
    s.push_str("## Linear stability of steady sliding\n\n");
    s.push_str(&format!(
        "stable (or neutral): {stable}; unstable: {unstable_n}; no steady sliding: {sprag} sprag, {lost} contact loss; invalid scenes: {invalid}.\n"
    ));
    let pairs = boundary_pairs(m);
    let idx = by_index(m);
    let k1 = &m.sweeps[0].key;
    if !pairs.is_empty() {
        let show: Vec<String> = pairs
            .iter()
            .take(12)
            .map(|&(a, b)| {
                let (ca, cb) = (idx[a], idx[b]);
                let v = |c: Option<&CellJson>| c.and_then(|c| c.params.get(k1)).and_then(|v| v.as_f64()).map_or("?".into(), sig4);
                let other: String = ca.map_or(String::new(), |c| {
                    swept_values(m, c).iter().skip(1).map(|(k, v)| format!(" at {k} = {}", v.map_or("?".into(), sig4))).collect()
                });
                let dir = if ca.and_then(unstable) == Some(true) { "unstable -> stable" } else { "stable -> unstable" };
                format!("- {k1} between {} and {}{other}: {dir}", v(ca), v(cb))
            })
            .collect();
        s.push_str(&format!("\nThe boundary along {k1} ({} crossings{}):\n\n{}\n", pairs.len(), if pairs.len() > 12 { ", the first 12" } else { "" }, show.join("\n")));
    }
    // regimes
    s.push_str("\n## Regimes of the runs\n\n| regime | from sliding | from rest |\n|---|---:|---:|\n");
    for (r, _) in REGIMES {
        let a = count(&|c| regime_of(c.from_sliding.as_ref()) == r);
        let b = count(&|c| regime_of(c.from_rest.as_ref()) == r);
        if a + b > 0 {
            s.push_str(&format!("| {r} | {a} | {b} |\n"));
        }
    }
    let bi: Vec<&CellJson> = m.cells.iter().filter(|c| bistable(c)).collect();
    s.push_str(&format!(
        "\nBistable cells (steady sliding stays steady, the start from rest keeps stick-slipping: the subcritical band): {}{}.\n",
        bi.len(),
        bi.first().map_or(String::new(), |c| format!(", e.g. {}", params_text(m, c)))
    ));
    let disagree = count(&|c| {
        let (Some(l), Some(r)) = (&c.linear, &c.from_sliding) else { return false };
        // a run over the work budget was not run: it says nothing either way
        l.no_steady_sliding.is_none() && r.regime != "budget" && l.stable != (r.regime == "steady_sliding")
    });
    s.push_str(&format!(
        "Cells where the run from sliding disagrees with the linear analysis (linearly stable but not steady, or unstable but steady): {disagree} (expected near the boundary, where growth is too slow for the run's length).\n"
    ));
    // cells
    let two = m.sweeps.len() == 2 && m.sweeps[0].n <= 160 && m.shard.is_none() && m.cells.len() == m.cells_total;
    if two {
        s.push_str(&grid_text(m));
    }
    if m.sweeps.len() == 1 || m.cells.len() <= 60 {
        s.push_str("\n## Cells\n\n");
        let keys: Vec<&str> = m.sweeps.iter().map(|w| w.key.as_str()).collect();
        s.push_str(&format!(
            "| {} | linear | growth [1/s] | mode [Hz] | from sliding | from rest | stick fraction | stick-slip [Hz] | pad_x pp [m/s^2] | groan RMS [m/s^2] |\n",
            keys.join(" | ")
        ));
        s.push_str(&format!("|{}---|---:|---:|---|---|---:|---:|---:|---:|\n", "---:|".repeat(keys.len())));
        for c in &m.cells {
            let vals: Vec<String> = swept_values(m, c).iter().map(|(_, v)| v.map_or("?".into(), sig4)).collect();
            let lin = match &c.linear {
                None => "invalid".to_string(),
                Some(l) => match &l.no_steady_sliding {
                    Some(k) => format!("no sliding ({k})"),
                    None if l.stable => "stable".into(),
                    None => "unstable".into(),
                },
            };
            let r = c.from_rest.as_ref();
            s.push_str(&format!(
                "| {} | {lin} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
                vals.join(" | "),
                opt(c.linear.as_ref().and_then(|l| l.max_growth_rate)),
                opt(c.linear.as_ref().and_then(|l| l.unstable_hz)),
                regime_of(c.from_sliding.as_ref()),
                regime_of(r),
                opt(r.and_then(|r| r.stick_fraction)),
                opt(r.and_then(|r| r.stick_slip_hz)),
                opt(r.and_then(|r| r.pad_x_pp)),
                opt(r.and_then(|r| r.groan_rms)),
            ));
        }
        s.push_str("\nStick fraction to groan RMS: the run from rest. Invalid cells: see --json (`invalid`).\n");
    }
    s
}

/// The 2-D map as text: one letter per cell (the run from rest), rows the second sweep from
/// its last value down, upper case where steady sliding is linearly unstable.
fn grid_text(m: &MapJson) -> String {
    let (a, b) = (&m.sweeps[0], &m.sweeps[1]);
    let mut s = format!(
        "\n## The map (run from rest)\n\nColumns: {} from {} to {}; rows: {} from {} (bottom) to {} (top). Letters: {}; upper case where steady sliding is linearly unstable.\n\n```\n",
        a.key,
        sig4(a.from),
        sig4(a.to),
        b.key,
        sig4(b.from),
        sig4(b.to),
        REGIMES
            .iter()
            .filter(|(r, _)| *r != "budget" || m.cells.iter().any(|c| regime_of(c.from_rest.as_ref()) == "budget"))
            .map(|(r, c)| format!("{c} {r}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    for j in (0..b.n).rev() {
        for i in 0..a.n {
            let c = &m.cells[i + a.n * j];
            let l = letter(regime_of(c.from_rest.as_ref()));
            s.push(if unstable(c) == Some(true) { l.to_ascii_uppercase() } else { l });
        }
        s.push('\n');
    }
    s.push_str("```\n");
    s
}

/// One row per cell: the swept values, the linear analysis, then each run's regime and
/// statistics (SI units; empty where a value does not exist).
pub fn write_csv(m: &MapJson, path: &Path) -> Result<()> {
    let err = |e: &dyn std::fmt::Display| HostError::Output(format!("{}: cannot write the CSV: {e}", path.display()));
    let mut w = csv::Writer::from_path(path).map_err(|e| err(&e))?;
    let mut header: Vec<String> = vec!["cell".into()];
    header.extend(m.sweeps.iter().map(|s| s.key.clone()));
    header.extend(["invalid", "linear_stable", "max_growth_rate_per_s", "unstable_hz", "no_steady_sliding"].map(String::from));
    for run in ["from_sliding", "from_rest"] {
        for q in ["regime", "stick_fraction", "stick_slip_hz", "pad_x_pp_m_s2", "groan_rms_m_s2", "slide_v_pp_m_s", "halt_s"] {
            header.push(format!("{run}_{q}"));
        }
    }
    // unilateral contact: each run's edges' open fractions, at the end of the row
    let edges = m.cells.iter().flat_map(|c| [&c.from_sliding, &c.from_rest]).flatten().any(|r| r.open_fraction_trail.is_some() || r.open_fraction_lead.is_some());
    if edges {
        for run in ["from_sliding", "from_rest"] {
            header.extend(["open_fraction_trail", "open_fraction_lead"].map(|q| format!("{run}_{q}")));
        }
    }
    w.write_record(&header).map_err(|e| err(&e))?;
    let o = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    for c in &m.cells {
        let mut row: Vec<String> = vec![c.index.to_string()];
        row.extend(swept_values(m, c).iter().map(|(_, v)| v.map_or(String::new(), |v| v.to_string())));
        row.push(c.invalid.clone().unwrap_or_default());
        match &c.linear {
            Some(l) => row.extend([l.stable.to_string(), o(l.max_growth_rate), o(l.unstable_hz), l.no_steady_sliding.clone().unwrap_or_default()]),
            None => row.extend([String::new(), String::new(), String::new(), String::new()]),
        }
        for r in [&c.from_sliding, &c.from_rest] {
            match r {
                Some(r) => row.extend([
                    r.regime.clone(),
                    o(r.stick_fraction),
                    o(r.stick_slip_hz),
                    o(r.pad_x_pp),
                    o(r.groan_rms),
                    o(r.slide_v_pp),
                    o(r.halt_s),
                ]),
                None => row.extend(std::iter::repeat_n(String::new(), 7)),
            }
        }
        if edges {
            for r in [&c.from_sliding, &c.from_rest] {
                row.extend([o(r.as_ref().and_then(|r| r.open_fraction_trail)), o(r.as_ref().and_then(|r| r.open_fraction_lead))]);
            }
        }
        w.write_record(&row).map_err(|e| err(&e))?;
    }
    w.flush().map_err(|e| err(&e))?;
    Ok(())
}
