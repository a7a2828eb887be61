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

/// The mesh of a fit figure's panel: axis descriptions, 11 px tick labels by
/// [`style::tick_label`], faint grid lines at the ticks only (a macro: the panels' axes differ
/// in type, log and linear).
macro_rules! fit_mesh {
    ($chart:expr, $x_desc:expr, $y_desc:expr, $path:expr) => {
        $chart
            .configure_mesh()
            .x_desc($x_desc)
            .y_desc($y_desc)
            .label_style((style::FONT, 11))
            .x_label_formatter(&|x| style::tick_label(*x))
            .y_label_formatter(&|x| style::tick_label(*x))
            .light_line_style(WHITE.mix(0.0))
            .bold_line_style(BLACK.mix(0.08))
            .draw()
            .map_err(|e| style::draw_err($path, e))?
    };
}

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
/// (|ln ratio| above twice the panel's RMS and above 0.5, at most 4 a panel, and only where
/// the label covers no other label). Below, where the fit computed profile-likelihood
/// intervals, one panel per free key: its profile (delta chi^2 against the key's value), the
/// 95 % threshold and the interval.
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
    // the profiles' row(s) below, one panel per free key, where intervals were computed
    let profiled: Vec<usize> = (0..r.free.len()).filter(|k| r.profiles.get(*k).is_some_and(|p| p.len() >= 2)).collect();
    let (p_cols, p_rows) = if profiled.is_empty() { (0, 0) } else { (profiled.len().min(4), profiled.len().div_ceil(4)) };
    let comparison_h = (420 * rows as u32).max(330);
    let (w, h) = ((440 * cols as u32 + legend_w).max(300 * p_cols as u32), comparison_h + PROFILE_ROW_H * p_rows as u32);
    let root = SVGBackend::new(path, (w, h)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| style::draw_err(path, e))?;
    let (top, bottom) = root.split_vertically(comparison_h);
    if !profiled.is_empty() {
        // panels as wide as the comparison's (the row's unused slots left blank)
        draw_profiles(r, &profiled, &bottom.split_evenly((p_rows, p_cols.max(cols.min(4)))), path)?;
    }
    let (plots, legend) = top.split_horizontally(440 * cols as u32);
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
        if ticks.len() < 2 {
            // a span within one 1-2-5 step (points clustered): round linear ticks on the log axis
            ticks = style::ticks_linear(lo, hi, 4).into_iter().filter(|x| *x > lo && *x < hi).collect();
        }
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
        fit_mesh!(chart, style::axis_label("measured", stat.unit()), style::axis_label("model", stat.unit()), path);
        chart.draw_series(LineSeries::new([(lo, lo), (hi, hi)], BLACK.mix(0.4))).map_err(|e| style::draw_err(path, e))?;
        let lrs: Vec<f64> = pts.iter().filter_map(|(c, _)| c.log_ratio()).collect();
        let rms = (lrs.iter().map(|x| x * x).sum::<f64>() / lrs.len().max(1) as f64).sqrt();
        let mut off: Vec<(f64, usize)> = pts.iter().enumerate().filter_map(|(i, (c, _))| c.log_ratio().map(|l| (l.abs(), i))).collect();
        off.sort_by(|a, b| b.0.total_cmp(&a.0));
        let wanted: Vec<usize> = off.iter().filter(|(l, _)| *l > (2.0 * rms).max(0.5)).take(4).map(|(_, i)| *i).collect();
        for (c, held) in pts.iter() {
            let m = c.model.expect("filtered");
            draw_marker(chart.plotting_area(), (c.measured, m), c.key.channel, colour_of(&c.key.case), !held)
                .map_err(|e| style::draw_err(path, e))?;
        }
        // labels, furthest off first, each where it covers no label placed before it (else none)
        let mut placed: Vec<LabelBox> = Vec::new();
        for i in wanted {
            let (c, _) = pts[i];
            let m = c.model.expect("filtered");
            let label = if c.key.channel.is_some() { format!("{} {}", c.key.case, c.key.channel_name()) } else { c.key.case.clone() };
            let at = chart.backend_coord(&(c.measured, m));
            let Some(offset) = free_label_offset(at, &label, &placed) else { continue };
            placed.push(LabelBox::of(at, offset, &label));
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at((c.measured, m)) + Text::new(label, offset, (style::FONT, 10).into_font().color(&BLACK.mix(0.8))),
                ))
                .map_err(|e| style::draw_err(path, e))?;
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

/// Height of a row of profile panels [px].
const PROFILE_ROW_H: u32 = 300;

/// A label's box in pixels: left, top, right, bottom.
#[derive(Clone, Copy, Debug, PartialEq)]
struct LabelBox(i32, i32, i32, i32);

/// Width of one character of the labels' 10 px font [px] (a sans-serif's average, rounded up).
const LABEL_CHAR_W: i32 = 6;
/// Height of a label's line [px].
const LABEL_H: i32 = 12;

impl LabelBox {
    /// The box of `label` drawn at `offset` from the point at pixel `at` (text anchored at its
    /// top left).
    fn of(at: (i32, i32), offset: (i32, i32), label: &str) -> LabelBox {
        let (x, y) = (at.0 + offset.0, at.1 + offset.1);
        LabelBox(x, y, x + LABEL_CHAR_W * label.chars().count() as i32, y + LABEL_H)
    }

    fn overlaps(&self, o: &LabelBox) -> bool {
        self.0 < o.2 && o.0 < self.2 && self.1 < o.3 && o.1 < self.3
    }
}

/// The first of four places around the point at `at` (above right, below right, above left,
/// below left) where `label` covers none of `placed`; `None` where every place does.
fn free_label_offset(at: (i32, i32), label: &str, placed: &[LabelBox]) -> Option<(i32, i32)> {
    let w = LABEL_CHAR_W * label.chars().count() as i32;
    [(6, -LABEL_H - 2), (6, 4), (-6 - w, -LABEL_H - 2), (-6 - w, 4)]
        .into_iter()
        .find(|off| !placed.iter().any(|b| b.overlaps(&LabelBox::of(at, *off, label))))
}

/// The unit of scene key `key`, from its description in the scene file (`[N/m]` -> `N/m`).
fn key_unit(key: &str) -> &'static str {
    scene_file::KEYS
        .iter()
        .find(|(k, _)| *k == key)
        .and_then(|(_, doc)| {
            let a = doc.find('[')?;
            let b = a + doc[a..].find(']')?;
            Some(&doc[a + 1..b])
        })
        .unwrap_or("-")
}

/// One panel per profiled free key: delta chi^2 against the key's value (the other keys
/// refitted at each point), the 95 % threshold (3.841), the interval's ends (a side that does
/// not close inside the bounds marked "open"), and the optimum.
fn draw_profiles<DB: DrawingBackend>(r: &FitReport, keys: &[usize], panels: &[DrawingArea<DB, plotters::coord::Shift>], path: &Path) -> Result<()> {
    let threshold = crate::fit::solve::PROFILE_DCHI2_95;
    for (&k, area) in keys.iter().zip(panels) {
        let pts = &r.profiles[k];
        let key = &r.free[k].key;
        let (lo, hi) = pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (x, _)| (a.min(*x), b.max(*x)));
        let pad = 0.05 * (hi - lo).max(1e-12 * hi.abs().max(1e-300));
        let (lo, hi) = (lo - pad, hi + pad);
        let y_hi = (pts.iter().map(|(_, d)| *d).filter(|d| d.is_finite()).fold(0.0, f64::max) * 1.1).clamp(2.0 * threshold, 10.0 * threshold);
        let x_ticks = style::ticks_linear(lo, hi, 5);
        let y_ticks = style::ticks_linear(0.0, y_hi, 6);
        let mut chart = ChartBuilder::on(area)
            .caption(format!("profile of {key}"), (style::FONT, 15))
            .margin(10)
            .x_label_area_size(36)
            .y_label_area_size(48)
            .build_cartesian_2d(
                style::TickedAxis { range: lo..hi, ticks: x_ticks },
                style::TickedAxis { range: -0.02 * y_hi..y_hi, ticks: y_ticks },
            )
            .map_err(|e| style::draw_err(path, e))?;
        fit_mesh!(chart, style::axis_label(key, key_unit(key)), style::axis_label("delta chi^2", "-"), path);
        let blue = style::PALETTE[0];
        let shown: Vec<(f64, f64)> = pts.iter().map(|(x, d)| (*x, d.min(y_hi))).collect();
        chart.draw_series(LineSeries::new(shown.clone(), blue.stroke_width(1))).map_err(|e| style::draw_err(path, e))?;
        chart.draw_series(shown.iter().map(|p| Circle::new(*p, 2, blue.filled()))).map_err(|e| style::draw_err(path, e))?;
        chart
            .draw_series(LineSeries::new([(lo, threshold), (hi, threshold)], style::PALETTE[2].stroke_width(1)))
            .map_err(|e| style::draw_err(path, e))?;
        let font = (style::FONT, 10).into_font();
        chart
            .draw_series(std::iter::once(Text::new("95 %", (lo, threshold), font.clone().color(&style::PALETTE[2]))))
            .map_err(|e| style::draw_err(path, e))?;
        let (a, b) = r.intervals.get(k).copied().unwrap_or((None, None));
        for (end, side_x) in [(a, lo), (b, hi)] {
            match end {
                Some(x) => chart
                    .draw_series(LineSeries::new([(x, 0.0), (x, threshold)], BLACK.mix(0.6).stroke_width(1)))
                    .map(|_| ()),
                None => chart
                    .draw_series(std::iter::once(
                        EmptyElement::at((side_x, 0.5 * threshold))
                            + Text::new("open", (if side_x == lo { 4 } else { -30 }, 0), font.clone().color(&BLACK.mix(0.7))),
                    ))
                    .map(|_| ()),
            }
            .map_err(|e| style::draw_err(path, e))?;
        }
        chart
            .draw_series(std::iter::once(
                EmptyElement::at((r.values[k], 0.0)) + Polygon::new(vec![(0, -6), (5, 0), (0, 6), (-5, 0)], BLACK.filled()),
            ))
            .map_err(|e| style::draw_err(path, e))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_label_goes_where_it_covers_no_label_placed_before() {
        let at = (100, 100);
        let first = free_label_offset(at, "push_trail pad_x", &[]).expect("nothing placed");
        assert_eq!(first, (6, -LABEL_H - 2), "above right when free");
        let placed = [LabelBox::of(at, first, "push_trail pad_x")];
        // a point 3 px away: above right would overlap the first label, below right does not
        let second = free_label_offset((103, 101), "pull_lead pad_x", &placed).expect("a free place");
        assert!(!LabelBox::of((103, 101), second, "pull_lead pad_x").overlaps(&placed[0]), "{second:?}");
        assert_ne!(second, first);
        // a point surrounded on all four sides gets no label
        let all: Vec<LabelBox> = [(6, -LABEL_H - 2), (6, 4), (-6 - 36, -LABEL_H - 2), (-6 - 36, 4)]
            .into_iter()
            .map(|o| LabelBox::of(at, o, "abcdef"))
            .collect();
        assert_eq!(free_label_offset(at, "abcdef", &all), None);
    }

    #[test]
    fn units_come_from_the_scene_keys_descriptions() {
        assert_eq!(key_unit("k_b"), "N/m");
        assert_eq!(key_unit("mu_k"), "-");
        assert_eq!(key_unit("c_x"), "N s/m");
        assert_eq!(key_unit("no_such_key"), "-");
    }
}
