//! A chart: panels in a grid (rows of equal panels, filled left to right),
//! each with two axes (linear or logarithmic) and series of marks, lines or
//! shaded spans drawn in order, later series over earlier ones; a series
//! with a legend entry is listed in its panel's legend box (a series without
//! points is a legend entry only). What the survey plot and the run
//! timeline are drawn from. Text is as the report has it: the renderer
//! escapes it.

/// The chart.
#[derive(Debug, Clone, PartialEq)]
pub struct Plot {
    /// Size in pixels, width by height.
    pub size_px: (u32, u32),
    /// Panels, left to right then row after row, sharing the size evenly.
    pub panels: Vec<Panel>,
    /// Rows of panels (1: side by side).
    pub rows: u32,
}

/// One panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    /// Title above the panel.
    pub caption: String,
    /// Horizontal axis.
    pub x: Axis,
    /// Vertical axis.
    pub y: Axis,
    /// Series, drawn in order.
    pub series: Vec<Series>,
    /// The corner the legend box sits in.
    pub legend: Corner,
}

/// An axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// Its title (quantity and unit).
    pub label: String,
    /// Lowest and highest value shown.
    pub range: (f64, f64),
    /// Logarithmic (`range` then positive).
    pub log: bool,
}

/// Where a legend box sits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Corner {
    /// Top left.
    UpperLeft,
    /// Top right.
    UpperRight,
    /// Right of the plot area, outside it, from its top: it never covers
    /// data (the panel's plot area narrows by the legend's width).
    Outside,
}

/// An RGB colour with an opacity in `[0, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Colour {
    /// Red, green, blue.
    pub rgb: (u8, u8, u8),
    /// Opacity (1 opaque).
    pub alpha: f64,
}

impl Colour {
    /// An opaque colour.
    pub const fn rgb(r: u8, g: u8, b: u8) -> Self {
        Colour {
            rgb: (r, g, b),
            alpha: 1.0,
        }
    }
    /// The same colour at opacity `alpha`.
    pub const fn alpha(self, alpha: f64) -> Self {
        Colour { alpha, ..self }
    }
}

/// How a series draws its points (sizes in pixels).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mark {
    /// A filled circle.
    Dot {
        /// Radius.
        radius: u32,
    },
    /// A circle outline.
    Ring {
        /// Radius.
        radius: u32,
        /// Stroke width.
        width: u32,
    },
    /// A filled triangle.
    Triangle {
        /// Size.
        size: u32,
    },
    /// The point's label as text, offset from the point.
    Label {
        /// Font size.
        size: u32,
        /// Offset right and down from the point.
        offset: (i32, i32),
    },
    /// A line through the points, in order.
    Line {
        /// Stroke width.
        width: u32,
    },
    /// Filled rectangles, one per pair of points (opposite corners): shaded
    /// intervals.
    Span,
}

/// A series of points drawn one way.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// How the points are drawn.
    pub mark: Mark,
    /// The colour of its line, of its legend entry, and of the points that
    /// have none of their own.
    pub colour: Colour,
    /// The points.
    pub points: Vec<Point>,
    /// Its entry in the panel's legend, if any.
    pub legend: Option<String>,
}

/// One point of a series.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// Horizontal value.
    pub x: f64,
    /// Vertical value.
    pub y: f64,
    /// Its own colour (`None`: the series' colour).
    pub colour: Option<Colour>,
    /// Its label, for [`Mark::Label`].
    pub label: String,
}

impl Point {
    /// A point in the series' colour, without a label.
    pub fn at(x: f64, y: f64) -> Self {
        Point {
            x,
            y,
            colour: None,
            label: String::new(),
        }
    }
}
