//! Every tolerance, default and resource limit of the crate, in one place,
//! each documented where it is defined (what it decides, in which unit, and why
//! that value). Modules import them from here; none defines its own.
//! How output looks is not a tolerance and lives with what draws it: the
//! printed precision of numbers in [`crate::document::numbers`], the table
//! layout in [`crate::render::layout`], the survey plot's size and range in
//! `report::survey_plot`.
//!
//! Absolute tolerances are in metres and radians unless the name says
//! otherwise (`_DEG`: degrees).

// ---------------------------------------------------------------------------
// Geometry: rotations, quaternions, screws (`geometry`)
// ---------------------------------------------------------------------------

/// Frobenius distance `||R^T R - I||_F` at or below which a rotation matrix is
/// taken as given (no projection): double-precision rounding of exact entries.
pub const ORTHONORMAL_EXACT_TOL: f64 = 1e-14;

/// `||R^T R - I||_F` above which a rotation is projected with a
/// `non-orthonormal-rotation` warning. Published calibrations print 6 to 9
/// significant digits, which leaves an error near 1e-7; 1e-6 lets those pass
/// quietly and flags values rounded to four or five digits.
pub const ORTHONORMAL_WARN_TOL: f64 = 1e-6;

/// `||R^T R - I||_F` above which the matrix is not accepted as a rotation.
/// A four-digit rounding of a real rotation stays below 1e-3.
pub const ORTHONORMAL_ERROR_TOL: f64 = 1e-2;

/// `| ||q|| - 1 |` above which a quaternion is normalised with a
/// `non-unit-quaternion` warning (seven printed digits stay below it).
pub const QUATERNION_WARN_TOL: f64 = 1e-6;

/// `||R^T R - I||_F` up to which a non-orthonormal rotation is rounding of
/// published digits: a `non-orthonormal-rotation` *warning* (projected, the gate
/// passes). Beyond it, up to [`ORTHONORMAL_ERROR_TOL`], the diagnostic has
/// severity `error` (`audit check` fails; `--allow` accepts it). 5e-3 is the
/// matrix analogue of a quaternion off by 1e-3: `R` scaled by `1 + 1.4e-3`
/// (`||R^T R - I||_F = sqrt(3) ((1 + e)^2 - 1)`), or every entry rounded to three
/// decimals. The shipped calibrations reach 1.3e-4 (GEODE's four-digit matrices).
pub const ORTHONORMAL_ROUNDING_TOL: f64 = 5e-3;

/// `| ||q|| - 1 |` up to which a non-unit quaternion is rounding: a
/// `non-unit-quaternion` *warning* (normalised, the gate passes); beyond it the
/// diagnostic has severity `error`. A quaternion printed with three digits
/// (norm 1.001) is a warning; one of norm 1.01 is an error.
pub const QUATERNION_ROUNDING_TOL: f64 = 2e-3;

/// Quaternion norm below which there is no rotation to recover: an error.
pub const QUATERNION_MIN_NORM: f64 = 1e-6;

/// Rotation angle (rad) below which a transform is treated as having no rotation:
/// its screw axis would lie `||d|| / phi` away, beyond any physical meaning.
pub const ANGLE_ZERO_TOL: f64 = 1e-9;

/// Length (m) below which a translation is zero: a picometre, far below any
/// calibration, far above the rounding of a composed chain.
pub const LENGTH_ZERO_TOL: f64 = 1e-12;

/// `sin(phi)` at or below which a rotation is an exact half-turn for the purpose
/// of choosing the axis sign (the skew part carries no sign information there).
pub const HALF_TURN_SIN_TOL: f64 = 1e-12;

/// Tolerance on the bottom row `[0 0 0 1]` of a homogeneous matrix.
pub const BOTTOM_ROW_TOL: f64 = 1e-9;

/// Axis norm below which an axis-angle rotation axis counts as zero (an error).
pub const AXIS_MIN_NORM: f64 = 1e-12;

// ---------------------------------------------------------------------------
// URDF joints (`formats::urdf`)
// ---------------------------------------------------------------------------

/// `| ||axis|| - 1 |` above which a movable joint's axis is normalised with a
/// `non-unit-axis` warning (nine printed digits stay below it).
pub const UNIT_AXIS_TOL: f64 = 1e-9;

/// Largest `|value|` a `--joint NAME=VALUE` takes (rad or m): a prismatic
/// joint beyond [`MAX_TRANSLATION_M`] is refused anyway, and a revolute angle
/// of a million radians means a typo; refused before any file is read.
pub const MAX_JOINT_VALUE: f64 = 1e6;

/// A `--joint` value on a revolute or continuous joint above this (rad) in
/// magnitude looks like degrees: a `degrees-in-radian-field` warning.
pub const DEGREES_LIKE_RAD: f64 = 2.0 * std::f64::consts::PI;

// ---------------------------------------------------------------------------
// Certificate bands (`geometry::certificate`)
// ---------------------------------------------------------------------------

/// Most characteristic lengths one analysis carries (fixed capacity, no heap).
pub const MAX_ELLS: usize = 8;

/// Relative margin around the band edges inside which a ratio is treated as
/// *inside* the band (not certified). The computed edges `s_min^2`, `s_max^2` and
/// the ratio `lambda / kappa` each carry a few ulps of rounding; 8 ulps cover
/// them, so a ratio reported as outside is outside the exact band too.
pub const BAND_EDGE_MARGIN: f64 = 8.0 * f64::EPSILON;

/// Accepted characteristic lengths `--ell` (m). With a lever arm up to
/// [`MAX_TRANSLATION_M`] the band edges grow like `(||d|| / ell)^2`, at most
/// 1e24 here: finite, so no band field of a report becomes `null`.
pub const ELL_RANGE_M: (f64, f64) = (1e-6, 1e6);

/// Accepted detector threshold `--kappa` (and the largest `--lambda`): the
/// ratio `lambda / kappa` stays below 1e200 and the band products finite.
pub const KAPPA_RANGE: (f64, f64) = (1e-100, 1e100);

// ---------------------------------------------------------------------------
// Frame graph (`frames`)
// ---------------------------------------------------------------------------

/// Two edges between the same frames agree when their translations differ by at
/// most this (m)...
pub const DUPLICATE_TRANSLATION_TOL: f64 = 1e-9;

/// ...and the rotation between them is at most this angle (rad).
pub const DUPLICATE_ROTATION_TOL: f64 = 1e-9;

/// Deepest level [`FrameGraph::tree`](crate::frames::FrameGraph::tree) indents.
pub const TREE_MAX_INDENT: usize = 40;

/// Frames listed in a cycle message before the middle is elided.
pub const CYCLE_LIST_MAX: usize = 12;

/// A redundant edge (one that closes a loop in a file, Kalibr's `T_cn_cnm1`
/// beside the cameras' `T_cam_imu`) agrees with the tree path between its
/// frames when their translations differ by at most this (m): the files print
/// 8 or so significant digits and a calibration is good to millimetres, so a
/// larger gap means the file's own numbers do not close the loop...
pub const REDUNDANT_TRANSLATION_TOL: f64 = 1e-3;

/// ...and the rotation between them is at most this angle (rad, 0.057 deg).
pub const REDUNDANT_ROTATION_TOL: f64 = 1e-3;

// ---------------------------------------------------------------------------
// Reading files (`formats`)
// ---------------------------------------------------------------------------

/// Default cap on the size of one input file (bytes); `--max-file-size` changes it.
pub const DEFAULT_MAX_FILE_SIZE: u64 = 16 * 1024 * 1024;

/// A translation component above this (m) in a field documented as metres is
/// reported as `millimetres-in-metre-field`: no LiDAR extrinsic in the survey
/// exceeds 2 m.
pub const METRE_FIELD_WARN_M: f64 = 10.0;

/// A translation component above this (m) is refused: no sensor extrinsic is
/// 1000 km long, and beyond it the analysis squares lengths towards the ends of
/// the f64 range (adjoint singular values `||d||^{\pm 1}`, bands `||d||^{\pm 2}`),
/// so a report would print numbers that mean nothing.
pub const MAX_TRANSLATION_M: f64 = 1e6;

/// Deepest YAML nesting read (block and flow). Calibration files nest at
/// most ~8 levels (a tf_static dump); the deserializer recurses once per level
/// with a large frame (tens of KiB in a debug build).
pub const MAX_YAML_DEPTH: usize = 32;

/// Longest string the Python reader (launch `$(eval ...)`, launch.py)
/// creates, in bytes: by `+`, `*`, `str.join`/`replace`/`zfill`/`format`,
/// f-strings, `str()`/`repr()`. Launch files build names and numbers of tens
/// of bytes; a file asking for more is refused before the string exists.
pub const MAX_PY_STR_BYTES: usize = 1 << 20;

/// Most items in one list, tuple or dict the Python reader creates (`range`,
/// comprehensions, `+`, `append`/`extend`, `split`, iterating a string).
pub const MAX_PY_ITEMS: usize = 100_000;

/// The Python reader's work budget for one file, in bytes: every value an
/// expression evaluates to is charged its size (a string its bytes, a tuple
/// or dict its items, a list its slots, each value 32 bytes), so the values
/// a file creates in all, which bounds the memory it can hold, stay under
/// 256 MiB. Evaluating a real launch file charges a few KiB.
pub const MAX_PY_WORK_BYTES: usize = 256 << 20;

/// Deepest nesting of lists, tuples and dicts in one another that the Python
/// reader creates (`[[...]]` built in a loop): printing, comparing, copying
/// and dropping a value recurse once per level. Launch files nest 2-3
/// levels (a list of parameter dicts); a value deeper than this is refused
/// when it is evaluated, before anything walks it (the xacro evaluator's
/// `XACRO_MAX_VALUE_DEPTH` is the same number, for the same reason).
pub const MAX_PY_VALUE_DEPTH: usize = 100;

/// Calls of a launch.py file's own functions nested deeper than this are
/// refused (a function that calls itself).
pub const MAX_PY_CALL_DEPTH: usize = 32;

/// Loop iterations and function calls a launch.py file may make in all,
/// beyond which it is refused (a real file makes tens).
pub const MAX_PY_STEPS: usize = 100_000;

/// Largest baseline file read or written by `audit check` (bytes). The
/// baseline is streamed both ways and held compactly (`baseline::Store`, about
/// a fifth of its text), and `--write-baseline` refuses to write one past this
/// cap, so that every baseline the tool writes it reads. The tool writes about
/// 1 KB per file of one edge and one pair (pretty JSON: 102 MB for 100,000
/// rig files), so 1 GiB is about a million such files, held in about 200 MB.
pub const MAX_BASELINE_FILE_SIZE: u64 = 1024 * 1024 * 1024;

/// Largest `audit.toml` read by `audit check` (bytes): a manifest names a few
/// robots with their files, renames and pairs, well under a KiB each.
pub const MAX_MANIFEST_FILE_SIZE: u64 = 1024 * 1024;

/// Largest `--initial-guess-file` read (bytes): a 4x4 matrix as a registration
/// tool or a person writes it is under 1 KiB.
pub const MAX_MATRIX_FILE_SIZE: u64 = 64 * 1024;

/// Random characters (letters and digits, 62 each: 71 bits) in the name of a
/// temporary file the writer creates beside its target
/// (`pipeline::write_atomic`): a name planted in advance is never met.
pub const WRITE_TEMP_RANDOM_CHARS: usize = 12;

/// Temporary files registered at once for removal on SIGINT, SIGTERM and
/// SIGHUP (`pipeline::cleanup`; each write registers one for its duration: a
/// command writes one or two). A write beyond it still works, unprotected
/// against those signals.
pub const MAX_SIGNAL_CLEANUP_PATHS: usize = 64;

/// Longest value (characters) a message quotes from a file before it is
/// shortened (the head and the tail kept, with the count of what was cut).
pub const MAX_QUOTED_CHARS: usize = 120;

/// Longest message (characters) any diagnostic carries: a backstop for
/// messages that quote several values.
pub const MAX_MESSAGE_CHARS: usize = 2000;

/// Largest message, chunk (after decompression) or record a bag reader
/// takes (bytes). rosbag2 and `rosbag record` write chunks of 768 KiB to a
/// few MiB, a chunk holding at least one message; the largest legitimate
/// messages are far below this: a 128k-point `PointCloud2` (Ouster OS1-128,
/// 48-byte points) is ~6 MiB, a 262k-point one 12 MiB, a robot description a
/// few MiB, an uncompressed 4K RGB image 24 MiB. A length beyond it is
/// corruption or a bomb, refused before allocating, and a decompression stops
/// as its output passes it. At most one chunk is decompressed at a time, so
/// this bounds the reader's memory (issue 27: 1 GiB at most overall).
pub const MAX_BAG_MESSAGE_BYTES: usize = 256 << 20;

/// Largest rosbag2 `metadata.yaml` read (bytes): a few KiB in practice, with
/// one entry per split file and topic.
pub const MAX_BAG_METADATA_BYTES: u64 = 16 * 1024 * 1024;

/// A bag file decompresses to at most this many times its own size in all
/// (every chunk, message and compressed split counted), or
/// [`MIN_BAG_FILE_OUTPUT_BYTES`], whichever is larger. Recorded sensor data
/// compresses 1.5-4x with zstd, lz4 or bz2 (organised clouds full of NaN
/// no-returns up to ~20x); 100x leaves room for all of it, while a bomb (18 KB
/// bz2 chunks that grow to GBs) stops after a bounded amount of work: the cap
/// bounds the time as well as the disk a compressed split's temporary file
/// takes.
pub const MAX_BAG_EXPANSION: u64 = 100;

/// The per-file decompression cap of a small file (bytes): 1 GiB, so that a
/// small bag with one large compressed message still reads.
pub const MIN_BAG_FILE_OUTPUT_BYTES: u64 = 1 << 30;

/// Most bytes of messages the transform reader keeps from one bag (`/tf_static`,
/// `/robot_description`, on request `/tf`): every message is decoded after
/// the read, so they are held together. A bag's static tree and description
/// take kilobytes to a few MiB; a `/tf` of an hour at 1 kHz ~200 MiB.
pub const MAX_BAG_KEPT_BYTES: usize = 512 << 20;

/// SQLite's hard heap limit (bytes, process-wide), set before the first
/// `.db3` is opened: a query over a hostile database (a recursive view, a
/// huge sort) fails with "out of memory" instead of growing; reading a bag
/// needs a few MiB (the page cache below and one row at a time).
pub const MAX_SQLITE_HEAP_BYTES: i64 = 256 << 20;

/// SQLite's page cache per connection (KiB): enough for the table scans of a
/// rosbag2 read, well inside [`MAX_SQLITE_HEAP_BYTES`].
pub const MAX_SQLITE_CACHE_KIB: u32 = 16 * 1024;

/// A bag read that will go through at least this many bytes shows a progress
/// line on stderr when stderr is a terminal (below it the read takes well
/// under a second).
pub const BAG_PROGRESS_MIN_BYTES: u64 = 64 * 1024 * 1024;

/// Most elements one xacro expansion may produce. The largest description in
/// the fixtures (a UR arm with ros2_control) expands to about 400 elements
/// and a full mobile manipulator to a few thousand; beyond 200 000 it is a
/// macro bomb (each doubling macro level doubles the count).
pub const XACRO_MAX_ELEMENTS: usize = 200_000;

/// Most bytes of text (attributes and text) one xacro expansion may produce.
pub const XACRO_MAX_OUTPUT_BYTES: usize = 32 * 1024 * 1024;

/// Longest string one `${...}` value may be (bytes): `'a' * 10**9` stops
/// here. The longest attribute of the real-package corpus is a few hundred
/// bytes (docs/xacro.md).
pub const XACRO_MAX_STRING_BYTES: usize = 4 * 1024 * 1024;

/// Most items one list, tuple or dict of a `${...}` expression may hold
/// (`[0] * 10**9` stops here; a million values take 24 MB).
pub const XACRO_MAX_LIST_ITEMS: usize = 1_000_000;

/// Most bytes of values (strings, lists, dicts) one expansion may create in
/// all, counted as they are created, so live memory stays below it however
/// values are shared or dropped. Real descriptions create a few hundred KB.
pub const XACRO_MAX_EVAL_BYTES: u64 = 256 * 1024 * 1024;

/// Most evaluation steps of one expansion: an expression node, an element,
/// an item copied, compared or printed, 16 bytes of text scanned each count
/// one. The real-package corpus takes at most about 60 000 (docs/xacro.md);
/// ten million take about a second (a debug build: several), and stop an
/// expression over shared nested lists (exponential work in little text)
/// well before [`XACRO_MAX_SECONDS`].
pub const XACRO_MAX_STEPS: u64 = 10_000_000;

/// Deepest nesting of macro calls. Python xacro stops at Python's recursion
/// limit (1000 frames, a few dozen frames per call); real files nest fewer
/// than 10 levels.
pub const XACRO_MAX_MACRO_DEPTH: usize = 100;

/// Deepest nesting of `xacro:include` (a file including itself stops here).
pub const XACRO_MAX_INCLUDE_DEPTH: usize = 32;

/// Deepest nesting of elements, in a source file and in the expansion
/// (counting macro bodies, blocks and `xacro:if`/`unless` as levels). Python
/// xacro 2.1.1 fails between 500 and 1000 nested elements (measured; its
/// recursion limit); a URDF nests about five.
pub const XACRO_MAX_ELEMENT_DEPTH: usize = 500;

/// Deepest chain of lazy properties evaluated inside one another (`a` is
/// `${b}`, `b` is `${c}`, ...). Python xacro 2.1.1 fails between 150 and 200
/// (measured); real files chain a few.
pub const XACRO_MAX_PROPERTY_DEPTH: usize = 150;

/// Wall time (s) after which an expansion is stopped (the built-in expander,
/// and the child of `--xacro external`, killed with its process group); real
/// descriptions expand in milliseconds.
pub const XACRO_MAX_SECONDS: f64 = 10.0;

/// `--xacro external`: once the child has exited, how long (s) its output
/// pipes may stay open (a background process it left holding them is killed
/// with the process group first; one outside the group is given up on).
pub const XACRO_EXTERNAL_DRAIN_SECONDS: f64 = 1.0;

/// Most bytes of the external `xacro` program's stderr kept for the error
/// message (`--xacro external`); Python tracebacks of real failures are a few
/// KiB.
pub const XACRO_MAX_STDERR_BYTES: u64 = 16 * 1024;

/// Deepest nesting of one `${...}` expression, in nodes: parentheses, unary
/// operators, `**`, conditional expressions, calls and subscripts inside one
/// another, lists in lists (a chain of one operator, `a + b + c + ...`, is
/// one level, as are `x[0][1]` and `a.b.c`). Python refuses more than 200
/// nested parentheses; real expressions nest a few levels.
pub const XACRO_MAX_EXPR_DEPTH: usize = 100;

/// Deepest nesting of list, tuple and dict values that printing, comparing
/// and searching walk (`[[[...]]]` built through properties).
pub const XACRO_MAX_VALUE_DEPTH: usize = 100;

/// `$(find pkg)`: directory levels searched below each package-path entry
/// (a colcon workspace keeps packages at `src/<repo>/<pkg>`).
pub const XACRO_PACKAGE_SEARCH_DEPTH: usize = 3;

/// `$(find pkg)` without a package path: ancestor directories of the input
/// searched (each with [`XACRO_PACKAGE_SEARCH_DEPTH`] levels below it).
pub const XACRO_PACKAGE_SEARCH_UP: usize = 3;

/// `$(find pkg)`: most directories one search visits (a package path
/// pointing at `/` or a huge tree stops here with the count, not after
/// minutes). A ROS distribution's share directory holds about 1 000
/// packages.
pub const XACRO_PACKAGE_SEARCH_MAX_DIRS: usize = 20_000;

/// `$(find pkg)`: bytes of each `package.xml` read to find its `<name>`
/// (the name is near the top; real manifests are a few KiB).
pub const XACRO_PACKAGE_XML_BYTES: u64 = 64 * 1024;

/// Deepest element nesting the URDF reader reads. A URDF nests about five
/// levels (robot, link, visual, geometry, mesh); the pull reader's namespace
/// scopes count levels in 16 bits, so a deeper document is refused here, well
/// before that (issue 12).
pub const URDF_MAX_XML_DEPTH: usize = 1000;

/// Smallest zstd window (log2 bytes) an Arrow IPC buffer's decoder accepts
/// (`formats::arrow_ipc`): 2 MiB, zstd's window at its default level 3 when
/// the writer did not give the size. Above it the window may be as large as
/// the buffer's claimed length (itself within the `--max-file-size` budget),
/// so a forged frame header cannot make the decoder allocate more.
pub const ARROW_ZSTD_MIN_WINDOW_LOG: u32 = 21;

// ---------------------------------------------------------------------------
// Rig analysis and verdicts (`analysis`)
// ---------------------------------------------------------------------------

/// Entry-wise tolerance for "R is a signed permutation" (each entry within it of
/// 0 or +-1). A rotation written with nine or more digits passes; `rpy` given to
/// five digits (an error near 1e-6) does not.
pub const SIGNED_PERMUTATION_TOL: f64 = 1e-9;

/// Absolute zero-pitch tolerance on `|h|` (m) where no uncertainty is at hand
/// (the detector's adapted metric, library callers of `analyze`). The reports
/// default to `--pitch-tol auto` (`PITCH_K`); this is also their floor
/// (`PITCH_FLOAT_FLOOR_M`).
pub const DEFAULT_PITCH_TOL: f64 = 1e-9;

/// Rotation angle (degrees) below which a rig's screw axis is set by calibration
/// noise around the identity rather than by the mounting. The survey flags such
/// rigs "small rotation: axis set by calibration noise" and prints `h` beside the
/// angle; they still count as nonzero pitch unless `|h|` is within the pitch
/// tolerance (see calibrations/README.md). 5 degrees: the real near-identity rigs
/// shipped here rotate 0.35 to 3.1 degrees (the issue: "0.3 to 3 degrees") and the
/// next smallest rotation is a deliberate 53.6-degree mount, so any threshold
/// between 3.1 and 53 degrees classifies the shipped rigs the same way.
pub const SMALL_ROTATION_DEG: f64 = 5.0;

/// Angle (rad) within which of a half-turn the table marks `h` (`±`): its sign
/// follows the rounding of the published numbers.
pub const NEAR_HALF_TURN_RAD: f64 = 1e-6;

/// `k` of the three-way pitch verdict (`--pitch-tol auto`,
/// [`crate::geometry::uncertainty`]): `h` is zero when within `k` standard
/// uncertainties. 3: a uniform rounding never exceeds `sqrt(3)` of its standard
/// uncertainty, and a Gaussian calibration error exceeds 3 of them 0.3% of the time.
pub const PITCH_K: f64 = 3.0;

/// Widest `PITCH_K * sigma_h` (m) at which "`h` is consistent with zero" still
/// means zero pitch: a millimetre, the precision of published LiDAR-IMU
/// calibrations. Wider, the verdict is `undecidable`.
pub const PITCH_RESOLUTION_M: f64 = 1e-3;

/// `|h|` (m) at or below which `h` is zero whatever its uncertainty: the old
/// absolute default, far above the double rounding of a composed chain (about
/// 1e-16 m per metre of lever arm) and far below any written digit.
pub const PITCH_FLOAT_FLOOR_M: f64 = DEFAULT_PITCH_TOL;

/// A number literal with this many significant digits or more is the shortest
/// print of a double (what a xacro expression such as `${pi/2}` writes, 16 or
/// 17 digits): exact, no rounding of its own.
pub const EXACT_SIGNIFICANT_DIGITS: usize = 16;

/// Step of the central differences of the uncertainty propagation (rad or m,
/// relative above 1). The truncation error is of order step^2 = 1e-12 relative;
/// the cancellation error 1e-16 / 1e-6 = 1e-10 relative.
pub const UNCERTAINTY_STEP: f64 = 1e-6;

/// Largest `--sigma-t` (m) accepted: a metre of calibration uncertainty is no
/// calibration; first order is meaningless long before.
pub const MAX_SIGMA_T_M: f64 = 1.0;

/// Largest `--sigma-r` (degrees) accepted: beyond 10 degrees the first-order
/// propagation is no longer within 10% of Monte Carlo.
pub const MAX_SIGMA_R_DEG: f64 = 10.0;

// ---------------------------------------------------------------------------
// `audit check` drift against a baseline
// ---------------------------------------------------------------------------

/// Default drift tolerance on a translation (m): a millimetre, below what a
/// recalibration moves on purpose and above the printed digits of any format.
pub const DEFAULT_MAX_TRANSLATION_DRIFT: f64 = 1e-3;

/// Default drift tolerance on a rotation (deg): the angle of `R_base^T R_now`.
pub const DEFAULT_MAX_ROTATION_DRIFT_DEG: f64 = 0.05;

/// Deepest directory level `audit check` walks below a checked directory. A
/// calibration tree is shallow (a ROS workspace nests ~6 levels); a directory
/// deeper than this is a `limit` finding (an error), never skipped silently.
/// Symlink loops are caught by the walk's visited set, not by this limit.
pub const MAX_WALK_DEPTH: usize = 64;

/// File names a directory walk never reads as calibrations: the manifest and
/// build files of every ROS package (`package.xml` has a `.xml` name,
/// `CMakeLists.txt` a `.txt` one).
pub const DEFAULT_WALK_EXCLUDES: &[&str] = &["package.xml", "CMakeLists.txt"];

/// Default `audit diff --tolerance` on a translation change (mm): the length
/// of `d_new - d_old`, per edge and for the composed chain. A millimetre, as
/// [`DEFAULT_MAX_TRANSLATION_DRIFT`]: below what a recalibration moves on
/// purpose, above the printed digits of any format.
pub const DEFAULT_DIFF_TRANSLATION_TOL_MM: f64 = 1.0;

/// Default `audit diff --tolerance` on a rotation change (deg): the angle of
/// `R_old^T R_new`, as [`DEFAULT_MAX_ROTATION_DRIFT_DEG`].
pub const DEFAULT_DIFF_ROTATION_TOL_DEG: f64 = 0.05;

// ---------------------------------------------------------------------------
// Many calibrations of one frame pair (`audit spread`, `analysis::spread`)
// ---------------------------------------------------------------------------

/// Relative gap `(w4 - w3) / w4` of the top two eigenvalues of `K = sum q q^T`
/// below which the chordal rotation mean is not unique (rotations spread over
/// a great circle): an error rather than an arbitrary answer. Repeated
/// calibrations have a gap near 1 (0.99998 for 0.05 deg scatter).
pub const SPREAD_MEAN_MIN_GAP: f64 = 1e-6;

/// Fewest calibrations the outlier rule is applied to: with two, the median
/// lies midway and neither can be told from the other.
pub const OUTLIER_MIN_COUNT: usize = 3;

/// Below this many calibrations the robust scale (the MAD of a handful of
/// numbers) is itself uncertain, and the report says so: the rule flags 7.6 %
/// of clean calibrations at N = 5 and 1.9 % at N = 10 (simulation in
/// tests/fixtures/spread/outlier_rule_simulation.txt).
pub const OUTLIER_FEW: usize = 10;

/// The normal consistency constant of the MAD: `sigma = MAD / 0.6745` for
/// normal data (Iglewicz and Hoaglin, 1993; NIST/SEMATECH e-Handbook 1.3.5.17).
pub const MAD_NORMAL_CONSTANT: f64 = 0.6745;

/// Floor of the MAD of the translation deviations (m): 0.01 mm, so identical
/// values (a copied file) do not divide by zero.
pub const MAD_FLOOR_M: f64 = 1e-5;

/// Floor of the MAD of the rotation deviations (deg): 0.001 deg.
pub const MAD_FLOOR_DEG: f64 = 1e-3;

/// The chi(3) radius whose tail equals the two-sided normal tail of Iglewicz
/// and Hoaglin's `|M| > 3.5` (`2 Phi(-3.5) = 4.65e-4`): a standardised 3-D
/// distance beyond it flags a calibration (`sqrt(chi2.isf(2 norm.sf(3.5), 3))`
/// in scipy).
pub const OUTLIER_RADIUS: f64 = 4.228678646349064;

/// [`OUTLIER_RADIUS`] over the median of chi(3) (1.5382): the limit also
/// grows with the median distance, `max(ratio * median d, radius)`, so a
/// noisy robust scale from few calibrations does not flag half of them.
pub const OUTLIER_RATIO: f64 = 2.7491580569740623;

// ---------------------------------------------------------------------------
// Degeneracy detector (`degeneracy`)
// ---------------------------------------------------------------------------

/// Default degeneracy threshold on generalized eigenvalues (`lambda < tau`).
pub const DEFAULT_TAU: f64 = 1e-2;

/// Relative pivot tolerance of the Cholesky factorisation of a metric: pivot `k`
/// (the Schur complement `d_k` before the square root) must exceed
/// `CHOLESKY_REL_TOL * M_kk`. The ratio `d_k / M_kk` is invariant to the length
/// unit (a diagonal rescaling), so the test does not depend on metres versus
/// millimetres. For exactly collinear points the ratio is rounding (`~1e-16`).
pub const CHOLESKY_REL_TOL: f64 = 1e-10;

/// In the canonical basis of a degenerate subspace, a direction whose rotational
/// part has singular value at or below this (for a unit coordinate vector) is a
/// pure translation.
pub const PURE_TRANSLATION_TOL: f64 = 1e-6;

/// `|pitch|` (m/rad) at or below which a degenerate twist is a pure rotation
/// about an axis (zero pitch).
pub const TWIST_PITCH_TOL: f64 = 1e-9;

/// Jacobi metric: a diagonal entry of `H` below `JACOBI_FLOOR * max_k H_kk` is
/// raised to that floor (a zero diagonal entry means that row of `H` is zero, the
/// axis is exactly unobserved, and its generalized eigenvalue is 0 whatever the
/// floor).
pub const JACOBI_FLOOR: f64 = 1e-12;

/// Default characteristic lengths (m).
pub const DEFAULT_ELLS: [f64; 4] = [0.25, 1.0, 2.85, 10.0];

/// Largest simulated range noise `--noise` (m, one standard deviation): the
/// scenes span a few metres, so a metre of noise already erases them.
pub const MAX_SIM_NOISE_M: f64 = 1.0;

/// Accepted voxel sizes `--voxel` of the simulation (m): below 2 cm the
/// scenes hold millions of points; above 10 m a scene is one voxel.
pub const SIM_VOXEL_RANGE_M: (f64, f64) = (0.02, 10.0);

/// Most seeds per configuration and scene `calibrate-threshold --seeds`
/// takes: each seed is three scenes per configuration (216 instances at the
/// default eight); a thousand is hours of work.
pub const MAX_CALIBRATION_SEEDS: u64 = 1000;

/// Most worker threads `calibrate-threshold --threads` starts (the scenes are
/// independent; more threads than cores only add memory).
pub const MAX_CALIBRATION_THREADS: usize = 64;

/// Most values a list option of `calibrate-threshold` takes (`--noise`,
/// `--voxel`): each one multiplies the sweep.
pub const MAX_LIST_VALUES: usize = 16;

/// Footprint of a real scan's degenerate subspace (`audit degeneracy`): an
/// axis is flagged when its score, the diagonal entry of the Euclidean
/// projector onto the subspace (in `[0, 1]`, summing to the dimension), is at
/// least this. On a ground plane the in-plane axes score about 0.996 and the
/// others below 0.01 (issue 16), where the absolute 1e-6 used before flagged
/// all six.
pub const FOOTPRINT_SCORE_TOL: f64 = 0.1;

/// A degenerate direction is a translation when its rotation fraction
/// `L |omega| / |[L omega; t]|` about the centroid (`L` the cloud's RMS radius)
/// is at most this: translation-dominated (its rotation moves the points by
/// at most 0.3 of what the whole twist does). On the ground-plane crop of the
/// real scan (tests/fixtures/detector/scans) the two in-plane translations
/// score 0.16 and 0.02 and the rotation about the vertical 1.0; the issue's
/// "general screws" with pitch 18.5 and 60.5 m/rad scored about 0.26 and 0.08.
pub const ROTATION_FRACTION_TOL: f64 = 0.3;

/// A degenerate rotation is zero-pitch when `|pitch| <= SCREW_PITCH_REL_TOL * L`
/// (`L` the cloud's RMS radius): it advances by at most a tenth of the cloud's
/// size per radian.
pub const SCREW_PITCH_REL_TOL: f64 = 0.1;

/// Default neighbourhood radius (m) of `audit degeneracy --estimate-normals`:
/// the synthetic pipeline's 0.30 m (paper).
pub const RAW_NORMAL_RADIUS_M: f64 = 0.30;

/// Default fewest neighbours (the point itself counted) for a normal of a raw
/// scan: the synthetic pipeline's 8 (paper).
pub const RAW_MIN_NEIGHBOURS: usize = 8;

/// Duplicate points of a raw scan, merged before the voxel grid and the
/// normals (`degeneracy::normals::merge_duplicates`): two points are one when
/// they fall in the same cell of a grid (anchored at the origin) whose edge
/// is this fraction of the scan's scale `max(1 m, largest |coordinate|)`.
/// 2^-40 (9.1e-13) is a few thousand f64 ulps of the largest coordinate: it
/// merges every exact duplicate (a driver or a converter repeating records)
/// and points equal but for arithmetic rounding, and nothing a sensor can
/// resolve: 0.9 pm near the origin, 3.6 um for UTM coordinates of 4e6 m (a
/// LiDAR resolves millimetres). Relative, so far-from-origin scans are
/// treated as ones at the origin; points that differ by less but straddle a
/// cell boundary stay two (each then a neighbour of the other, as any two
/// close points are).
pub const DUPLICATE_POINT_REL_TOL: f64 = 1.0 / (1u64 << 40) as f64;

/// Accepted `--voxel` of `audit degeneracy` (m): from a millimetre to 10 m.
pub const RAW_VOXEL_RANGE_M: (f64, f64) = (1e-3, 10.0);

/// Default correspondence gate of a scan pair (`audit degeneracy --target`,
/// m): the paper's 1.0 m.
pub const PAIR_GATE_M: f64 = 1.0;

// ---------------------------------------------------------------------------
// Point files (`degeneracy::points`)
// ---------------------------------------------------------------------------

/// `| |n| - 1 |` above which a normal is renormalised with a warning.
pub const NORMAL_UNIT_TOL: f64 = 1e-6;

/// `|n|` below which a normal is zero (an error).
pub const NORMAL_ZERO_TOL: f64 = 1e-12;

/// Largest accepted `|coordinate|`, in the file's unit. A LiDAR scan spans at most
/// kilometres (1e6 in millimetres); beyond 1e9 the squares summed into `H` and
/// `M` lose every digit of the small eigenvalues, and near 1e154 they overflow.
pub const MAX_COORDINATE: f64 = 1e9;

/// Largest `COUNT` of one PCD field.
pub const MAX_PCD_COUNT: usize = 1 << 16;

/// Largest point file read (bytes).
pub const MAX_POINT_FILE_SIZE: u64 = 4 * 1024 * 1024 * 1024;

/// Fewest points for which `degeneracy` assembly is split over threads (below
/// it, starting a thread costs about as much as it saves: 2^18 points are
/// about half a millisecond of assembly on one core).
pub const ASSEMBLY_PARALLEL_MIN_POINTS: usize = 1 << 18;

/// Read buffer of the streaming point-file readers (bytes).
pub const POINT_READ_BUFFER: usize = 1 << 16;

/// Longest line of a point file's header or of a text point file (bytes): a
/// binary file without line breaks is refused here instead of being buffered.
pub const MAX_POINT_LINE_BYTES: usize = 1 << 20;

/// Largest binary record of a point file (bytes; PCD descriptors use < 2 KiB).
pub const MAX_POINT_RECORD_BYTES: usize = 1 << 20;

/// Points decoded per call into the `las` crate (LAS and LAZ): 64 Ki points
/// of at most a few hundred bytes, a bounded buffer however many the header
/// claims.
pub const LAS_READ_BATCH: u64 = 1 << 16;

/// Point file size from which `degeneracy` and `sweep` show a progress bar
/// while reading (on a terminal only): 32 MiB, about 1.4 million points with
/// float normals, 0.7 million with double ones, or 3 to 10 million in LAZ.
pub const PROGRESS_MIN_BYTES: u64 = 32 << 20;

/// Point count from which `degeneracy` shows a progress bar (on a terminal).
pub const PROGRESS_MIN_POINTS: usize = 1 << 20;

/// A scan's weakest point-displacement direction counts as unconstrained by
/// every point when its eigenvalue (its Rayleigh quotient `v^T H v / v^T M v`,
/// in `[0, 1]`: the mean squared normal component of the points' motion over
/// their mean squared motion) is at most this: the points' shares of it
/// (`--format mcap`, `weakest_share`) are then rounding, and are written as 0.
pub const SHARE_ZERO_EIGENVALUE: f64 = 1e-12;

/// Most points of a scan drawn in its 3D scene (`--format mcap`): a larger
/// scan is drawn as every k-th point, k the smallest that fits (2 million
/// points are 32 MB of cloud data, about 43 MB in the file's base64 JSON,
/// which Foxglove loads whole).
pub const MAX_SCENE_CLOUD_POINTS: usize = 2_000_000;

// ---------------------------------------------------------------------------
// Recorded runs (`audit run`, `run`)
// ---------------------------------------------------------------------------

/// Default voxel edge (m) of a run's scans whose normals are estimated: the
/// paper's 0.10 m (its real-data pipeline), which the Python peer of the
/// benchmark also uses. A scan with normal fields is used as stored.
pub const RUN_VOXEL_M: f64 = 0.10;

/// Most cells (`height * width`) one scan may have: 2^22 (4.2 million; a
/// 128-beam, 2048-column sweep is 262,144). A larger scan is skipped with a
/// named warning; the bound keeps one scan's working memory (~130 bytes per
/// point with normals estimated) near 0.5 GiB.
pub const MAX_SCAN_CELLS: usize = 1 << 22;

/// Most cells of all the scans in flight at once (read, queued or being
/// worked on): the work queue waits below it (one scan is always let
/// through). With [`MAX_SCAN_CELLS`] it bounds a run's memory independently
/// of its length (docs/runs.md states the bound).
pub const MAX_RUN_INFLIGHT_CELLS: usize = 1 << 22;

/// Most scans in flight per worker thread (the queue's depth).
pub const RUN_SCANS_PER_WORKER: usize = 2;

/// A pose sample within this many seconds of a scan's time is the scan's
/// pose (no interpolation): the rounding of timestamps printed with 6 to 9
/// decimals, far below a scan period (0.1 s at 10 Hz).
pub const POSE_TIME_TOL_S: f64 = 1e-6;

/// Largest poses file read (bytes): a KITTI sequence's poses are ~200 B per
/// scan (4,541 scans: 0.9 MB); 256 MiB is a million scans' worth.
pub const MAX_POSE_FILE_BYTES: u64 = 256 << 20;

/// Most pairs a run's scan pairs reach back (`--pair-step`): each step held
/// back is one scan's bytes in memory.
pub const MAX_PAIR_STEP: usize = 64;

/// Points the timeline keeps per series at most: when a run has more scans,
/// neighbouring bins merge (the smallest eigenvalue of each bin kept), so
/// the picture costs the same for any length.
pub const TIMELINE_BINS: usize = 2048;

/// Degenerate intervals and label-change examples kept per family and frame
/// in the summary (the counts go on past them).
pub const MAX_RUN_EXAMPLES: usize = 1000;

/// Warnings printed per kind of skipped scan before the rest are only
/// counted (the CSV and JSON lines name every one).
pub const MAX_SKIP_WARNINGS: usize = 20;
