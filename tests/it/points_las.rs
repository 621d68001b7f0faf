//! LAS and LAZ scans (issue 16): read like laspy + lazrs, raw scans only,
//! detected by their magic, bounded against lying headers; and scan pairs that
//! honour the source's weights. References: expected_las.json, written by
//! tests/fixtures/detector/scans/make_reference_las.py (laspy, lazrs, numpy).

use crate::common::{audit, nums, rel, run_cli};
use extrinsic_audit::internals::degeneracy::points::{parse_points, read_xyz, PointFormat};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/detector/scans")
}

/// A scan: a real one from the test-data folder, or the weighted ground crop
/// made from one at run time (`None` where absent).
fn scan(file: &str) -> Option<PathBuf> {
    use crate::common::testdata::{file as real, AUTZEN_LAS, AUTZEN_LAZ, GICP_SCAN, LAS_1_4};
    match file {
        "autzen.las" => real(AUTZEN_LAS),
        "autzen.laz" => real(AUTZEN_LAZ),
        "32-1-472-150-76.laz" => real(LAS_1_4),
        "251370668.pcd" => real(GICP_SCAN),
        "ground_crop.pcd" => crate::common::derived::ground_crop().map(|c| c.pcd.clone()),
        "ground_crop_weighted.csv" => {
            crate::common::derived::ground_crop().map(|c| c.weighted_csv.clone())
        }
        other => panic!("no scan named {other}"),
    }
}

/// [`scan`], the test returning (skipped) where it is absent.
macro_rules! scan {
    ($file:expr) => {
        match scan($file) {
            Some(p) => p,
            None => return,
        }
    };
}

fn expected() -> Value {
    let text = std::fs::read_to_string(dir().join("expected_las.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn pd_eigenvalues(r: &Value) -> Vec<f64> {
    let f = r["families"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["family"] == "point_displacement")
        .unwrap();
    nums(&f["eigenvalues"])
}

fn json(args: &[&str]) -> Value {
    let (code, out, err) = run_cli(args);
    assert_eq!(code, 0, "{args:?}: {err}");
    serde_json::from_str(&out).unwrap()
}

#[test]
fn las_and_laz_read_like_laspy_with_the_scale_and_offset_exact() {
    let e = expected();
    for (file, key, format) in [
        ("autzen.las", "autzen_las", PointFormat::Las),
        ("autzen.laz", "autzen_laz", PointFormat::Laz),
    ] {
        let d = read_xyz(&scan!(file)).unwrap();
        let e = &e[key];
        assert_eq!(d.format, format);
        assert_eq!(d.points.len() as u64, e["count"].as_u64().unwrap());
        // X * scale + offset in f64 is exact to the bit against laspy.
        assert_eq!(d.points[0].to_vec(), nums(&e["first"]), "{file}");
        assert_eq!(
            d.points.last().unwrap().to_vec(),
            nums(&e["last"]),
            "{file}"
        );
        let sum: Vec<f64> = (0..3)
            .map(|c| d.points.iter().map(|p| p[c]).sum())
            .collect();
        assert!(rel(&sum, &nums(&e["sum"])) < 1e-14, "{file}");
        assert!(d.warnings.is_empty(), "{:?}", d.warnings);
    }
    // The same points, uncompressed (format 1) and compressed (format 3).
    let a = read_xyz(&scan!("autzen.las")).unwrap();
    let b = read_xyz(&scan!("autzen.laz")).unwrap();
    assert_eq!(a.points, b.points);
}

#[test]
fn las_without_estimate_normals_is_refused_like_a_raw_pcd() {
    for file in ["autzen.las", "autzen.laz"] {
        let p = scan!(file);
        let (code, _, err) = run_cli(&["degeneracy", p.to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(file), "{err}");
        assert!(
            err.contains("missing normal_x normal_y normal_z")
                && err.contains("add --estimate-normals"),
            "{err}"
        );
    }
}

#[test]
fn las_is_detected_by_its_magic_from_a_file_a_stream_and_memory() {
    let tmp = tempfile::tempdir().unwrap();
    let renamed = tmp.path().join("scan.dat");
    std::fs::copy(scan!("autzen.laz"), &renamed).unwrap();
    let d = read_xyz(&renamed).unwrap();
    assert_eq!((d.format, d.points.len()), (PointFormat::Laz, 106));
    // In memory, the normal-reading path refuses it, naming the normals.
    let bytes = std::fs::read(scan!("autzen.las")).unwrap();
    let e = parse_points(&bytes).unwrap_err();
    assert!(e.message.contains("missing normal_x"), "{e}");
    // From standard input: the same answer as from the file.
    let from_file = json(&[
        "degeneracy",
        renamed.to_str().unwrap(),
        "--estimate-normals",
        "--normal-radius",
        "2000",
        "--format",
        "json",
    ]);
    let out = audit()
        .args([
            "degeneracy",
            "-",
            "--estimate-normals",
            "--normal-radius",
            "2000",
            "--format",
            "json",
        ])
        .write_stdin(std::fs::read(&renamed).unwrap())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let from_stdin: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(from_file["families"], from_stdin["families"]);
}

#[test]
fn an_airborne_laz_strip_in_utm_matches_numpy() {
    // 5,658 points about 5e6 m from the origin: H and M in the file's frame,
    // point-displacement eigenvalues (frame-invariant) against numpy's about
    // the centroid.
    let p = scan!("32-1-472-150-76.laz");
    let r = json(&[
        "degeneracy",
        p.to_str().unwrap(),
        "--estimate-normals",
        "--normal-radius",
        "5",
        "--show-matrices",
        "--format",
        "json",
    ]);
    let e = &expected()["strip"];
    assert_eq!(r["normals"]["points_read"], e["points_read"]);
    assert_eq!(r["normals"]["kept"], e["kept"]);
    let m = &r["matrices"];
    let (dh, dm) = (
        rel(&nums(&m["h"]), &nums(&e["h"])),
        rel(&nums(&m["m"]), &nums(&e["m"])),
    );
    assert!(dh < 1e-9 && dm < 1e-9, "H {dh:e}, M {dm:e}");
    let got = pd_eigenvalues(&r);
    let want = nums(&e["eigenvalues"]);
    for k in 0..6 {
        assert!(
            (got[k] - want[k]).abs() < 1e-9 * want[5],
            "{got:?} vs {want:?}"
        );
    }
}

#[test]
fn a_scan_pair_honours_the_source_weights() {
    // The weighted ground crop against the full scan it was cut from.
    let source = scan!("ground_crop_weighted.csv");
    let r = json(&[
        "degeneracy",
        source.to_str().unwrap(),
        "--target",
        scan!("251370668.pcd").to_str().unwrap(),
        "--estimate-normals",
        "--voxel",
        "0.1",
        "--gate",
        "0.5",
        "--show-matrices",
        "--format",
        "json",
    ]);
    let e = &expected()["weighted_pair"];
    assert_eq!(r["pair"]["correspondences"], e["matched"]);
    assert_eq!(r["pair"]["source_points"], e["source_points"]);
    let m = &r["matrices"];
    let dh = rel(&nums(&m["h"]), &nums(&e["h"]));
    let dm = rel(&nums(&m["m"]), &nums(&e["m"]));
    assert!(dh < 1e-12 && dm < 1e-12, "H {dh:e}, M {dm:e}");
    // The weights changed the answer.
    assert!(rel(&nums(&e["h_unweighted"]), &nums(&e["h"])) > 0.01);
    let got = pd_eigenvalues(&r);
    let want = nums(&e["eigenvalues"]);
    assert!(rel(&got, &want) < 1e-12, "{got:?} vs {want:?}");
    // I6 is compared per unit of weight, as for one cloud.
    let i6 = &r["families"][0];
    let ws = e["weight_sum"].as_f64().unwrap();
    let (t, tp) = (
        i6["threshold"].as_f64().unwrap(),
        i6["threshold_per_point"].as_f64().unwrap(),
    );
    assert!((t - tp * ws).abs() < 1e-9 * t, "{t} vs {tp} x {ws}");
}

fn write(tmp: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = tmp.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

fn set_u32(b: &mut [u8], at: usize, v: u32) {
    b[at..at + 4].copy_from_slice(&v.to_le_bytes());
}

/// The error of reading `bytes` as the file `name` (which it names).
fn refused(tmp: &Path, name: &str, bytes: &[u8]) -> String {
    let p = write(tmp, name, bytes);
    let e = match read_xyz(&p) {
        Ok(d) => panic!("{name}: read {} points, expected an error", d.points.len()),
        Err(e) => e.to_string(),
    };
    assert!(e.contains(name), "{e}");
    e
}

#[test]
fn lying_and_truncated_las_headers_are_errors_naming_the_counts() {
    let tmp = tempfile::tempdir().unwrap();
    let las = std::fs::read(scan!("autzen.las")).unwrap();
    // Truncated in the records: 106 claimed, fewer held.
    let e = refused(tmp.path(), "cut.las", &las[..las.len() - 50]);
    assert!(
        e.contains("header claims 106 points") && e.contains("holds 104"),
        "{e}"
    );
    // More records than claimed.
    let mut fewer = las.clone();
    set_u32(&mut fewer, 107, 100);
    let e = refused(tmp.path(), "fewer.las", &fewer);
    assert!(
        e.contains("header claims 100 points") && e.contains("more bytes"),
        "{e}"
    );
    // A count whose byte length overflows.
    let mut huge = las.clone();
    set_u32(&mut huge, 107, u32::MAX);
    let e = refused(tmp.path(), "huge.las", &huge);
    assert!(e.contains("header claims 4294967295 points"), "{e}");
    // Cut inside the header.
    let e = refused(tmp.path(), "header.las", &las[..100]);
    assert!(e.contains("at least 227 bytes"), "{e}");
    // A record too short to hold x, y, z (LAS and LAZ).
    for (file, name) in [("autzen.las", "short.las"), ("autzen.laz", "short.laz")] {
        let mut short = std::fs::read(scan!(file)).unwrap();
        short[105..107].copy_from_slice(&10u16.to_le_bytes());
        let e = refused(tmp.path(), name, &short);
        assert!(e.contains("at least 20 bytes, found 10"), "{e}");
    }
    // A zero scale.
    let mut zero = las.clone();
    zero[131..139].copy_from_slice(&0f64.to_le_bytes());
    let e = refused(tmp.path(), "scale.las", &zero);
    assert!(e.contains("non-zero x scale"), "{e}");
}

#[test]
fn lying_and_truncated_laz_files_are_errors() {
    let tmp = tempfile::tempdir().unwrap();
    let laz = std::fs::read(scan!("32-1-472-150-76.laz")).unwrap();
    // Truncated: the chunk table (at the end) is gone.
    let e = refused(tmp.path(), "cut.laz", &laz[..laz.len() / 2]);
    assert!(e.contains("chunk table"), "{e}");
    // A count above or below what the chunks hold.
    for (name, n) in [("more.laz", 5659u32), ("less.laz", 5000)] {
        let mut b = laz.clone();
        set_u32(&mut b, 107, n);
        let e = refused(tmp.path(), name, &b);
        assert!(
            e.contains(&format!("header claims {n} points"))
                && e.contains("expected the count to match the data"),
            "{e}"
        );
    }
}

#[test]
fn every_byte_of_a_las_or_laz_header_damaged_is_an_answer_not_a_panic() {
    // Each of the first 400 bytes set to 0xff (then to 0x00), one at a time:
    // read or refused, never a panic or an abort.
    let tmp = tempfile::tempdir().unwrap();
    for file in ["autzen.las", "autzen.laz"] {
        let orig = std::fs::read(scan!(file)).unwrap();
        for fill in [0xffu8, 0x00] {
            for at in 0..400.min(orig.len()) {
                let mut b = orig.clone();
                b[at] = fill;
                let p = write(tmp.path(), file, &b);
                if let Err(e) = read_xyz(&p) {
                    assert!(!e.message.is_empty());
                }
            }
        }
    }
}

#[test]
fn class_keeps_the_ground_points_like_laspy() {
    use extrinsic_audit::internals::degeneracy::points::read_xyz_classes;
    use extrinsic_audit::NoProgress;
    let e = expected();
    // Both decoders (las for LAS, laz for LAZ) read the classification.
    for (file, key) in [("autzen.las", "autzen_las"), ("autzen.laz", "autzen_laz")] {
        let d = read_xyz_classes(&scan!(file), &[2], &NoProgress).unwrap();
        assert_eq!(
            d.points.len() as u64,
            e[key]["ground_count"].as_u64().unwrap()
        );
        let sum: Vec<f64> = (0..3)
            .map(|c| d.points.iter().map(|p| p[c]).sum())
            .collect();
        assert!(rel(&sum, &nums(&e[key]["ground_sum"])) < 1e-14, "{file}");
    }
    // The strip's ground: H, M and eigenvalues against numpy.
    let p = scan!("32-1-472-150-76.laz");
    let r = json(&[
        "degeneracy",
        p.to_str().unwrap(),
        "--estimate-normals",
        "--normal-radius",
        "5",
        "--class",
        "2",
        "--show-matrices",
        "--format",
        "json",
    ]);
    let e = &e["strip_ground"];
    assert_eq!(r["normals"]["points_read"], e["points_read"]);
    assert_eq!(r["normals"]["kept"], e["kept"]);
    let m = &r["matrices"];
    assert!(rel(&nums(&m["h"]), &nums(&e["h"])) < 1e-9);
    assert!(rel(&nums(&m["m"]), &nums(&e["m"])) < 1e-9);
    let (got, want) = (pd_eigenvalues(&r), nums(&e["eigenvalues"]));
    for k in 0..6 {
        assert!(
            (got[k] - want[k]).abs() < 1e-9 * want[5],
            "{got:?} vs {want:?}"
        );
    }
    // Not a LAS file, or no --estimate-normals: a usage error.
    let pcd = scan!("ground_crop.pcd");
    for args in [
        vec![
            "degeneracy",
            pcd.to_str().unwrap(),
            "--estimate-normals",
            "--class",
            "2",
        ],
        vec!["degeneracy", p.to_str().unwrap(), "--class", "2"],
    ] {
        let (code, _, err) = run_cli(&args);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("--class"), "{err}");
    }
}

#[test]
fn damaged_compressed_points_are_an_error_not_a_panic() {
    // Bytes of the LASzip stream overwritten: laz-rs trips its debug
    // assertions or overflow checks on some (caught), errors on others.
    let tmp = tempfile::tempdir().unwrap();
    let orig = std::fs::read(scan!("32-1-472-150-76.laz")).unwrap();
    let start = u32::from_le_bytes(orig[96..100].try_into().unwrap()) as usize;
    let mut failed = 0;
    for k in 0..60 {
        let mut b = orig.clone();
        let at = start + 8 + (k * 7919) % (orig.len() - start - 64);
        b[at] ^= 0x5a;
        b[at + 1] = b[at + 1].wrapping_add(k as u8);
        let p = write(tmp.path(), "damaged.laz", &b);
        if let Err(e) = read_xyz(&p) {
            assert!(e.to_string().contains("damaged.laz"), "{e}");
            failed += 1;
        }
    }
    // The exact-count check catches most: a damaged stream rarely decodes
    // to exactly the header's count.
    assert!(failed >= 30, "{failed} of 60 refused");
}
