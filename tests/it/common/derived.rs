//! Files derived at run time from the real test data (issue 25): a crop or a
//! weighted copy of a third-party scan is made here, in the test target's
//! temporary folder, never committed. Each is made once per test binary.
//!
//! The rules are the reference script's
//! (tests/fixtures/detector/scans/make_reference.py, `ground_crop` and
//! `crop_weights`), done the way numpy does them, and expected.json records the
//! crop's point count, coordinate sums and end points, which [`ground_crop`]
//! checks before it hands the files out: a crop that is not the script's fails
//! the test rather than comparing against numbers made from other points.

use super::testdata;
use extrinsic_audit::internals::degeneracy::points::read_xyz;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The ground-plane crop of fast_gicp's scan 251370668: the ascii PCD the
/// reference script reads, and the same points with the `w` column.
pub struct GroundCrop {
    /// `x y z`, ascii PCD.
    pub pcd: PathBuf,
    /// `x,y,z,w` CSV, w = 0.5 + (i mod 7) / 4 for point i in file order.
    pub weighted_csv: PathBuf,
}

/// Horizontal radius of the crop and half-height of its slab, metres.
const CROP_RADIUS_M: f64 = 10.0;
const CROP_HALF_HEIGHT_M: f64 = 0.1;

/// The ground crop, or `None` (the test skips) where the scan is absent.
pub fn ground_crop() -> Option<&'static GroundCrop> {
    static MADE: OnceLock<Option<GroundCrop>> = OnceLock::new();
    MADE.get_or_init(|| {
        let scan = testdata::file(testdata::GICP_SCAN)?;
        Some(make_ground_crop(&scan))
    })
    .as_ref()
}

fn make_ground_crop(scan: &Path) -> GroundCrop {
    let points = read_xyz(scan).expect("the fast_gicp scan reads").points;
    let crop = crop_ground(&points);
    check_against_reference(&crop);
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("derived");
    std::fs::create_dir_all(&dir).unwrap();
    let mut pcd = format!(
        "# .PCD v0.7 - ground-plane crop of 251370668.pcd (koide3/fast_gicp, BSD-3-Clause)\n\
         VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n\
         WIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA ascii\n",
        n = crop.len()
    );
    let mut csv = String::from("x,y,z,w\n");
    for (i, p) in crop.iter().enumerate() {
        // `{}` prints the shortest text that reads back as the same f64, so
        // the files hold the scan's float32 values exactly.
        pcd.push_str(&format!("{} {} {}\n", p[0], p[1], p[2]));
        let w = 0.5 + (i % 7) as f64 / 4.0;
        csv.push_str(&format!("{},{},{},{w}\n", p[0], p[1], p[2]));
    }
    GroundCrop {
        pcd: write_new(&dir, "ground_crop.pcd", &pcd),
        weighted_csv: write_new(&dir, "ground_crop_weighted.csv", &csv),
    }
}

/// numpy's steps: `near` = points with hypot(x, y) < 10; the histogram of
/// their z over `np.arange(-5, -1, 0.02)` (edges start + i * delta with delta
/// = (start + step) - start, as numpy fills a float range; bin k holds
/// edges[k] <= z < edges[k + 1], the last bin closed); the ground height the
/// first fullest bin's lower edge + 0.01; the crop the near points within 0.1
/// of it, in file order.
fn crop_ground(points: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let near: Vec<[f64; 3]> = points
        .iter()
        .filter(|p| p[0].hypot(p[1]) < CROP_RADIUS_M)
        .copied()
        .collect();
    let (start, step) = (-5.0_f64, 0.02_f64);
    let len = ((-1.0 - start) / step).ceil() as usize;
    let delta = (start + step) - start;
    let edges: Vec<f64> = (0..len).map(|i| start + i as f64 * delta).collect();
    let mut hist = vec![0usize; len - 1];
    for p in &near {
        let z = p[2];
        if z < edges[0] || z > edges[len - 1] {
            continue;
        }
        // The last edge belongs to the last bin.
        let k = edges.partition_point(|&e| e <= z).min(len - 1) - 1;
        hist[k] += 1;
    }
    let best = hist.iter().copied().max().unwrap();
    let k = hist.iter().position(|&c| c == best).unwrap();
    let ground = edges[k] + 0.01;
    near.into_iter()
        .filter(|p| (p[2] - ground).abs() < CROP_HALF_HEIGHT_M)
        .collect()
}

/// The crop against the reference script's record of it (expected.json's
/// `ground_crop`): count, end points exactly, sums to 1e-12 relative (numpy
/// sums pairwise, this sums in order).
fn check_against_reference(crop: &[[f64; 3]]) {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/detector/scans/expected.json");
    let e: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let e = &e["ground_crop"];
    assert_eq!(
        crop.len() as u64,
        e["points"].as_u64().unwrap(),
        "crop size"
    );
    let xyz = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    assert_eq!(crop[0].to_vec(), xyz(&e["first"]), "first point");
    assert_eq!(crop[crop.len() - 1].to_vec(), xyz(&e["last"]), "last point");
    for (k, want) in xyz(&e["sum"]).into_iter().enumerate() {
        let got: f64 = crop.iter().map(|p| p[k]).sum();
        assert!(
            (got - want).abs() <= 1e-12 * want.abs(),
            "sum {k}: {got} vs {want}"
        );
    }
}

/// Write `text` to `dir/name` through a temporary file created exclusively
/// and renamed into place, so parallel test binaries never see half a file.
fn write_new(dir: &Path, name: &str, text: &str) -> PathBuf {
    let mut tmp = tempfile::NamedTempFile::new_in(dir).unwrap();
    tmp.write_all(text.as_bytes()).unwrap();
    let path = dir.join(name);
    tmp.persist(&path).unwrap();
    path
}
