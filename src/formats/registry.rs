//! The format registry: one [`FormatSpec`] per format (id, description, file
//! extensions, a content sniffer, the parser), listed once in [`FORMATS`].
//!
//! Detection: a file-name extension that belongs to exactly one format selects
//! it outright (score [`EXTENSION`]); otherwise every format's sniffer scores
//! the content and the highest score wins, ties going to the earlier entry of
//! [`FORMATS`]. XML that no XML format claims is refused with its root element.
//!
//! Adding a format: its parser file defines a `pub const SPEC: FormatSpec`, and
//! [`FORMATS`] gets one line.

use super::{
    av2, kitti_m2dgr, kitti_object, launch, lio_yaml, nuscenes, ouster, ouster_extrinsics,
    rig_toml, urdf, xacro, xml, yaml_dialects,
};
use super::{LoadOptions, Loaded};
use crate::diagnostic::{Error, Result};
use crate::formats::source::LineIndex;
use std::cell::OnceCell;
use std::path::Path;

/// Score of a file-name extension that selects one format outright.
pub const EXTENSION: u8 = 100;
/// The highest score a sniffer gives content (a URDF `<robot>`, a launch file
/// with static transform publishers): detection stops at the first sniffer
/// that returns it, so the others (the YAML dialect among them) never scan the
/// text. Equal scores go to the earlier entry anyway.
pub const CERTAIN: u8 = 90;
/// Lowest score an XML format gives text it recognises: below it, XML text is
/// refused as no known format.
pub const XML_CLAIM: u8 = 80;

/// A parser: text as read from `path` into edges.
pub type ParseFn = fn(&str, &Path, &LoadOptions) -> Result<Loaded>;

/// One format.
#[derive(Debug)]
pub struct FormatSpec {
    /// What `--input-format` takes and provenance prints (`fast-lio`).
    pub id: &'static str,
    /// One line: what the numbers of this format mean.
    pub description: &'static str,
    /// File-name endings (lower case, without the leading dot) that select
    /// this format outright.
    pub extensions: &'static [&'static str],
    /// File-name endings (with the dot) a directory walk reads as calibration
    /// files that may be in this format (`audit check DIR`).
    pub walk: &'static [&'static str],
    /// How sure the content looks like this format (`None`: not at all).
    pub sniff: fn(&Sniff) -> Option<u8>,
    /// The parser.
    pub parse: ParseFn,
}

/// A format: a handle on its [`FormatSpec`] (compared by id).
#[derive(Clone, Copy)]
pub struct Format(pub &'static FormatSpec);

impl Format {
    /// The id (`urdf`, `fast-lio`, ...).
    pub fn name(self) -> &'static str {
        self.0.id
    }
    /// One line: what the numbers of this format mean.
    pub fn description(self) -> &'static str {
        self.0.description
    }
    /// The format whose id is `name` (case and `_`/`-` insensitive); the error
    /// lists the ids.
    pub fn from_name(name: &str) -> Result<Format> {
        let n = name.trim().to_ascii_lowercase().replace('_', "-");
        FORMATS
            .iter()
            .find(|f| f.id == n)
            .map(|f| Format(f))
            .ok_or_else(|| {
                Error::usage(format!(
                    "unknown input format '{name}': expected one of {}",
                    FORMATS.iter().map(|f| f.id).collect::<Vec<_>>().join(", ")
                ))
            })
    }
}

impl PartialEq for Format {
    fn eq(&self, o: &Self) -> bool {
        self.0.id == o.0.id
    }
}
impl Eq for Format {}

impl std::fmt::Debug for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Format({})", self.0.id)
    }
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.0.id)
    }
}

impl From<Format> for &'static str {
    fn from(f: Format) -> &'static str {
        f.0.id
    }
}

/// Every format, in detection-tie order.
pub const FORMATS: &[&FormatSpec] = &[
    &urdf::SPEC,
    &xacro::SPEC,
    &launch::LAUNCH_XML,
    &launch::LAUNCH_YAML,
    &launch::LAUNCH_PY,
    &launch::STATIC_TF_COMMANDS,
    &yaml_dialects::TF_STATIC_ECHO,
    &yaml_dialects::FAST_LIO,
    &yaml_dialects::LIO_SAM,
    &launch::LIO_LIVOX_LAUNCH,
    &yaml_dialects::COCO_LIC,
    &yaml_dialects::SLICT,
    &lio_yaml::IG_LIO,
    &lio_yaml::DLIO,
    &lio_yaml::VINS_MONO,
    &yaml_dialects::TF_TREE_YAML,
    &yaml_dialects::MATRIX_YAML,
    &yaml_dialects::QUATERNION_YAML,
    &nuscenes::NUSCENES,
    &ouster_extrinsics::SPEC,
    &av2::AV2_FEATHER,
    &av2::AV2_JSON,
    &ouster::SPEC,
    &kitti_m2dgr::KITTI_CALIB,
    &kitti_object::KITTI_OBJECT,
    &kitti_m2dgr::M2DGR_TXT,
    &rig_toml::SPEC,
];

/// Every format with its one-line description.
pub fn all_formats() -> impl Iterator<Item = (Format, &'static str)> {
    FORMATS.iter().map(|f| (Format(f), f.description))
}

/// What a sniffer sees: the extension, the text and a few derived facts.
pub struct Sniff<'a> {
    /// Lower-case extension, with the known double ones (`launch.py`, ...).
    pub ext: String,
    /// The whole text.
    pub text: &'a str,
    /// The first 4096 characters.
    pub head: String,
    /// The text after a BOM and whitespace.
    pub trimmed: &'a str,
    yaml: OnceCell<&'static str>,
}

impl<'a> Sniff<'a> {
    /// The sniffing context of `text` read from `path`.
    pub fn new(path: &Path, text: &'a str) -> Self {
        Sniff {
            ext: extension(path),
            text,
            head: text.chars().take(4096).collect(),
            trimmed: text.trim_start_matches('\u{feff}').trim_start(),
            yaml: OnceCell::new(),
        }
    }
    /// Whether the text starts like XML.
    pub fn looks_xml(&self) -> bool {
        self.trimmed.starts_with('<')
    }
    /// Whether the text may be read as XML (it looks like it, or its
    /// extension says so).
    pub fn xml_candidate(&self) -> bool {
        self.looks_xml() || matches!(self.ext.as_str(), "urdf" | "xml" | "launch" | "launch.xml")
    }
    /// The YAML dialect the keys name (decided once for all dialects).
    pub fn yaml_dialect(&self) -> &'static str {
        self.yaml.get_or_init(|| yaml_dialects::dialect(self.text))
    }
}

fn extension(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    for multi in [
        ".launch.xml",
        ".launch.yaml",
        ".launch.yml",
        ".launch.py",
        ".urdf.xacro",
    ] {
        if name.ends_with(multi) {
            return multi[1..].to_string();
        }
    }
    path.extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default()
}

/// Detect the format of `text` read from `path`.
pub fn detect(path: &Path, text: &str) -> Result<Format> {
    let s = Sniff::new(path, text);
    if let Some(f) = FORMATS
        .iter()
        .find(|f| f.extensions.contains(&s.ext.as_str()))
    {
        return Ok(Format(f));
    }
    let mut best: Option<(u8, &'static FormatSpec)> = None;
    for f in FORMATS {
        if let Some(score) = (f.sniff)(&s) {
            if score >= CERTAIN {
                return Ok(Format(f));
            }
            if best.is_none_or(|(b, _)| score > b) {
                best = Some((score, f));
            }
        }
    }
    match best {
        Some((score, f)) if score >= XML_CLAIM || !s.looks_xml() => Ok(Format(f)),
        _ if s.looks_xml() => Err(unknown_xml(text).in_file(path)),
        _ => Ok(Format(&yaml_dialects::MATRIX_YAML)),
    }
}

fn unknown_xml(text: &str) -> Error {
    match roxmltree::Document::parse_with_options(text, xml::parse_options()) {
        Ok(doc) => {
            let root = doc.root_element();
            let (l, c) = LineIndex::new(text).pos(root.range().start);
            Error::parse(format!(
                "root element is <{}>: expected a URDF <robot> or a ROS <launch> file; pass --input-format NAME to force a format",
                root.tag_name().name()
            ))
            .at_line(l, Some(c))
        }
        Err(e) => xml::error(&e, text),
    }
}

/// Whether a directory walk reads this file (any format's walk extensions, or
/// a bag; no hidden files).
pub fn is_calibration_file(path: &Path) -> bool {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    !name.starts_with('.')
        && (super::bag::is_bag(path)
            || FORMATS
                .iter()
                .any(|f| f.walk.iter().any(|ext| name.ends_with(ext))))
}
