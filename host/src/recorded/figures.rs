//! The figures of `analyze --plots` and `sil --plots` (SVG): each channel against time, like
//! the thesis's Fig. 3.2 to 3.5 (acceleration [m/s^2] against time [s]), drawn from the
//! bounded min/max envelope (every peak visible), and the four Welch spectra on one log axis
//! with the groan band shaded.

use crate::output::style::{self, draw_err};
use std::path::{Path, PathBuf};

use plotters::prelude::*;
use stickslip_model::rig::bandpass::GROAN_BAND_HZ;
use stickslip_model::rig::ACCEL_NAMES;

use super::analysis::Analysis;
use crate::error::{HostError, Result};

/// What each accelerometer measures (the thesis's section 3.4).
pub const CHANNEL_TITLES: [&str; 4] = [
    "friction band (disc) acceleration along x",
    "pad acceleration along x",
    "pad acceleration in y near the trailing edge",
    "pad acceleration in y near the leading edge",
];

/// Highest frequency drawn in the spectra figure [Hz] (or fs / 2 if lower).
pub const SPECTRUM_MAX_HZ: f64 = 2000.0;

const COLORS: [RGBColor; 4] = style::PALETTE;

/// Writes `{disc_x,pad_x,pad_trail,pad_lead}.svg` and `spectra.svg` into `dir` (created if
/// missing); `what` names the record in the captions. Returns the paths.
pub fn write_all(dir: &Path, what: &str, a: &Analysis) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)
        .map_err(|e| HostError::Output(format!("{}: cannot create the figure directory: {e}", dir.display())))?;
    let mut out = Vec::new();
    for c in 0..4 {
        let path = dir.join(format!("{}.svg", ACCEL_NAMES[c]));
        channel(&path, what, a, c).map_err(|e| draw_err(&path, e))?;
        out.push(path);
    }
    if a.spectrum.is_some() {
        let path = dir.join("spectra.svg");
        spectra(&path, what, a).map_err(|e| draw_err(&path, e))?;
        out.push(path);
    }
    Ok(out)
}

type DrawResult = std::result::Result<(), Box<dyn std::error::Error>>;

/// The series labels, upper right, as every figure here has them.
fn legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
) -> std::result::Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    style::legend(chart, SeriesLabelPosition::UpperRight, 15, style::LEGEND_LINE)
}

fn channel(path: &Path, what: &str, a: &Analysis, c: usize) -> DrawResult {
    let env = &a.envelope;
    let st = &a.channels[c];
    let (mut lo, mut hi) = (st.min, st.max);
    if !(hi > lo) {
        lo -= 1.0;
        hi += 1.0;
    }
    let span = hi - lo;
    let (y0, y1) = (lo - 0.08 * span, hi + 0.25 * span); // room for the legend
    let (t0, mut t1) = (a.t_first, a.t_last);
    if !(t1 > t0) {
        t1 = t0 + 1.0 / a.sample_rate_hz;
    }
    let root = SVGBackend::new(path, (1000, 520)).into_drawing_area();
    root.fill(&WHITE)?;
    let caption = format!("{}: {} ({what})", ACCEL_NAMES[c], CHANNEL_TITLES[c]);
    let y_desc = format!("{} [m/s^2]", ACCEL_NAMES[c]);
    let mut chart = style::time_chart(&root, caption, 20, t0..t1, y0..y1, &y_desc)?;
    // one point per sample while the buckets hold one; else each bucket's min and max
    let pts: Vec<(f64, f64)> = env
        .iter()
        .flat_map(|b| {
            let tm = 0.5 * (b.t0 + b.t1);
            if b.t0 == b.t1 {
                vec![(b.t0, b.min[c])]
            } else {
                vec![(tm, b.min[c]), (tm, b.max[c])]
            }
        })
        .collect();
    chart
        .draw_series(LineSeries::new(pts, ShapeStyle::from(&COLORS[1]).stroke_width(1)))?
        .label(format!("peak-to-peak {:.4} m/s^2", st.pp))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 30, y)], ShapeStyle::from(&COLORS[1]).stroke_width(2)));
    legend(&mut chart)?;
    root.present()?;
    Ok(())
}

fn spectra(path: &Path, what: &str, a: &Analysis) -> DrawResult {
    let s = a.spectrum.as_ref().expect("checked by the caller");
    let fmax = SPECTRUM_MAX_HZ.min(a.sample_rate_hz / 2.0);
    let kmax = ((fmax / s.resolution_hz).floor() as usize).min(s.segment / 2);
    let mut top = 0.0f64;
    for p in &s.psd {
        for &v in p.iter().take(kmax + 1).skip(1) {
            top = top.max(v);
        }
    }
    if !(top.is_finite() && top > 1e-290) {
        top = 1.0; // a silent record: any scale
    }
    let floor = top * 1e-10;
    let root = SVGBackend::new(path, (1000, 620)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "Power spectral density ({what}): Welch, Hann, {} samples x {} segment{}, {:.4} Hz bins",
                s.segment,
                s.segments,
                if s.segments == 1 { "" } else { "s" },
                s.resolution_hz
            ),
            (style::FONT, 18),
        )
        .margin(18)
        .x_label_area_size(50)
        .y_label_area_size(90)
        .build_cartesian_2d(0.0..fmax, (floor..top * 10.0).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("frequency [Hz]")
        .y_desc("PSD [(m/s^2)^2/Hz]")
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style((style::FONT, 15))
        .axis_desc_style((style::FONT, 17))
        .light_line_style(WHITE.mix(0.0))
        .draw()?;
    let (g0, g1) = GROAN_BAND_HZ;
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [(g0.min(fmax), floor), (g1.min(fmax), top * 10.0)],
            RGBColor(255, 220, 120).mix(0.35).filled(),
        )))?
        .label(format!("groan band {g0} to {g1} Hz"))
        .legend(|(x, y)| Rectangle::new([(x, y - 6), (x + 30, y + 6)], RGBColor(255, 220, 120).mix(0.6).filled()));
    for (c, p) in s.psd.iter().enumerate() {
        let pts = (1..=kmax).map(|k| (s.freq(k), p[k].max(floor)));
        let color = COLORS[c];
        let peak = a.channels[c].peak_hz.map_or("none".to_string(), |f| format!("{f:.1} Hz"));
        chart
            .draw_series(LineSeries::new(pts, ShapeStyle::from(&color).stroke_width(1)))?
            .label(format!("{} (peak {peak})", ACCEL_NAMES[c]))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 30, y)], ShapeStyle::from(&color).stroke_width(2)));
    }
    legend(&mut chart)?;
    root.present()?;
    Ok(())
}
