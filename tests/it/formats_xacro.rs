//! xacro: the built-in expander against Python xacro (`pip install xacro`,
//! tests/fixtures/xacro/generate.py) on real description packages (read in
//! place from the test-data folder, `$(find pkg)` resolved there), edge by
//! edge to 1e-12; every edge points at a `<joint>` line in the xacro source;
//! `--arg`, `--package-path`; the external fallback with a stand-in program.
//! Refusals (unknown macro, missing include, recursion, bomb, ...) are in the
//! bad-input catalogue (tests/bad_inputs/8*-xacro-*, 9*-xacro-*).

use crate::common::testdata;
use extrinsic_audit::internals::formats::{load_file, Parsed};
use extrinsic_audit::{Format, LoadOptions};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

const DIR: &str = "tests/fixtures/xacro";

/// The packages the project's own rig includes with `$(find pkg)`
/// (velodyne_description, realsense2_description), in the test-data folder.
const RIG_PACKAGES: [&str; 2] = [
    testdata::VELODYNE_SIMULATOR,
    "IntelRealSense__realsense-ros",
];

struct Case {
    name: String,
    input: PathBuf,
    args: BTreeMap<String, String>,
    package_paths: Vec<PathBuf>,
}

/// A path of cases.tsv: `test-data/<repo>/...` in the test-data folder (the
/// repository's files checked; `None` where absent), else under DIR.
fn input(rel: &str) -> Option<PathBuf> {
    let Some(real) = rel.strip_prefix("test-data/") else {
        return Some(Path::new(DIR).join(rel));
    };
    let (repo, rest) = real.split_once('/').expect("test-data/<repo>/<path>");
    Some(testdata::dir(repo)?.join(rest))
}

/// The --package-path the own rig needs (`None`: absent).
fn rig_packages() -> Option<Vec<PathBuf>> {
    RIG_PACKAGES.iter().map(|p| testdata::dir(p)).collect()
}

/// The cases of cases.tsv whose files are there.
fn cases() -> Vec<Case> {
    let text = std::fs::read_to_string(Path::new(DIR).join("cases.tsv")).expect("cases.tsv");
    text.lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|l| {
            let cols: Vec<&str> = l.split('\t').collect();
            let args = cols
                .get(2)
                .map(|a| {
                    a.split_whitespace()
                        .map(|kv| {
                            let (k, v) = kv.split_once(":=").expect("NAME:=VALUE");
                            (k.to_string(), v.to_string())
                        })
                        .collect()
                })
                .unwrap_or_default();
            Some(Case {
                name: cols[0].to_string(),
                input: input(cols[1])?,
                args,
                package_paths: rig_packages()?,
            })
        })
        .collect::<Option<Vec<Case>>>()
        .unwrap_or_default()
}

/// The case `name` (`None`: its files are absent).
fn case(name: &str) -> Option<Case> {
    cases().into_iter().find(|c| c.name == name)
}

fn native(c: &Case) -> Parsed {
    let mut opts = LoadOptions::default();
    opts.xacro_args = c.args.clone();
    opts.package_paths = c.package_paths.clone();
    load_file(&c.input, &opts).unwrap_or_else(|e| panic!("{}: {e}", c.name))
}

/// Python xacro's edges (expected/<case>.json, generate.py: parent, child,
/// origin xyz and rpy of every joint), read back as a URDF of those joints so
/// that both sides go through the same transform code.
fn expected(c: &Case) -> Parsed {
    let p = Path::new(DIR)
        .join("expected")
        .join(format!("{}.json", c.name));
    edge_table(&p, &c.name)
}

/// An edge table (`{"edges": [{"parent", "child", "xyz", "rpy"}]}`) as the
/// URDF reader reads those joints.
pub fn edge_table(p: &Path, name: &str) -> Parsed {
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(p).expect("expected json")).expect("json");
    let vec3 = |e: &serde_json::Value, k: &str| {
        let n = crate::common::nums(&e[k]);
        assert_eq!(n.len(), 3, "{}: {k}", name);
        format!("{:?} {:?} {:?}", n[0], n[1], n[2])
    };
    let joints: String = v["edges"]
        .as_array()
        .expect("edges")
        .iter()
        .enumerate()
        .map(|(i, e)| {
            format!(
                "<joint name=\"j{i}\" type=\"fixed\"><parent link=\"{}\"/><child link=\"{}\"/><origin xyz=\"{}\" rpy=\"{}\"/></joint>\n",
                e["parent"].as_str().expect("parent"),
                e["child"].as_str().expect("child"),
                vec3(e, "xyz"),
                vec3(e, "rpy")
            )
        })
        .collect();
    let links: std::collections::BTreeSet<&str> = v["edges"]
        .as_array()
        .expect("edges")
        .iter()
        .flat_map(|e| [e["parent"].as_str(), e["child"].as_str()])
        .flatten()
        .collect();
    let links: String = links
        .iter()
        .map(|l| format!("<link name=\"{l}\"/>\n"))
        .collect();
    let dir = tempfile::tempdir().expect("tempdir");
    let urdf = dir.path().join(format!("{}.urdf", name));
    std::fs::write(
        &urdf,
        format!("<robot name=\"expected\">\n{links}{joints}</robot>\n"),
    )
    .expect("write");
    load_file(&urdf, &LoadOptions::default()).unwrap_or_else(|e| panic!("{}: {e}", name))
}

/// Largest entry difference of the 4x4 matrices, per edge keyed by
/// (parent, child); panics when the edge sets differ.
pub fn compare(name: &str, got: &Parsed, want: &Parsed) -> f64 {
    let key = |l: &Parsed| -> BTreeMap<(String, String), nalgebra::Matrix4<f64>> {
        l.edges
            .iter()
            .map(|e| ((e.parent.clone(), e.child.clone()), e.transform.matrix4()))
            .collect()
    };
    let (g, w) = (key(got), key(want));
    assert_eq!(g.len(), got.edges.len(), "{}: duplicate edges", name);
    assert_eq!(
        g.keys().collect::<Vec<_>>(),
        w.keys().collect::<Vec<_>>(),
        "{}: the edge sets differ",
        name
    );
    g.iter()
        .map(|(k, m)| (m - w[k]).abs().max())
        .fold(0.0, f64::max)
}

#[test]
fn native_expansion_equals_python_xacro_on_real_packages() {
    let all = cases();
    if all.is_empty() {
        return; // the test data is absent (skipped, counted)
    }
    assert!(all.len() >= 19, "only {} cases", all.len());
    let mut total = 0;
    for c in &all {
        let got = native(c);
        let want = expected(c);
        let d = compare(&c.name, &got, &want);
        assert!(d <= 1e-12, "{}: transforms differ by {d:e}", c.name);
        assert!(!got.edges.is_empty(), "{}: no edges", c.name);
        total += got.edges.len();
    }
    assert!(total > 250, "{total} edges in all");
}

/// Every pair of LiDAR / IMU / laser frames (and each such frame against the
/// root), composed through the frame graph, equals Python xacro's to 1e-12.
#[test]
fn lidar_and_imu_paths_equal_python_xacro() {
    use extrinsic_audit::internals::frames::FrameGraph;
    let sensor = |f: &str| {
        let f = f.to_ascii_lowercase();
        ["lidar", "laser", "velodyne", "imu", "scan"]
            .iter()
            .any(|k| f.contains(k))
    };
    let all = cases();
    if all.is_empty() {
        return;
    }
    let mut pairs = 0;
    for c in &all {
        let (mut g, mut w) = (FrameGraph::new(), FrameGraph::new());
        g.add(native(c)).expect("graph");
        w.add(expected(c)).expect("graph");
        let frames: Vec<String> = g.frames().into_iter().filter(|f| sensor(f)).collect();
        let root = native(c).edges[0].parent.clone();
        for (i, a) in frames.iter().enumerate() {
            for b in std::iter::once(&root).chain(&frames[i + 1..]) {
                let (Ok(x), Ok(y)) = (g.transform(b, a), w.transform(b, a)) else {
                    continue;
                };
                let d = (x.transform.matrix4() - y.transform.matrix4()).abs().max();
                assert!(d <= 1e-12, "{}: {b} -> {a}: {d:e}", c.name);
                pairs += 1;
            }
        }
    }
    assert!(pairs >= 30, "{pairs} sensor pairs");
}

/// Every edge names the file and line of a `<joint>` in the xacro sources (the
/// included file that wrote it, not the top file), and is marked as xacro.
#[test]
fn every_edge_points_at_its_joint_in_the_xacro_source() {
    let all = cases();
    if all.is_empty() {
        return;
    }
    let mut from_included = 0;
    for c in &all {
        for e in native(c).edges {
            let loc = &e.provenance.location;
            let file = loc.file.as_ref().expect("file");
            let line = loc.line.expect("line");
            let text = std::fs::read_to_string(file).expect("source file");
            let l = text.lines().nth(line - 1).unwrap_or("");
            assert!(
                l.contains("<joint") || l.contains("<xacro:element"),
                "{}: edge {} -> {} at {}:{line} is not a joint line: {l:?}",
                c.name,
                e.parent,
                e.child,
                file.display()
            );
            assert_eq!(e.provenance.format, "xacro");
            if **file != *c.input {
                from_included += 1;
            }
        }
    }
    assert!(
        from_included > 100,
        "{from_included} edges from included files"
    );
}

/// The PR2 base laser: base.urdf.xacro calls the Hokuyo macro of
/// hokuyo_lx30_laser.urdf.xacro with an `<origin>` block; the edge points at
/// the `<joint>` in the Hokuyo macro, the numbers are those of the block.
#[test]
fn pr2_base_laser_comes_from_the_included_macro() {
    let Some(c) = case("pr2") else { return };
    let l = native(&c);
    let e = l
        .edges
        .iter()
        .find(|e| e.child == "base_laser_link")
        .expect("base laser");
    assert_eq!(e.parent, "base_link");
    let file = e.provenance.location.file.as_ref().expect("file");
    assert!(
        file.ends_with("pr2_description/urdf/sensors/hokuyo_lx30_laser.urdf.xacro"),
        "{}",
        file.display()
    );
    let d = e.transform.translation();
    assert!(
        (d.x - 0.275).abs() < 1e-15 && d.y.abs() < 1e-15 && (d.z - 0.252).abs() < 1e-15,
        "{d}"
    );
}

/// `--arg` overrides an `xacro:arg` default (here the DEBUG switch that hangs
/// the Unitree A1 from a world link).
#[test]
fn arg_overrides_the_default() {
    let Some(mut c) = case("unitree_a1") else {
        return;
    };
    assert!(!native(&c).edges.iter().any(|e| e.parent == "world"));
    c.args.insert("DEBUG".into(), "true".into());
    let l = native(&c);
    let e = l
        .edges
        .iter()
        .find(|e| e.parent == "world")
        .expect("world joint");
    assert_eq!(e.child, "base");
}

/// `$(find pkg)` of a package that is nowhere is an error naming it; with
/// `--package-path` pointing at a directory holding it, the file expands (a
/// file in a temporary directory: the upward search cannot find it).
#[test]
fn find_uses_the_package_path() {
    let warthog = crate::real!(testdata::WARTHOG_XACRO);
    let velodyne = crate::real_dir!(testdata::VELODYNE_SIMULATOR);
    let e = load_file(&warthog, &LoadOptions::default()).expect_err("no warthog_description");
    assert!(e.message.contains("$(find warthog_description)"), "{e}");
    assert!(e.message.contains("--package-path"), "{e}");
    assert_eq!(e.location.line, Some(372), "{e}");

    let dir = tempfile::tempdir().expect("tempdir");
    let input = crate::common::vlp16_rig_xacro(dir.path());
    let e = load_file(&input, &LoadOptions::default()).expect_err("not found");
    assert!(e.message.contains("$(find velodyne_description)"), "{e}");
    let mut opts = LoadOptions::default();
    opts.package_paths = vec![velodyne];
    let l = load_file(&input, &opts).expect("expanded");
    let mount = l
        .edges
        .iter()
        .find(|e| e.child == "lidar_base_link")
        .expect("mount");
    let d = mount.transform.translation();
    assert!((d.x - 0.1).abs() < 1e-15 && d.y == 0.0 && (d.z - 0.25).abs() < 1e-15);
    let r = mount.transform.rotation();
    assert!((r[(1, 0)] - 1.0).abs() < 1e-15 && (r[(0, 1)] + 1.0).abs() < 1e-15);
    let scan = l.edges.iter().find(|e| e.child == "lidar").expect("scan");
    assert!((scan.transform.translation().z - 0.0377).abs() < 1e-15);
    let f = scan.provenance.location.file.as_ref().expect("file");
    assert!(
        f.ends_with("velodyne_description/urdf/VLP-16.urdf.xacro"),
        "{}",
        f.display()
    );
}

/// The velodyne example of this fork calls its macros without the `xacro:`
/// prefix: Python xacro 2 copies `<VLP-16>` as is (the LiDARs vanish from the
/// URDF), and so does this expander, with a warning naming the element.
#[test]
fn a_macro_called_without_prefix_is_copied_with_a_warning() {
    let Some(c) = case("velodyne_example") else {
        return;
    };
    let l = native(&c);
    assert_eq!(l.edges.len(), 1);
    let w: Vec<_> = l
        .warnings
        .iter()
        .filter(|w| w.message.contains("no `xacro:` prefix"))
        .collect();
    assert_eq!(w.len(), 3, "{w:?}");
    assert!(w[0].message.contains("<VLP-16>"), "{}", w[0].message);
    assert_eq!(w[0].location.line, Some(36));
}

/// `--xacro external` runs the `xacro` program: a stand-in shell script
/// printing a fixed URDF proves the wiring.
#[cfg(unix)]
#[test]
fn external_xacro_on_request() {
    let dir = tempfile::tempdir().expect("tempdir");
    crate::common::fake_xacro(dir.path());
    let l = load_file(
        &Path::new(DIR).join("own/lidar_rig/urdf/rig.urdf.xacro"),
        &{
            let mut o = LoadOptions::default();
            o.xacro_search_path = Some(dir.path().into());
            o.xacro_external = true;
            o
        },
    )
    .expect("expanded");
    assert_eq!(l.edges.len(), 1);
    assert!(l.edges[0].provenance.key.contains("expanded"));
    assert!((l.edges[0].transform.translation().z - 0.5).abs() < 1e-15);
}

/// A failing external `xacro` shows its whole stderr (the cause is on the
/// first line; xacro's last line only names the file), and a child that
/// prints without end is stopped at the file-size cap.
#[cfg(unix)]
#[test]
fn external_xacro_failures_keep_the_cause_and_are_bounded() {
    use std::os::unix::fs::PermissionsExt;
    let input = Path::new(DIR).join("own/lidar_rig/urdf/rig.urdf.xacro");
    let run = |body: &str| {
        let dir = tempfile::tempdir().expect("tempdir");
        let script = dir.path().join("xacro");
        std::fs::write(&script, format!("#!/bin/sh\n{body}\n")).expect("write");
        std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).expect("chmod");
        load_file(&input, &{
            let mut o = LoadOptions::default();
            o.xacro_search_path = Some(dir.path().into());
            o.xacro_external = true;
            o.max_file_size = 1 << 16;
            o
        })
        .expect_err("refused")
        .to_string()
    };
    let e = run(
        "echo 'name error: undefined macro wheel' >&2; echo 'when processing file: x' >&2; exit 2",
    );
    assert!(e.contains("undefined macro wheel"), "{e}");
    assert!(e.contains("when processing file"), "{e}");
    let t = std::time::Instant::now();
    let e = run("exec yes '<robot>'");
    assert!(e.contains("printed more than 65536 bytes"), "{e}");
    // Stopped at the output cap (the message), not at the time limit.
    assert!(t.elapsed() < std::time::Duration::from_secs(15));
}

/// Bad input never panics or hangs: deterministic mutations (a character
/// deleted or inserted, a line duplicated or dropped) of real xacro files,
/// each expanded with its includes. A stand-in for a fuzz run (the `xacro`
/// fuzz target exists; cargo-fuzz is not installed on this machine).
#[test]
fn mutated_xacro_never_panics_or_hangs() {
    use extrinsic_audit::internals::formats::load_str;
    use rand_core::{RngCore, SeedableRng};
    let files: Vec<PathBuf> = [
        "own/lidar_rig/urdf/rig.urdf.xacro",
        "test-data/IntelRealSense__realsense-ros/realsense2_description/urdf/_d435.urdf.xacro",
        "test-data/unitreerobotics__unitree_ros/robots/go1_description/xacro/robot.xacro",
        "test-data/ToyotaResearchInstitute__velodyne_simulator/velodyne_description/urdf/VLP-16.urdf.xacro",
    ]
    .iter()
    .filter_map(|f| input(f))
    .collect();
    const ALPHABET: &[u8] = b"${}()<>\"'/*$:= -_.x019\n";
    let mut rng = rand_pcg::Pcg64::seed_from_u64(15);
    let (mut ok, mut refused) = (0, 0);
    for i in 0..400 {
        let path = &files[i % files.len()];
        let mut text = std::fs::read_to_string(path).expect("read").into_bytes();
        for _ in 0..1 + rng.next_u32() % 3 {
            let at = rng.next_u32() as usize % text.len().max(1);
            match rng.next_u32() % 4 {
                0 => {
                    text.remove(at);
                }
                1 => text.insert(at, ALPHABET[rng.next_u32() as usize % ALPHABET.len()]),
                _ => {
                    let start = text[..at]
                        .iter()
                        .rposition(|b| *b == b'\n')
                        .map_or(0, |p| p + 1);
                    let end = text[at..]
                        .iter()
                        .position(|b| *b == b'\n')
                        .map_or(text.len(), |p| at + p + 1);
                    let line: Vec<u8> = text[start..end].to_vec();
                    if rng.next_u32() % 2 == 0 {
                        text.splice(start..start, line);
                    } else {
                        text.drain(start..end);
                    }
                }
            }
        }
        let text = String::from_utf8_lossy(&text).into_owned();
        let t = crate::common::hostile::cpu_now();
        let mut opts = LoadOptions::default();
        opts.format = Some(Format::from_name("xacro").expect("a format"));
        opts.package_paths = rig_packages().unwrap_or_default();
        match load_str(&text, path, &opts) {
            Ok(l) => {
                ok += 1;
                for e in &l.edges {
                    let m = e.transform.matrix4();
                    assert!(
                        m.iter().all(|x| x.is_finite()),
                        "{}: non-finite edge",
                        path.display()
                    );
                }
            }
            Err(e) => {
                refused += 1;
                assert!(!e.message.is_empty());
            }
        }
        crate::common::hostile::assert_quick(t, 5, &format!("mutation {i}"));
    }
    assert!(
        (ok >= 30 || files.len() < 4) && refused >= 100,
        "{ok} expanded, {refused} refused"
    );
}

/// The CLI flags: `--arg NAME=VALUE` reaches `$(arg)`, `--xacro external`
/// without the program is a clear exit-2 refusal.
#[test]
fn cli_arg_and_xacro_mode() {
    let rig = format!("{DIR}/own/lidar_rig/urdf/rig.urdf.xacro");
    let Some(packages) = rig_packages() else {
        return;
    };
    let out = crate::common::audit()
        .args([
            &rig,
            "--package-path",
            packages[0].to_str().unwrap(),
            "--package-path",
            packages[1].to_str().unwrap(),
            "--arg",
            "prefix=r1_",
            "--arg",
            "with_camera=false",
            "--frames",
        ])
        .output()
        .expect("run");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("r1_camera_placeholder"), "{stdout}");
    assert!(!stdout.contains("camera_link"), "{stdout}");
    let out = crate::common::audit()
        .env("PATH", "")
        .args([&rig, "--xacro", "external", "--frames"])
        .output()
        .expect("run");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("--xacro external"), "{stderr}");
}

/// The macro bomb of the catalogue (2^21 links) is refused at the element cap,
/// quickly, naming the limit.
#[test]
fn macro_bomb_is_refused_quickly() {
    let t = crate::common::hostile::cpu_now();
    let e = load_file(
        Path::new("tests/bad_inputs/83-xacro-bomb.urdf.xacro"),
        &LoadOptions::default(),
    )
    .expect_err("bomb");
    assert!(e.message.contains("elements: a macro bomb?"), "{e}");
    crate::common::hostile::assert_quick(t, 20, "the catalogue's macro bomb");
}

/// Old-style xacro elements without the prefix (`<property>`, `<include>`)
/// are copied as Python xacro 2 copies them, each with a warning.
#[test]
fn unprefixed_xacro_elements_are_warned_about() {
    let text = r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <property name="h" value="0.5"/>
  <link name="a"/><link name="b"/>
  <joint name="j" type="fixed"><parent link="a"/><child link="b"/><origin xyz="0 0 1"/></joint>
</robot>
"#;
    let mut opts = LoadOptions::default();
    opts.format = Some(Format::from_name("xacro").expect("a format"));
    let l = extrinsic_audit::internals::formats::load_str(text, Path::new("old.urdf.xacro"), &opts)
        .expect("expands");
    let w: Vec<_> = l
        .warnings
        .iter()
        .filter(|w| w.message.contains("without the `xacro:` prefix"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", l.warnings);
    assert_eq!(w[0].location.line, Some(2));
}
