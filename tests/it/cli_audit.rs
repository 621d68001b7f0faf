//! The `audit` binary on real files: the rig report's numbers against an
//! independent fixture (tests/fixtures/cli/gen_reports.py: pytransform3d and
//! numpy), the JSON schema, frame listing, errors and exit codes.

use crate::common::schema;

use serde_json::Value;

use crate::common::audit;

fn json_out(args: &[&str]) -> Value {
    let out = audit().args(args).output().expect("run");
    assert_eq!(
        out.status.code(),
        Some(0),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("json")
}

fn num(v: &Value) -> f64 {
    v.as_f64().expect("number")
}

fn close(a: f64, b: f64, tol: f64, what: &str) {
    assert!(
        (a - b).abs() <= tol * (1.0 + b.abs()),
        "{what}: got {a}, expected {b}"
    );
}

#[test]
fn urdf_reports_match_independent_fixture() {
    let fx: Value = serde_json::from_str(
        &std::fs::read_to_string("tests/fixtures/cli/urdf_reports.json").expect("fixture"),
    )
    .expect("json");
    let reports = fx["reports"].as_array().expect("reports");
    assert!(reports.len() >= 6);
    for r in reports {
        let Some(file) = crate::common::testdata::urdf(r["file"].as_str().unwrap()) else {
            continue;
        };
        let file = file.to_str().unwrap();
        let (from, to) = (r["from"].as_str().unwrap(), r["to"].as_str().unwrap());
        let what = format!("{file} {from}->{to}");
        let j = json_out(&[file, "--from", from, "--to", to, "--format", "json"]);
        let errs = schema::check(&j, &schema::rig_report_spec(), "$");
        assert!(errs.is_empty(), "{what}: {errs:?}");
        for k in 0..3 {
            close(
                num(&j["transform"]["translation_m"][k]),
                num(&r["translation_m"][k]),
                1e-12,
                &what,
            );
        }
        close(num(&j["lever_arm_m"]), num(&r["lever_arm_m"]), 1e-12, &what);
        close(
            num(&j["rotation"]["angle_rad"]),
            num(&r["angle_rad"]),
            1e-9,
            &what,
        );
        assert_eq!(j["screw"]["kind"], r["kind"], "{what}");
        if r["h"].is_null() {
            assert!(j["screw"]["translation_along_axis_m"].is_null(), "{what}");
        } else {
            let h = num(&j["screw"]["translation_along_axis_m"]);
            let hx = num(&r["h"]);
            if r["near_half_turn"].as_bool().unwrap() {
                close(h.abs(), hx.abs(), 1e-9, &what);
                assert!(h >= 0.0, "{what}: at a half-turn the tool picks h >= 0");
            } else {
                close(h, hx, 1e-9, &what);
                close(
                    num(&j["screw"]["pitch_m_per_rad"]),
                    num(&r["pitch"]),
                    1e-9,
                    &what,
                );
                for k in 0..3 {
                    close(
                        num(&j["screw"]["axis_point_m"][k]),
                        num(&r["axis_point"][k]),
                        1e-9,
                        &what,
                    );
                }
            }
        }
        for k in 0..6 {
            close(
                num(&j["adjoint"]["singular_values"][k]),
                num(&r["singular_values"][k]),
                1e-12,
                &what,
            );
        }
        let certs = j["certificate"].as_array().unwrap();
        assert_eq!(certs.len(), 4, "default --ell is 0.25,1,2.85,10");
        for (c, x) in certs.iter().zip(r["certificate"].as_array().unwrap()) {
            close(num(&c["ell_m"]), num(&x["ell_m"]), 0.0, &what);
            close(num(&c["band"][0]), num(&x["band"][0]), 1e-10, &what);
            close(num(&c["band"][1]), num(&x["band"][1]), 1e-10, &what);
        }
        let zero_pitch = r["kind"] == "zero_pitch";
        assert_eq!(
            j["adapted_metric"]["exists"],
            Value::Bool(zero_pitch),
            "{what}"
        );
        if zero_pitch {
            assert!(
                num(&j["adapted_metric"]["invariance_residual"]) < 1e-12,
                "{what}"
            );
        }
        // Only point displacement is invariant on a rig with a lever arm, except
        // the adapted constant metric at zero pitch.
        for d in j["detectors"].as_array().unwrap() {
            let fam = d["family"].as_str().unwrap();
            let expect = fam == "point_displacement" || (zero_pitch && fam == "adapted_constant");
            assert_eq!(d["invariant_on_rig"], Value::Bool(expect), "{what} {fam}");
        }
        // Provenance: every edge used names its file and line.
        for s in j["sources"].as_array().unwrap() {
            assert_eq!(s["file"].as_str().unwrap(), file);
            assert!(s["line"].as_u64().unwrap() > 0);
            assert_eq!(s["format"], "urdf");
        }
    }
}

#[test]
fn table_report_opens_with_verdict_and_lists_chain() {
    let urdf = crate::real!(crate::common::testdata::ANYMAL_C);
    let out = audit()
        .args([urdf.to_str().unwrap(), "--from", "base", "--to", "lidar"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let s = String::from_utf8(out.stdout).unwrap();
    let first = s.lines().next().unwrap();
    assert_eq!(
        first,
        "lever arm 0.391 m, h = -0.1422 +- 4.082e-5 m (rounding), pitch nonzero: no constant metric is frame-invariant on this rig; only the point-displacement metric is. To do: use the point-displacement metric (frame-invariant on every rig): h = -0.1422 m rules out an adapted metric M0, and an eigenvalue threshold tuned in lidar acts in base as 0.6782 to 1.475 times itself (lever arm 0.391 m, l = 1 m)."
    );
    assert!(s.contains("anymal.urdf:666"), "chain names file:line:\n{s}");
    assert!(s.contains("joint \"lidar_cage_to_lidar\" <origin>"));
    assert!(!s.contains('\x1b'), "no colour when not a terminal");
}

#[test]
fn zero_pitch_rig_gets_adapted_metric_in_markdown() {
    // Unitree H1: pelvis -> mid360_link through the revolute torso joint at 0.
    let h1 = crate::real!(crate::common::testdata::UNITREE_H1);
    let out = audit()
        .args([
            h1.to_str().unwrap(),
            "--from",
            "pelvis",
            "--to",
            "mid360_link",
            "--format",
            "markdown",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let s = String::from_utf8(out.stdout).unwrap();
    assert!(s.starts_with("**lever arm 0.677 m, h = 0 +- "), "{s}");
    assert!(s.contains("### Adapted constant metric"));
    assert!(s.contains("exists:"));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("joint-at-default") && err.contains("torso_joint"),
        "{err}"
    );
}

#[test]
fn joint_value_changes_the_transform() {
    let h1 = crate::real!(crate::common::testdata::UNITREE_H1);
    let h1 = h1.to_str().unwrap();
    let base = json_out(&[
        h1,
        "--from",
        "pelvis",
        "--to",
        "mid360_link",
        "--format",
        "json",
    ]);
    let turned = json_out(&[
        h1,
        "--from",
        "pelvis",
        "--to",
        "mid360_link",
        "--joint",
        "torso_joint=0.5",
        "--format",
        "json",
    ]);
    // The torso joint turns about z: the lever arm is unchanged only if the
    // LiDAR sits on the axis, which it does not.
    assert_ne!(base["transform"], turned["transform"]);
    // A typo in a joint name is an error that suggests the real one.
    let out = audit()
        .args([
            h1,
            "--from",
            "pelvis",
            "--to",
            "mid360_link",
            "--joint",
            "torso_jiont=0.5",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("did you mean `torso_joint`?"));
}

#[test]
fn kappa_lambda_certificate() {
    // Paper check: lever arm 0.552 m, l = 1 gives the band [0.58, 1.72]. The
    // NTU VIRAL vertical OS1-16 has 0.5531 m.
    let j = json_out(&[
        "calibrations/ntuviral-vert-os1-16.toml",
        "--ell",
        "1",
        "--kappa",
        "0.01",
        "--lambda",
        "0.02",
        "--format",
        "json",
    ]);
    let band = &j["certificate"][0]["band"];
    close(num(&band[0]), 0.58, 0.005, "lower");
    close(num(&band[1]), 1.72, 0.005, "upper");
    assert_eq!(
        j["kappa_check"]["certified"][0],
        Value::Bool(true),
        "ratio 2 > 1.73"
    );
    let j = json_out(&[
        "calibrations/ntuviral-vert-os1-16.toml",
        "--ell",
        "1",
        "--kappa",
        "0.01",
        "--lambda",
        "0.015",
        "--format",
        "json",
    ]);
    assert_eq!(
        j["kappa_check"]["certified"][0],
        Value::Bool(false),
        "ratio 1.5 inside"
    );
}

#[test]
fn single_edge_file_needs_no_frames() {
    let j = json_out(&[
        "tests/fixtures/formats/fastlio_avia.yaml",
        "--format",
        "json",
    ]);
    assert_eq!(j["from"], "imu");
    assert_eq!(j["to"], "lidar");
    assert_eq!(j["screw"]["kind"], "pure_translation");
    close(
        num(&j["lever_arm_m"]),
        0.055518556,
        1e-8,
        "FAST-LIO Avia lever arm",
    );
}

#[test]
fn frames_lists_tree() {
    let urdf = crate::real!(crate::common::testdata::ANYMAL_C);
    let out = audit()
        .args([urdf.to_str().unwrap(), "--frames"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let s = String::from_utf8(out.stdout).unwrap();
    for f in ["base", "lidar_cage", "lidar", "imu_link"] {
        assert!(s.contains(f), "{f} missing:\n{s}");
    }
}

#[test]
fn unknown_frame_suggests_and_exits_2() {
    let out = audit()
        .args([
            "tests/fixtures/urdf/anymal_c_lidar.urdf",
            "--from",
            "base",
            "--to",
            "lidr",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("lidr"), "{err}");
    assert!(err.contains("lidar"), "suggests the closest name: {err}");
}

#[test]
fn usage_errors_exit_2() {
    // Missing file.
    let out = audit()
        .args(["no/such/file.urdf", "--from", "a", "--to", "b"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no/such/file.urdf"));
    // Only one of --from / --to.
    let out = audit()
        .args(["tests/fixtures/urdf/anymal_c_lidar.urdf", "--from", "base"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    // A non-positive characteristic length.
    let out = audit()
        .args([
            "tests/fixtures/urdf/anymal_c_lidar.urdf",
            "--from",
            "base",
            "--to",
            "lidar",
            "--ell",
            "0",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    // Several edges and no frames named.
    let out = audit()
        .args(["tests/fixtures/urdf/anymal_c_lidar.urdf"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--from"));
}

#[test]
fn completions_and_help() {
    for shell in ["bash", "zsh", "fish"] {
        let out = audit().args(["completions", shell]).output().unwrap();
        assert_eq!(out.status.code(), Some(0));
        let s = String::from_utf8(out.stdout).unwrap();
        assert!(s.contains("survey") && s.contains("--from"), "{shell}");
    }
    for sub in [
        &["--help"][..],
        &["survey", "--help"],
        &["check", "--help"],
        &["tunnel", "--help"],
        &["simulate", "--help"],
        &["degeneracy", "--help"],
        &["calibrate-threshold", "--help"],
        &["completions", "--help"],
    ] {
        let out = audit().args(sub).output().unwrap();
        assert_eq!(out.status.code(), Some(0));
        assert!(
            String::from_utf8_lossy(&out.stdout).contains("Examples:"),
            "{sub:?}"
        );
    }
}

#[test]
fn bad_input_catalogue_exits_2_and_names_file() {
    let dir = std::path::Path::new("tests/bad_inputs");
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        let name = p.file_name().unwrap().to_str().unwrap().to_string();
        if name.ends_with(".expected") || name.ends_with(".args") || name.ends_with(".md") {
            continue;
        }
        let stem = name.split('.').next().unwrap();
        let expected = std::fs::read_to_string(dir.join(format!("{stem}.expected")))
            .unwrap_or_else(|_| panic!("{stem}.expected"));
        let mut cmd = audit();
        cmd.env("PATH", "");
        // The 6N cases are point files (LAS, LAZ): `audit degeneracy` reads them.
        let point_file = name.ends_with(".las") || name.ends_with(".laz");
        if point_file {
            cmd.args(["degeneracy", "--estimate-normals"]);
        }
        cmd.arg(&p);
        if let Ok(a) = std::fs::read_to_string(dir.join(format!("{stem}.args"))) {
            cmd.args(a.split_whitespace());
        } else if !point_file {
            cmd.arg("--frames");
        }
        let out = cmd.output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {err}");
        assert!(
            err.contains(expected.trim()),
            "{name}:\n got {err}\n want {expected}"
        );
        assert!(err.contains(&name), "{name}: message names the file: {err}");
        n += 1;
    }
    assert!(n >= 25, "catalogue has {n} inputs");
}

#[test]
fn rename_attaches_a_nameless_file_to_a_urdf() {
    // A FAST-LIO extrinsic (imu -> lidar, Avia numbers) attached to ANYmal C's
    // imu_link: lidar -> avia = T(lidar, imu_link) from the pytransform3d
    // fixture, composed with the FAST-LIO numbers.
    let dir = tempfile::tempdir().unwrap();
    let fl = dir.path().join("fast_lio.yaml");
    std::fs::write(
        &fl,
        "mapping:\n  extrinsic_T: [ 0.04165, 0.02326, -0.0284 ]\n  extrinsic_R: [ 0, -1, 0, 1, 0, 0, 0, 0, 1 ]\n",
    )
    .unwrap();
    let urdf = crate::real!(crate::common::testdata::ANYMAL_C);
    let urdf = urdf.to_str().unwrap();
    let j = json_out(&[
        urdf,
        fl.to_str().unwrap(),
        "--rename",
        "fast_lio.yaml:imu=imu_link",
        "--rename",
        "fast_lio.yaml:lidar=avia",
        "--from",
        "lidar",
        "--to",
        "avia",
        "--format",
        "json",
    ]);
    let fx: Value = serde_json::from_str(
        &std::fs::read_to_string("tests/fixtures/urdf/expected_pairs.json").unwrap(),
    )
    .unwrap();
    let p = fx["pairs"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["file"] == "anymal_c.urdf" && p["from"] == "lidar" && p["to"] == "imu_link")
        .unwrap();
    let t = |i: usize, k: usize| num(&p["T"][i][k]);
    let b = [0.04165, 0.02326, -0.0284];
    let rb = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
    for i in 0..3 {
        let d = t(i, 3) + (0..3).map(|k| t(i, k) * b[k]).sum::<f64>();
        close(
            num(&j["transform"]["translation_m"][i]),
            d,
            1e-12,
            "translation",
        );
        for c in 0..3 {
            let r: f64 = (0..3).map(|k| t(i, k) * rb[k][c]).sum();
            close(
                num(&j["transform"]["rotation_matrix"][i][c]),
                r,
                1e-12,
                "rotation",
            );
        }
    }
    let sources = j["sources"].as_array().unwrap();
    assert_eq!(sources.last().unwrap()["format"], "fast-lio");
    assert!(sources[..sources.len() - 1]
        .iter()
        .all(|s| s["format"] == "urdf"));
    // A rename that matches nothing is a usage error.
    let out = audit()
        .args([
            urdf, "--rename", "imuu=x", "--from", "base", "--to", "lidar",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--rename imuu=x"));
}

/// `audit check` on every catalogue file (issue 7): a file that cannot be used
/// is a finding (exit 1) or unreadable (exit 2), never a panic (101) or a
/// signal, and the output names the file. `.args` options are mapped to
/// `check`'s (`--from A --to B` -> `--pair A:B`); a case that needs an option
/// `check` does not have (`--key`, `--input-format`) may pass (exit 0) there.
#[test]
fn bad_input_catalogue_under_check_is_a_finding_naming_the_file() {
    let dir = std::path::Path::new("tests/bad_inputs");
    let mut n = 0;
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        let name = p.file_name().unwrap().to_str().unwrap().to_string();
        if name.ends_with(".expected") || name.ends_with(".args") || name.ends_with(".md") {
            continue;
        }
        let stem = name.split('.').next().unwrap();
        let mut cmd = audit();
        cmd.env("PATH", "").arg("check").arg(&p);
        let mut unsupported = false;
        if let Ok(a) = std::fs::read_to_string(dir.join(format!("{stem}.args"))) {
            let w: Vec<&str> = a.split_whitespace().collect();
            let mut i = 0;
            while i + 1 < w.len() {
                match w[i] {
                    "--from" if w.get(i + 2) == Some(&"--to") && i + 3 < w.len() => {
                        cmd.arg("--pair").arg(format!("{}:{}", w[i + 1], w[i + 3]));
                        i += 4;
                        continue;
                    }
                    "--joint" | "--max-file-size" => {
                        cmd.args([w[i], w[i + 1]]);
                    }
                    _ => unsupported = true,
                }
                i += 2;
            }
        }
        let out = cmd.output().unwrap();
        let all = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        let code = out.status.code();
        assert!(code.is_some(), "{name}: killed by a signal: {all}");
        assert_ne!(code, Some(101), "{name}: panicked: {all}");
        if unsupported && code == Some(0) {
            continue;
        }
        assert!(
            matches!(code, Some(1) | Some(2)),
            "{name}: exit {code:?}, expected 1 (finding) or 2: {all}"
        );
        assert!(all.contains(&name), "{name}: output names the file: {all}");
        n += 1;
    }
    assert!(n >= 25, "catalogue has {n} inputs");
}

/// `--invert` reads the numbers as the pose of the parent in the child: the
/// FAST-LIO extrinsic (identity rotation, d = (0.04165, 0.02326, -0.0284))
/// gives imu -> lidar = its inverse, translation -d. (Before, the edge was
/// flipped and inverted at once, which states the same pose: a no-op.)
#[test]
fn invert_reads_the_file_the_other_way() {
    let args = [
        "tests/fixtures/formats/fastlio_avia.yaml",
        "--from",
        "imu",
        "--to",
        "lidar",
        "--format",
        "json",
    ];
    let t = |extra: &[&str]| -> Vec<f64> {
        let (code, out, err) = crate::common::run_cli(&[&args[..], extra].concat());
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        v["transform"]["translation_m"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    assert_eq!(t(&[]), [0.04165, 0.02326, -0.0284]);
    assert_eq!(t(&["--invert"]), [-0.04165, -0.02326, 0.0284]);
}

/// A LAS/LAZ scan given to the rig audit is named for what it is, with the
/// command that reads it (not "expected UTF-8 text").
#[test]
fn a_las_scan_given_as_extrinsics_points_to_degeneracy() {
    use crate::common::testdata::{AUTZEN_LAS, AUTZEN_LAZ};
    for (f, real) in [("autzen.las", AUTZEN_LAS), ("autzen.laz", AUTZEN_LAZ)] {
        let p = crate::real!(real);
        let out = audit()
            .args([p.to_str().unwrap(), "--frames"])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{f}: {err}");
        assert!(err.contains(f), "{f}: names the file: {err}");
        assert!(err.contains("LAS/LAZ point cloud"), "{f}: {err}");
        assert!(err.contains("audit degeneracy"), "{f}: {err}");
    }
}
