//! Point-file inputs found by the `points` fuzz target (fuzz/, FUZZING.md): each
//! used to give a silent wrong answer (a huge normal overflowed to a zero
//! normal; coordinates near 1e200 overflowed H and M) and now has a defined
//! outcome.

use extrinsic_audit::internals::degeneracy::points::read_points;
use extrinsic_audit::internals::tolerances::MAX_COORDINATE;
use std::path::Path;

const DIR: &str = "fuzz/regressions/points";

#[test]
fn huge_normal_is_renormalised_not_zeroed() {
    let d = read_points(
        Path::new(DIR)
            .join("csv-huge-normal-becomes-zero.csv")
            .as_path(),
    )
    .expect("a finite normal of any length is a direction");
    assert_eq!(d.normals[0], [1.0, 0.0, 0.0]);
    for n in &d.normals {
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        assert!((len - 1.0).abs() < 1e-15, "{n:?}");
    }
    assert!(d
        .warnings
        .iter()
        .any(|w| w.message.contains("renormalised")));
}

#[test]
fn huge_coordinates_are_refused_with_line() {
    let e = read_points(Path::new(DIR).join("csv-huge-coordinates.csv").as_path())
        .expect_err("1e200 m cannot be assembled into H");
    let msg = e.to_string();
    assert!(msg.contains("csv-huge-coordinates.csv:2"), "{msg}");
    assert!(
        msg.contains(&format!("{MAX_COORDINATE:e}")) && msg.contains("1e200"),
        "{msg}"
    );
    let e = read_points(Path::new(DIR).join("ply-zero-normal-accepted").as_path())
        .expect_err("binary PLY with a 1e226 coordinate");
    assert!(e.to_string().contains("vertex 23"), "{e}");
}

#[test]
fn ply_huge_normal_reads_like_unit() {
    let d = read_points(
        Path::new(DIR)
            .join("ply-ascii-huge-normal-becomes-zero.ply")
            .as_path(),
    )
    .expect("reads");
    assert!(d.normals.iter().all(|n| n.iter().all(|x| x.is_finite())));
    assert!(d
        .normals
        .iter()
        .all(|n| ((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() - 1.0).abs() < 1e-15));
}

#[test]
fn pcd_count_zero_is_refused_not_a_panic() {
    // Found by run 3: COUNT 0 made a field's element index point past the
    // record and the ascii reader indexed out of bounds.
    let e = read_points(Path::new(DIR).join("pcd-count-zero.pcd").as_path())
        .expect_err("COUNT 0 is not a field");
    assert!(
        e.to_string()
            .contains("field \"x\": expected COUNT between 1 and"),
        "{e}"
    );
}
