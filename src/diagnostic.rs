//! Diagnostics: one type for errors, warnings and `audit check` findings.
//!
//! A [`Diagnostic`] has a typed [`Code`] (kebab-case name, stable: CI filters,
//! annotations and `--allow` use it), a [`Severity`], the place in the input
//! ([`Location`]: file, 1-based line and column where known), a message that says
//! what was expected and what was found, and optional help. The same value is
//! rendered as text, JSON, GitHub annotations or anything else by `render`.
//!
//! [`Error`] and [`Warning`] are names for the same type, used where a function
//! returns one or the other; a `Result`'s error always has severity `error` and
//! maps to exit code 2 (usage or input error). Findings of `audit check` exit 1.

use crate::tolerances::MAX_MESSAGE_CHARS;
use std::fmt;
use std::path::Path;
use std::sync::Arc;

/// Where in the input something was found. All parts are optional: the core
/// maths knows no file, a loader attaches one.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Location {
    /// The file, as the user named it (or as found in a directory walk).
    /// Shared: every edge of a file points at one copy of its name (issue
    /// 29: one allocation per edge less; [`Location::in_shared`]).
    pub file: Option<Arc<Path>>,
    /// 1-based line.
    pub line: Option<usize>,
    /// 1-based column (characters).
    pub column: Option<usize>,
}

impl Location {
    /// A whole file.
    pub fn file(path: impl AsRef<Path>) -> Self {
        Location {
            file: Some(path.as_ref().into()),
            line: None,
            column: None,
        }
    }
    /// A line (and column) in a file.
    pub fn at(path: impl AsRef<Path>, line: usize, column: Option<usize>) -> Self {
        Location {
            file: Some(path.as_ref().into()),
            line: Some(line),
            column,
        }
    }
    /// A line (and column) in a file whose name is already shared: no copy
    /// of the name (a reader's many locations in one file).
    pub fn in_shared(file: &Arc<Path>, line: usize, column: Option<usize>) -> Self {
        Location {
            file: Some(Arc::clone(file)),
            line: Some(line),
            column,
        }
    }
    /// Neither file nor line known.
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

/// How bad a diagnostic is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// The input is wrong or the command cannot do what was asked.
    Error,
    /// Suspicious input: reported, the answer is still given.
    Warning,
}

impl Severity {
    /// Its name, as the JSON (serde), the text lines and the CSV write it.
    pub fn name(self) -> &'static str {
        match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
        }
    }
}

macro_rules! codes {
    ($( $(#[doc = $doc:literal])* $variant:ident = $name:literal, $sev:ident; )*) => {
        /// Every diagnostic code, with its stable kebab-case name and default
        /// severity. The table in docs/ARCHITECTURE.md lists them.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Code {
            $( $(#[doc = $doc])* $variant, )*
        }

        impl Code {
            /// Every code, in declaration order.
            pub const ALL: &'static [Code] = &[$(Code::$variant),*];

            /// The stable name (`non-unit-quaternion`, ...).
            pub fn name(self) -> &'static str {
                match self { $(Code::$variant => $name,)* }
            }

            /// What the code means: its doc comment in this table, as lines
            /// (SARIF rule descriptions).
            pub fn doc_lines(self) -> &'static [&'static str] {
                match self { $(Code::$variant => &[$($doc),*],)* }
            }

            /// The severity a diagnostic of this code has unless a policy
            /// (`--allow`, a check rule) changes it.
            pub fn default_severity(self) -> Severity {
                match self { $(Code::$variant => Severity::$sev,)* }
            }
        }
    };
}

codes! {
    // Errors: the input cannot be used (exit code 2, or a check finding).
    /// The file could not be read.
    Io = "io", Error;
    /// The file is not valid in its format (syntax, structure, types).
    Parse = "parse", Error;
    /// The numbers are there but do not describe a rigid transform
    /// (non-finite, det -1, zero quaternion, bad bottom row, ...).
    Invalid = "invalid", Error;
    /// Frame graph problems: unknown frame, not connected, cycle, two parents,
    /// conflicting duplicate edge, a joint that must be set.
    Frame = "frames", Error;
    /// Input beyond a resource limit (file size, nesting, alias expansion, ...).
    Limit = "limit", Error;
    /// The command line asks for something impossible.
    Usage = "usage", Error;
    /// `audit --strict`: warnings were raised, and every warning is an error.
    WarningsDenied = "warnings-denied", Error;

    // Warnings raised while reading: the answer is given, the input is suspicious.
    /// A rotation matrix off orthonormal by more than the warning tolerance;
    /// it was projected to the nearest rotation.
    NonOrthonormalRotation = "non-orthonormal-rotation", Warning;
    /// A quaternion whose norm is off 1 by more than the tolerance; normalised.
    NonUnitQuaternion = "non-unit-quaternion", Warning;
    /// A translation that looks like millimetres in a field documented as metres.
    MillimetresInMetreField = "millimetres-in-metre-field", Warning;
    /// A `--joint` value on a revolute or continuous joint that looks like
    /// degrees (`|value| > 2 pi`) in a field taken as radians.
    DegreesInRadianField = "degrees-in-radian-field", Warning;
    /// A movable joint (revolute, continuous, prismatic) on a path, taken at its
    /// default position because the user did not set it.
    JointAtDefault = "joint-at-default", Warning;
    /// The same edge given twice, agreeing within tolerance.
    DuplicateEdge = "duplicate-edge", Warning;
    /// A frame convention the tool had to assume; the message says which.
    AssumedConvention = "assumed-convention", Warning;
    /// A movable URDF joint whose axis is not a unit vector; normalised.
    NonUnitAxis = "non-unit-axis", Warning;
    /// A value present in the file but ignored (e.g. a commented alternative, a
    /// key the tool does not use); the message says which and why.
    Ignored = "ignored", Warning;
    /// A URDF 1.0 `<origin quat_xyzw>`: ROS (urdfdom) ignores it, and so does
    /// the pose reported; `--urdf-version 1.1` reads it.
    QuatXyzwIgnored = "quat-xyzw-ignored", Warning;
    /// A joint position outside its URDF `<limit lower upper>`; used as given,
    /// as robot_state_publisher does.
    JointOutsideLimit = "joint-outside-limit", Warning;
    /// A URDF that ROS (urdfdom) refuses for a reason that does not change a
    /// pose (two root links, a revolute joint without `<limit>`, ...): read
    /// anyway; the message gives urdfdom's reason.
    RefusedByRos = "refused-by-ros", Warning;
    /// A redundant edge (one closing a loop in a file) that disagrees with
    /// the tree path between its frames beyond the redundant-edge tolerances;
    /// the message gives both values.
    RedundantEdgeDisagrees = "redundant-edge-disagrees", Warning;
    /// A key given twice in one file with different values: the edges it
    /// would give are left out (the rest of the file is read); the message
    /// names both lines.
    AmbiguousKey = "ambiguous-key", Warning;
    /// A scan (or scan pair) of a recorded run left out of the analysis,
    /// with its reason (empty, fields or steps that lie, no pose, ...); the
    /// other scans are still reported.
    ScanSkipped = "scan-skipped", Warning;
    /// A recorded run stopped reading at damage (a truncated or corrupt
    /// file): the scans before it are reported.
    RunDamaged = "run-damaged", Warning;
    /// A frame a scan or a body frame needs that the run's transforms never
    /// name: the scan is reported in its own frame only.
    FrameMissing = "frame-missing", Warning;
    /// A message an xacro file prints with `xacro.warning()` or
    /// `xacro.error()`: Python xacro prints it and goes on, and so does the
    /// expander; the message gives the text and where it was raised.
    XacroMessage = "xacro-message", Warning;
    /// `$(find pkg)` found two or more packages named `pkg` on the search
    /// path: the message says which directory was used and where the others
    /// are.
    DuplicatePackage = "duplicate-package", Warning;
    /// A frame name that resembles another frame of the graph (a Unicode
    /// confusable such as Cyrillic `і` for `i`, compatibility forms, case,
    /// white space at its ends) but is not it: two frames where one was
    /// meant; the message names the frame it resembles.
    ConfusableFrameName = "confusable-frame-name", Warning;
    /// A frame name with white space at its start or end (kept as part of
    /// the name, as tf2 keeps it).
    PaddedFrameName = "padded-frame-name", Warning;

    // Findings of `audit check` (errors unless a policy says otherwise).
    /// A file in the checked paths is not in the baseline.
    NewFile = "new-file", Error;
    /// An edge in the file is not in the baseline.
    NewEdge = "new-edge", Error;
    /// An edge in the baseline is no longer in the file.
    MissingEdge = "missing-edge", Error;
    /// A file in the baseline is gone (`--write-baseline --prune` accepts it).
    RemovedFile = "removed-file", Error;
    /// A frame pair checked in the baseline is no longer checked in the file
    /// (a rig that changed its declared pair: the message names both).
    PairChanged = "pair-changed", Error;
    /// A transform moved beyond the drift tolerances since the baseline.
    Drift = "drift", Error;
    /// A verdict (screw kind, zero pitch, adapted metric) changed since the
    /// baseline.
    VerdictChanged = "verdict-changed", Error;
    /// A checked pair's lever arm exceeds `--max-lever-arm`.
    LeverArm = "lever-arm", Error;
    /// A checked pair does not have zero screw pitch (`--require-zero-pitch`).
    NonzeroPitch = "nonzero-pitch", Error;
    /// A checked pair deviates from the mean of the same pair over the
    /// checked files beyond `--fleet-tolerance` (one calibration per vehicle).
    FleetDeviation = "fleet-deviation", Error;
}

impl Code {
    /// The code named `name` (as printed by [`Code::name`]).
    pub fn from_name(name: &str) -> Option<Code> {
        Code::ALL.iter().copied().find(|c| c.name() == name)
    }

    /// What the code means, in one line (its doc comment).
    pub fn description(self) -> String {
        self.doc_lines()
            .iter()
            .map(|l| l.trim())
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// The warning codes a reader can raise (what `--allow` accepts).
    pub fn warnings() -> impl Iterator<Item = Code> {
        Code::ALL
            .iter()
            .copied()
            .filter(|c| c.default_severity() == Severity::Warning)
    }
}

impl fmt::Display for Code {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl serde::Serialize for Code {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// One error, warning or finding, with the place it refers to.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    /// What kind of problem.
    pub code: Code,
    /// How bad (the code's default unless a policy changed it).
    pub severity: Severity,
    /// Where in the input.
    pub location: Location,
    /// What was expected and what was found.
    pub message: String,
    /// How to fix it, when there is something to say.
    pub help: Option<String>,
}

/// A diagnostic of severity `error`: the error type of every fallible function.
pub type Error = Diagnostic;
/// A diagnostic of severity `warning`.
pub type Warning = Diagnostic;

impl Diagnostic {
    /// A diagnostic of `code` with its default severity and no location.
    /// The message is bounded: past [`MAX_MESSAGE_CHARS`] its middle is cut,
    /// with the count of what was cut (a message may quote a file's values).
    pub fn new(code: Code, message: impl Into<String>) -> Self {
        Diagnostic {
            code,
            severity: code.default_severity(),
            location: Location::default(),
            message: bounded(message.into()),
            help: None,
        }
    }
    /// A [`Code::Parse`] error.
    pub fn parse(message: impl Into<String>) -> Self {
        Self::new(Code::Parse, message)
    }
    /// A [`Code::Invalid`] error.
    pub fn invalid(message: impl Into<String>) -> Self {
        Self::new(Code::Invalid, message)
    }
    /// A [`Code::Frame`] error.
    pub fn frame(message: impl Into<String>) -> Self {
        Self::new(Code::Frame, message)
    }
    /// A [`Code::Usage`] error.
    pub fn usage(message: impl Into<String>) -> Self {
        Self::new(Code::Usage, message)
    }
    /// A [`Code::Limit`] error.
    pub fn limit(message: impl Into<String>) -> Self {
        Self::new(Code::Limit, message)
    }
    /// A [`Code::Io`] error reading `path`.
    pub fn io(path: &Path, err: &std::io::Error) -> Self {
        Self::new(Code::Io, format!("cannot read: {err}")).in_file(path)
    }
    /// The same diagnostic with another severity.
    pub fn with_severity(mut self, severity: Severity) -> Self {
        self.severity = severity;
        self
    }
    /// The same diagnostic with help text.
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(bounded(help.into()));
        self
    }
    /// Attach a file, keeping a line that is already known.
    pub fn in_file(mut self, path: impl AsRef<Path>) -> Self {
        if self.location.file.is_none() {
            self.location.file = Some(path.as_ref().into());
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
    /// Attach the parts of `loc` that are not known yet.
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
    /// Exit code of a command that fails with this error: 2 (usage or input).
    pub fn exit_code(&self) -> i32 {
        2
    }
}

impl fmt::Display for Diagnostic {
    /// Errors: `file:line:col: message`; warnings: `warning[code]: file:line:col:
    /// message`; a warning's code at severity error: `error[code]: ...` (the
    /// place omitted when unknown).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.severity == Severity::Warning {
            write!(f, "warning[{}]: ", self.code)?;
        } else if self.code.default_severity() == Severity::Warning {
            // A warning's code raised to an error (beyond rounding, or a policy).
            write!(f, "error[{}]: ", self.code)?;
        }
        if self.location.is_empty() {
            write!(f, "{}", self.message)
        } else {
            write!(f, "{}: {}", self.location, self.message)
        }
    }
}

impl std::error::Error for Diagnostic {}

impl serde::Serialize for Diagnostic {
    /// `{severity, code, file, line, column?, message, help?}`: `file` is ""
    /// and `line` null when unknown.
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("severity", &self.severity)?;
        m.serialize_entry("code", &self.code)?;
        let file = self
            .location
            .file
            .as_ref()
            .map(|f| f.to_string_lossy().replace('\\', "/"))
            .unwrap_or_default();
        m.serialize_entry("file", &file)?;
        m.serialize_entry("line", &self.location.line)?;
        if let Some(c) = self.location.column {
            m.serialize_entry("column", &c)?;
        }
        m.serialize_entry("message", &self.message)?;
        if let Some(h) = &self.help {
            m.serialize_entry("help", h)?;
        }
        m.end()
    }
}

/// `s` shortened to [`MAX_MESSAGE_CHARS`] ([`crate::sanitize::shorten`]).
fn bounded(s: String) -> String {
    match crate::sanitize::shorten(&s, MAX_MESSAGE_CHARS) {
        std::borrow::Cow::Borrowed(_) => s,
        std::borrow::Cow::Owned(o) => o,
    }
}

/// `Result` with a [`Diagnostic`] error.
pub type Result<T, E = Error> = std::result::Result<T, E>;
