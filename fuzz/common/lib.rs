//! Shared checks for the fuzz targets: load bytes through `load_str` with a
//! path chosen by the target (and a selector byte), assert that success never
//! carries a wrong number, and feed the edges to a `FrameGraph`.

use extrinsic_audit::internals::formats::{load_bytes, load_str, Parsed};
use extrinsic_audit::internals::frames::FrameGraph;
use extrinsic_audit::Transform;
use extrinsic_audit::{Format, LoadOptions};
use std::path::Path;

/// Orthonormality tolerance asserted on every edge of a successful load.
pub const ORTHO_TOL: f64 = 1e-9;

/// Panic unless `t` is finite with an orthonormal, det +1 rotation.
pub fn assert_sane(t: &Transform, what: &str) {
    let r = t.rotation();
    let d = t.translation();
    assert!(
        r.iter().all(|x| x.is_finite()) && d.iter().all(|x| x.is_finite()),
        "{what}: non-finite transform returned with Ok: {t:?}"
    );
    let e = (r.transpose() * r - nalgebra::Matrix3::identity()).norm();
    assert!(
        e <= ORTHO_TOL,
        "{what}: rotation off orthonormal by {e:e}: {t:?}"
    );
    let det = r.determinant();
    assert!((det - 1.0).abs() <= 1e-8, "{what}: det {det}: {t:?}");
}

/// Split the input into (selector, text). Non-UTF-8 is converted lossily so the
/// parsers still see most of the input.
pub fn split(data: &[u8]) -> Option<(u8, String)> {
    let (&sel, rest) = data.split_first()?;
    Some((sel, String::from_utf8_lossy(rest).into_owned()))
}

/// Load `text` as if read from `path` (and, for odd selectors, with the format
/// forced), check the result, build the graph and query it.
pub fn load_and_check(text: &str, path: &str, format: Option<Format>, sel: u8) {
    if let Ok(loaded) = load_str(text, Path::new(path), &options(format, sel)) {
        check_loaded(loaded);
    }
}

/// [`load_and_check`] on raw bytes through `load_bytes` (binary formats:
/// Arrow IPC `.feather`).
pub fn load_bytes_and_check(bytes: &[u8], path: &str, format: Option<Format>, sel: u8) {
    if let Ok(loaded) = load_bytes(bytes.to_vec(), Path::new(path), &options(format, sel)) {
        check_loaded(loaded);
    }
}

/// The options a selector byte sets: `--invert`, `--key`, `--joint`.
fn options(format: Option<Format>, sel: u8) -> LoadOptions {
    let mut opts = LoadOptions::default();
    opts.format = format;
    opts.invert = sel & 0x40 != 0;
    if sel & 0x80 != 0 {
        opts.key = Some("T_imu_lidar".into());
    }
    if sel & 0x20 != 0 {
        opts.joints.insert("joint".into(), 0.5);
    }
    opts
}

/// Every edge finite and orthonormal; the graph built from them answers every
/// query with a finite transform or an error.
pub fn check_loaded(loaded: Parsed) {
    assert!(!loaded.edges.is_empty(), "Ok with no edges");
    for e in &loaded.edges {
        assert_sane(&e.transform, &format!("edge {} -> {}", e.parent, e.child));
    }
    let mut g = FrameGraph::new();
    if g.add(loaded).is_err() {
        return;
    }
    let frames = g.frames();
    let n = frames.len().min(8);
    for a in &frames[..n] {
        for b in &frames[..n] {
            if let Ok(c) = g.transform(a, b) {
                let t = c.transform;
                let r = t.rotation();
                let d = t.translation();
                assert!(
                    r.iter().all(|x| x.is_finite()) && d.iter().all(|x| x.is_finite()),
                    "composed {a} -> {b} not finite: {t:?}"
                );
            }
        }
    }
    let _ = g.tree();
}
