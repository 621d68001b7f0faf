//! Real third-party files (robot descriptions, calibration files, scans) are
//! not in this repository: tests read them in place from the test-data folder,
//! one folder per source repository (`<owner>__<repo>/<path in the repo>`),
//! listed with repository, commit, path and sha256 in its `MANIFEST.tsv`.
//!
//! The folder is `$EXTRINSIC_AUDIT_TEST_DATA`, else `test-data` in a `shared`
//! folder beside the checkout (`CARGO_MANIFEST_DIR/../shared/test-data`).
//! Where the folder has no `MANIFEST.tsv` the table of docs/test-data.md
//! (generated from it) stands in, so a contributor who fetched the files by
//! hand needs nothing else. [`file`] checks the sha256 before it hands a path
//! out: a wrong file fails the test, a missing one skips it with a message
//! naming the repository, commit and path to fetch. Each test that skipped is
//! counted, and the count is printed in one line when the test binary exits.
//! The same lookup for shell and Python: tools/testdata.py.

use sha2::{Digest, Sha256};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, Once, OnceLock};

/// The override of the folder's location.
pub const ENV: &str = "EXTRINSIC_AUDIT_TEST_DATA";

/// The documentation of the folder, with the manifest's table between these
/// markers.
pub const DOC: &str = "docs/test-data.md";
const TABLE_BEGIN: &str = "<!-- table:begin -->";
const TABLE_END: &str = "<!-- table:end -->";

// Files several modules read (paths inside the test-data folder).
pub const ANYMAL_C: &str =
    "Gepetto__example-robot-data/robots/anymal_c_simple_description/urdf/anymal.urdf";
pub const ANYMAL_D: &str = "ANYbotics__anymal_d_simple_description/urdf/anymal.urdf";
pub const PR2: &str = "Gepetto__example-robot-data/robots/pr2_description/urdf/pr2.urdf";
pub const UNITREE_H1: &str = "unitreerobotics__unitree_ros/robots/h1_description/urdf/h1.urdf";
pub const AUTZEN_LAS: &str = "gadomski__las-rs/tests/data/autzen.las";
pub const AUTZEN_LAZ: &str = "gadomski__las-rs/tests/data/autzen.laz";
pub const LAS_1_4: &str = "gadomski__las-rs/tests/data/32-1-472-150-76.laz";
pub const GICP_SCAN: &str = "koide3__fast_gicp/data/251370668.pcd";
pub const GICP_SCAN_2: &str = "koide3__fast_gicp/data/251371071.pcd";
pub const GICP_RELATIVE: &str = "koide3__fast_gicp/data/relative.txt";
pub const CAR6: &str = "PointCloudLibrary__pcl/test/car6.pcd";
pub const WARTHOG_XACRO: &str = "norlab-ulaval__warthog_mapping/params/warthog.urdf.xacro";
pub const OUSTER_OS0_JSON: &str =
    "ouster-lidar__ouster-sdk/tests/pcaps/OS-0-128-U1_v2.3.0_1024x10.json";
pub const LIOSAM_PARAMS: &str = "TixiaoShan__LIO-SAM/config/params.yaml";
pub const LIOSAM_MID360: &str = "nkymzsy__LIO-SAM-MID360/config/params9axisIMU.yaml";
pub const VELODYNE_SIMULATOR: &str = "ToyotaResearchInstitute__velodyne_simulator";

/// The real robot descriptions by the name expected_pairs.json and
/// urdf_reports.json give them (the file names they had in tests/fixtures/urdf).
pub const URDFS: &[(&str, &str)] = &[
    ("anymal_c.urdf", ANYMAL_C),
    ("anymal_d.urdf", ANYMAL_D),
    ("pr2.urdf", PR2),
    (
        "tiago_pro.urdf",
        "Gepetto__example-robot-data/robots/tiago_pro_description/robots/tiago_pro.urdf",
    ),
    (
        "turtlebot3_burger.urdf",
        "ROBOTIS-GIT__turtlebot3/turtlebot3_description/urdf/turtlebot3_burger.urdf",
    ),
    (
        "turtlebot3_waffle.urdf",
        "ROBOTIS-GIT__turtlebot3/turtlebot3_description/urdf/turtlebot3_waffle.urdf",
    ),
    (
        "unitree_b2.urdf",
        "unitreerobotics__unitree_ros/robots/b2_description/urdf/b2_description.urdf",
    ),
    (
        "unitree_g1_29dof.urdf",
        "unitreerobotics__unitree_ros/robots/g1_description/g1_29dof.urdf",
    ),
    (
        "unitree_go2.urdf",
        "unitreerobotics__unitree_ros/robots/go2_description/urdf/go2_description.urdf",
    ),
    ("unitree_h1.urdf", UNITREE_H1),
];

/// The URDF `name` (a file name of [`URDFS`], read from the test-data folder:
/// `None` where absent), else the project's own tests/fixtures/urdf/`name`.
pub fn urdf(name: &str) -> Option<PathBuf> {
    match URDFS.iter().find(|(n, _)| *n == name) {
        Some((_, real)) => file(real),
        None => Some(
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("tests/fixtures/urdf")
                .join(name),
        ),
    }
}

/// One row of the manifest.
#[derive(Clone, Debug)]
pub struct Entry {
    /// The path inside the test-data folder.
    pub path: String,
    /// The path the copy had in this repository before issue 25 (`-` if none).
    pub project_path: String,
    pub repository: String,
    pub commit: String,
    pub path_in_repo: String,
    pub sha256: String,
    pub licence: String,
}

/// The test-data folder (it may not exist).
pub fn root() -> PathBuf {
    match std::env::var_os(ENV) {
        Some(p) if !p.is_empty() => PathBuf::from(p),
        _ => Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/test-data"),
    }
}

/// The manifest's rows: the folder's MANIFEST.tsv, else the table of DOC.
pub fn manifest() -> &'static [Entry] {
    static M: OnceLock<Vec<Entry>> = OnceLock::new();
    M.get_or_init(
        || match std::fs::read_to_string(root().join("MANIFEST.tsv")) {
            Ok(text) => parse_manifest(&text),
            Err(_) => doc_table(),
        },
    )
}

/// MANIFEST.tsv: a header line, then project_path, shared_path (`test-data/...`),
/// repository, commit, path_in_repo, sha256, licence, tab-separated.
pub fn parse_manifest(text: &str) -> Vec<Entry> {
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let c: Vec<&str> = l.split('\t').collect();
            assert_eq!(c.len(), 7, "MANIFEST.tsv: 7 columns expected, found {l:?}");
            Entry {
                project_path: c[0].into(),
                path: c[1].trim_start_matches("test-data/").into(),
                repository: c[2].into(),
                commit: c[3].into(),
                path_in_repo: c[4].into(),
                sha256: c[5].into(),
                licence: c[6].into(),
            }
        })
        .collect()
}

/// The table of docs/test-data.md (written by tools/testdata.py from the
/// manifest): `| file | repository | commit | path in repository | sha256 | licence |`,
/// each cell but the licence in backticks.
pub fn doc_table() -> Vec<Entry> {
    let doc = Path::new(env!("CARGO_MANIFEST_DIR")).join(DOC);
    let text = std::fs::read_to_string(&doc).unwrap_or_else(|e| panic!("{}: {e}", doc.display()));
    let cell = |s: &str| s.trim().trim_matches('`').to_string();
    text.lines()
        .skip_while(|l| !l.starts_with(TABLE_BEGIN))
        .take_while(|l| !l.starts_with(TABLE_END))
        .filter(|l| l.starts_with("| `"))
        .map(|l| {
            let c: Vec<&str> = l.trim_matches('|').split(" | ").collect();
            assert_eq!(c.len(), 6, "{DOC}: 6 columns expected, found {l:?}");
            Entry {
                path: cell(c[0]),
                project_path: "-".into(),
                repository: cell(c[1]),
                commit: cell(c[2]),
                path_in_repo: cell(c[3]),
                sha256: cell(c[4]),
                licence: c[5].trim().into(),
            }
        })
        .collect()
}

/// The entry of `name`: a path inside the folder (with or without a leading
/// `test-data/`) or the project path the copy had.
pub fn entry(name: &str) -> &'static Entry {
    let n = name.trim_start_matches("test-data/");
    manifest()
        .iter()
        .find(|e| e.path == n)
        .or_else(|| manifest().iter().find(|e| e.project_path == n))
        .unwrap_or_else(|| panic!("{name}: not in the test-data manifest ({DOC})"))
}

/// The path of the real file `name` (see [`entry`]), its sha256 checked; `None`
/// (the test skips: return) where the folder does not have it.
pub fn file(name: &str) -> Option<PathBuf> {
    let e = entry(name);
    let path = root().join(&e.path);
    if !path.is_file() {
        skip(e);
        return None;
    }
    verify(&path, e);
    used();
    Some(path)
}

/// The folder `prefix` inside the test-data folder (e.g. a repository's, for
/// `--package-path` or xacro's `$(find pkg)`), every manifest file under it
/// checked; `None` (skip) where one of them is missing.
pub fn dir(prefix: &str) -> Option<PathBuf> {
    let p = prefix.trim_end_matches('/');
    let files: Vec<&Entry> = manifest()
        .iter()
        .filter(|e| e.path.starts_with(&format!("{p}/")))
        .collect();
    assert!(
        !files.is_empty(),
        "{prefix}: no file of the manifest under it"
    );
    for e in &files {
        let path = root().join(&e.path);
        if !path.is_file() {
            skip(e);
            return None;
        }
        verify(&path, e);
    }
    used();
    Some(root().join(p))
}

/// The bytes of the real file `name`, or `None` (skip).
pub fn read(name: &str) -> Option<Vec<u8>> {
    file(name).map(|p| std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display())))
}

/// The sha256 of `bytes`, lower-case hex.
pub fn sha256(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Let `file` return early with the skip: `let p = real!(ANYMAL_C);`.
#[macro_export]
macro_rules! real {
    ($name:expr) => {
        match $crate::common::testdata::file($name) {
            Some(p) => p,
            None => return,
        }
    };
}

/// [`real!`] for a folder: `let pkg = real_dir!(VELODYNE_SIMULATOR);`.
#[macro_export]
macro_rules! real_dir {
    ($name:expr) => {
        match $crate::common::testdata::dir($name) {
            Some(p) => p,
            None => return,
        }
    };
}

fn verify(path: &Path, e: &Entry) {
    static DONE: Mutex<BTreeSet<PathBuf>> = Mutex::new(BTreeSet::new());
    if DONE.lock().unwrap().contains(path) {
        return;
    }
    let bytes = std::fs::read(path).unwrap_or_else(|err| panic!("{}: {err}", path.display()));
    let got = sha256(&bytes);
    assert_eq!(
        got,
        e.sha256,
        "{}: sha256 {got}, the manifest says {} ({} {} {}): a different file",
        path.display(),
        e.sha256,
        e.repository,
        e.commit,
        e.path_in_repo
    );
    DONE.lock().unwrap().insert(path.to_path_buf());
}

/// The tests that read real data (`true`) or skipped for want of it (`false`).
static TESTS: Mutex<BTreeMap<String, bool>> = Mutex::new(BTreeMap::new());

/// The tests skipped for another reason than a file missing from the
/// test-data folder, with the reason (the summary names them: "test data not
/// found" would be a false explanation of their skip).
static OTHER_SKIPS: Mutex<BTreeMap<String, String>> = Mutex::new(BTreeMap::new());

fn test_name() -> String {
    std::thread::current().name().unwrap_or("main").to_string()
}

/// Count the calling test among those that read real data (done by [`file`]
/// and [`dir`]; for a test that reads the folder otherwise).
pub fn used() {
    TESTS.lock().unwrap().entry(test_name()).or_insert(true);
    at_exit();
}

fn skip(e: &Entry) {
    skipped(&format!(
        "needs {} from the test-data folder {} (not there): {} at commit {}, path {} \
         (the manifest: MANIFEST.tsv in that folder, or {DOC}; override: {ENV})",
        e.path,
        root().display(),
        e.repository,
        e.commit,
        e.path_in_repo
    ));
}

/// Skip the calling test (it returns next) for want of real data: say why,
/// and count it in the summary line.
pub fn skip_because(why: &str) {
    OTHER_SKIPS
        .lock()
        .unwrap()
        .insert(test_name(), why.to_string());
    skipped(why);
}

/// Count the calling test as skipped, saying why on standard error.
fn skipped(why: &str) {
    eprintln!("skipped: {}: {why}", test_name());
    TESTS.lock().unwrap().insert(test_name(), false);
    at_exit();
}

/// The one line at the end of the run.
fn summary_line() -> Option<String> {
    let t = TESTS.lock().ok()?;
    if t.is_empty() {
        return None;
    }
    let skipped = t.values().filter(|ran| !**ran).count();
    let others = OTHER_SKIPS.lock().ok()?;
    let missing = skipped - others.len().min(skipped);
    let mut why: Vec<String> = others.iter().map(|(n, r)| format!("{n}: {r}")).collect();
    if missing > 0 {
        why.insert(
            0,
            format!(
                "{missing} for test data not found in {}; see {DOC} to get it, or set {ENV}",
                root().display()
            ),
        );
    }
    Some(if skipped == 0 {
        format!(
            "real-data tests: {} ran on the test data in {}",
            t.len(),
            root().display()
        )
    } else {
        format!(
            "real-data tests: {skipped} skipped, {} ran ({})",
            t.len() - skipped,
            why.join("; ")
        )
    })
}

extern "C" fn print_summary() {
    if let Some(line) = summary_line() {
        use std::io::Write;
        let _ = writeln!(std::io::stdout(), "{line}");
        let _ = std::io::stdout().flush();
    }
}

fn at_exit() {
    static ONCE: Once = Once::new();
    // libtest has no end-of-run hook; the C runtime's exit handlers run after
    // its last line ("test result: ...") on every path out of main.
    ONCE.call_once(|| unsafe {
        libc::atexit(print_summary);
    });
}
