//! A fit's figure: model against measured, per statistic, every case (`fit --plot`).

use super::*;

/// The cases' colours in the figure (Okabe-Ito), in the order of [`super::super::model::case_names`],
/// then the scene's own name.
pub(super) const CASE_COLOURS: [RGBColor; 7] = [
    RGBColor(213, 94, 0),
    RGBColor(230, 159, 0),
    RGBColor(204, 121, 167),
    RGBColor(0, 114, 178),
    RGBColor(86, 180, 233),
    RGBColor(0, 158, 115),
    RGBColor(0, 0, 0),
];

/// Draws a channel's marker at `at` on `area` in `colour` (filled: fitted; open: held out):
/// disc_x a circle, pad_x a triangle, pad_trail a cross, pad_lead a square, a per-case
/// statistic a diamond.
pub(super) fn draw_marker<DB: DrawingBackend, CT: plotters::coord::CoordTranslate>(
    area: &DrawingArea<DB, CT>,
    at: CT::From,
    channel: Option<usize>,
    colour: RGBColor,
    filled: bool,
) -> std::result::Result<(), DrawingAreaErrorKind<DB::ErrorType>>
where
    CT::From: Clone + 'static,
{
    let st = if filled { colour.filled() } else { colour.stroke_width(2) };
    let e = EmptyElement::at(at);
    match channel {
        Some(0) => area.draw(&(e + Circle::new((0, 0), 4, st))),
        Some(1) => area.draw(&(e + TriangleMarker::new((0, 0), 5, st))),
        Some(2) => area.draw(&(e + Cross::new((0, 0), 4, colour.stroke_width(2)))),
        Some(_) => area.draw(&(e + Rectangle::new([(-4, -4), (4, 4)], st))),
        None => area.draw(&(e + Polygon::new(vec![(0, -5), (5, 0), (0, 5), (-5, 0)], st))),
    }
}

/// The figure: one panel per statistic, model against measured on log axes (ticks at 1, 2, 5)
/// with the line model = measured; channels by marker shape, cases by colour (a legend at the
/// right), fitted filled, held out open; only the points furthest off the diagonal labelled
/// (|ln ratio| above twice the panel's RMS and above 0.5, at most 4 a panel).
pub fn write_plot(r: &FitReport, path: &Path) -> Result<()> {
    let stats: Vec<Stat> = Stat::ALL
        .into_iter()
        .filter(|s| r.fitted.iter().chain(&r.holdout).any(|c| c.key.stat == *s && c.model.is_some()))
        .collect();
    if stats.is_empty() {
        return Err(HostError::Output(format!("{}: no statistic has a model value to plot", path.display())));
    }
    let mut cases: Vec<String> = super::super::model::case_names();
    for c in r.fitted.iter().chain(&r.holdout) {
        if !cases.contains(&c.key.case) {
            cases.push(c.key.case.clone());
        }
    }
    let colour_of = |case: &str| CASE_COLOURS[cases.iter().position(|c| c == case).unwrap_or(0).min(CASE_COLOURS.len() - 1)];
    let cols = stats.len().min(3);
    let rows = stats.len().div_ceil(cols);
    let legend_w = 190u32;
    let (w, h) = (440 * cols as u32 + legend_w, (420 * rows as u32).max(330));
    let root = SVGBackend::new(path, (w, h)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| style::draw_err(path, e))?;
    let (plots, legend) = root.split_horizontally(w - legend_w);
    let panels = plots.split_evenly((rows, cols));
    for (stat, area) in stats.iter().zip(panels.iter()) {
        let pts: Vec<(&Compared, bool)> = r
            .fitted
            .iter()
            .map(|c| (c, false))
            .chain(r.holdout.iter().map(|c| (c, true)))
            .filter(|(c, _)| c.key.stat == *stat && c.model.is_some_and(|m| m > 0.0))
            .collect();
        let vals = pts.iter().flat_map(|(c, _)| [c.measured, c.model.unwrap_or(c.measured)]);
        let (lo, hi) = vals.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        let (lo, hi) = (lo / 1.5, hi * 1.5);
        let mut ticks = style::ticks_log(lo, hi);
        if ticks.len() > 9 {
            ticks.retain(|x| (x / 10f64.powf(x.log10().floor()) - 1.0).abs() < 1e-9);
        }
        let mut chart = ChartBuilder::on(area)
            .caption(format!("{} [{}]", stat.name(), stat.unit()), (style::FONT, 16))
            .margin(10)
            .x_label_area_size(36)
            .y_label_area_size(56)
            .build_cartesian_2d((lo..hi).log_scale().with_key_points(ticks.clone()), (lo..hi).log_scale().with_key_points(ticks))
            .map_err(|e| style::draw_err(path, e))?;
        chart
            .configure_mesh()
            .x_desc(style::axis_label("measured", stat.unit()))
            .y_desc(style::axis_label("model", stat.unit()))
            .label_style((style::FONT, 11))
            .x_label_formatter(&|x| style::tick_label(*x))
            .y_label_formatter(&|x| style::tick_label(*x))
            .light_line_style(WHITE.mix(0.0))
            .bold_line_style(BLACK.mix(0.08))
            .draw()
            .map_err(|e| style::draw_err(path, e))?;
        chart.draw_series(LineSeries::new([(lo, lo), (hi, hi)], BLACK.mix(0.4))).map_err(|e| style::draw_err(path, e))?;
        let lrs: Vec<f64> = pts.iter().filter_map(|(c, _)| c.log_ratio()).collect();
        let rms = (lrs.iter().map(|x| x * x).sum::<f64>() / lrs.len().max(1) as f64).sqrt();
        let mut off: Vec<(f64, usize)> = pts.iter().enumerate().filter_map(|(i, (c, _))| c.log_ratio().map(|l| (l.abs(), i))).collect();
        off.sort_by(|a, b| b.0.total_cmp(&a.0));
        let labelled: Vec<usize> = off.iter().filter(|(l, _)| *l > (2.0 * rms).max(0.5)).take(4).map(|(_, i)| *i).collect();
        for (i, (c, held)) in pts.iter().enumerate() {
            let m = c.model.expect("filtered");
            draw_marker(chart.plotting_area(), (c.measured, m), c.key.channel, colour_of(&c.key.case), !held)
                .map_err(|e| style::draw_err(path, e))?;
            if labelled.contains(&i) {
                let label = if c.key.channel.is_some() { format!("{} {}", c.key.case, c.key.channel_name()) } else { c.key.case.clone() };
                chart
                    .draw_series(std::iter::once(
                        EmptyElement::at((c.measured, m)) + Text::new(label, (6, -12), (style::FONT, 10).into_font().color(&BLACK.mix(0.8))),
                    ))
                    .map_err(|e| style::draw_err(path, e))?;
            }
        }
    }
    // the legend: cases by colour, channels by shape, fitted / held out
    let font = (style::FONT, 12).into_font();
    let mut y = 24;
    legend.draw(&Text::new("case (colour)", (10, y), font.clone())).map_err(|e| style::draw_err(path, e))?;
    let used: Vec<&String> = cases.iter().filter(|c| r.fitted.iter().chain(&r.holdout).any(|x| &x.key.case == *c)).collect();
    for c in used {
        y += 18;
        draw_marker(&legend, (18, y + 6), Some(0), colour_of(c), true).map_err(|e| style::draw_err(path, e))?;
        legend.draw(&Text::new(c.clone(), (32, y), font.clone())).map_err(|e| style::draw_err(path, e))?;
    }
    y += 30;
    legend.draw(&Text::new("channel (shape)", (10, y), font.clone())).map_err(|e| style::draw_err(path, e))?;
    let names = stickslip_model::rig::ACCEL_NAMES;
    let mut shapes: Vec<(Option<usize>, String)> = (0..names.len()).map(|i| (Some(i), names[i].to_string())).collect();
    shapes.push((None, "per case".into()));
    for (ch, name) in shapes {
        y += 18;
        draw_marker(&legend, (18, y + 6), ch, BLACK, true).map_err(|e| style::draw_err(path, e))?;
        legend.draw(&Text::new(name, (32, y), font.clone())).map_err(|e| style::draw_err(path, e))?;
    }
    y += 30;
    draw_marker(&legend, (18, y + 6), Some(0), BLACK, true).map_err(|e| style::draw_err(path, e))?;
    legend.draw(&Text::new("fitted", (32, y), font.clone())).map_err(|e| style::draw_err(path, e))?;
    if !r.holdout.is_empty() {
        y += 18;
        draw_marker(&legend, (18, y + 6), Some(0), BLACK, false).map_err(|e| style::draw_err(path, e))?;
        legend.draw(&Text::new("held out", (32, y), font.clone())).map_err(|e| style::draw_err(path, e))?;
    }
    y += 18;
    legend.draw(&PathElement::new(vec![(10, y + 6), (26, y + 6)], BLACK.mix(0.4))).map_err(|e| style::draw_err(path, e))?;
    legend.draw(&Text::new("model = measured", (32, y), font)).map_err(|e| style::draw_err(path, e))?;
    root.present().map_err(|e| style::draw_err(path, e))
}
