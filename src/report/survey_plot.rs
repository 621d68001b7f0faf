//! The survey plot (`audit survey PATHS --plot survey.svg`) as a document:
//! one [`Plot`] block, drawn as SVG by the renderer.
//!
//! Left: each rig's lever arm `||d||` (m) against its screw translation `|h|`
//! (m), zero-pitch rigs (an adapted constant metric exists) in green, general
//! screws in blue, rigs without a rotation (no screw axis, `h` undefined,
//! drawn at `|h| = 0`) as orange triangles; every point is labelled with its
//! rig id. Right: each rig's certificate band `[s_min^2, s_max^2]` at
//! `delta = ||d|| / l` against the characteristic length `l` (both axes
//! logarithmic), the rig with the largest lever arm in red.

use super::survey::{SurveyReport, SurveyRigJson};
use crate::document::plot::{Axis, Colour, Corner, Mark, Panel, Plot, Point, Series};
use crate::document::{Block, Document};
use crate::geometry::certificate::band;

/// Characteristic lengths (m) spanned by the band panel: 10 cm (a handheld
/// rig's scene) to 100 m (open roads).
pub const PLOT_ELL_RANGE_M: (f64, f64) = (0.1, 100.0);

/// Size (px, width x height) of the plot: two panels side by side.
pub const PLOT_SIZE_PX: (u32, u32) = (1400, 640);

/// Points along each band curve.
const CURVE_POINTS: usize = 120;

const ZERO_PITCH: Colour = Colour::rgb(39, 174, 96);
const GENERAL: Colour = Colour::rgb(41, 128, 185);
const NO_ROTATION: Colour = Colour::rgb(230, 126, 34);
const LARGEST: Colour = Colour::rgb(192, 57, 43);
const LABEL_GREY: Colour = Colour::rgb(80, 80, 80);
const BLACK: Colour = Colour::rgb(0, 0, 0);

/// `|h|` as plotted: 0 for a rig without a rotation.
fn abs_h(r: &SurveyRigJson) -> f64 {
    r.screw_translation_m.map_or(0.0, f64::abs)
}

fn colour(r: &SurveyRigJson) -> Colour {
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

fn series(mark: Mark, colour: Colour, points: Vec<Point>) -> Series {
    Series {
        mark,
        colour,
        points,
        legend: None,
    }
}

fn scatter(rigs: &[SurveyRigJson]) -> Panel {
    let xmax = axis_top(rigs.iter().map(|r| r.lever_arm_m).fold(0.0, f64::max));
    let ymax = axis_top(rigs.iter().map(abs_h).fold(0.0, f64::max));
    let at = |r: &SurveyRigJson| Point::at(r.lever_arm_m, abs_h(r));
    // The legend first (entries without points), then the labels, the
    // markers, and the zero-pitch rings last so that no marker hides them.
    let mut all: Vec<Series> = [
        ("zero pitch (ringed): adapted metric M0 exists", ZERO_PITCH),
        ("general screw: no constant metric", GENERAL),
        ("no rotation (h undefined)", NO_ROTATION),
    ]
    .into_iter()
    .map(|(label, c)| {
        let n = rigs.iter().filter(|r| colour(r) == c).count();
        Series {
            legend: Some(format!("{label} ({n})")),
            ..series(Mark::Dot { radius: 4 }, c, vec![])
        }
    })
    .collect();
    let labels = rigs
        .iter()
        .map(|r| Point {
            label: r.id.clone(),
            ..at(r)
        })
        .collect();
    let label = Mark::Label {
        size: 9,
        offset: (6, -4),
    };
    all.push(series(label, LABEL_GREY, labels));
    let (no_rot, screws): (Vec<&SurveyRigJson>, Vec<&SurveyRigJson>) =
        rigs.iter().partition(|r| colour(r) == NO_ROTATION);
    let screws = screws
        .iter()
        .map(|r| Point {
            colour: Some(colour(r)),
            ..at(r)
        })
        .collect();
    all.push(series(Mark::Dot { radius: 4 }, GENERAL, screws));
    let no_rot = no_rot
        .iter()
        .map(|r| Point::at(r.lever_arm_m, 0.0))
        .collect();
    all.push(series(Mark::Triangle { size: 5 }, NO_ROTATION, no_rot));
    let rings = rigs.iter().filter(|r| r.zero_pitch).map(at).collect();
    let ring = Mark::Ring {
        radius: 7,
        width: 2,
    };
    all.push(series(ring, BLACK, rings));
    Panel {
        caption: "lever arm against screw translation".into(),
        x: Axis {
            label: "lever arm ||d|| (m)".into(),
            range: (0.0, xmax),
            log: false,
        },
        y: Axis {
            label: "|h| = |e . d| (m)".into(),
            range: (0.0, ymax),
            log: false,
        },
        series: all,
        legend: Corner::UpperLeft,
    }
}

/// The lower and upper band edges along a log-spaced `l`, for one lever arm.
fn band_curves(lever: f64) -> [Vec<Point>; 2] {
    let (lo, hi) = PLOT_ELL_RANGE_M;
    let curve: Vec<(f64, [f64; 2])> = (0..CURVE_POINTS)
        .map(|i| {
            let t = i as f64 / (CURVE_POINTS - 1) as f64;
            let ell = lo * (hi / lo).powf(t);
            (ell, band(lever / ell))
        })
        .collect();
    [0, 1].map(|k| curve.iter().map(|(l, b)| Point::at(*l, b[k])).collect())
}

fn bands(rigs: &[SurveyRigJson]) -> Panel {
    let (lo, hi) = PLOT_ELL_RANGE_M;
    let largest = rigs
        .iter()
        .max_by(|a, b| a.lever_arm_m.total_cmp(&b.lever_arm_m));
    let top = largest
        .map_or(2.0, |r| band(r.lever_arm_m / lo)[1])
        .max(2.0);
    // Zero-pitch rigs drawn last, over the others; the largest over all.
    let mut order: Vec<&SurveyRigJson> = rigs.iter().collect();
    order.sort_by_key(|r| r.zero_pitch);
    let mut all = Vec::new();
    for r in order {
        let c = colour(r).alpha(if r.zero_pitch { 0.9 } else { 0.35 });
        for edge in band_curves(r.lever_arm_m) {
            all.push(series(Mark::Line { width: 1 }, c, edge));
        }
    }
    if let Some(r) = largest {
        let [lower, upper] = band_curves(r.lever_arm_m);
        all.push(Series {
            legend: Some(format!(
                "largest lever arm: {} ({:.3} m)",
                r.id, r.lever_arm_m
            )),
            ..series(Mark::Line { width: 2 }, LARGEST, lower)
        });
        all.push(series(Mark::Line { width: 2 }, LARGEST, upper));
    }
    Panel {
        caption: "certificate band against characteristic length".into(),
        x: Axis {
            label: "characteristic length l (m)".into(),
            range: (lo, hi),
            log: true,
        },
        y: Axis {
            label: "eigenvalue factor [s_min^2, s_max^2]".into(),
            range: (1.0 / top, top),
            log: true,
        },
        series: all,
        legend: Corner::UpperRight,
    }
}

impl SurveyReport {
    /// The survey plot: a document of one plot block (drawn as SVG).
    pub fn plot(&self) -> Document {
        let mut doc = Document::new();
        // The plot draws every rig: its rows, whole, for the picture only.
        let rigs: Vec<SurveyRigJson> = self.rigs.iter().collect();
        doc.push(Block::Plot(Plot {
            size_px: PLOT_SIZE_PX,
            panels: vec![scatter(&rigs), bands(&rigs)],
            rows: 1,
        }));
        doc
    }
}
