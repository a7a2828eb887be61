//! The figures of `cases --plots`, in the manner of the thesis's Fig. 2.5 to 2.12: for each
//! caliper, displacement, velocity, angular displacement and angular velocity against time,
//! the three load positions as three lines. SVG (no system fonts needed).

use std::path::{Path, PathBuf};

use plotters::element::DashedPathElement;
use plotters::prelude::*;

use crate::error::Result;
use crate::output::style::{self, draw_err};

/// One line of a figure: a load position's samples (t [s], [x, x', phi, phi'] in SI).
pub struct Line<'a> {
    pub label: String,
    pub samples: &'a [(f64, [f64; 4])],
}

/// What the caption says about the run.
pub struct FigureContext<'a> {
    /// "push" or "pull".
    pub caliper: &'a str,
    /// Plotted window [s].
    pub from: f64,
    pub to: f64,
    /// Simulated run length [s].
    pub run_s: f64,
    /// Band speed V [m/s], drawn on the velocity figure.
    pub v: f64,
}

struct Quantity {
    file: &'static str,
    title: &'static str,
    axis: &'static str,
    /// Display value = SI value * scale.
    scale: f64,
}

const QUANTITIES: [Quantity; 4] = [
    Quantity {
        file: "displacement",
        title: "pad displacement x",
        axis: "displacement x [mm]",
        scale: 1e3,
    },
    Quantity {
        file: "velocity",
        title: "pad velocity x'",
        axis: "velocity x' [mm/s]",
        scale: 1e3,
    },
    Quantity {
        file: "angular_displacement",
        title: "pad rotation phi",
        axis: "angular displacement phi [mrad]",
        scale: 1e3,
    },
    Quantity {
        file: "angular_velocity",
        title: "pad angular velocity phi'",
        axis: "angular velocity phi' [rad/s]",
        scale: 1.0,
    },
];

/// Most points drawn per line; longer series keep each bin's minimum and maximum, so the
/// peaks stay visible.
const MAX_POINTS: usize = 4000;

fn decimate(samples: &[(f64, [f64; 4])], i: usize, scale: f64) -> Vec<(f64, f64)> {
    let pts = samples.iter().map(|(t, z)| (*t, z[i] * scale));
    if samples.len() <= MAX_POINTS {
        return pts.collect();
    }
    let bins = MAX_POINTS / 2;
    let per = samples.len().div_ceil(bins);
    let mut out = Vec::with_capacity(2 * bins + 2);
    let all: Vec<(f64, f64)> = pts.collect();
    for chunk in all.chunks(per) {
        let (mut lo, mut hi) = (chunk[0], chunk[0]);
        for &p in chunk {
            if p.1 < lo.1 {
                lo = p;
            }
            if p.1 > hi.1 {
                hi = p;
            }
        }
        if lo.0 <= hi.0 {
            out.push(lo);
            out.push(hi);
        } else {
            out.push(hi);
            out.push(lo);
        }
    }
    out
}

/// Line styles of the three load positions, after the thesis: trailing short dashes,
/// centre solid, leading long dashes (and three colours).
fn line_style(k: usize) -> (RGBColor, Option<(u32, u32)>) {
    match k {
        0 => (style::PALETTE[0], Some((6, 4))),
        1 => (style::PALETTE[1], None),
        _ => (style::PALETTE[2], Some((16, 6))),
    }
}

/// Writes the four figures of one caliper into `dir`; returns their paths.
pub fn caliper_figures(dir: &Path, ctx: &FigureContext, lines: &[Line]) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for (qi, q) in QUANTITIES.iter().enumerate() {
        let path = dir.join(format!("{}_{}.svg", ctx.caliper, q.file));
        figure(&path, ctx, lines, qi, q).map_err(|e| draw_err(&path, e))?;
        written.push(path);
    }
    Ok(written)
}

fn figure(
    path: &Path,
    ctx: &FigureContext,
    lines: &[Line],
    qi: usize,
    q: &Quantity,
) -> std::result::Result<(), Box<dyn std::error::Error>> {
    let series: Vec<Vec<(f64, f64)>> = lines
        .iter()
        .map(|l| decimate(l.samples, qi, q.scale))
        .collect();
    let band = (qi == 1).then_some(ctx.v * q.scale);
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for &(_, y) in series.iter().flatten() {
        lo = lo.min(y);
        hi = hi.max(y);
    }
    if let Some(b) = band {
        lo = lo.min(b);
        hi = hi.max(b);
    }
    if !(lo.is_finite() && hi.is_finite()) {
        lo = -1.0;
        hi = 1.0;
    }
    let mut span = hi - lo;
    if span.is_nan() || span <= 0.0 {
        span = lo.abs().max(1.0) * 0.1;
        lo -= span / 2.0;
        hi += span / 2.0;
    }
    // Room for the legend above the data.
    let (y0, y1) = (lo - 0.05 * span, hi + 0.35 * span);

    let root = SVGBackend::new(path, (1000, 620)).into_drawing_area();
    root.fill(&WHITE)?;
    let caliper = if ctx.caliper == "push" {
        "Push"
    } else {
        "Pull"
    };
    let window = if ctx.from <= 0.0 && ctx.to >= ctx.run_s {
        format!("whole run, 0 to {} s", ctx.run_s)
    } else {
        format!("t = {} to {} s of a {} s run", ctx.from, ctx.to, ctx.run_s)
    };
    let caption = format!("{caliper} caliper: {} against time ({window})", q.title);
    let mut chart = style::time_chart(&root, caption, 22, ctx.from..ctx.to, y0..y1, q.axis)?;

    for (k, (line, pts)) in lines.iter().zip(&series).enumerate() {
        let (color, dash) = line_style(k);
        let st = ShapeStyle::from(&color).stroke_width(2);
        let anno = match dash {
            None => chart.draw_series(LineSeries::new(pts.iter().copied(), st))?,
            Some((d, g)) => {
                chart.draw_series(DashedLineSeries::new(pts.iter().copied(), d, g, st))?
            }
        };
        anno.label(line.label.clone())
            .legend(move |(x, y)| match dash {
                None => PathElement::new(vec![(x, y), (x + 36, y)], st).into_dyn(),
                Some((d, g)) => {
                    DashedPathElement::new(vec![(x, y), (x + 36, y)], d, g, st).into_dyn()
                }
            });
    }
    if let Some(b) = band {
        let st = ShapeStyle::from(&RGBColor(120, 120, 120)).stroke_width(1);
        chart
            .draw_series(DashedLineSeries::new(
                vec![(ctx.from, b), (ctx.to, b)],
                3,
                3,
                st,
            ))?
            .label(format!("band speed V = {} mm/s", b))
            .legend(move |(x, y)| {
                DashedPathElement::new(vec![(x, y), (x + 36, y)], 3, 3, st).into_dyn()
            });
    }
    style::legend(&mut chart, SeriesLabelPosition::UpperRight, 15, 48)?;
    root.present()?;
    Ok(())
}
