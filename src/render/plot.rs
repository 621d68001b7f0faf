//! A [`Plot`] as SVG, drawn with `plotters` (SVG backend, no fonts: text is
//! left to the viewer): the panels in their grid, each with its caption, axis
//! titles and mesh, its series in order, then its legend box. Text from the
//! document (point labels, legend entries) is shown with control and
//! bidirectional characters as visible escapes; plotters escapes it for XML.

use crate::diagnostic::{Code, Error, Result};
use crate::document::plot::{Axis, Colour, Corner, Mark, Panel, Plot, Point, Series};
use crate::render::labels;
use crate::sanitize;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::element::DynElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// The drawing area of one panel, and its chart.
type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;
type Chart<'a, 'b, X, Y> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, Y>>;

/// Width (px) kept right of a panel's plot area for a [`Corner::Outside`]
/// legend: 34 characters of the legend font (plotters draws 12 px as 9.7).
const OUTSIDE_LEGEND_PX: u32 = 230;

fn plot_err(e: impl std::fmt::Display) -> Error {
    Error::new(Code::Io, format!("cannot draw the plot: {e}"))
}

fn rgba(c: Colour) -> RGBAColor {
    RGBAColor(c.rgb.0, c.rgb.1, c.rgb.2, c.alpha)
}

fn shown(s: &str) -> String {
    sanitize::visible(s, false).into_owned()
}

/// The plot as an SVG document.
pub fn svg(p: &Plot) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, p.size_px).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let rows = (p.rows.max(1) as usize).min(p.panels.len().max(1));
        let areas = root.split_evenly((rows, p.panels.len().max(1).div_ceil(rows)));
        for (area, panel) in areas.iter().zip(&p.panels) {
            let (x, y) = (panel.x.range, panel.y.range);
            match (panel.x.log, panel.y.log) {
                (false, false) => draw(area, panel, x.0..x.1, y.0..y.1),
                (true, true) => draw(area, panel, (x.0..x.1).log_scale(), (y.0..y.1).log_scale()),
                (true, false) => draw(area, panel, (x.0..x.1).log_scale(), y.0..y.1),
                (false, true) => draw(area, panel, x.0..x.1, (y.0..y.1).log_scale()),
            }?;
        }
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}

/// One panel on its area, in the coordinates `x` and `y`.
fn draw<X, Y>(area: &Area, p: &Panel, x: X, y: Y) -> Result<()>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let right = match p.legend {
        Corner::Outside => 12 + OUTSIDE_LEGEND_PX,
        _ => 12,
    };
    let mut chart = ChartBuilder::on(area)
        .caption(shown(&p.caption), ("sans-serif", 18))
        .margin(12)
        .margin_right(right)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(x, y)
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc(shown(&p.x.label))
        .y_desc(shown(&p.y.label))
        .x_label_formatter(&|v| tick(on_step(*v, &p.x)))
        .y_label_formatter(&|v| tick(on_step(*v, &p.y)))
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(plot_err)?;
    for s in &p.series {
        series(&mut chart, s)?;
    }
    let corner = match p.legend {
        Corner::UpperLeft => SeriesLabelPosition::UpperLeft,
        Corner::UpperRight => SeriesLabelPosition::UpperRight,
        Corner::Outside => return outside_legend(area, &chart, &p.series),
    };
    chart
        .configure_series_labels()
        .position(corner)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .draw()
        .map_err(plot_err)?;
    Ok(())
}

/// A linear axis's tick value rounded to a millionth of the axis span, far
/// below its tick step (a tenth of the span or so): plotters accumulates the
/// ticks in floating point, so the tick at zero arrives as `-6.94e-18`. Log
/// axes are left alone (their ticks are powers of ten).
fn on_step(v: f64, axis: &Axis) -> f64 {
    let span = (axis.range.1 - axis.range.0).abs();
    if axis.log || !(span.is_finite() && span > 0.0) || !v.is_finite() {
        return v;
    }
    let q = 10f64.powf((span.log10() - 6.0).floor());
    // `+ 0.0` turns `-0.0` into `0`.
    (v / q).round() * q + 0.0
}

/// A tick label with at most three significant digits: plain between 1e-3
/// and 1e4, else `1.5e-5` (plotters' own labels on a log axis print the
/// tick's binary value, `9.99999999e-5`).
fn tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || !a.is_finite() {
        return format!("{v}");
    }
    let trim = |s: String| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if (1e-3..1e4).contains(&a) {
        let decimals = (2 - a.log10().floor() as i32).max(0) as usize;
        trim(format!("{v:.decimals$}"))
    } else {
        let s = format!("{v:.2e}");
        match s.split_once('e') {
            Some((m, e)) => format!("{}e{e}", trim(m.to_string())),
            None => s,
        }
    }
}

/// One series, with its legend entry (its mark, or a short line) when it
/// has one.
fn series<'a, 'b: 'a, X, Y>(chart: &mut Chart<'a, 'b, X, Y>, s: &Series) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let c = rgba(s.colour);
    let of = |p: &Point| p.colour.map_or(c, rgba);
    let at = |p: &Point| (p.x, p.y);
    let anno = match s.mark {
        Mark::Dot { radius } => {
            let r = radius as i32;
            let dot = |p: &Point| Circle::new(at(p), r, of(p).filled());
            chart.draw_series(s.points.iter().map(dot))
        }
        Mark::Ring { radius, width } => {
            let r = radius as i32;
            let ring = |p: &Point| Circle::new(at(p), r, of(p).stroke_width(width));
            chart.draw_series(s.points.iter().map(ring))
        }
        Mark::Triangle { size } => {
            let z = size as i32;
            let tri = |p: &Point| TriangleMarker::new(at(p), z, of(p).filled());
            chart.draw_series(s.points.iter().map(tri))
        }
        Mark::Label { size, offset } => {
            // Placed so that no label covers another (render::labels); a
            // label moved off its mark's offset gets a thin leader to its point.
            let texts: Vec<String> = s.points.iter().map(|p| shown(&p.label)).collect();
            let boxes: Vec<((i32, i32), i32)> = s
                .points
                .iter()
                .zip(&texts)
                .map(|(p, t)| (chart.backend_coord(&at(p)), labels::width(t, size)))
                .collect();
            let h = labels::height(size);
            let (xs, ys) = chart.plotting_area().get_pixel_range();
            let area = [xs.start, ys.start, xs.end, ys.end];
            let offsets = labels::place(&boxes, h, offset, area);
            let moved = s.points.iter().zip(&offsets).filter(|(_, &o)| o != offset);
            let leader = |(p, &(ox, oy)): (&Point, &(i32, i32))| {
                let line = vec![(0, 0), (ox, oy + h / 2)];
                EmptyElement::at(at(p)) + PathElement::new(line, of(p).mix(0.4).stroke_width(1))
            };
            chart.draw_series(moved.map(leader)).map_err(plot_err)?;
            let text = |((p, t), &o): ((&Point, &String), &(i32, i32))| {
                let font = ("sans-serif", size).into_font().color(&of(p));
                EmptyElement::at(at(p)) + Text::new(t.clone(), o, font)
            };
            chart.draw_series(s.points.iter().zip(&texts).zip(&offsets).map(text))
        }
        Mark::Span => {
            let rect = |c: &[Point]| Rectangle::new([at(&c[0]), at(&c[1])], of(&c[0]).filled());
            chart.draw_series(s.points.chunks_exact(2).map(rect))
        }
        Mark::Line { width } => chart.draw_series(LineSeries::new(
            s.points.iter().map(at),
            c.stroke_width(width),
        )),
    }
    .map_err(plot_err)?;
    // plotters lists every series with an icon, labelled or not: only the
    // labelled ones get an entry.
    if let Some(l) = s.legend.as_deref() {
        let mark = s.mark;
        anno.label(shown(l)).legend(move |at| icon(mark, c, at));
    }
    Ok(())
}

/// A legend entry's icon for `mark` in `c`, its left end at `(x, y)`: the
/// mark itself, or a short line.
fn icon<'a, 'b>(
    mark: Mark,
    c: RGBAColor,
    (x, y): (i32, i32),
) -> DynElement<'a, SVGBackend<'b>, (i32, i32)> {
    match mark {
        Mark::Dot { radius } => Circle::new((x + 8, y), radius as i32, c.filled()).into_dyn(),
        Mark::Ring { radius, width } => {
            Circle::new((x + 8, y), radius as i32, c.stroke_width(width)).into_dyn()
        }
        Mark::Triangle { size } => {
            TriangleMarker::new((x + 8, y), size as i32, c.filled()).into_dyn()
        }
        Mark::Label { .. } => Circle::new((x + 8, y), 2, c.filled()).into_dyn(),
        Mark::Span => Rectangle::new([(x, y - 5), (x + 16, y + 5)], c.filled()).into_dyn(),
        Mark::Line { width } => {
            PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(width)).into_dyn()
        }
    }
}

/// Height (px) of one legend entry.
const LEGEND_LINE_PX: i32 = 16;

/// The legend of a [`Corner::Outside`] panel, drawn here rather than by
/// plotters (whose box takes its width from text it cannot measure without
/// fonts): a box [`OUTSIDE_LEGEND_PX`] - 10 wide right of the plot area,
/// from its top, one entry per labelled series.
fn outside_legend<X, Y>(area: &Area, chart: &Chart<X, Y>, series: &[Series]) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let entries: Vec<(&Series, &str)> = series
        .iter()
        .filter_map(|s| s.legend.as_deref().map(|l| (s, l)))
        .collect();
    if entries.is_empty() {
        return Ok(());
    }
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let base = area.get_base_pixel();
    let (x0, y0) = (xr.end - base.0 + 10, yr.start - base.1);
    let h = LEGEND_LINE_PX * entries.len() as i32 + 8;
    let w = OUTSIDE_LEGEND_PX as i32 - 10;
    let corners = [(x0, y0), (x0 + w, y0 + h)];
    area.draw(&Rectangle::new(corners, WHITE.filled()))
        .and_then(|_| area.draw(&Rectangle::new(corners, BLACK.mix(0.3))))
        .map_err(plot_err)?;
    let font =
        TextStyle::from(("sans-serif", 12).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
    for (i, (s, l)) in entries.iter().enumerate() {
        let y = y0 + 4 + LEGEND_LINE_PX * i as i32 + LEGEND_LINE_PX / 2;
        area.draw(&icon(s.mark, rgba(s.colour), (x0 + 6, y)))
            .and_then(|_| area.draw(&Text::new(shown(l), (x0 + 28, y), font.clone())))
            .map_err(plot_err)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn ticks_have_three_significant_digits_at_most() {
        let cases = [
            (9.99999999e-5, "1e-4"),
            (1.5e-5, "1.5e-5"),
            (0.001, "0.001"),
            (0.25, "0.25"),
            (1.0, "1"),
            (12.5, "12.5"),
            (2500.0, "2500"),
            (1e6, "1e6"),
            (-0.5, "-0.5"),
            (0.0, "0"),
        ];
        for (v, want) in cases {
            assert_eq!(super::tick(v), want, "{v}");
        }
    }

    #[test]
    fn a_tick_at_zero_is_zero_on_a_linear_axis() {
        let mut axis = super::Axis {
            label: String::new(),
            range: (-0.15, 0.1),
            log: false,
        };
        // A tick at zero reached by steps of 0.05 from -0.15, in floating point.
        let zero: f64 = -0.15 + 0.05 + 0.05 + 0.05;
        assert!(zero != 0.0 && zero.abs() < 1e-16, "{zero:e}");
        let label = |v: f64, a: &super::Axis| super::tick(super::on_step(v, a));
        assert_eq!(label(zero, &axis), "0");
        assert_eq!(label(-6.938893903907228e-18, &axis), "0");
        for (v, want) in [(0.05, "0.05"), (-0.1, "-0.1"), (0.025, "0.025")] {
            assert_eq!(label(v, &axis), want);
        }
        // A log axis keeps its values (1e-5 is a tick there, not a zero).
        axis.log = true;
        axis.range = (1e-6, 1.0);
        assert_eq!(label(1e-5, &axis), "1e-5");
    }
}
