//! The shipped calibrations (calibrations/*.toml) against independently computed
//! reference values (tests/fixtures/survey/expected.json, made by
//! tests/fixtures/survey/make_expected.py with numpy/scipy/pytransform3d; see
//! tests/fixtures/survey/README.md).
//!
//! Every rig is parsed with `formats::rig_toml::parse`, its own edges are composed
//! from `[rig] from` to `[rig] to` by a small composer local to this test (the
//! frame graph is tested elsewhere), and the lever arm, rotation angle, axis,
//! screw translation `h`, the transform itself, sigma_max and the band are
//! compared to the reference to 1e-9. For rigs within 1e-6 rad of a half-turn
//! the sign of `h` depends on rounding (the axis sign is chosen by `h >= 0` only
//! at an exact half-turn), so `|h|` is compared there.

use extrinsic_audit::internals::analysis::metric::adapted_metric_matrix;
use extrinsic_audit::internals::formats::rig_toml;
use extrinsic_audit::internals::formats::Parsed;
use extrinsic_audit::internals::tolerances::{DEFAULT_PITCH_TOL, SMALL_ROTATION_DEG};
use extrinsic_audit::{Edge, LoadOptions};
use extrinsic_audit::{ScrewKind, Transform};
use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::path::{Path, PathBuf};

const TOL: f64 = 1e-9;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn expected() -> Value {
    let p = root().join("tests/fixtures/survey/expected.json");
    let text = std::fs::read_to_string(&p).expect("read expected.json");
    serde_json::from_str(&text).expect("expected.json is JSON")
}

/// calibrations/*.toml, sorted.
fn rig_files() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("calibrations"))
        .expect("calibrations/ exists")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

/// A sidecar rig (`[[include]]`): its edges come from `formats::load_file`.
fn is_sidecar(text: &str) -> bool {
    let v: toml::Table = toml::from_str(text).expect("valid TOML");
    v.contains_key("include")
}

fn load(path: &Path) -> Parsed {
    let text = std::fs::read_to_string(path).expect("read rig");
    let opts = LoadOptions::default();
    // A rig file parsed on its own cannot load what it includes: the loader can.
    let loaded = if is_sidecar(&text) {
        extrinsic_audit::internals::formats::load_file(path, &opts)
    } else {
        rig_toml::parse(&text, path, &opts)
    };
    loaded.unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// `T_from_to` by breadth-first search over the rig's own edges (walked down as
/// given, up as inverses). Local to this test on purpose.
fn compose(edges: &[Edge], from: &str, to: &str) -> Transform {
    let mut adj: BTreeMap<&str, Vec<(&str, Transform)>> = BTreeMap::new();
    for e in edges {
        adj.entry(e.parent.as_str())
            .or_default()
            .push((e.child.as_str(), e.transform));
        adj.entry(e.child.as_str())
            .or_default()
            .push((e.parent.as_str(), e.transform.inverse()));
    }
    let mut seen: BTreeMap<&str, Transform> = BTreeMap::new();
    seen.insert(from, Transform::identity());
    let mut queue = VecDeque::from([from]);
    while let Some(f) = queue.pop_front() {
        let t0 = seen[f];
        for (g, t) in adj.get(f).cloned().unwrap_or_default() {
            if !seen.contains_key(g) {
                seen.insert(g, t0.compose(&t));
                queue.push_back(g);
            }
        }
    }
    *seen
        .get(to)
        .unwrap_or_else(|| panic!("no path from {from} to {to}"))
}

fn num(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is not a number in {v}"))
}

/// Largest difference seen by `close` (printed with `--nocapture`).
static MAX_DIFF: std::sync::Mutex<f64> = std::sync::Mutex::new(0.0);

fn close(what: &str, id: &str, got: f64, want: f64) {
    if let Ok(mut m) = MAX_DIFF.lock() {
        *m = m.max((got - want).abs());
    }
    assert!(
        (got - want).abs() <= TOL,
        "{id}: {what}: tool {got:.15e}, reference {want:.15e}, |diff| {:.3e} > {TOL:e}",
        (got - want).abs()
    );
}

struct RigResult {
    id: String,
    t: Transform,
    in_statistics: bool,
    dataset: String,
}

/// Compare one rig to its reference row; returns what the summary needs.
fn check_rig(path: &Path, reference: &Value) -> RigResult {
    let loaded = load(path);
    let meta = loaded.rig.clone().expect("rig metadata");
    let id = meta.id.clone();
    assert_eq!(reference["id"], id.as_str());
    assert_eq!(reference["from"], meta.from.as_str(), "{id}: from");
    assert_eq!(reference["to"], meta.to.as_str(), "{id}: to");
    assert_eq!(
        reference["placeholder"], meta.placeholder,
        "{id}: placeholder"
    );
    assert_eq!(reference["in_statistics"], meta.in_statistics(), "{id}");
    let t = compose(&loaded.edges, &meta.from, &meta.to);

    // The transform itself (catches direction and composition mistakes).
    let d = t.translation();
    for k in 0..3 {
        close(
            "translation",
            &id,
            d[k],
            reference["translation_m"][k].as_f64().unwrap(),
        );
        for j in 0..3 {
            let want = reference["rotation_matrix"][k][j].as_f64().unwrap();
            close("rotation entry", &id, t.rotation()[(k, j)], want);
        }
    }
    close(
        "lever arm",
        &id,
        t.lever_arm(),
        num(reference, "lever_arm_m"),
    );
    let s = t.screw(DEFAULT_PITCH_TOL);
    close("angle (rad)", &id, s.angle, num(reference, "angle_rad"));
    close(
        "angle (deg)",
        &id,
        s.angle.to_degrees(),
        num(reference, "angle_deg"),
    );
    assert_eq!(reference["kind"], s.kind.name(), "{id}: screw kind");
    assert_eq!(
        reference["zero_pitch"],
        s.kind == ScrewKind::ZeroPitch,
        "{id}: zero pitch"
    );
    let near_half_turn = reference["near_half_turn"].as_bool().unwrap();
    match (s.translation_along_axis, reference["h"].as_f64()) {
        (None, None) => {}
        (Some(h), Some(want)) => {
            if near_half_turn {
                close("|h|", &id, h.abs(), num(reference, "abs_h"));
            } else {
                close("h", &id, h, want);
                let e = s.axis.expect("axis");
                for k in 0..3 {
                    close("axis", &id, e[k], reference["axis"][k].as_f64().unwrap());
                }
            }
        }
        (got, want) => panic!("{id}: h: tool {got:?}, reference {want:?}"),
    }
    let small = s.angle > 0.0 && s.angle.to_degrees() < SMALL_ROTATION_DEG;
    assert_eq!(reference["small_rotation"], small, "{id}: small rotation");

    let delta = t.lever_arm();
    let sigma = delta / 2.0 + (1.0 + delta * delta / 4.0).sqrt();
    close("sigma_max", &id, sigma, num(reference, "sigma_max"));
    close(
        "band lower",
        &id,
        1.0 / (sigma * sigma),
        reference["band_l1"][0].as_f64().unwrap(),
    );
    close(
        "band upper",
        &id,
        sigma * sigma,
        reference["band_l1"][1].as_f64().unwrap(),
    );

    // Adapted metric: exists exactly for zero pitch (and the identity).
    let m = adapted_metric_matrix(&t, DEFAULT_PITCH_TOL);
    assert_eq!(
        m.is_some(),
        reference["adapted_metric_exists"].as_bool().unwrap(),
        "{id}: adapted metric existence"
    );
    if let Some(m0) = m {
        let a = t.adjoint();
        let res = (a.transpose() * m0 * a - m0).norm() / m0.norm();
        assert!(res < 1e-12, "{id}: invariance residual {res:e}");
    }

    RigResult {
        id,
        t,
        in_statistics: meta.in_statistics(),
        dataset: meta.dataset,
    }
}

#[test]
fn every_rig_matches_the_independent_reference() {
    let exp = expected();
    let rows: BTreeMap<String, &Value> = exp["rigs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| (r["id"].as_str().unwrap().to_string(), r))
        .collect();
    let mut results = Vec::new();
    let mut files_seen = BTreeSet::new();
    for path in rig_files() {
        let text = std::fs::read_to_string(&path).unwrap();
        if is_sidecar(&text) {
            continue; // checked by sidecar_rig_matches_its_native_twin
        }
        let stem = path.file_stem().unwrap().to_string_lossy().to_string();
        let row = rows.get(&stem).unwrap_or_else(|| {
            panic!(
                "{}: no reference row (re-run make_expected.py)",
                path.display()
            )
        });
        assert_eq!(row["file"], format!("{stem}.toml").as_str());
        results.push(check_rig(&path, row));
        files_seen.insert(stem);
    }
    let expected_ids: BTreeSet<String> = rows.keys().cloned().collect();
    assert_eq!(
        files_seen, expected_ids,
        "rig files and reference rows differ"
    );

    // Summary line: count, range, median, pitch counts.
    let s = &exp["summary"];
    let stats: Vec<&RigResult> = results.iter().filter(|r| r.in_statistics).collect();
    assert_eq!(stats.len() as u64, s["count"].as_u64().unwrap());
    let mut levers: Vec<f64> = stats.iter().map(|r| r.t.lever_arm()).collect();
    levers.sort_by(f64::total_cmp);
    let n = levers.len();
    let median = if n % 2 == 1 {
        levers[n / 2]
    } else {
        0.5 * (levers[n / 2 - 1] + levers[n / 2])
    };
    close(
        "summary min",
        "summary",
        levers[0],
        num(s, "lever_arm_min_m"),
    );
    close(
        "summary median",
        "summary",
        median,
        num(s, "lever_arm_median_m"),
    );
    close(
        "summary max",
        "summary",
        levers[n - 1],
        num(s, "lever_arm_max_m"),
    );
    let kinds: Vec<ScrewKind> = stats
        .iter()
        .map(|r| r.t.screw(DEFAULT_PITCH_TOL).kind)
        .collect();
    let count = |k: ScrewKind| kinds.iter().filter(|&&x| x == k).count() as u64;
    assert_eq!(
        count(ScrewKind::General) + count(ScrewKind::PureTranslation),
        s["nonzero_pitch_count"].as_u64().unwrap()
    );
    assert_eq!(
        count(ScrewKind::ZeroPitch),
        s["zero_pitch_count"].as_u64().unwrap()
    );
    assert_eq!(
        count(ScrewKind::General),
        s["general_count"].as_u64().unwrap()
    );
    let datasets: BTreeSet<&str> = stats.iter().map(|r| r.dataset.as_str()).collect();
    assert_eq!(datasets.len() as u64, s["datasets"].as_u64().unwrap());

    if let Ok(m) = MAX_DIFF.lock() {
        println!(
            "largest |tool - reference| over all compared values: {:.3e}",
            *m
        );
    }

    // What the issue asks of the shipped set.
    let nonzero_lever = stats.iter().filter(|r| r.t.lever_arm() > 1e-12).count();
    assert!(nonzero_lever >= 19, "{nonzero_lever} rigs with a lever arm");
    assert!(datasets.len() >= 6, "{} datasets", datasets.len());
    for must in [
        "geode-alpha-vlp16",
        "geode-beta-os1-64",
        "geode-gamma-avia",
        "ntnu-os0-128-vn100",
        "m3dgr-mid360-d435i-imu",
        "m3dgr-avia-d435i-imu",
        "norlab-warthog-rs32-mti10",
        "norlab-warthog-rs16left-mti10",
        "liosam-mid360-9axis",
    ] {
        assert!(
            stats.iter().any(|r| r.id == must),
            "{must} missing from the survey"
        );
    }
}

#[test]
fn zero_pitch_rig_gets_an_invariant_adapted_metric() {
    let t = compose_rig("liosam-mid360-9axis");
    let s = t.screw(DEFAULT_PITCH_TOL);
    assert_eq!(s.kind, ScrewKind::ZeroPitch);
    assert_eq!(s.translation_along_axis, Some(0.0), "h is exactly zero");
    let m0 = adapted_metric_matrix(&t, DEFAULT_PITCH_TOL).expect("adapted metric");
    let a = t.adjoint();
    let res = (a.transpose() * m0 * a - m0).norm() / m0.norm();
    assert!(res < 1e-12, "invariance residual {res:e}");
    // The reference made its own M0; both are invariant.
    let exp = expected();
    let row = exp["rigs"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["id"] == "liosam-mid360-9axis")
        .unwrap();
    assert!(num(row, "adapted_metric_invariance_residual") < 1e-12);
}

#[test]
fn nonzero_pitch_rig_gets_no_adapted_metric() {
    for id in [
        "geode-gamma-avia",
        "ouster-os0-128-fw2.3",
        "m3dgr-mid360-d435i-imu",
    ] {
        let t = compose_rig(id);
        assert_eq!(t.screw(DEFAULT_PITCH_TOL).kind, ScrewKind::General, "{id}");
        assert!(
            adapted_metric_matrix(&t, DEFAULT_PITCH_TOL).is_none(),
            "{id}"
        );
    }
    // A pure translation (infinite pitch) has none either.
    let t = compose_rig("fastlio-avia");
    assert!(adapted_metric_matrix(&t, DEFAULT_PITCH_TOL).is_none());
}

fn compose_rig(id: &str) -> Transform {
    let path = root().join("calibrations").join(format!("{id}.toml"));
    let loaded = load(&path);
    let meta = loaded.rig.as_ref().unwrap();
    compose(&loaded.edges, &meta.from, &meta.to)
}

#[test]
fn every_rig_carries_provenance() {
    let mut ids = BTreeSet::new();
    for path in rig_files() {
        let text = std::fs::read_to_string(&path).unwrap();
        if is_sidecar(&text) {
            continue;
        }
        let loaded = load(&path);
        let m = loaded.rig.as_ref().unwrap();
        let stem = path.file_stem().unwrap().to_string_lossy().to_string();
        assert_eq!(m.id, stem, "file name = id");
        assert!(ids.insert(m.id.clone()), "duplicate id {}", m.id);
        for (what, s) in [
            ("sensor", &m.sensor),
            ("platform", &m.platform),
            ("dataset", &m.dataset),
            ("licence", &m.licence),
            ("direction", &m.direction),
            ("source repo", &m.source_repo),
            ("source path", &m.source_path),
            ("category", &m.category),
        ] {
            assert!(!s.trim().is_empty(), "{}: empty {what}", m.id);
        }
        assert_eq!(m.source_commit.len(), 40, "{}: full commit hash", m.id);
        assert!(m.source_commit.chars().all(|c| c.is_ascii_hexdigit()));
        assert_eq!(m.placeholder, m.category == "placeholder", "{}", m.id);
        // Each edge points at its [[transform]] header line and names its key.
        let headers: Vec<usize> = text
            .lines()
            .enumerate()
            .filter(|(_, l)| l.trim() == "[[transform]]")
            .map(|(i, _)| i + 1)
            .collect();
        assert_eq!(headers.len(), loaded.edges.len(), "{}", m.id);
        for (e, line) in loaded.edges.iter().zip(headers) {
            assert_eq!(e.provenance.format, "rig-toml");
            assert_eq!(e.provenance.location.line, Some(line), "{}", m.id);
            assert_eq!(e.provenance.location.file.as_deref(), Some(path.as_path()));
            assert!(!e.provenance.key.is_empty());
        }
    }
}

#[test]
fn rounded_rotations_warn_with_their_line() {
    // GEODE alpha prints its rotation with four decimals (det 1.00006).
    let path = root().join("calibrations/geode-alpha-vlp16.toml");
    let loaded = load(&path);
    let w = loaded
        .warnings
        .iter()
        .find(|w| w.code.name() == "non-orthonormal-rotation")
        .expect("warning");
    assert_eq!(w.location.file.as_deref(), Some(path.as_path()));
    assert!(w.location.line.is_some());
    // Published values with 16 digits pass quietly.
    let quiet = load(&root().join("calibrations/hilti2023-hhs-hesai.toml"));
    assert!(quiet.warnings.is_empty(), "{:?}", quiet.warnings);
}

/// The sidecar rig (raw URDF beside a TOML with `[[include]]`) must give the same
/// transform as its native twin. Needs `formats::load_file` and the URDF loader,
/// which live on another branch: run with `cargo test -- --ignored` after merge.
#[test]
fn sidecar_rig_matches_its_native_twin() {
    let exp = expected();
    let dups = exp["duplicates"].as_object().expect("duplicates");
    assert!(!dups.is_empty());
    for path in rig_files() {
        let text = std::fs::read_to_string(&path).unwrap();
        if !is_sidecar(&text) {
            continue;
        }
        let loaded = load(&path);
        let meta = loaded.rig.clone().unwrap();
        assert!(!meta.in_statistics());
        let twin = meta.duplicate_of.clone().expect("duplicate_of");
        assert_eq!(dups[&meta.id]["duplicate_of"], twin.as_str());
        let row = exp["rigs"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["id"] == twin.as_str())
            .unwrap_or_else(|| panic!("{twin} not in expected.json"));
        let t = compose(&loaded.edges, &meta.from, &meta.to);
        let d = t.translation();
        for k in 0..3 {
            close(
                "translation",
                &meta.id,
                d[k],
                row["translation_m"][k].as_f64().unwrap(),
            );
            for j in 0..3 {
                let want = row["rotation_matrix"][k][j].as_f64().unwrap();
                close("rotation entry", &meta.id, t.rotation()[(k, j)], want);
            }
        }
        close(
            "lever arm",
            &meta.id,
            t.lever_arm(),
            num(row, "lever_arm_m"),
        );
    }
}

/// calibrations/README.md lists every rig file, keeps the markers for the
/// generated survey block, and its comparison with the paper quotes the current
/// summary (count, range, median, pitch counts).
#[test]
fn readme_lists_every_rig_and_quotes_the_summary() {
    let readme = std::fs::read_to_string(root().join("calibrations/README.md")).unwrap();
    for path in rig_files() {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        assert!(
            readme.contains(&format!("]({name})")),
            "README rig list lacks a link to {name}"
        );
    }
    let begin = readme.find("<!-- survey:begin -->").expect("begin marker");
    let end = readme.find("<!-- survey:end -->").expect("end marker");
    assert!(begin < end);
    let s = &expected()["summary"];
    let row = format!(
        "| rigs (placeholders excluded) | 19 | {} ({} datasets or projects) |",
        s["count"], s["datasets"]
    );
    assert!(readme.contains(&row), "README lacks {row:?}");
    let range = format!(
        "| lever arm range | 0.032–0.552 m | {:.4}–{:.4} m |",
        num(s, "lever_arm_min_m"),
        num(s, "lever_arm_max_m")
    );
    assert!(readme.contains(&range), "README lacks {range:?}");
    let median = format!(
        "| median lever arm | 0.114 m | {:.4} m |",
        num(s, "lever_arm_median_m")
    );
    assert!(readme.contains(&median), "README lacks {median:?}");
    let pitch = format!(
        "| nonzero screw translation | 18 | {} ({} general screws + {} pure translations) |",
        s["nonzero_pitch_count"], s["general_count"], s["pure_translation_count"]
    );
    assert!(readme.contains(&pitch), "README lacks {pitch:?}");
}
