//! Edges and their provenance: the data every loader produces and the frame
//! graph stores. Defined here, below both, so that the graph knows no file
//! format and a format is only a client that adds edges.

use crate::diagnostic::Location;
use crate::geometry::{EdgePrecision, Precision, Transform};

/// Where an edge's numbers came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Provenance {
    /// File, line, column where known.
    pub location: Location,
    /// The id of the format that read it (`urdf`, `fast-lio`, ...), as
    /// `--input-format` takes it.
    pub format: &'static str,
    /// The key or element it came from, e.g. `joint "lidar_joint" <origin>` or
    /// `extrinsic_T + extrinsic_R`.
    pub key: String,
    /// Where the translation's and the rotation's numbers are written, when
    /// the format knows it (a finding about a changed number points there).
    pub values: ValuesAt,
}

/// Line and column (1-based) in the edge's file where its translation and
/// its rotation are written: a rig TOML's `translation = [...]` inside the
/// `[[transform]]` table, a URDF `<origin>`'s `xyz` and `rpy` attributes, a
/// YAML file's keys. `None`: the format gives only the edge's own location.
/// Kept as `u32` (24 bytes, not 48: every edge holds one, issue 29); a
/// position past `u32::MAX` is not kept ([`ValuesAt::new`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ValuesAt {
    /// The translation's numbers.
    pub translation: Option<(u32, u32)>,
    /// The rotation's numbers.
    pub rotation: Option<(u32, u32)>,
}

impl ValuesAt {
    /// Where the translation's and the rotation's numbers are written (line,
    /// column). A line or column that does not fit in `u32` (a text of over
    /// 4 GiB) is dropped: a finding then points at the edge's own location.
    pub fn new(translation: Option<(usize, usize)>, rotation: Option<(usize, usize)>) -> Self {
        let small = |p: Option<(usize, usize)>| {
            p.and_then(|(l, c)| Some((u32::try_from(l).ok()?, u32::try_from(c).ok()?)))
        };
        ValuesAt {
            translation: small(translation),
            rotation: small(rotation),
        }
    }

    /// `at` moved to the translation's numbers (`translation`) or the
    /// rotation's, where known; `at` itself otherwise.
    pub fn locate(&self, at: &Location, translation: bool) -> Location {
        let pos = if translation {
            self.translation
        } else {
            self.rotation
        };
        match pos {
            Some((line, column)) => Location {
                line: Some(line as usize),
                column: Some(column as usize),
                ..at.clone()
            },
            None => at.clone(),
        }
    }
}

impl Provenance {
    /// The location of the translation's numbers (`translation`) or of the
    /// rotation's, falling back to the edge's own location where the format
    /// does not say.
    pub fn value_location(&self, translation: bool) -> Location {
        self.values.locate(&self.location, translation)
    }
}

/// The kind of a non-fixed joint (URDF `<joint type>`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum JointType {
    /// Rotation about the axis, within limits (rad).
    Revolute,
    /// Rotation about the axis, no limits (rad).
    Continuous,
    /// Translation along the axis (m).
    Prismatic,
    /// Six degrees of freedom: no pose until set.
    Floating,
    /// Motion in a plane: no pose until set.
    Planar,
}

impl JointType {
    /// The URDF name (`revolute`, ...).
    pub fn name(self) -> &'static str {
        match self {
            JointType::Revolute => "revolute",
            JointType::Continuous => "continuous",
            JointType::Prismatic => "prismatic",
            JointType::Floating => "floating",
            JointType::Planar => "planar",
        }
    }

    /// The joint type named `name` in a URDF (`fixed` is not a joint state).
    pub fn from_name(name: &str) -> Option<JointType> {
        [
            JointType::Revolute,
            JointType::Continuous,
            JointType::Prismatic,
            JointType::Floating,
            JointType::Planar,
        ]
        .into_iter()
        .find(|j| j.name() == name)
    }

    /// Whether one number (`--joint NAME=VALUE`) sets the joint.
    pub fn has_one_value(self) -> bool {
        !matches!(self, JointType::Floating | JointType::Planar)
    }
}

impl std::fmt::Display for JointType {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// State of a non-fixed joint an edge passes through (URDF).
#[derive(Debug, Clone, PartialEq)]
pub struct JointState {
    /// The joint's name in the file.
    pub name: String,
    /// Its kind.
    pub joint_type: JointType,
    /// The position used (rad or m); `None` when the joint cannot be used until
    /// it is set (floating, planar).
    pub value: Option<f64>,
    /// True when the value is the default (0) rather than set by `--joint`.
    pub defaulted: bool,
}

/// One parent -> child edge: `transform` is the pose of `child` in `parent`.
#[derive(Debug, Clone, PartialEq)]
pub struct Edge {
    /// Parent frame.
    pub parent: String,
    /// Child frame.
    pub child: String,
    /// Pose of `child` in `parent`: `p_parent = R p_child + d`.
    pub transform: Transform,
    /// Where the numbers came from.
    pub provenance: Provenance,
    /// `Some` for non-fixed joints; boxed (8 bytes, not 48, in the many
    /// fixed edges: issue 29).
    pub joint: Option<Box<JointState>>,
    /// The rounding of the numbers as written and the user's uncertainty
    /// (conventions in `crate::geometry::uncertainty`). `Edge::new` records
    /// none; a reader that keeps the text adds it with [`Edge::with_precision`].
    /// Stored compactly (`Precision::full` gives the covariance).
    pub precision: Precision,
}

impl Edge {
    /// A fixed edge read by format `format` at `location`.
    pub fn new(
        parent: impl Into<String>,
        child: impl Into<String>,
        transform: Transform,
        location: Location,
        format: impl Into<&'static str>,
        key: impl Into<String>,
    ) -> Self {
        Edge {
            parent: parent.into(),
            child: child.into(),
            transform,
            provenance: Provenance {
                location,
                format: format.into(),
                key: key.into(),
                values: ValuesAt::default(),
            },
            joint: None,
            precision: Precision::default(),
        }
    }

    /// The same edge with its precision as written (see
    /// [`crate::geometry::uncertainty::rounding_covariance`]).
    pub fn with_precision(mut self, precision: EdgePrecision) -> Self {
        self.precision = precision.into();
        self
    }

    /// The same edge with where its numbers are written.
    pub fn with_values(mut self, values: ValuesAt) -> Self {
        self.provenance.values = values;
        self
    }

    /// The same edge with its precision in the compact form.
    pub fn with_compact_precision(mut self, precision: Precision) -> Self {
        self.precision = precision;
        self
    }

    /// The same edge read the other way: child becomes parent, transform inverted.
    pub fn inverted(mut self) -> Self {
        std::mem::swap(&mut self.parent, &mut self.child);
        // (T Exp(xi))^-1 = T^-1 Exp(-Ad(T) xi): the rounding's covariance follows.
        self.precision.transform_rounding(&self.transform.adjoint());
        self.transform = self.transform.inverse();
        self.provenance.key = format!("{} (inverted by --invert)", self.provenance.key);
        self
    }
}

#[cfg(test)]
mod tests {
    use super::ValuesAt;
    use crate::diagnostic::Location;

    /// Positions are kept as `u32`: one that does not fit is dropped, and
    /// the finding falls back to the edge's own location.
    #[test]
    fn values_at_keeps_what_fits_in_u32() {
        let big = u32::MAX as usize + 1;
        let v = ValuesAt::new(Some((3, 7)), Some((big, 1)));
        assert_eq!((v.translation, v.rotation), (Some((3, 7)), None));
        let at = Location::at("a.urdf", 2, Some(5));
        assert_eq!(v.locate(&at, true), Location::at("a.urdf", 3, Some(7)));
        assert_eq!(v.locate(&at, false), at);
    }
}
