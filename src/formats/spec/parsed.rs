//! What a parser returns ([`Parsed`], with [`RigMeta`] for rig files), and
//! the checks every parser applies to the numbers it reads.

use crate::diagnostic::{Code, Location, Warning};
use crate::frames::Edge;
use crate::tolerances::METRE_FIELD_WARN_M;

/// Metadata a rig file carries (TOML rig files; see `rig_toml`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RigMeta {
    /// Unique rig id (`[rig] id`; the shipped files are named `<id>.toml`).
    pub id: String,
    /// What was measured (`[rig] sensor`), e.g. the LiDAR and IMU models.
    pub sensor: String,
    /// What it is mounted on (`[rig] platform`).
    pub platform: String,
    /// The dataset or project the calibration comes from (`[rig] dataset`).
    pub dataset: String,
    /// Body (IMU) frame the survey reports from: the rig's transform is the
    /// pose of `to` in `from`.
    pub from: String,
    /// LiDAR frame the survey reports to.
    pub to: String,
    /// Source repository, `owner/name` (`[rig.source] repo`).
    pub source_repo: String,
    /// File in that repository the numbers come from, with the table or section
    /// when they sit in prose (`[rig.source] path`).
    pub source_path: String,
    /// Full commit hash of the source (`[rig.source] commit`).
    pub source_commit: String,
    /// The source's licence as far as known (`[rig] licence`).
    pub licence: String,
    /// Which frame is expressed in which, as the source documents it.
    pub direction: String,
    /// Identity or zero extrinsic (co-located placeholder): kept out of statistics.
    pub placeholder: bool,
    /// `factory`, `dataset-calibration`, `cad-or-nominal`, `third-party-config`
    /// or `placeholder` (rig TOML `[rig] category`; empty when not given).
    pub category: String,
    /// Free-text caveats from the rig file (empty when none).
    pub notes: String,
    /// A web address of the source, when the rig file gives one.
    pub source_url: Option<String>,
    /// Set when this file describes the same rig as another (e.g. a raw-file
    /// sidecar beside the native TOML): kept out of statistics; it must give the
    /// same transform as the rig it names.
    pub duplicate_of: Option<String>,
}

impl RigMeta {
    /// Whether the rig counts in survey statistics: not a placeholder and not a
    /// duplicate of another rig.
    pub fn in_statistics(&self) -> bool {
        !self.placeholder && self.duplicate_of.is_none()
    }
}

/// What one file yields.
#[derive(Debug, Clone, Default)]
pub struct Parsed {
    /// The edges the file yields (each the pose of its child in its parent),
    /// in file order, with provenance.
    pub edges: Vec<Edge>,
    /// Frames declared without an edge (URDF links no joint attaches).
    pub frames: Vec<crate::frames::FrameDecl>,
    /// Named warnings raised while reading (suspicious but usable input).
    pub warnings: Vec<Warning>,
    /// The rig metadata, for TOML rig files (`None` for every other format).
    pub rig: Option<RigMeta>,
    /// The robot the file describes, where it names one (URDF and expanded
    /// xacro `<robot name>`): the survey's platform for a file that is not a
    /// rig file.
    pub platform: Option<String>,
    /// Edges that close a loop with `edges` (Kalibr `T_cn_cnm1`): checked
    /// against the tree, not part of it (see `frames::graph`).
    pub redundant: Vec<Edge>,
}

impl From<Parsed> for crate::frames::EdgeSet {
    fn from(l: Parsed) -> Self {
        crate::frames::EdgeSet {
            edges: l.edges,
            frames: l.frames,
            warnings: l.warnings,
            redundant: l.redundant,
        }
    }
}

/// Parse one number as written in a file (also `+1`, `1.`, `.5`, `1e-3`).
/// `nan` / `inf` parse and are refused later by the transform constructors.
pub fn parse_number(s: &str) -> Option<f64> {
    let t = s.trim();
    if t.is_empty() {
        return None;
    }
    t.parse::<f64>().ok()
}

/// Warn about translation components that look like millimetres in a metre field.
pub fn check_metres(d: &[f64; 3], what: &str, loc: &Location, warnings: &mut Vec<Warning>) {
    if d.iter().any(|x| x.abs() > METRE_FIELD_WARN_M) {
        warnings.push(
            Warning::new(
                Code::MillimetresInMetreField,
                format!(
                    "{what} = [{}, {}, {}] m: a component above {METRE_FIELD_WARN_M} m in a field documented as metres; is it in millimetres?",
                    d[0], d[1], d[2]
                ),
            )
            .at(loc),
        );
    }
}

/// Attach the location of a problem to every warning a constructor produced.
pub(crate) fn locate_warnings(ws: Vec<Warning>, loc: &Location, out: &mut Vec<Warning>) {
    out.extend(ws.into_iter().map(|w| w.at(loc)));
}
