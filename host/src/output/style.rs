//! One figure style for every SVG the tool writes (`cases --plots`, `analyze --plots`, `accuracy`
//! and `stability --plot`, `map --plot`, `fit --plot`): the font, the palette, the legend box,
//! axis labels with as many decimals as their span needs, the time-series chart, and the error
//! a figure that cannot be written becomes.

use std::ops::Range;
use std::path::Path;

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::HostError;

/// The font family of every caption, label and legend.
pub const FONT: &str = "sans-serif";

/// Series colours (Okabe and Ito's colour-blind-safe set): blue, black, vermillion, green.
pub const PALETTE: [RGBColor; 4] = [RGBColor(0, 114, 178), RGBColor(0, 0, 0), RGBColor(213, 94, 0), RGBColor(0, 158, 115)];

/// Decimal places for axis labels spanning `range`.
pub fn decimals(range: f64) -> usize {
    if range.is_nan() || range <= 0.0 {
        return 3;
    }
    (2.0 - range.log10().floor()).clamp(0.0, 9.0) as usize
}

/// An axis label with `d` decimals, without a "-0.000".
pub fn tick(v: f64, d: usize) -> String {
    let s = format!("{v:.d$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// A figure that could not be written, as the tool's output error (exit code 1).
pub fn draw_err(path: &Path, e: impl std::fmt::Display) -> HostError {
    HostError::Output(format!("{}: cannot write the figure: {e}", path.display()))
}

/// Width of a legend entry's line sample [px] (plotters' default).
pub const LEGEND_LINE: u32 = 30;

/// The series labels in a white box with a black border, at `position`, in `font_size`, with
/// line samples `line` pixels wide.
pub fn legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
    font_size: u32,
    line: u32,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    chart
        .configure_series_labels()
        .position(position)
        .legend_area_size(line)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, font_size))
        .draw()
}

/// A chart of quantities against time.
pub type TimeChart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A time-series chart on `root`: `caption` at `caption_size`, time `t` [s] along x, `y` along
/// y described by `y_desc`, labels with the decimals their spans need, no minor grid.
pub fn time_chart<'a, DB: DrawingBackend + 'a>(
    root: &'a DrawingArea<DB, Shift>,
    caption: String,
    caption_size: u32,
    t: Range<f64>,
    y: Range<f64>,
    y_desc: &str,
) -> Result<TimeChart<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    let (xd, yd) = (decimals(t.end - t.start), decimals(y.end - y.start));
    let mut chart = ChartBuilder::on(root)
        .caption(caption, (FONT, caption_size))
        .margin(18)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(t, y)?;
    chart
        .configure_mesh()
        .x_desc("time t [s]")
        .y_desc(y_desc)
        .x_label_formatter(&|v| tick(*v, xd))
        .y_label_formatter(&|v| tick(*v, yd))
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .light_line_style(WHITE.mix(0.0))
        .draw()?;
    Ok(chart)
}
