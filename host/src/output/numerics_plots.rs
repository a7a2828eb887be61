//! The figures of `accuracy --plot` (error against run time, log-log, one panel per scene,
//! one line per method and precision) and `stability --plot` (the outcome map: one panel per
//! sweep, the swept value across, method and precision down). SVG.

use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use stickslip_model::methods::MethodKind;

use crate::error::Result;
use crate::numerics::accuracy;
use crate::output::style;
use crate::numerics::stability;

const SCENES: [&str; 3] = ["oracle_1dof", "pull_center", "push_center"];

fn series_color(i: usize) -> RGBColor {
    const C: [RGBColor; 6] = [
        RGBColor(0, 0, 0),
        RGBColor(214, 39, 40),
        RGBColor(31, 119, 180),
        RGBColor(44, 160, 44),
        RGBColor(148, 103, 189),
        RGBColor(255, 127, 14),
    ];
    C[i % C.len()]
}

/// Error against run time, one panel per scene.
pub fn accuracy(rep: &accuracy::Report, path: &Path) -> Result<()> {
    let root = SVGBackend::new(path, (1500, 520)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| style::draw_err(path, e))?;
    let panels = root.split_evenly((1, SCENES.len()));
    let floor = 1e-16;
    for (panel, scene) in panels.iter().zip(SCENES) {
        let rows: Vec<&accuracy::Row> = rep.rows.iter().filter(|r| r.scene == scene && r.error.is_some()).collect();
        let (mut tmin, mut tmax) = (f64::INFINITY, 0.0f64);
        for r in &rows {
            tmin = tmin.min(r.run_s.max(1e-7));
            tmax = tmax.max(r.run_s.max(1e-7));
        }
        if rows.is_empty() {
            continue;
        }
        let mut chart = ChartBuilder::on(panel)
            .caption(format!("{scene}: error against run time"), (style::FONT, 18))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d((tmin / 2.0..tmax * 2.0).log_scale(), (floor..10.0).log_scale())
            .map_err(|e| style::draw_err(path, e))?;
        chart
            .configure_mesh()
            .x_desc("run time [s] (minimum over repeats)")
            .y_desc("relative error [-]")
            .x_label_formatter(&|v| format!("{v:.0e}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| style::draw_err(path, e))?;
        // (label, points, dashed)
        type Line = (String, Vec<(f64, f64)>, bool);
        let mut lines: Vec<Line> = Vec::new();
        for kind in MethodKind::ALL {
            for prec in ["f64", "f32"] {
                let mut pts: Vec<(f64, f64)> = rows
                    .iter()
                    .filter(|r| r.method == kind.name() && r.precision == prec)
                    .map(|r| (r.run_s.max(1e-7), r.error.unwrap_or(1.0).max(floor)))
                    .collect();
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                lines.push((format!("{} {prec}", kind.name()), pts, prec == "f32"));
            }
        }
        let mut ad: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.method == "dop853_adaptive")
            .map(|r| (r.run_s.max(1e-7), r.error.unwrap_or(1.0).max(floor)))
            .collect();
        ad.sort_by(|a, b| a.0.total_cmp(&b.0));
        lines.push(("DOP853 adaptive f64".into(), ad, false));
        for (i, (label, pts, dashed)) in lines.into_iter().enumerate() {
            if pts.is_empty() {
                continue;
            }
            let color = series_color(i / 2);
            let shape = ShapeStyle { color: color.to_rgba(), filled: true, stroke_width: if dashed { 1 } else { 2 } };
            chart
                .draw_series(LineSeries::new(pts.clone(), shape))
                .map_err(|e| style::draw_err(path, e))?
                .label(label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], shape));
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, shape))).map_err(|e| style::draw_err(path, e))?;
        }
        style::legend(&mut chart, SeriesLabelPosition::LowerLeft, 11, style::LEGEND_LINE)
            .map_err(|e| style::draw_err(path, e))?;
    }
    root.present().map_err(|e| style::draw_err(path, e))?;
    Ok(())
}

fn outcome_color(o: &str) -> RGBColor {
    match o {
        "bounded" => RGBColor(120, 190, 120),
        "sprag" => RGBColor(240, 160, 40),
        "contact_loss" => RGBColor(90, 140, 220),
        _ => RGBColor(220, 60, 60),
    }
}

/// The outcome map: one panel per sweep.
pub fn stability(rep: &stability::Report, path: &Path) -> Result<()> {
    let sweeps = &stability::SWEEPS;
    let root = SVGBackend::new(path, (1600, 1000)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| style::draw_err(path, e))?;
    let (title, body) = root.split_vertically(50);
    title
        .draw(&Text::new(
            "Outcome per run: green bounded, orange sprag (model), blue contact loss (model), red method unstable",
            (20, 15),
            (style::FONT, 18),
        ))
        .map_err(|e| style::draw_err(path, e))?;
    let panels = body.split_evenly((2, 4));
    let labels: Vec<String> = MethodKind::ALL
        .iter()
        .flat_map(|k| ["f64", "f32"].map(|p| format!("{} {p}", k.name())))
        .collect();
    for (panel, sweep) in panels.iter().zip(sweeps.iter()) {
        let n = sweep.values.len();
        let m = labels.len();
        let mut chart = ChartBuilder::on(panel)
            .caption(format!("{} [{}]", sweep.key, sweep.unit), (style::FONT, 16))
            .margin(8)
            .x_label_area_size(30)
            .y_label_area_size(130)
            .build_cartesian_2d(0.0..n as f64, 0.0..m as f64)
            .map_err(|e| style::draw_err(path, e))?;
        let values = sweep.values;
        let labels_ref = &labels;
        chart
            .configure_mesh()
            .disable_mesh()
            .disable_y_axis()
            .disable_x_axis()
            .draw()
            .map_err(|e| style::draw_err(path, e))?;
        // one label per column, under its centre
        let below = TextStyle::from((style::FONT, 10).into_font()).pos(Pos::new(HPos::Center, VPos::Top));
        for (i, v) in values.iter().enumerate() {
            let (px, py) = chart.backend_coord(&(i as f64 + 0.5, 0.0));
            root.draw(&Text::new(style::tick_label(*v), (px, py + 4), below.clone())).map_err(|e| style::draw_err(path, e))?;
        }
        // one label per row, drawn beside it (axis ticks would skip rows)
        let beside = TextStyle::from((style::FONT, 10).into_font()).pos(Pos::new(HPos::Right, VPos::Center));
        for (j, label) in labels_ref.iter().enumerate() {
            let (px, py) = chart.backend_coord(&(0.0, (m - j - 1) as f64 + 0.5));
            root.draw(&Text::new(label.clone(), (px - 6, py), beside.clone())).map_err(|e| style::draw_err(path, e))?;
        }
        for (j, label) in labels.iter().enumerate() {
            let (method, prec) = label.split_once(' ').unwrap_or((label, ""));
            for (i, v) in values.iter().enumerate() {
                let r = rep.rows.iter().find(|r| {
                    r.sweep == sweep.key && r.method == method && r.precision == prec && stability::value_of(r, sweep.key) == *v
                });
                let color = r.map_or(RGBColor(200, 200, 200), |r| outcome_color(&r.outcome));
                let y = (m - j - 1) as f64;
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(i as f64 + 0.05, y + 0.08), (i as f64 + 0.95, y + 0.92)],
                        color.filled(),
                    )))
                    .map_err(|e| style::draw_err(path, e))?;
            }
        }
    }
    root.present().map_err(|e| style::draw_err(path, e))?;
    Ok(())
}
