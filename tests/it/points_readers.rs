//! Point-file readers and `audit degeneracy`.

use crate::common::run_cli;
use extrinsic_audit::internals::degeneracy::points::*;
use extrinsic_audit::internals::degeneracy::scene::SceneRng;
use extrinsic_audit::internals::pipeline::detector::degeneracy;
use extrinsic_audit::Transform;
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/detector")
        .join(name)
}

#[test]
fn all_formats_read_the_same_tunnel() {
    let base = read_points(&fixture("tunnel_small.csv")).unwrap();
    assert_eq!(base.points.len(), 408);
    assert_eq!(base.format, PointFormat::Csv);
    assert!(base.warnings.is_empty());
    for (name, fmt) in [
        ("tunnel_small_ascii.ply", PointFormat::PlyAscii),
        ("tunnel_small_le.ply", PointFormat::PlyBinaryLittleEndian),
        ("tunnel_small_be.ply", PointFormat::PlyBinaryBigEndian),
        ("tunnel_small_ascii.pcd", PointFormat::PcdAscii),
    ] {
        let d = read_points(&fixture(name)).unwrap();
        assert_eq!(d.format, fmt, "{name}");
        assert_eq!(d.points, base.points, "{name}");
        assert_eq!(d.normals, base.normals, "{name}");
        assert!(d.weights.is_none());
    }
    // float32 files agree to float precision.
    for name in ["tunnel_small_float.ply", "tunnel_small_bin.pcd"] {
        let d = read_points(&fixture(name)).unwrap();
        assert_eq!(d.points.len(), 408, "{name}");
        for i in 0..408 {
            for k in 0..3 {
                assert!((d.points[i][k] - base.points[i][k]).abs() < 1e-6, "{name}");
                assert!(
                    (d.normals[i][k] - base.normals[i][k]).abs() < 1e-6,
                    "{name}"
                );
            }
        }
    }
    let w = read_points(&fixture("tunnel_small_noheader.csv")).unwrap();
    assert_eq!(w.points, base.points);
    assert_eq!(w.weights.as_ref().unwrap().len(), 408);
}

#[test]
fn writers_round_trip_ascii_and_binary_exactly() {
    let mut rng = SceneRng::new(5);
    let mut p = Vec::new();
    let mut n = Vec::new();
    for _ in 0..257 {
        p.push([rng.normal() * 3.0, rng.normal() * 1e-3, rng.normal() * 1e4]);
        let u = rng.unit_vector();
        n.push([u.x, u.y, u.z]);
    }
    let w: Vec<f64> = (0..257).map(|i| i as f64 * 0.5).collect();
    let csv = parse_points(&write_csv(&p, &n, Some(&w))).unwrap();
    assert_eq!(csv.points, p);
    assert_eq!(csv.weights.unwrap(), w);
    for enc in [
        Encoding::Ascii,
        Encoding::BinaryLittleEndian,
        Encoding::BinaryBigEndian,
    ] {
        let ply = parse_points(&write_ply(&p, &n, enc)).unwrap();
        assert_eq!(ply.points, p, "{enc:?}");
        assert_eq!(ply.normals, n, "{enc:?}");
        let pcd = parse_points(&write_pcd(&p, &n, enc)).unwrap();
        assert_eq!(pcd.points, p, "{enc:?}");
        assert_eq!(pcd.normals, n, "{enc:?}");
    }
}

#[test]
fn malformed_files_are_clear_errors() {
    let e = read_points(&fixture("zero_normal.csv")).unwrap_err();
    assert_eq!(e.location.line, Some(4), "{e}");
    assert!(e.to_string().contains("zero_normal.csv:4"), "{e}");
    assert!(e.message.contains("zero normal"), "{e}");
    let e = read_points(&fixture("truncated_le.ply")).unwrap_err();
    assert!(
        e.message.contains("claims 408 vertices") && e.message.contains("holds 10"),
        "{e}"
    );
    let e = read_points(&fixture("huge_count.ply")).unwrap_err();
    assert!(e.message.contains("claims 1000000000000000"), "{e}");
    let e = read_points(&fixture("compressed.pcd")).unwrap_err();
    assert!(
        // The fixture's sizes after DATA are zero: refused, naming both sizes.
        e.message.contains("binary_compressed") && e.message.contains("announce 0 bytes"),
        "{e}"
    );
    let e = read_points(&fixture("does_not_exist.csv")).unwrap_err();
    assert!(e.to_string().contains("does_not_exist.csv"));
    // Non-unit normals: renormalised with one warning.
    let d = read_points(&fixture("nonunit.csv")).unwrap();
    assert_eq!(d.warnings.len(), 1);
    assert!(d.warnings[0].message.contains("408 normals were not unit"));
    assert!((d.normals[5][0].hypot(d.normals[5][1]) - 1.0).abs() < 1e-15);
    // Assorted garbage never panics.
    for bytes in [
        &b""[..],
        b"ply\n",
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n",
        b"ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty list uchar float x\nend_header\n",
        b"VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n",
        b"VERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\nTYPE F F F F F F\nPOINTS 99999999999\nDATA binary\n\0\0\0",
        b"x,y,z,nx,ny,nz\n1,2,3,a,0,0\n",
        b"1,2,3\n",
        b"1,2,3,0,0,1\n1,2,3,0,0\n",
        b"1,2,3,0,0,1,-5\n",
    ] {
        assert!(parse_points(bytes).is_err(), "{:?}", String::from_utf8_lossy(bytes));
    }
}

fn degeneracy_json(
    d: &PointData,
    t: &Transform,
    tau: f64,
    ells: &[f64],
) -> extrinsic_audit::Result<serde_json::Value> {
    let r = degeneracy(d, t, tau, ells)?;
    Ok(serde_json::to_value(&r).unwrap())
}

#[test]
fn degeneracy_json_has_the_design_schema() {
    let d = read_points(&fixture("tunnel_small_le.ply")).unwrap();
    let ells = [0.25, 1.0, 2.85, 10.0];
    let v = degeneracy_json(&d, &Transform::identity(), 1e-2, &ells).unwrap();
    assert_eq!(v["schema_version"], 1);
    assert_eq!(v["points"], 408);
    assert_eq!(
        v["frame"]["translation_m"],
        serde_json::json!([0.0, 0.0, 0.0])
    );
    assert_eq!(v["frame"]["rpy_rad"].as_array().unwrap().len(), 3);
    let fams = v["families"].as_array().unwrap();
    let names: Vec<&str> = fams.iter().map(|f| f["family"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        [
            "unnormalized",
            "characteristic_length",
            "characteristic_length",
            "characteristic_length",
            "characteristic_length",
            "block_scaling",
            "jacobi",
            "point_displacement"
        ]
    );
    for f in fams {
        let ev: Vec<f64> = f["eigenvalues"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert_eq!(ev.len(), 6);
        assert!(ev.windows(2).all(|w| w[0] <= w[1]));
        assert!(f["threshold"].as_f64().unwrap() > 0.0);
        assert!(f["degenerate_count"].is_u64());
    }
    // Point displacement uses --tau; the baselines their calibrated thresholds.
    assert_eq!(fams[7]["threshold"].as_f64(), Some(1e-2));
    // I6 per point: the threshold on its eigenvalues is 0.04582 x the points.
    assert_eq!(fams[0]["threshold_per_point"].as_f64(), Some(0.04582));
    let n = v["points"].as_f64().unwrap();
    assert!((fams[0]["threshold"].as_f64().unwrap() - 0.04582 * n).abs() < 1e-9 * n);
    assert!(fams[7].get("threshold_per_point").is_none());
    assert_eq!(fams[1]["ell_m"].as_f64(), Some(0.25));
    let pd = fams.last().unwrap();
    assert_eq!(pd["degenerate_count"], 2);
    let sub = v["degenerate_subspace"].as_array().unwrap();
    assert_eq!(sub.len(), 2);
    assert_eq!(sub[0]["screw"]["kind"], "zero_pitch");
    assert_eq!(sub[0]["twist"].as_array().unwrap().len(), 6);
    assert!(sub[0]["eigenvalue"].as_f64().unwrap().abs() < 1e-12);
    assert!(sub[0]["screw"]["direction"].is_null());
    assert_eq!(sub[1]["screw"]["kind"], "pure_translation");
    let dir: Vec<f64> = sub[1]["screw"]["direction"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!(
        (dir[0].abs() + dir[1].abs()) < 1e-12 && (dir[2] - 1.0).abs() < 1e-12,
        "{dir:?}"
    );
    assert!(sub[1]["screw"]["axis"].is_null() && sub[1]["screw"]["pitch_m_per_rad"].is_null());
    assert_eq!(
        v["footprint"],
        serde_json::json!([false, false, true, false, false, true])
    );
    // Shifted one metre: footprint gains trans-y; axis point at x = -1.
    let t = Transform::from_translation([1.0, 0.0, 0.0]).unwrap();
    let v = degeneracy_json(&d, &t, 1e-2, &ells).unwrap();
    assert_eq!(
        v["footprint"],
        serde_json::json!([false, false, true, false, true, true])
    );
    let ap = v["degenerate_subspace"][0]["screw"]["axis_point_m"]
        .as_array()
        .unwrap()
        .clone();
    assert!((ap[0].as_f64().unwrap() + 1.0).abs() < 1e-9, "{ap:?}");
    assert_eq!(
        v["frame"]["translation_m"],
        serde_json::json!([1.0, 0.0, 0.0])
    );
    // Point-displacement eigenvalues unchanged; I6's changed.
    let v0 = degeneracy_json(&d, &Transform::identity(), 1e-2, &ells).unwrap();
    let ev = |v: &serde_json::Value, k: usize| -> Vec<f64> {
        v["families"][k]["eigenvalues"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    for (a, b) in ev(&v0, 7).iter().zip(ev(&v, 7).iter()) {
        assert!((a - b).abs() < 1e-12);
    }
    assert!(ev(&v0, 0)
        .iter()
        .zip(ev(&v, 0).iter())
        .any(|(a, b)| (a - b).abs() > 1e-3));
}

#[test]
fn degeneracy_command_runs_and_reports_errors() {
    let pcd = fixture("tunnel_small_bin.pcd");
    let pcd = pcd.to_str().unwrap();
    let base = [
        "degeneracy",
        pcd,
        "--shift",
        "1,0,0",
        "--rotate-rpy",
        "0,0,0.3",
    ];
    let (code, s, _) = run_cli(&base);
    assert_eq!(code, 0);
    assert!(s.contains("point displacement"), "{s}");
    assert!(
        s.contains("zero pitch") && s.contains("pure translation"),
        "{s}"
    );
    let mut a = base.to_vec();
    a.extend(["--format", "json"]);
    let (code, out, _) = run_cli(&a);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["families"][7]["degenerate_count"], 2);
    let col = fixture("collinear.csv");
    let (code, _, err) = run_cli(&["degeneracy", col.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("points are collinear"), "{err}");
    assert!(err.contains("collinear.csv"), "{err}");
    assert_eq!(run_cli(&["degeneracy", pcd, "--shift", "1,2"]).0, 2);
    assert_eq!(run_cli(&["degeneracy", pcd, "--tau=-1"]).0, 2);
}

/// A fixture with `from` replaced by `to` (once, in the header), written to
/// `dir/name`.
fn edited(dir: &tempfile::TempDir, fixture_name: &str, from: &str, to: &str, name: &str) -> String {
    let bytes = std::fs::read(fixture(fixture_name)).unwrap();
    let at = bytes
        .windows(from.len())
        .position(|w| w == from.as_bytes())
        .unwrap();
    let mut out = bytes[..at].to_vec();
    out.extend_from_slice(to.as_bytes());
    out.extend_from_slice(&bytes[at + from.len()..]);
    let p = dir.path().join(name);
    std::fs::write(&p, out).unwrap();
    p.to_str().unwrap().to_string()
}

/// `audit degeneracy` (streamed, several threads for binary files) and
/// `--estimate-normals` (read into memory, one thread) on `path`: exit 2 and
/// both messages contain every piece of `want`.
fn refused_both_ways(path: &str, want: &[&str]) {
    for extra in [&[][..], &["--estimate-normals"][..]] {
        let mut a = vec!["degeneracy", path];
        a.extend_from_slice(extra);
        let (code, out, err) = run_cli(&a);
        assert_eq!(code, 2, "{a:?}: {out}{err}");
        for w in want {
            assert!(err.contains(w), "{a:?}: expected {w:?} in {err}");
        }
    }
}

#[test]
fn header_count_mismatch_is_an_error_naming_file_and_line() {
    let d = tempfile::tempdir().unwrap();
    // ascii PLY: 11 header lines, vertex k on line 12 + k; `element vertex` on line 4.
    let p = edited(
        &d,
        "tunnel_small_ascii.ply",
        "vertex 408",
        "vertex 407",
        "fewer.ply",
    );
    refused_both_ways(
        &p,
        &[
            "fewer.ply:419",
            "header line 4 claims 407 vertices",
            "line 419 is past them",
        ],
    );
    let p = edited(
        &d,
        "tunnel_small_ascii.ply",
        "vertex 408",
        "vertex 409",
        "more.ply",
    );
    refused_both_ways(
        &p,
        &[
            "more.ply:4",
            "header line 4 claims 409 vertices, the file holds 408",
        ],
    );
    // binary PLY (48-byte records): one record too many in the file.
    let p = edited(
        &d,
        "tunnel_small_le.ply",
        "vertex 408",
        "vertex 407",
        "fewer_le.ply",
    );
    refused_both_ways(
        &p,
        &[
            "fewer_le.ply:4",
            "header line 4 claims 407 vertices of 48 bytes, the file holds 48 more bytes",
        ],
    );
    let p = edited(
        &d,
        "tunnel_small_le.ply",
        "vertex 408",
        "vertex 409",
        "more_le.ply",
    );
    refused_both_ways(
        &p,
        &[
            "more_le.ply:4",
            "claims 409 vertices of 48 bytes, the file holds 408",
        ],
    );
    // binary PCD (32-byte records), POINTS on line 10.
    let p = edited(
        &d,
        "tunnel_small_bin.pcd",
        "POINTS 408",
        "POINTS 400",
        "fewer.pcd",
    );
    refused_both_ways(
        &p,
        &[
            "fewer.pcd:10",
            "header line 10 claims 400 points of 32 bytes, the file holds 256 more bytes",
        ],
    );
    // ascii PCD.
    let p = edited(
        &d,
        "tunnel_small_ascii.pcd",
        "POINTS 408",
        "POINTS 407",
        "fewer_ascii.pcd",
    );
    refused_both_ways(
        &p,
        &["fewer_ascii.pcd:", "claims 407 points, the file holds more"],
    );
    let p = edited(
        &d,
        "tunnel_small_ascii.pcd",
        "POINTS 408",
        "POINTS 409",
        "more_ascii.pcd",
    );
    refused_both_ways(
        &p,
        &["more_ascii.pcd:", "claims 409 points, the file holds 408"],
    );
    // The unedited files still read.
    for f in [
        "tunnel_small_ascii.ply",
        "tunnel_small_le.ply",
        "tunnel_small_bin.pcd",
        "tunnel_small_ascii.pcd",
    ] {
        let f = fixture(f);
        assert_eq!(run_cli(&["degeneracy", f.to_str().unwrap()]).0, 0, "{f:?}");
    }
}

#[test]
fn duplicate_ply_property_or_pcd_field_is_an_error_naming_both_lines() {
    let d = tempfile::tempdir().unwrap();
    // `property double x` is on line 5; a second one after nz (line 10) is line 11.
    let p = edited(
        &d,
        "tunnel_small_ascii.ply",
        "property double nz\n",
        "property double nz\nproperty double x\n",
        "dup.ply",
    );
    refused_both_ways(
        &p,
        &[
            "dup.ply:11",
            "declares property \"x\" twice, at header lines 5 and 11",
        ],
    );
    let p = edited(&d, "tunnel_small_bin.pcd", "curvature\n", "x\n", "dup.pcd");
    refused_both_ways(&p, &["dup.pcd:3", "FIELDS declares \"x\" twice"]);
}

/// A binary PLY of the 408-point tunnel (f64 x y z nx ny nz) followed by a
/// `face` element with a list property (`uchar` count, `int` or `ushort`
/// items) holding `faces`, little or big endian, with `extra` bytes appended.
fn ply_with_faces(little: bool, faces: &[Vec<u32>], item: &str, extra: &[u8]) -> Vec<u8> {
    let base = read_points(&fixture("tunnel_small.csv")).unwrap();
    let fmt = if little {
        "binary_little_endian"
    } else {
        "binary_big_endian"
    };
    let mut b = format!(
        "ply\nformat {fmt} 1.0\nelement vertex {}\nproperty double x\nproperty double y\nproperty double z\n\
property double nx\nproperty double ny\nproperty double nz\nelement face {}\n\
property list uchar {item} vertex_indices\nproperty uchar flag\nend_header\n",
        base.points.len(),
        faces.len()
    )
    .into_bytes();
    let f64b = |x: f64| {
        if little {
            x.to_le_bytes()
        } else {
            x.to_be_bytes()
        }
    };
    for (p, n) in base.points.iter().zip(&base.normals) {
        for x in p.iter().chain(n) {
            b.extend_from_slice(&f64b(*x));
        }
    }
    for f in faces {
        b.push(f.len() as u8);
        for &i in f {
            match (item, little) {
                ("int", true) => b.extend_from_slice(&(i as i32).to_le_bytes()),
                ("int", false) => b.extend_from_slice(&(i as i32).to_be_bytes()),
                (_, true) => b.extend_from_slice(&(i as u16).to_le_bytes()),
                (_, false) => b.extend_from_slice(&(i as u16).to_be_bytes()),
            }
        }
        b.push(7);
    }
    b.extend_from_slice(extra);
    b
}

#[test]
fn binary_ply_list_elements_after_the_vertices_are_read_by_their_counts() {
    let dir = tempfile::tempdir().unwrap();
    let faces = vec![vec![0, 1, 2], vec![3, 4, 5, 6], vec![], vec![7, 8, 9]];
    let base = read_points(&fixture("tunnel_small.csv")).unwrap();
    for little in [true, false] {
        for item in ["int", "ushort"] {
            // Exact: read by both paths (held points, and streamed H and M).
            let path = dir.path().join(format!("faces_{little}_{item}.ply"));
            std::fs::write(&path, ply_with_faces(little, &faces, item, b"")).unwrap();
            let d = read_points(&path).unwrap();
            assert_eq!(d.points, base.points);
            let a = accumulate_file(&path, None).unwrap();
            assert_eq!(a.assembly.count, 408);
            // Too little: the last face's last index cut off.
            let full = ply_with_faces(little, &faces, item, b"");
            let cut = &full[..full.len() - 2];
            // Too much: bytes after the last face.
            let more = ply_with_faces(little, &faces, item, b"\x01\x02\x03");
            for (bytes, want) in [
                (
                    cut.to_vec(),
                    "header claims 4 `face` items, the file ends in item 3",
                ),
                (
                    more,
                    "the file holds 3 more bytes after the header's last element `face`",
                ),
            ] {
                let p = dir.path().join("bad.ply");
                std::fs::write(&p, &bytes).unwrap();
                for e in [
                    read_points(&p).unwrap_err(),
                    accumulate_file(&p, None).unwrap_err(),
                    parse_points(&bytes).unwrap_err(),
                ] {
                    let m = e.to_string();
                    assert!(m.contains(want), "{m}");
                }
                let m = read_points(&p).unwrap_err().to_string();
                assert!(m.contains("bad.ply"), "{m}");
            }
        }
    }
    // A list whose count type is a float is refused at the header.
    let bad = String::from_utf8_lossy(&ply_with_faces(true, &faces, "int", b""))
        .replace("list uchar int", "list float int");
    let e = parse_points(bad.as_bytes()).unwrap_err();
    assert!(e.message.contains("integer list count type"), "{e}");
}
