//! One figure style for every SVG the tool writes (`cases --plots`, `analyze --plots`, `sil
//! --plots`, `accuracy` and `stability --plot`, `map --plot`, `fit --plot`): the font, the
//! palette, the legend box, the time-series chart, and the error a figure that cannot be written
//! becomes. The rules every figure follows:
//! - **ticks at round values**: steps of 1, 2 or 5 x 10^k on a linear axis ([`ticks_linear`]),
//!   1, 2, 5 in each decade on a log axis ([`ticks_log`]), never at cell centres or data values;
//! - **labels as short as the step needs**: [`tick_label`] (as many decimals as the span or
//!   step needs, no trailing zeros, no "-0");
//! - **a unit on every axis**: `name [unit]`, [`axis_label`] (`[-]` for a ratio);
//! - **no overlapping labels**: at most [`MAX_TICKS`] ticks an axis, legends in a box, with
//!   room kept for them above the data of a line chart ([`LEGEND_ROOM`]).

use std::ops::Range;
use std::path::Path;

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::HostError;

/// The font family of every caption, label and legend.
pub const FONT: &str = "sans-serif";

/// Series colours (Okabe and Ito's colour-blind-safe set): blue, black, vermillion, green.
pub const PALETTE: [RGBColor; 4] = [RGBColor(0, 114, 178), RGBColor(0, 0, 0), RGBColor(213, 94, 0), RGBColor(0, 158, 115)];

/// Most ticks an axis carries: few enough that their labels never overlap.
pub const MAX_TICKS: usize = 8;

/// An axis description with its unit: `name [unit]` (`v [m/s]`).
pub fn axis_label(name: &str, unit: &str) -> String {
    format!("{name} [{unit}]")
}

/// Round ticks over [lo, hi] on a linear axis: the multiples of the smallest step of 1, 2 or 5
/// x 10^k that gives at most `max` of them (at least the two ends' neighbours in a span of
/// zero: a step of 1 x 10^k about the value).
pub fn ticks_linear(lo: f64, hi: f64, max: usize) -> Vec<f64> {
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (hi, lo) };
    if !(lo.is_finite() && hi.is_finite()) || max == 0 {
        return Vec::new();
    }
    let span = if hi > lo { hi - lo } else { lo.abs().max(1e-300) };
    let mut k = (span / max as f64).log10().floor() as i32;
    loop {
        for m in [1.0, 2.0, 5.0] {
            let step = m * 10f64.powi(k);
            let (a, b) = ((lo / step - 1e-9).ceil() as i64, (hi / step + 1e-9).floor() as i64);
            if b - a < max as i64 {
                return (a..=b).map(|i| round_to_step(i as f64 * step, step)).collect();
            }
        }
        k += 1;
    }
}

/// `x` rounded to the decimals of `step` (0.30000000000000004 becomes 0.3).
fn round_to_step(x: f64, step: f64) -> f64 {
    let d = (-step.log10().floor()).max(0.0) as i32 + 1;
    let f = 10f64.powi(d.min(300));
    (x * f).round() / f
}

/// Round ticks over [lo, hi] (lo > 0) on a log axis: 1, 2 and 5 x 10^k.
pub fn ticks_log(lo: f64, hi: f64) -> Vec<f64> {
    let mut v = Vec::new();
    let mut d = lo.log10().floor() as i32;
    while 10f64.powi(d) <= hi * 1.000001 {
        for m in [1.0, 2.0, 5.0] {
            let x = m * 10f64.powi(d);
            if x >= lo * 0.999999 && x <= hi * 1.000001 {
                v.push(x);
            }
        }
        d += 1;
    }
    v
}

/// A round tick's label: the shortest decimal (to 6 places), or 2e-4 style outside 1e-3 ..
/// 1e5.
pub fn tick_label(x: f64) -> String {
    if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e5) {
        let e = x.abs().log10().floor() as i32;
        let m = x / 10f64.powi(e);
        let m = format!("{:.3}", m);
        let m = m.trim_end_matches('0').trim_end_matches('.');
        return format!("{m}e{e}");
    }
    let s = format!("{x:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.to_string() }
}

/// A linear f64 axis over `range` whose ticks are `ticks` (round values: [`ticks_linear`], or
/// a swept key's values placed on a cell axis), for axes whose coordinates are not the values
/// their labels show.
#[derive(Clone, Debug)]
pub struct TickedAxis {
    pub range: Range<f64>,
    pub ticks: Vec<f64>,
}

impl Ranged for TickedAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        RangedCoordf64::from(self.range.clone()).map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, _hint: Hint) -> Vec<f64> {
        self.ticks.clone()
    }

    fn range(&self) -> Range<f64> {
        self.range.clone()
    }
}

/// A figure that could not be written, as the tool's output error (exit code 1).
pub fn draw_err(path: &Path, e: impl std::fmt::Display) -> HostError {
    HostError::Output(format!("{}: cannot write the figure: {e}", path.display()))
}

/// Room above the data for a legend in the upper corner of a line chart, as a fraction of the
/// data's span: the legend covers no line.
pub const LEGEND_ROOM: f64 = 0.3;

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
pub type TimeChart<'a, DB> = ChartContext<'a, DB, Cartesian2d<TickedAxis, TickedAxis>>;

/// A time-series chart on `root`: `caption` at `caption_size`, time `t` [s] along x, `y` along
/// y described by `y_desc` (with its unit), round ticks ([`ticks_linear`]: up to 11 along the
/// wide time axis) labelled by [`tick_label`], no minor grid.
pub fn time_chart<'a, DB: DrawingBackend + 'a>(
    root: &'a DrawingArea<DB, Shift>,
    caption: String,
    caption_size: u32,
    t: Range<f64>,
    y: Range<f64>,
    y_desc: &str,
) -> Result<TimeChart<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    let (xt, yt) = (ticks_linear(t.start, t.end, MAX_TICKS + 3), ticks_linear(y.start, y.end, MAX_TICKS));
    let mut chart = ChartBuilder::on(root)
        .caption(caption, (FONT, caption_size))
        .margin(18)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(TickedAxis { range: t, ticks: xt }, TickedAxis { range: y, ticks: yt })?;
    chart
        .configure_mesh()
        .x_desc("time t [s]")
        .y_desc(y_desc)
        .x_label_formatter(&|v| tick_label(*v))
        .y_label_formatter(&|v| tick_label(*v))
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .light_line_style(WHITE.mix(0.0))
        .draw()?;
    Ok(chart)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_ticks_are_round_and_few() {
        assert_eq!(ticks_linear(0.0175, 0.0625, 6), vec![0.02, 0.03, 0.04, 0.05, 0.06]);
        assert_eq!(ticks_linear(0.0, 1.0, 8), vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0]);
        assert_eq!(ticks_linear(-3.2, 41.0, 8), vec![0.0, 10.0, 20.0, 30.0, 40.0]);
        assert!(ticks_linear(0.005337, 0.005337, 8).len() <= 8);
    }

    #[test]
    fn labels_are_short() {
        assert_eq!(tick_label(0.3), "0.3");
        assert_eq!(tick_label(0.05), "0.05");
        assert_eq!(tick_label(-0.0), "0");
        assert_eq!(tick_label(2e-4), "2e-4");
        assert_eq!(tick_label(2.5e-5), "2.5e-5");
        assert_eq!(tick_label(1e6), "1e6");
        assert_eq!(axis_label("v", "m/s"), "v [m/s]");
    }
}
