//! Writing a report: JSON (the report itself, its schema in docs/schemas),
//! or its document drawn as text, markdown, CSV, SARIF, GitHub annotations
//! or a picture.

use crate::diagnostic::{Result, Warning};
use crate::document::Report;
use crate::render::{self, Layout, OutputFormat, Style};
use std::path::PathBuf;

/// How a report is written besides its format. `Default`: no colour, no
/// terminal (every column, nothing wrapped), no warnings.
#[derive(Debug, Clone, Default, PartialEq)]
#[non_exhaustive]
pub struct RenderOptions {
    /// The warnings met while making the report (already shown to the
    /// user): the JSON's `warnings`.
    pub warnings: Vec<Warning>,
    /// ANSI colour in the tables (for a terminal).
    pub color: bool,
    /// The terminal's width in columns: tables fit it (a compact set of
    /// columns, words wrapped); `None`: not a terminal.
    pub width: Option<usize>,
    /// Every column even on a narrow terminal (`--wide`).
    pub wide: bool,
    /// Only these table columns, by header (`--columns`; one that names no
    /// column of the report is an error).
    pub columns: Vec<String>,
    /// Paths under this directory are shown relative to it.
    pub cwd: Option<PathBuf>,
}

/// `report` in `format`: JSON with `schema_version` first and the
/// `warnings` last, or its document drawn; a format that cannot draw the
/// report (a picture of a table, SARIF without findings) is an error naming
/// the formats that can.
///
/// ```
/// use extrinsic_audit::{render, LoadOptions, OutputFormat, RenderOptions, RigOptions, Robot};
///
/// # fn main() -> extrinsic_audit::Result<()> {
/// let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/urdf/anymal_c_lidar.urdf");
/// let robot = Robot::load(&[urdf], &LoadOptions::default())?;
/// let (report, warnings) = robot.report("base", "lidar", &RigOptions::default())?;
/// let mut opts = RenderOptions::default();
/// opts.warnings = warnings;
/// // JSON: the schema of docs/schemas/rig-report.schema.json.
/// let json: serde_json::Value = serde_json::from_str(&render(&report, OutputFormat::Json, &opts)?).unwrap();
/// assert_eq!(json["schema_version"], 1);
/// let lever = json["lever_arm_m"].as_f64().unwrap();
/// assert!((lever - 0.39079002034340643).abs() < 1e-12); // pytransform3d's
/// assert_eq!(json["warnings"], serde_json::json!([]));
/// // Markdown prints the lever arm to the millimetre.
/// assert!(render(&report, OutputFormat::Markdown, &opts)?.contains("0.391"));
/// // A rig report has no picture: SVG refuses it, naming what can draw it.
/// let e = render(&report, OutputFormat::Svg, &opts).unwrap_err();
/// // (MCAP draws its 3D scene: the frame tree, the chain marked.)
/// assert!(e.message.ends_with("this report takes text, markdown, json, github, csv or mcap"));
/// # Ok(())
/// # }
/// ```
pub fn render<R: Report>(report: &R, format: OutputFormat, opts: &RenderOptions) -> Result<String> {
    let (style, layout) = opts.parts();
    render::render(report, &opts.warnings, format, style, &layout)
}

/// `report` in `format` as bytes: what [`render()`] gives, and the binary
/// formats too (MCAP: the 3D scene as Foxglove's JSON-schema messages on
/// `/tf`, `/audit/scene`, `/audit/points`).
///
/// ```
/// use extrinsic_audit::{render_bytes, LoadOptions, OutputFormat, RenderOptions, RigOptions, Robot};
///
/// # fn main() -> extrinsic_audit::Result<()> {
/// let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/urdf/anymal_c_lidar.urdf");
/// let robot = Robot::load(&[urdf], &LoadOptions::default())?;
/// let (report, _) = robot.report("base", "lidar", &RigOptions::default())?;
/// let mcap = render_bytes(&report, OutputFormat::Mcap, &RenderOptions::default())?;
/// // An MCAP file opens and closes with its magic, b"\x89MCAP0\r\n".
/// assert_eq!(&mcap[..8], b"\x89MCAP0\r\n");
/// assert_eq!(&mcap[mcap.len() - 8..], b"\x89MCAP0\r\n");
/// // The text formats are the same bytes as `render`'s.
/// let text = render_bytes(&report, OutputFormat::Markdown, &RenderOptions::default())?;
/// assert_eq!(text, extrinsic_audit::render(&report, OutputFormat::Markdown, &RenderOptions::default())?.into_bytes());
/// # Ok(())
/// # }
/// ```
pub fn render_bytes<R: Report>(
    report: &R,
    format: OutputFormat,
    opts: &RenderOptions,
) -> Result<Vec<u8>> {
    let (style, layout) = opts.parts();
    render::render_bytes(report, &opts.warnings, format, style, &layout)
}

/// [`render_bytes`] written to `out` as it is made (JSON and MCAP stream).
pub fn render_to<R: Report>(
    report: &R,
    format: OutputFormat,
    opts: &RenderOptions,
    out: &mut dyn std::io::Write,
) -> Result<()> {
    let (style, layout) = opts.parts();
    render::render_to(report, &opts.warnings, format, style, &layout, out)
}

impl RenderOptions {
    fn parts(&self) -> (Style, Layout) {
        let layout = Layout {
            width: self.width,
            wide: self.wide,
            columns: self.columns.clone(),
            cwd: self.cwd.clone(),
        };
        let style = if self.color {
            Style { color: true }
        } else {
            Style::plain()
        };
        (style, layout)
    }
}
