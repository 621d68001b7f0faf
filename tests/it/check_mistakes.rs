//! `audit check` on a robot whose files give one edge twice (an `audit.toml`
//! group): a disagreement with both values and the convention mistake that
//! reconciles them, not "two parents"; two sources that agree pass.

use crate::common::run_cli;

const RIG: &str = "[rig]\nid = \"ID\"\nsensor = \"s\"\nplatform = \"p\"\ndataset = \"d\"\n\
category = \"cad-or-nominal\"\nlicence = \"authored\"\ndirection = \"x\"\nfrom = \"FROM\"\nto = \"lidar\"\n\n\
[rig.source]\nrepo = \"a/b\"\npath = \"p\"\ncommit = \"0000000000000000000000000000000000000000\"\n";

fn transform(parent: &str, t: [f64; 3], extra: &str) -> String {
    format!(
        "\n[[transform]]\nparent = \"{parent}\"\nchild = \"CHILD\"\nunit = \"m\"\nsource_key = \"k\"\n\
         translation = [{}, {}, {}]\nrpy = [0.12, -0.35, 1.1]\n{extra}\n",
        t[0], t[1], t[2]
    )
}

/// `a.toml`: base -> imu (0.1, 0, 0.2), base -> lidar; `b.toml`: imu ->
/// lidar as `b_extra` writes it. The tree's imu -> lidar is (0.215, -0.043,
/// 0.318), rpy (0.12, -0.35, 1.1).
fn robot(b_body: &str) -> (tempfile::TempDir, i32, String) {
    let dir = tempfile::tempdir().unwrap();
    let imu =
        "\n[[transform]]\nparent = \"base\"\nchild = \"imu\"\nunit = \"m\"\nsource_key = \"k\"\n\
               translation = [0.1, 0.0, 0.2]\nrpy = [0.0, 0.0, 0.0]\n";
    let a = format!(
        "{}{imu}{}",
        RIG.replace("ID", "a").replace("FROM", "base"),
        transform("base", [0.315, -0.043, 0.518], "").replace("CHILD", "lidar")
    );
    std::fs::write(dir.path().join("a.toml"), a).unwrap();
    let b = format!("{}{b_body}", RIG.replace("ID", "b").replace("FROM", "imu"));
    std::fs::write(dir.path().join("b.toml"), b).unwrap();
    std::fs::write(
        dir.path().join("audit.toml"),
        "[[robot]]\nname = \"r\"\nfiles = [\"a.toml\", \"b.toml\"]\n",
    )
    .unwrap();
    let (code, out, err) = run_cli(&["check", dir.path().to_str().unwrap()]);
    (dir, code, format!("{out}{err}"))
}

#[test]
#[allow(clippy::approx_constant)] // 0.318 m is a lever arm, not 1/pi
fn check_names_the_mistake_between_two_sources_of_one_edge() {
    let edge =
        |extra: &str| transform("imu", [0.215, -0.043, 0.318], extra).replace("CHILD", "lidar");
    // Agreeing sources: a redundant edge, no finding.
    let (_d, code, out) = robot(&edge(""));
    assert_eq!(code, 0, "{out}");
    assert!(!out.contains("two parents"), "{out}");
    // The second file inverted: both values, the gap, the mistake.
    let (_d, code, out) = robot(&edge("invert = true"));
    assert_eq!(code, 1, "{out}");
    assert!(!out.contains("two parents"), "{out}");
    assert!(out.contains("error[redundant-edge-disagrees]: edge imu -> lidar has two sources that disagree by 759.099 mm"), "{out}");
    assert!(
        out.contains("gives t = [-0.164654, 0.176266, -0.301691] m"),
        "{out}"
    );
    assert!(out.contains("the tree imu <- base -> lidar"), "{out}");
    assert!(
        out.contains(
            "this file equals the tree inverted (parent and child swapped; residual 0.000 mm"
        ),
        "{out}"
    );
    // Written in millimetres, read as metres.
    let mm =
        "\n[[transform]]\nparent = \"imu\"\nchild = \"lidar\"\nunit = \"m\"\nsource_key = \"k\"\n\
              translation = [215.0, -43.0, 318.0]\nrpy = [0.12, -0.35, 1.1]\n";
    let (_d, code, out) = robot(mm);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains(
            "this file equals the tree with its translation in millimetres read as metres"
        ),
        "{out}"
    );
    // A genuine 4 mm disagreement: both values, no mistake.
    let (_d, code, out) =
        robot(&transform("imu", [0.219, -0.043, 0.318], "").replace("CHILD", "lidar"));
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("disagree by 4.000 mm"), "{out}");
    assert!(
        out.contains("no usual convention mistake reconciles them"),
        "{out}"
    );
}

/// `cal/r.toml` written as `old`, accepted as the baseline, then `new`:
/// what `check --baseline` says (exit 1 expected).
fn drift(old: &str, new: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("cal");
    std::fs::create_dir(&cal).unwrap();
    std::fs::write(cal.join("r.toml"), old).unwrap();
    let base = dir.path().join("base.json");
    let (c, o, e) = run_cli(&[
        "check",
        cal.to_str().unwrap(),
        "--write-baseline",
        base.to_str().unwrap(),
    ]);
    assert_eq!(c, 0, "{o}{e}");
    std::fs::write(cal.join("r.toml"), new).unwrap();
    let (code, out, err) = run_cli(&[
        "check",
        cal.to_str().unwrap(),
        "--baseline",
        base.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{out}{err}");
    format!("{out}{err}")
}

#[test]
#[allow(clippy::approx_constant)] // 0.318 m is a lever arm, not 1/pi
fn baseline_drift_names_the_convention_mistake() {
    // Issue 30: drift against the baseline is a second source of the edge.
    let file = |t: [f64; 3], extra: &str| {
        format!(
            "{}{}",
            RIG.replace("ID", "r").replace("FROM", "imu"),
            transform("imu", t, extra).replace("CHILD", "lidar")
        )
    };
    let old = file([0.215, -0.043, 0.318], "");
    let out = drift(&old, &file([0.215, -0.043, 0.318], "invert = true"));
    assert!(out.contains("drifted since the baseline"), "{out}");
    assert!(
        out.contains(
            "the file equals the baseline inverted (parent and child swapped; residual 0.000 mm"
        ),
        "{out}"
    );
    // Millimetres written where metres are read.
    let out = drift(&old, &file([215.0, -43.0, 318.0], ""));
    assert!(
        out.contains(
            "the file equals the baseline with its translation in millimetres read as metres"
        ),
        "{out}"
    );
    // A recalibration (5 mm along x): drift, and no mistake named.
    let out = drift(&old, &file([0.220, -0.043, 0.318], ""));
    assert!(out.contains("drifted since the baseline"), "{out}");
    assert!(!out.contains(" equals the baseline"), "{out}");
}

/// A Kalibr-like matrix YAML whose `T_cam0_cam1` closes the loop imu ->
/// cam0, imu -> cam1: cam1 is turned 90 deg about z, so the tree's cam0 ->
/// cam1 is R = Rz(90), t = (0, 0.2, 0), and its inverse R^T, (-0.2, 0, 0).
fn loop_file(cam0_cam1: &str) -> (tempfile::TempDir, String) {
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "T_imu_cam0:\n  - [1.0, 0.0, 0.0, 0.1]\n  - [0.0, 1.0, 0.0, 0.0]\n  - [0.0, 0.0, 1.0, 0.0]\n  - [0.0, 0.0, 0.0, 1.0]\n\
T_imu_cam1:\n  - [0.0, -1.0, 0.0, 0.1]\n  - [1.0, 0.0, 0.0, 0.2]\n  - [0.0, 0.0, 1.0, 0.0]\n  - [0.0, 0.0, 0.0, 1.0]\n\
T_cam0_cam1:\n{cam0_cam1}"
    );
    let path = dir.path().join("chain.yaml");
    std::fs::write(&path, text).unwrap();
    let p = path.to_str().unwrap().to_string();
    (dir, p)
}

#[test]
fn a_redundant_edge_in_one_file_names_the_convention_mistake() {
    let rows = |r: [[f64; 4]; 3]| {
        r.iter()
            .chain(&[[0.0, 0.0, 0.0, 1.0]])
            .map(|r| format!("  - [{}, {}, {}, {}]\n", r[0], r[1], r[2], r[3]))
            .collect::<String>()
    };
    let inverted = rows([
        [0.0, 1.0, 0.0, -0.2],
        [-1.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ]);
    let (_d, p) = loop_file(&inverted);
    let (_, out, err) = run_cli(&[&p, "--from", "imu", "--to", "cam1"]);
    let all = format!("{out}{err}");
    assert!(all.contains("redundant-edge-disagrees"), "{all}");
    assert!(
        all.contains(
            "the file equals the tree inverted (parent and child swapped; residual 0.000 mm"
        ),
        "{all}"
    );
    // 5 cm off along y: no usual mistake explains it, and it says so.
    let off = rows([
        [0.0, -1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.25],
        [0.0, 0.0, 1.0, 0.0],
    ]);
    let (_d, p) = loop_file(&off);
    let (_, out, err) = run_cli(&[&p, "--from", "imu", "--to", "cam1"]);
    let all = format!("{out}{err}");
    assert!(all.contains("redundant-edge-disagrees"), "{all}");
    assert!(
        all.contains("no usual convention mistake reconciles them")
            && !all.contains(" equals the tree"),
        "{all}"
    );
}
