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
