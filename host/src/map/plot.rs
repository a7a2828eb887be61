//! `map --plot`: a 2-D map as heat maps (regime from rest, regime from sliding, stick-slip
//! frequency, groan level), each with the linear stability boundary of steady sliding drawn
//! over it as a black line on the cell edges where stability changes; a 1-D map as lines
//! against the swept key. Axes run over the cells (log sweeps evenly in log), with ticks at
//! round values of the swept key (not at the cells' centres) placed where they fall between the
//! cells, and the key's unit (the figure rules of [`crate::output::style`]). SVG.

use std::path::Path;

use plotters::prelude::*;

use super::cell::{CellJson, RunCell};
use super::output::{by_index, REGIMES};
use super::sweep::Sweep;
use super::MapJson;
use crate::error::Result;
use crate::output::format::sig4;
use crate::output::style;

fn regime_color(r: &str) -> RGBColor {
    match r {
        "steady_sliding" => RGBColor(120, 190, 120),
        "stick_slip" => RGBColor(214, 39, 40),
        "edge_open" => RGBColor(23, 190, 207),
        "sliding_oscillation" => RGBColor(255, 160, 60),
        "stuck" => RGBColor(150, 150, 150),
        "sprag" => RGBColor(148, 103, 189),
        "contact_loss" => RGBColor(31, 119, 180),
        "method_unstable" => RGBColor(0, 0, 0),
        "budget" => RGBColor(255, 0, 255),
        _ => RGBColor(235, 235, 235),
    }
}

/// Viridis, by linear interpolation between five of its colours; t in [0, 1].
fn viridis(t: f64) -> RGBColor {
    const S: [(f64, f64, f64); 5] = [(68., 1., 84.), (59., 82., 139.), (33., 145., 140.), (94., 201., 98.), (253., 231., 37.)];
    let t = t.clamp(0.0, 1.0) * 4.0;
    let i = (t.floor() as usize).min(3);
    let f = t - i as f64;
    let c = |a: f64, b: f64| (a + f * (b - a)).round() as u8;
    RGBColor(c(S[i].0, S[i + 1].0), c(S[i].1, S[i + 1].1), c(S[i].2, S[i + 1].2))
}

type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<style::TickedAxis, style::TickedAxis>>;

/// A swept key's axis over the cells (cell i centred at i): its description with the key's
/// unit, and round values of the key, each with the position it falls at between the cells.
struct SweepAxis {
    label: String,
    /// (position on the cell axis, value of the key)
    ticks: Vec<(f64, f64)>,
}

impl SweepAxis {
    /// At most `max` ticks: 1, 2, 5 x 10^k per decade for a log sweep (only the powers of 10
    /// when those are too many), multiples of a 1-2-5 step for a linear one.
    fn of(s: &Sweep, max: usize) -> SweepAxis {
        let unit = crate::scenes::scene_file::KEYS.iter().find(|(k, _)| *k == s.key).and_then(|(_, d)| {
            let a = d.rfind('[')?;
            let b = d[a..].find(']')?;
            Some(&d[a + 1..a + b])
        });
        let label = unit.map_or(s.key.clone(), |u| style::axis_label(&s.key, u));
        let last = (s.n.max(1) - 1) as f64;
        // position of a value, and the values at the cells' outer edges
        let pos = |v: f64| -> f64 {
            if s.n == 1 || s.to == s.from {
                0.0
            } else if s.log {
                (v / s.from).ln() / (s.to / s.from).ln() * last
            } else {
                (v - s.from) / (s.to - s.from) * last
            }
        };
        let ticks = if s.n == 1 || s.to == s.from {
            vec![s.from]
        } else {
            let half = 0.5 / last;
            let edge = |f: f64| if s.log { s.from * (s.to / s.from).powf(f) } else { s.from + f * (s.to - s.from) };
            let (lo, hi) = (edge(-half).min(edge(1.0 + half)), edge(-half).max(edge(1.0 + half)));
            let mut t = if s.log && lo > 0.0 { style::ticks_log(lo, hi) } else { Vec::new() };
            if t.len() > max {
                t.retain(|x| (x / 10f64.powf(x.log10().floor()) - 1.0).abs() < 1e-9);
            }
            if t.len() < 2 {
                t = style::ticks_linear(lo, hi, max);
            }
            t
        };
        let ticks = ticks.into_iter().map(|v| (pos(v), v)).filter(|(p, _)| (-0.5..=last + 0.5).contains(p)).collect();
        SweepAxis { label, ticks }
    }

    fn positions(&self) -> Vec<f64> {
        self.ticks.iter().map(|t| t.0).collect()
    }

    /// The label of the tick at position `x` (the nearest).
    fn label_at(&self, x: f64) -> String {
        self.ticks
            .iter()
            .min_by(|a, b| (a.0 - x).abs().total_cmp(&(b.0 - x).abs()))
            .map_or(String::new(), |t| style::tick_label(t.1))
    }
}

/// The series labels, upper right.
fn legend<'a, 'b: 'a>(chart: &mut Chart<'a, 'b>, path: &Path) -> Result<()> {
    style::legend(chart, SeriesLabelPosition::UpperRight, 12, style::LEGEND_LINE)
        .map_err(|e| style::draw_err(path, e))
}

/// Writes the figure of `m` (one or two sweeps) to `path`.
pub fn write(m: &MapJson, path: &Path) -> Result<()> {
    if m.sweeps.len() == 2 {
        heat_maps(m, path)
    } else {
        lines(m, path)
    }
}

fn regime(run: Option<&RunCell>) -> &str {
    run.map_or("invalid", |r| r.regime.as_str())
}

type Quantity<'a> = (&'a str, Box<dyn Fn(&CellJson) -> Option<f64> + 'a>, bool);

fn heat_maps(m: &MapJson, path: &Path) -> Result<()> {
    let (a, b) = (&m.sweeps[0], &m.sweeps[1]);
    let (ax, ay) = (SweepAxis::of(a, 6), SweepAxis::of(b, 6));
    let cells = by_index(m);
    let root = SVGBackend::new(path, (1400, 1150)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| style::draw_err(path, e))?;
    let title = format!("{}: regime map over {} x {} (black line: linear stability boundary of steady sliding)", m.scene, a.key, b.key);
    let root = root.titled(&title, (style::FONT, 20)).map_err(|e| style::draw_err(path, e))?;
    let panels = root.split_evenly((2, 2));
    let unstable = |c: Option<&CellJson>| c.and_then(|c| c.linear.as_ref()).map(|l| !l.stable);
    // boundary segments in cell coordinates
    let mut edges: Vec<[(f64, f64); 2]> = Vec::new();
    for j in 0..b.n {
        for i in 0..a.n {
            let here = unstable(cells[i + a.n * j]);
            if i + 1 < a.n {
                if let (Some(p), Some(q)) = (here, unstable(cells[i + 1 + a.n * j])) {
                    if p != q {
                        let x = i as f64 + 0.5;
                        edges.push([(x, j as f64 - 0.5), (x, j as f64 + 0.5)]);
                    }
                }
            }
            if j + 1 < b.n {
                if let (Some(p), Some(q)) = (here, unstable(cells[i + a.n * (j + 1)])) {
                    if p != q {
                        let y = j as f64 + 0.5;
                        edges.push([(i as f64 - 0.5, y), (i as f64 + 0.5, y)]);
                    }
                }
            }
        }
    }
    let quantities: [Quantity; 2] = [
        ("stick-slip frequency from rest [Hz]", Box::new(|c: &CellJson| c.from_rest.as_ref().and_then(|r| r.stick_slip_hz)), false),
        ("pad_x groan-band RMS from rest [m/s^2] (log colour, 4 decades)", Box::new(|c: &CellJson| c.from_rest.as_ref().and_then(|r| r.groan_rms).filter(|v| *v > 0.0)), true),
    ];
    for (p, panel) in panels.iter().enumerate() {
        let caption = match p {
            0 => "regime from rest".to_string(),
            1 => "regime from perturbed steady sliding".to_string(),
            _ => quantities[p - 2].0.to_string(),
        };
        // continuous colour range
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        if p >= 2 {
            for c in cells.iter().flatten() {
                if let Some(v) = (quantities[p - 2].1)(c) {
                    let v = if quantities[p - 2].2 { v.log10() } else { v };
                    lo = lo.min(v);
                    hi = hi.max(v);
                }
            }
        }
        if p >= 2 && quantities[p - 2].2 {
            // a log colour scale spans at most four decades below the largest value
            lo = lo.max(hi - 4.0);
        }
        let range = if p >= 2 && lo.is_finite() {
            let unit = |v: f64| if quantities[p - 2].2 { 10f64.powf(v) } else { v };
            format!(" (dark {} to yellow {})", sig4(unit(lo)), sig4(unit(hi)))
        } else {
            String::new()
        };
        let mut chart = ChartBuilder::on(panel)
            .caption(format!("{caption}{range}"), (style::FONT, 15))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(
                style::TickedAxis { range: -0.5..a.n as f64 - 0.5, ticks: ax.positions() },
                style::TickedAxis { range: -0.5..b.n as f64 - 0.5, ticks: ay.positions() },
            )
            .map_err(|e| style::draw_err(path, e))?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(ax.label.as_str())
            .y_desc(ay.label.as_str())
            .x_label_formatter(&|x| ax.label_at(*x))
            .y_label_formatter(&|y| ay.label_at(*y))
            .label_style((style::FONT, 12))
            .axis_desc_style((style::FONT, 14))
            .draw()
            .map_err(|e| style::draw_err(path, e))?;
        let color = |c: &CellJson| -> RGBColor {
            match p {
                0 => regime_color(regime(c.from_rest.as_ref())),
                1 => regime_color(regime(c.from_sliding.as_ref())),
                _ => match (quantities[p - 2].1)(c) {
                    Some(v) => {
                        let v = if quantities[p - 2].2 { v.log10() } else { v };
                        viridis(if hi > lo { (v - lo) / (hi - lo) } else { 0.5 })
                    }
                    None => RGBColor(235, 235, 235),
                },
            }
        };
        chart
            .draw_series(cells.iter().flatten().map(|c| {
                let (i, j) = ((c.index % a.n) as f64, (c.index / a.n) as f64);
                Rectangle::new([(i - 0.5, j - 0.5), (i + 0.5, j + 0.5)], color(c).filled())
            }))
            .map_err(|e| style::draw_err(path, e))?;
        chart
            .draw_series(edges.iter().map(|e| PathElement::new(e.to_vec(), BLACK.stroke_width(3))))
            .map_err(|e| style::draw_err(path, e))?;
        if p < 2 {
            for (r, _) in REGIMES {
                let present = cells.iter().flatten().any(|c| regime(if p == 0 { c.from_rest.as_ref() } else { c.from_sliding.as_ref() }) == r);
                if !present {
                    continue;
                }
                let col = regime_color(r);
                chart
                    .draw_series(std::iter::empty::<Rectangle<(f64, f64)>>())
                    .map_err(|e| style::draw_err(path, e))?
                    .label(r)
                    .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], col.filled()));
            }
            legend(&mut chart, path)?;
        }
    }
    root.present().map_err(|e| style::draw_err(path, e))?;
    Ok(())
}

/// One line of a 1-D map's panel: label, points, colour, dashed.
type Series = (String, Vec<(f64, f64)>, RGBColor, bool);

fn lines(m: &MapJson, path: &Path) -> Result<()> {
    let a = &m.sweeps[0];
    let ax = SweepAxis::of(a, style::MAX_TICKS);
    let cells = by_index(m);
    let root = SVGBackend::new(path, (1400, 950)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| style::draw_err(path, e))?;
    let title = format!("{}: sweep of {} (black verticals: linear stability boundary of steady sliding)", m.scene, a.key);
    let root = root.titled(&title, (style::FONT, 20)).map_err(|e| style::draw_err(path, e))?;
    let panels = root.split_evenly((2, 2));
    let x_of = |c: &CellJson| c.index as f64;
    let boundary: Vec<f64> = super::output::boundary_pairs(m).iter().map(|&(i, _)| i as f64 + 0.5).collect();
    type Get = fn(&RunCell) -> Option<f64>;
    let runs: [(&str, Get); 4] = [
        ("stick fraction [-]", |r| r.stick_fraction),
        ("stick-slip frequency [Hz]", |r| r.stick_slip_hz),
        ("pad_x groan-band RMS [m/s^2]", |r| r.groan_rms),
        ("", |_| None),
    ];
    for (p, panel) in panels.iter().enumerate() {
        let mut series: Vec<Series> = Vec::new();
        let caption;
        if p == 3 {
            caption = "largest growth rate of steady sliding [1/s]".to_string();
            let pts: Vec<(f64, f64)> = cells.iter().flatten().filter_map(|c| Some((x_of(c), c.linear.as_ref()?.max_growth_rate?))).collect();
            series.push(("linear analysis".into(), pts, RGBColor(0, 0, 0), false));
        } else {
            caption = runs[p].0.to_string();
            for (name, which, col, dashed) in [("from rest", 0, RGBColor(214, 39, 40), false), ("from sliding", 1, RGBColor(31, 119, 180), true)] {
                let pts: Vec<(f64, f64)> = cells
                    .iter()
                    .flatten()
                    .filter_map(|c| {
                        let r = if which == 0 { c.from_rest.as_ref() } else { c.from_sliding.as_ref() }?;
                        Some((x_of(c), (runs[p].1)(r)?))
                    })
                    .collect();
                series.push((name.into(), pts, col, dashed));
            }
        }
        let (mut lo, mut hi) = (0.0f64, f64::NEG_INFINITY);
        for (_, pts, _, _) in &series {
            for &(_, y) in pts {
                lo = lo.min(y);
                hi = hi.max(y);
            }
        }
        if !hi.is_finite() || hi <= lo {
            hi = lo + 1.0;
        }
        let pad = 0.05 * (hi - lo);
        // room above the data for the legend (upper right), so that it covers no line
        let top = hi + pad + style::LEGEND_ROOM * (hi - lo);
        let mut chart = ChartBuilder::on(panel)
            .caption(caption.as_str(), (style::FONT, 15))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(
                style::TickedAxis { range: -0.5..a.n as f64 - 0.5, ticks: ax.positions() },
                style::TickedAxis { range: lo - pad..top, ticks: style::ticks_linear(lo - pad, top, style::MAX_TICKS) },
            )
            .map_err(|e| style::draw_err(path, e))?;
        chart
            .configure_mesh()
            .x_desc(ax.label.as_str())
            .y_desc(caption.as_str())
            .x_label_formatter(&|x| ax.label_at(*x))
            .y_label_formatter(&|y| style::tick_label(*y))
            .label_style((style::FONT, 12))
            .axis_desc_style((style::FONT, 14))
            .draw()
            .map_err(|e| style::draw_err(path, e))?;
        for &x in &boundary {
            chart
                .draw_series(std::iter::once(PathElement::new(vec![(x, lo - pad), (x, top)], BLACK.stroke_width(1))))
                .map_err(|e| style::draw_err(path, e))?;
        }
        for (label, pts, col, dashed) in series {
            let shape = ShapeStyle { color: col.to_rgba(), filled: true, stroke_width: if dashed { 1 } else { 2 } };
            chart
                .draw_series(LineSeries::new(pts.clone(), shape))
                .map_err(|e| style::draw_err(path, e))?
                .label(label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], shape));
            // the regime of each point as its marker's colour
            if p == 0 {
                let which_rest = col == RGBColor(214, 39, 40);
                chart
                    .draw_series(cells.iter().flatten().filter_map(|c| {
                        let r = if which_rest { c.from_rest.as_ref() } else { c.from_sliding.as_ref() }?;
                        let y = r.stick_fraction?;
                        Some(Circle::new((x_of(c), y), if which_rest { 4 } else { 2 }, regime_color(&r.regime).filled()))
                    }))
                    .map_err(|e| style::draw_err(path, e))?;
            }
        }
        legend(&mut chart, path)?;
    }
    root.present().map_err(|e| style::draw_err(path, e))?;
    Ok(())
}
