//! The format registry: every format, listed once in [`FORMATS`], and the
//! detection the contract describes (`formats::spec`): binary formats by
//! their magic bytes, extensions or sniffer first; then an extension that
//! selects one text format; then the highest [`Confidence`] of the sniffers,
//! ties going to the earlier entry of [`FORMATS`].
//!
//! The registry knows no format's content: adding one is its own file with a
//! `pub const SPEC: FormatSpec`, and one line here.

use super::spec::{Confidence, Format, FormatSpec, Input};
use super::xml;
use crate::diagnostic::{Error, Result};
use std::borrow::Cow;
use std::path::Path;
use std::sync::OnceLock;

/// Every format, in detection-tie order (among the YAML dialects, which all
/// sniff at `Confidence::Keys`, the order decides which of two dialects
/// whose keys a file holds reads it).
pub const FORMATS: &[&FormatSpec] = &[
    &super::urdf::SPEC,
    &super::xacro::SPEC,
    &super::launch::LAUNCH_XML,
    &super::launch::LIO_LIVOX_LAUNCH,
    &super::launch_py::LAUNCH_PY,
    &super::launch::STATIC_TF_COMMANDS,
    &super::yaml_dialects::TF_STATIC_ECHO,
    &super::launch::LAUNCH_YAML,
    &super::fast_livo::FAST_LIVO,
    &super::yaml_dialects::FAST_LIO,
    &super::yaml_dialects::LIO_SAM,
    &super::lio_yaml::IG_LIO,
    &super::lio_yaml::DLIO,
    &super::lio_yaml::VINS_MONO,
    &super::yaml_dialects::SLICT,
    &super::yaml_dialects::COCO_LIC,
    &super::yaml_dialects::QUATERNION_YAML,
    &super::yaml_dialects::TF_TREE_YAML,
    &super::autoware::AUTOWARE_CALIBRATION,
    &super::orb_slam3::ORB_SLAM3,
    &super::okvis::OKVIS,
    &super::euroc::EUROC_SENSOR,
    &super::r3live::R3LIVE,
    &super::apollo::APOLLO_EXTRINSICS,
    &super::matrix_tree::MATRIX_YAML,
    &super::nuscenes::NUSCENES,
    &super::ouster_extrinsics::SPEC,
    &super::basalt::BASALT_CALIB,
    &super::glim::GLIM_SENSORS,
    &super::opencalib::OPENCALIB,
    &super::livox_driver2::LIVOX_DRIVER2,
    &super::av2::AV2_JSON,
    &super::ouster::SPEC,
    &super::bag::SPEC,
    &super::av2::AV2_FEATHER,
    &super::las::SPEC,
    &super::kitti_m2dgr::KITTI_CALIB,
    &super::kitti_object::KITTI_OBJECT,
    &super::kitti_m2dgr::M2DGR_TXT,
    &super::rig_toml::SPEC,
    &super::matrix_text::MATRIX4_TEXT,
];

/// Every format with its one-line description.
pub fn all_formats() -> impl Iterator<Item = (Format, &'static str)> {
    FORMATS.iter().map(|f| (Format(f), f.description))
}

impl Format {
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

/// The binary format that reads `input` (step 1 of detection): `forced` when
/// that is binary, else the first binary format whose magic bytes, extension
/// or sniffer recognise it. `None`: the input is text to the registry.
pub(crate) fn binary(input: &Input, forced: Option<Format>) -> Option<Format> {
    if let Some(f) = forced.filter(|f| f.0.is_binary()) {
        return Some(f);
    }
    FORMATS
        .iter()
        .filter(|f| f.is_binary())
        .find(|f| {
            f.magic_matches(input.head())
                || f.extensions.contains(&input.ext())
                || (f.sniff)(input).is_some()
        })
        .map(|f| Format(f))
}

/// The text format of `input` (steps 2 and 3 of detection): an extension one
/// format lists, else the sniffers' highest confidence.
pub(crate) fn detect_text(input: &Input) -> Result<Format> {
    let text_formats = || FORMATS.iter().filter(|f| !f.is_binary());
    if let Some(f) = text_formats().find(|f| f.extensions.contains(&input.ext())) {
        return Ok(Format(f));
    }
    let mut best: Option<(Confidence, &'static FormatSpec)> = None;
    for f in text_formats() {
        if let Some(c) = (f.sniff)(input) {
            if c == Confidence::Certain {
                return Ok(Format(f));
            }
            if best.is_none_or(|(b, _)| c > b) {
                best = Some((c, f));
            }
        }
    }
    if let Some((Confidence::Fallback, _)) = best {
        if let Some(kind) = prose_kind(input) {
            return Err(Error::parse(format!(
                "not a calibration file this tool reads: it looks like {kind}; \
                 expected a URDF, launch file, calibration YAML/JSON or text"
            ))
            .in_file(input.path()));
        }
    }
    match best {
        Some((c, f)) if c >= Confidence::Claim || !input.looks_xml() => Ok(Format(f)),
        _ if input.looks_xml() => Err(xml::unknown_root(input.text()?).in_file(input.path())),
        _ => Err(Error::parse(
            "expected a URDF, launch file, calibration YAML/JSON or text, found nothing a format reads",
        )
        .in_file(input.path())),
    }
}

/// What a file only the fallback YAML reader claims looks like, when it is
/// a document rather than calibration data: a documentation extension names
/// it (`.md`, `.rst`, `.html`, ...); a file with no YAML extension whose text
/// is not YAML is Markdown when it has a `# ` heading or a ```` ``` ```` fence
/// and plain text otherwise. A `.yaml`/`.yml` file is never prose: its parse
/// error is the answer. `None`: read it as YAML.
fn prose_kind(input: &Input) -> Option<String> {
    const DOCS: &[(&str, &str)] = &[
        ("md", "Markdown"),
        ("markdown", "Markdown"),
        ("rst", "reStructuredText"),
        ("html", "HTML"),
        ("htm", "HTML"),
        ("adoc", "AsciiDoc"),
        ("org", "an Org document"),
        ("tex", "LaTeX"),
    ];
    let ext = input.ext();
    if let Some((_, kind)) = DOCS.iter().find(|(e, _)| *e == ext) {
        return Some(format!("{kind} (.{ext})"));
    }
    if matches!(ext, "yaml" | "yml") {
        return None;
    }
    let text = input.text().ok()?;
    crate::formats::yaml::parse_documents(text).err()?;
    let markdown = text
        .lines()
        .any(|l| l.starts_with("```") || (l.starts_with("# ") && l.len() > 2));
    let kind = if markdown { "Markdown" } else { "plain text" };
    Some(format!("{kind}, not YAML"))
}

/// Every format's walk suffixes, each once, in the order of [`FORMATS`]
/// (several formats share `.yaml`, `.xml` and `.json`).
fn walk_suffixes() -> &'static [&'static str] {
    static SUFFIXES: OnceLock<Vec<&'static str>> = OnceLock::new();
    SUFFIXES.get_or_init(|| {
        let mut v: Vec<&'static str> = Vec::new();
        for ext in FORMATS.iter().flat_map(|f| f.walk.iter()) {
            if !v.contains(ext) {
                v.push(ext);
            }
        }
        v
    })
}

/// Whether a directory walk reads this file: a walk suffix of a format, or
/// (for the binary formats that list walk suffixes) their magic bytes or a
/// folder their sniffer claims; never a hidden file.
pub fn is_calibration_file(path: &Path) -> bool {
    let name = path
        .file_name()
        .map_or(Cow::Borrowed(""), |n| n.to_string_lossy());
    // A name already in lower case (the usual one) is matched as it is: no
    // copy per file of a walk (issue 29).
    let name = if name
        .bytes()
        .all(|b| b.is_ascii() && !b.is_ascii_uppercase())
    {
        name
    } else {
        Cow::Owned(name.to_lowercase())
    };
    if name.starts_with('.') {
        return false;
    }
    if walk_suffixes().iter().any(|ext| name.ends_with(ext)) {
        return true;
    }
    let mut walked = FORMATS
        .iter()
        .filter(|f| f.is_binary() && !f.walk.is_empty())
        .peekable();
    if walked.peek().is_none() {
        return false;
    }
    let Some(input) = Input::peek(path) else {
        return false;
    };
    walked.any(|f| f.magic_matches(input.head()) || (f.sniff)(&input).is_some())
}
