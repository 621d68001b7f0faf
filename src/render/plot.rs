//! The survey plot (`audit survey PATHS --plot survey.svg`), drawn with
//! `plotters` (SVG backend, no fonts: text is left to the viewer).
//!
//! Left: each rig's lever arm `||d||` (m) against its screw translation `|h|`
//! (m), zero-pitch rigs (an adapted constant metric exists) in green, general
//! screws in blue, rigs without a rotation (no screw axis, `h` undefined,
//! drawn at `|h| = 0`) as orange triangles; every point is labelled with its
//! rig id. Right: each rig's certificate band `[s_min^2, s_max^2]` at
//! `delta = ||d|| / l` against the characteristic length `l` (both axes
//! logarithmic), the rig with the largest lever arm in red.

use crate::diagnostic::{Code, Error, Result};
use crate::geometry::certificate::band;
use crate::report::survey::SurveyRigJson;
use crate::report::SurveyReport;
use crate::sanitize;
use crate::tolerances::{PLOT_ELL_RANGE_M, PLOT_SIZE_PX};
use plotters::prelude::*;

const ZERO_PITCH: RGBColor = RGBColor(39, 174, 96);
const GENERAL: RGBColor = RGBColor(41, 128, 185);
const NO_ROTATION: RGBColor = RGBColor(230, 126, 34);
const LARGEST: RGBColor = RGBColor(192, 57, 43);
/// Points along each band curve.
const CURVE_POINTS: usize = 120;

fn plot_err(e: impl std::fmt::Display) -> Error {
    Error::new(Code::Io, format!("cannot draw the survey plot: {e}"))
}

/// `|h|` as plotted: 0 for a rig without a rotation.
fn abs_h(r: &SurveyRigJson) -> f64 {
    r.screw_translation_m.map_or(0.0, f64::abs)
}

fn colour(r: &SurveyRigJson) -> RGBColor {
    match (r.zero_pitch, r.screw_translation_m) {
        (true, _) => ZERO_PITCH,
        (false, None) => NO_ROTATION,
        (false, Some(_)) => GENERAL,
    }
}

/// A round upper bound for an axis holding values up to `max`.
fn axis_top(max: f64) -> f64 {
    if !(max.is_finite() && max > 0.0) {
        return 1.0;
    }
    let step = 10f64.powf(max.log10().floor()) / 2.0;
    ((max * 1.1) / step).ceil() * step
}

fn scatter(
    area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
    rigs: &[SurveyRigJson],
) -> Result<()> {
    let xmax = axis_top(rigs.iter().map(|r| r.lever_arm_m).fold(0.0, f64::max));
    let ymax = axis_top(rigs.iter().map(abs_h).fold(0.0, f64::max));
    let mut chart = ChartBuilder::on(area)
        .caption("lever arm against screw translation", ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..xmax, 0.0..ymax)
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc("lever arm ||d|| (m)")
        .y_desc("|h| = |e . d| (m)")
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(plot_err)?;
    for (label, c) in [
        ("zero pitch (ringed): adapted metric M0 exists", ZERO_PITCH),
        ("general screw: no constant metric", GENERAL),
        ("no rotation (h undefined)", NO_ROTATION),
    ] {
        let n = rigs.iter().filter(|r| colour(r) == c).count();
        chart
            .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
            .map_err(plot_err)?
            .label(format!("{label} ({n})"))
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, c.filled()));
    }
    let grey = RGBColor(80, 80, 80);
    chart
        .draw_series(rigs.iter().map(|r| {
            let id = sanitize::visible(&r.id, false).into_owned();
            let font = ("sans-serif", 9).into_font().color(&grey);
            EmptyElement::at((r.lever_arm_m, abs_h(r))) + Text::new(id, (6, -4), font)
        }))
        .map_err(plot_err)?;
    let (no_rot, screws): (Vec<&SurveyRigJson>, Vec<&SurveyRigJson>) =
        rigs.iter().partition(|r| colour(r) == NO_ROTATION);
    chart
        .draw_series(
            screws
                .iter()
                .map(|r| Circle::new((r.lever_arm_m, abs_h(r)), 4, colour(r).filled())),
        )
        .map_err(plot_err)?;
    chart
        .draw_series(
            no_rot
                .iter()
                .map(|r| TriangleMarker::new((r.lever_arm_m, 0.0), 5, NO_ROTATION.filled())),
        )
        .map_err(plot_err)?;
    // Zero-pitch rigs last, ringed, so that no other marker hides them.
    chart
        .draw_series(
            rigs.iter()
                .filter(|r| r.zero_pitch)
                .map(|r| Circle::new((r.lever_arm_m, abs_h(r)), 7, BLACK.stroke_width(2))),
        )
        .map_err(plot_err)?;
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .draw()
        .map_err(plot_err)?;
    Ok(())
}

/// `(l, band)` along a log-spaced `l` for one lever arm.
fn band_curve(lever: f64) -> Vec<(f64, [f64; 2])> {
    let (lo, hi) = PLOT_ELL_RANGE_M;
    (0..CURVE_POINTS)
        .map(|i| {
            let t = i as f64 / (CURVE_POINTS - 1) as f64;
            let ell = lo * (hi / lo).powf(t);
            (ell, band(lever / ell))
        })
        .collect()
}

fn bands(
    area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
    rigs: &[SurveyRigJson],
) -> Result<()> {
    let (lo, hi) = PLOT_ELL_RANGE_M;
    let largest = rigs
        .iter()
        .max_by(|a, b| a.lever_arm_m.total_cmp(&b.lever_arm_m));
    let top = largest
        .map_or(2.0, |r| band(r.lever_arm_m / lo)[1])
        .max(2.0);
    let mut chart = ChartBuilder::on(area)
        .caption(
            "certificate band against characteristic length",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d((lo..hi).log_scale(), (1.0 / top..top).log_scale())
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc("characteristic length l (m)")
        .y_desc("eigenvalue factor [s_min^2, s_max^2]")
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(plot_err)?;
    // Zero-pitch rigs drawn last, over the others.
    let mut order: Vec<&SurveyRigJson> = rigs.iter().collect();
    order.sort_by_key(|r| r.zero_pitch);
    for r in order {
        let c = colour(r).mix(if r.zero_pitch { 0.9 } else { 0.35 });
        let curve = band_curve(r.lever_arm_m);
        for k in 0..2 {
            chart
                .draw_series(LineSeries::new(
                    curve.iter().map(|(l, b)| (*l, b[k])),
                    c.stroke_width(1),
                ))
                .map_err(plot_err)?;
        }
    }
    if let Some(r) = largest {
        let curve = band_curve(r.lever_arm_m);
        for k in 0..2 {
            let s = chart
                .draw_series(LineSeries::new(
                    curve.iter().map(|(l, b)| (*l, b[k])),
                    LARGEST.stroke_width(2),
                ))
                .map_err(plot_err)?;
            if k == 0 {
                let id = sanitize::visible(&r.id, false).into_owned();
                s.label(format!("largest lever arm: {id} ({:.3} m)", r.lever_arm_m))
                    .legend(|(x, y)| {
                        PathElement::new(vec![(x, y), (x + 16, y)], LARGEST.stroke_width(2))
                    });
            }
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .draw()
        .map_err(plot_err)?;
    Ok(())
}

/// The survey plot as an SVG document.
pub fn survey_svg(rep: &SurveyReport) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, PLOT_SIZE_PX).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (left, right) = root.split_horizontally(PLOT_SIZE_PX.0 / 2);
        scatter(&left, &rep.rigs)?;
        bands(&right, &rep.rigs)?;
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}
