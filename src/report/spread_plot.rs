//! The spread plot (`audit spread PATHS --plot spread.svg`) as a document:
//! one [`Plot`] block of six strip plots, the deviation of each calibration
//! from the mean per axis (rotation in deg, translation in mm, from-frame
//! axes) against its number, the outliers by the robust rule in red and
//! labelled with their names, the others in blue.

use super::spread::SpreadReport;
use crate::document::plot::{Axis, Colour, Corner, Mark, Panel, Plot, Point, Series};
use crate::document::{Block, Document};

/// Size (px, width x height): three panels by two rows.
pub const SPREAD_PLOT_SIZE_PX: (u32, u32) = (1400, 800);

const INLIER: Colour = Colour::rgb(41, 128, 185);
const OUTLIER: Colour = Colour::rgb(192, 57, 43);
const LABEL_GREY: Colour = Colour::rgb(80, 80, 80);

fn panel(r: &SpreadReport, caption: String, unit: &str, value: impl Fn(usize) -> f64) -> Panel {
    let n = r.calibrations.len();
    let top = (0..n).map(|i| value(i).abs()).fold(0.0, f64::max).max(1e-9) * 1.15;
    // Room above the points for the legend, right of them for the names.
    let (y_range, x_top) = ((-top, 1.7 * top), (n as f64 + 1.0) * 1.3);
    let at = |i: usize| Point::at((i + 1) as f64, value(i));
    let (out, ins): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| r.calibrations[i].outlier);
    let dots = |idx: &[usize], colour: Colour, legend: &str| Series {
        mark: Mark::Dot { radius: 4 },
        colour,
        points: idx.iter().map(|&i| at(i)).collect(),
        legend: Some(format!("{legend} ({})", idx.len())),
    };
    let labels = Series {
        mark: Mark::Label {
            size: 13,
            offset: (6, -6),
        },
        colour: LABEL_GREY,
        points: out
            .iter()
            .map(|&i| Point {
                label: r.calibrations[i].name.clone(),
                ..at(i)
            })
            .collect(),
        legend: None,
    };
    Panel {
        caption,
        x: Axis {
            label: "calibration #".into(),
            range: (0.0, x_top),
            log: false,
        },
        y: Axis {
            label: format!("deviation from the mean ({unit})"),
            range: y_range,
            log: false,
        },
        series: vec![
            dots(&ins, INLIER, "calibrations"),
            dots(&out, OUTLIER, "outliers"),
            labels,
        ],
        legend: Corner::UpperRight,
    }
}

impl SpreadReport {
    /// The spread plot (drawn only as SVG).
    pub fn plot(&self) -> Document {
        let mut panels = Vec::new();
        for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
            panels.push(panel(
                self,
                format!("rotation about {axis} ({} axes)", self.from),
                "deg",
                |i| self.calibrations[i].deviation.rotation_from_deg[k],
            ));
        }
        for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
            panels.push(panel(
                self,
                format!("translation along {axis} ({} axes)", self.from),
                "mm",
                |i| self.calibrations[i].deviation.translation_from_mm[k],
            ));
        }
        let mut doc = Document::new();
        doc.push(Block::Plot(Plot {
            size_px: SPREAD_PLOT_SIZE_PX,
            panels,
            rows: 2,
        }));
        doc
    }
}
