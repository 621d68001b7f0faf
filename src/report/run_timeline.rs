//! The run's timeline (`audit run RUN --timeline run.svg`, or `--format
//! svg`) as a document: one panel per family, in a grid of two columns.
//!
//! Each panel: the family's smallest eigenvalue over its threshold,
//! `lambda_min / threshold`, against time (s; the scan index when the run
//! has no times), on a logarithmic axis, one line per drawn frame (the scan
//! frame in black, the named body frames in colour); the threshold (1) as a
//! grey line: below it the family declares a direction degenerate. The
//! scan frame's degenerate intervals are shaded; a red triangle at the top
//! marks a bin where a body frame changed the family's decision. Every
//! point is a bin of consecutive scans (the smallest ratio in it), so a run
//! of any length draws the same number of points. Values below
//! [`FLOOR`] are drawn at it.

use super::run::RunReport;
use crate::document::plot::{Axis, Colour, Corner, Mark, Panel, Plot, Point, Series};
use crate::document::{Block, Document};

/// Size (px) of the picture: 2 columns of panels, 230 px per row.
pub const PANEL_PX: (u32, u32) = (700, 230);

/// The lowest ratio drawn (eight decades below the threshold): an exact
/// degeneracy (a corridor's `1e-16`) sits on the floor.
pub const FLOOR: f64 = 1e-8;

const FRAME_COLOURS: [Colour; 6] = [
    Colour::rgb(0, 0, 0),
    Colour::rgb(41, 128, 185),
    Colour::rgb(230, 126, 34),
    Colour::rgb(39, 174, 96),
    Colour::rgb(142, 68, 173),
    Colour::rgb(22, 160, 133),
];
const SHADE: Colour = Colour::rgb(231, 76, 60).alpha(0.18);
const THRESHOLD: Colour = Colour::rgb(120, 120, 120);
const CHANGED: Colour = Colour::rgb(192, 57, 43);

fn series(mark: Mark, colour: Colour, points: Vec<Point>, legend: Option<String>) -> Series {
    Series {
        mark,
        colour,
        points,
        legend,
    }
}

impl RunReport {
    /// The x of each bin (its first scan's), and the x range.
    fn bin_x(&self) -> (Vec<f64>, (f64, f64)) {
        let xs: Vec<f64> = self.timeline.x.iter().map(|b| b.0).collect();
        let lo = self.timeline.x.first().map_or(0.0, |b| b.0);
        let hi = self.timeline.x.last().map_or(1.0, |b| b.1);
        let hi = if hi > lo { hi } else { lo + 1.0 };
        (xs, (lo, hi))
    }

    /// One family's panel.
    fn timeline_panel(&self, k: usize, (lo, hi): (f64, f64), xs: &[f64], top: f64) -> Panel {
        let fam = &self.families[k];
        let mut all = Vec::new();
        // Shaded intervals first, under the lines.
        let mut spans = Vec::new();
        for i in self.shading.get(k).into_iter().flatten() {
            let (a, b) = match (i.start_s, i.end_s) {
                (Some(a), Some(b)) => (a, b),
                _ => (i.start as f64, i.end as f64),
            };
            let pad = (hi - lo) * 2e-3;
            spans.push(Point::at(a - pad, FLOOR));
            spans.push(Point::at(b + pad, top));
        }
        let legend = (!spans.is_empty()).then(|| "degenerate (scan frame)".to_string());
        all.push(series(Mark::Span, SHADE, spans, legend));
        all.push(series(
            Mark::Line { width: 1 },
            THRESHOLD,
            vec![Point::at(lo, 1.0), Point::at(hi, 1.0)],
            None,
        ));
        for (d, &f) in self.drawn.iter().enumerate() {
            let c = FRAME_COLOURS[d % FRAME_COLOURS.len()];
            let values = &self.timeline.margin[d][k];
            // A line per run of bins with values (a gap where none).
            let mut first = true;
            let mut run: Vec<Point> = Vec::new();
            let flush = |run: &mut Vec<Point>, all: &mut Vec<Series>, first: &mut bool| {
                if run.is_empty() {
                    return;
                }
                let legend = first.then(|| self.frames[f].name.clone());
                *first = false;
                all.push(series(
                    Mark::Line {
                        width: if d == 0 { 2 } else { 1 },
                    },
                    c,
                    std::mem::take(run),
                    legend,
                ));
            };
            for (x, v) in xs.iter().zip(values) {
                if v.is_finite() {
                    run.push(Point::at(*x, v.max(FLOOR)));
                } else {
                    flush(&mut run, &mut all, &mut first);
                }
            }
            flush(&mut run, &mut all, &mut first);
        }
        let marks: Vec<Point> = xs
            .iter()
            .zip(&self.timeline.changed[k])
            .filter(|(_, &c)| c)
            .map(|(x, _)| Point::at(*x, top / 1.6))
            .collect();
        let legend = (!marks.is_empty()).then(|| "a body frame changes the decision".to_string());
        all.push(series(Mark::Triangle { size: 5 }, CHANGED, marks, legend));
        let x_label = if self.span_s.is_some() {
            "time (s)"
        } else {
            "scan index"
        };
        Panel {
            caption: fam_caption(&fam.key),
            x: Axis {
                label: x_label.into(),
                range: (lo, hi),
                log: false,
            },
            y: Axis {
                label: "lambda_min / threshold".into(),
                range: (FLOOR, top),
                log: true,
            },
            series: all,
            legend: Corner::Outside,
        }
    }

    /// The timeline: a document of one plot block (drawn as SVG).
    pub fn timeline_plot(&self) -> Document {
        let (xs, range) = self.bin_x();
        let max = self
            .timeline
            .margin
            .iter()
            .flatten()
            .flatten()
            .copied()
            .filter(|v| v.is_finite())
            .fold(1.0f64, f64::max);
        // Room above the lines for the markers (the legend is outside).
        let top = 10f64.powf((max * 30.0).log10().ceil());
        let n = self.families.len();
        let panels = (0..n)
            .map(|k| self.timeline_panel(k, range, &xs, top))
            .collect();
        let rows = n.div_ceil(2).max(1) as u32;
        let mut doc = Document::new();
        doc.push(Block::Plot(Plot {
            size_px: (PANEL_PX.0 * 2, PANEL_PX.1 * rows),
            panels,
            rows,
        }));
        doc
    }
}

/// `point displacement`, `characteristic length l=0.25`.
fn fam_caption(key: &str) -> String {
    if let Some(l) = key.strip_prefix("l=") {
        format!("characteristic length l={l} m")
    } else {
        key.replace('_', " ").replace("jacobi", "Jacobi")
    }
}
