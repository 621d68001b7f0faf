//! Errors and named warnings, with the place in the input they refer to.
//!
//! Every error the tool reports names the file, the line where it is known, what
//! was expected and what was found. Every error maps to exit code 2 (usage or
//! input error); findings of `audit check` are not errors (exit code 1).
//! Warnings are named (`code`) so scripts and CI annotations can filter them.

use std::fmt;
use std::path::{Path, PathBuf};

/// Where in the input something was found. All parts are optional: the core
/// maths knows no file, a loader attaches one.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Location {
    pub file: Option<PathBuf>,
    /// 1-based line.
    pub line: Option<usize>,
    /// 1-based column.
    pub column: Option<usize>,
}

impl Location {
    pub fn file(path: impl AsRef<Path>) -> Self {
        Location {
            file: Some(path.as_ref().to_path_buf()),
            line: None,
            column: None,
        }
    }
    pub fn at(path: impl AsRef<Path>, line: usize, column: Option<usize>) -> Self {
        Location {
            file: Some(path.as_ref().to_path_buf()),
            line: Some(line),
            column,
        }
    }
    pub fn is_empty(&self) -> bool {
        self.file.is_none() && self.line.is_none()
    }
}

impl fmt::Display for Location {
    /// `file:line:column`, with whatever parts are known.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.file {
            Some(p) => write!(f, "{}", p.display())?,
            None => write!(f, "<input>")?,
        }
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
            if let Some(c) = self.column {
                write!(f, ":{c}")?;
            }
        }
        Ok(())
    }
}

/// What went wrong, coarsely; the message carries the detail.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// The file could not be read.
    Io,
    /// The file is not valid in its format (syntax, structure, types).
    Parse,
    /// The numbers are there but do not describe a rigid transform
    /// (non-finite, det -1, zero quaternion, bad bottom row, ...).
    Invalid,
    /// Frame graph problems: unknown frame, not connected, cycle, two parents,
    /// conflicting duplicate edge, a joint that must be set.
    Frame,
    /// Input beyond a resource limit (file size, nesting, alias expansion, ...).
    Limit,
    /// The command line asks for something impossible.
    Usage,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    pub kind: ErrorKind,
    pub location: Location,
    pub message: String,
}

impl Error {
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        Error {
            kind,
            location: Location::default(),
            message: message.into(),
        }
    }
    pub fn parse(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Parse, message)
    }
    pub fn invalid(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Invalid, message)
    }
    pub fn frame(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Frame, message)
    }
    pub fn usage(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Usage, message)
    }
    pub fn limit(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Limit, message)
    }
    pub fn io(path: &Path, err: &std::io::Error) -> Self {
        Self::new(ErrorKind::Io, format!("cannot read: {err}")).in_file(path)
    }
    /// Attach a file, keeping a line that is already known.
    pub fn in_file(mut self, path: impl AsRef<Path>) -> Self {
        if self.location.file.is_none() {
            self.location.file = Some(path.as_ref().to_path_buf());
        }
        self
    }
    /// Attach a line (and column) unless one is already known.
    pub fn at_line(mut self, line: usize, column: Option<usize>) -> Self {
        if self.location.line.is_none() {
            self.location.line = Some(line);
            self.location.column = column;
        }
        self
    }
    pub fn at(mut self, loc: &Location) -> Self {
        if self.location.file.is_none() {
            self.location.file = loc.file.clone();
        }
        if self.location.line.is_none() {
            self.location.line = loc.line;
            self.location.column = loc.column;
        }
        self
    }
    /// Every error is a usage or input error: exit code 2.
    pub fn exit_code(&self) -> i32 {
        2
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.location.is_empty() {
            write!(f, "{}", self.message)
        } else {
            write!(f, "{}: {}", self.location, self.message)
        }
    }
}

impl std::error::Error for Error {}

pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Named warnings. The name (kebab-case, see [`WarningCode::name`]) is stable:
/// CI filters and `::warning` annotations use it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum WarningCode {
    /// A rotation matrix off orthonormal by more than the warning tolerance;
    /// it was projected to the nearest rotation.
    NonOrthonormalRotation,
    /// A quaternion whose norm is off 1 by more than the tolerance; normalised.
    NonUnitQuaternion,
    /// A translation that looks like millimetres in a field documented as metres.
    MillimetresInMetreField,
    /// A movable joint (revolute, continuous, prismatic) on a path, taken at its
    /// default position because the user did not set it.
    JointAtDefault,
    /// The same edge given twice, agreeing within tolerance.
    DuplicateEdge,
    /// A rotation so small that its screw axis is set by calibration noise.
    SmallRotation,
    /// A rotation within a hair of a half-turn: the sign of the axis and of h
    /// depend on rounding.
    NearHalfTurn,
    /// A frame convention the tool had to assume; the message says which.
    AssumedConvention,
    /// A movable URDF joint whose axis is not a unit vector; normalised.
    NonUnitAxis,
    /// A value present in the file but ignored (e.g. a commented alternative, a
    /// key the tool does not use); the message says which and why.
    Ignored,
    /// A URDF 1.0 `<origin quat_xyzw>`: ROS (urdfdom) ignores it, and so does
    /// the pose reported; `--urdf-version 1.1` reads it.
    QuatXyzwIgnored,
    /// A joint position outside its URDF `<limit lower upper>`; used as given,
    /// as robot_state_publisher does.
    JointOutsideLimit,
    /// A URDF that ROS (urdfdom) refuses for a reason that does not change a
    /// pose (two root links, a revolute joint without `<limit>`, ...): read
    /// anyway; the message gives urdfdom's reason.
    RefusedByRos,
}

impl WarningCode {
    pub const ALL: [WarningCode; 13] = [
        WarningCode::NonOrthonormalRotation,
        WarningCode::NonUnitQuaternion,
        WarningCode::MillimetresInMetreField,
        WarningCode::JointAtDefault,
        WarningCode::DuplicateEdge,
        WarningCode::SmallRotation,
        WarningCode::NearHalfTurn,
        WarningCode::AssumedConvention,
        WarningCode::NonUnitAxis,
        WarningCode::Ignored,
        WarningCode::QuatXyzwIgnored,
        WarningCode::JointOutsideLimit,
        WarningCode::RefusedByRos,
    ];
    pub fn name(self) -> &'static str {
        match self {
            WarningCode::NonOrthonormalRotation => "non-orthonormal-rotation",
            WarningCode::NonUnitQuaternion => "non-unit-quaternion",
            WarningCode::MillimetresInMetreField => "millimetres-in-metre-field",
            WarningCode::JointAtDefault => "joint-at-default",
            WarningCode::DuplicateEdge => "duplicate-edge",
            WarningCode::SmallRotation => "small-rotation",
            WarningCode::NearHalfTurn => "near-half-turn",
            WarningCode::AssumedConvention => "assumed-convention",
            WarningCode::NonUnitAxis => "non-unit-axis",
            WarningCode::Ignored => "ignored",
            WarningCode::QuatXyzwIgnored => "quat-xyzw-ignored",
            WarningCode::JointOutsideLimit => "joint-outside-limit",
            WarningCode::RefusedByRos => "refused-by-ros",
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Warning {
    pub code: WarningCode,
    pub location: Location,
    pub message: String,
}

impl Warning {
    pub fn new(code: WarningCode, message: impl Into<String>) -> Self {
        Warning {
            code,
            location: Location::default(),
            message: message.into(),
        }
    }
    pub fn at(mut self, loc: &Location) -> Self {
        if self.location.file.is_none() {
            self.location.file = loc.file.clone();
        }
        if self.location.line.is_none() {
            self.location.line = loc.line;
            self.location.column = loc.column;
        }
        self
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.location.is_empty() {
            write!(f, "warning[{}]: {}", self.code.name(), self.message)
        } else {
            write!(
                f,
                "warning[{}]: {}: {}",
                self.code.name(),
                self.location,
                self.message
            )
        }
    }
}
