//! Resource limits (issue 7): every hostile input is refused with a clear
//! message, quickly, without exhausting memory or the stack. The binary runs in
//! a subprocess where a stack overflow would be an abort (a signal, not a
//! panic): each such test asserts a clean exit code 2 and a message naming the
//! file.

use crate::common::hostile;

use extrinsic_audit::internals::degeneracy::points::parse_points;
use extrinsic_audit::internals::formats::{load_file, load_str};
use extrinsic_audit::internals::frames::FrameGraph;
use extrinsic_audit::LoadOptions;
use hostile::{assert_quick, run_audit, write_tmp};
use std::path::Path;
use std::time::{Duration, Instant};

// ---------------------------------------------------------------- file size

#[test]
fn file_size_cap_library() {
    let dir = tempfile::tempdir().unwrap();
    let p = write_tmp(&dir, "big.yaml", &"# padding\n".repeat(1000));
    let mut opts = LoadOptions::default();
    opts.max_file_size = 1000;
    let e = load_file(&p, &opts).unwrap_err().to_string();
    assert!(
        e.contains("file is 10000 bytes: expected at most 1000 bytes (the --max-file-size cap)"),
        "{e}"
    );
    assert!(e.contains("big.yaml"), "{e}");
}

#[test]
fn file_size_cap_binary() {
    let dir = tempfile::tempdir().unwrap();
    let p = write_tmp(
        &dir,
        "fast_lio.yaml",
        &format!(
            "{}mapping:\n  extrinsic_T: [0.1, 0, 0]\n  extrinsic_R: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n",
            "# padding padding padding\n".repeat(100)
        ),
    );
    let out = run_audit(&[p.to_str().unwrap(), "--max-file-size", "512"], 20);
    assert_eq!(out.code, Some(2), "{}", out.stderr);
    assert!(out.stderr.contains("fast_lio.yaml"), "{}", out.stderr);
    assert!(
        out.stderr
            .contains("expected at most 512 bytes (the --max-file-size cap)"),
        "{}",
        out.stderr
    );
    // The same file within the cap loads.
    let out = run_audit(&[p.to_str().unwrap(), "--max-file-size", "100000"], 20);
    assert_eq!(out.code, Some(0), "{}", out.stderr);
    // And `check` (no --max-file-size flag: the default cap, 16 MiB) refuses a
    // file above the default cap as a finding.
    let big = write_tmp(
        &dir,
        "huge.yaml",
        &"#".repeat(extrinsic_audit::internals::tolerances::DEFAULT_MAX_FILE_SIZE as usize + 10),
    );
    let out = run_audit(&["check", big.to_str().unwrap()], 20);
    assert!(matches!(out.code, Some(1) | Some(2)), "{out:?}");
    assert!(out.stderr.contains("huge.yaml") || out.stdout.contains("huge.yaml"));
    assert!(
        (out.stderr.clone() + &out.stdout).contains("--max-file-size cap"),
        "{out:?}"
    );
}

// ---------------------------------------------------------------------- YAML

/// Billion laughs: 9 levels of 10 aliases each (10^9 nodes if expanded).
fn yaml_bomb() -> String {
    let mut s = String::from("a0: &a0 [\"lol\", \"lol\", \"lol\", \"lol\", \"lol\", \"lol\", \"lol\", \"lol\", \"lol\", \"lol\"]\n");
    for i in 1..10 {
        let prev = format!("*a{}", i - 1);
        let list = [prev.as_str(); 10].join(", ");
        s.push_str(&format!("a{i}: &a{i} [{list}]\n"));
    }
    s.push_str("extrinsic_T: *a9\nextrinsic_R: *a9\n");
    s
}

#[test]
fn yaml_alias_bomb_is_refused_quickly() {
    let text = yaml_bomb();
    let t = Instant::now();
    let e = load_str(&text, Path::new("bomb.yaml"), &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert_quick(t, 5, "alias bomb");
    assert!(e.starts_with("bomb.yaml"), "{e}");
    assert!(e.contains("YAML beyond the reader's limits"), "{e}");
    assert!(e.contains("alias bomb or deep nesting"), "{e}");

    let dir = tempfile::tempdir().unwrap();
    let p = write_tmp(&dir, "bomb.yaml", &text);
    let out = run_audit(&[p.to_str().unwrap(), "--frames"], 20);
    assert_eq!(out.code, Some(2), "{out:?}");
    assert!(out.stderr.contains("bomb.yaml"), "{out:?}");
    assert!(out.stderr.contains("beyond the reader's limits"), "{out:?}");
}

#[test]
fn yaml_nested_10000_deep_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in [
        (
            "flow_seq.yaml",
            format!(
                "extrinsic_T: {}{}\n",
                "[".repeat(10_000),
                "]".repeat(10_000)
            ),
        ),
        (
            "flow_map.yaml",
            format!("x: {}1{}\n", "{a: ".repeat(10_000), "}".repeat(10_000)),
        ),
        (
            // Block mappings one space deeper each: 10,000 levels is 50 MB of
            // indentation, so 2,000 levels (2 MB) here.
            "block_map.yaml",
            (0..2_000)
                .map(|i| format!("{}k{i}:\n", " ".repeat(i)))
                .collect::<String>(),
        ),
        (
            "tf_static.yaml",
            format!(
                "transforms:\n- child_frame_id: {}a{}\n",
                "[".repeat(100_000),
                "]".repeat(100_000)
            ),
        ),
    ] {
        let t = Instant::now();
        let e = load_str(&text, Path::new(name), &LoadOptions::default())
            .unwrap_err()
            .to_string();
        assert_quick(t, 5, name);
        assert!(e.starts_with(name), "{e}");
        let p = write_tmp(&dir, name, &text);
        let out = run_audit(&[p.to_str().unwrap(), "--frames"], 20);
        assert_eq!(out.code, Some(2), "{name}: {out:?}");
        assert!(out.stderr.contains(name), "{name}: {out:?}");
    }
    // The flow-nesting messages say what the limit is about.
    let e = load_str(
        &format!(
            "extrinsic_T: {}{}\n",
            "[".repeat(10_000),
            "]".repeat(10_000)
        ),
        Path::new("n.yaml"),
        &LoadOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("beyond the reader's limits"), "{e}");
}

#[test]
fn launch_yaml_and_toml_nesting_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in [
        (
            "deep.launch.yaml",
            format!("launch: {}{}\n", "[".repeat(10_000), "]".repeat(10_000)),
        ),
        (
            "deep.toml",
            format!("a = {}1{}\n", "[".repeat(10_000), "]".repeat(10_000)),
        ),
        (
            "deep_inline.toml",
            format!("a = {}1{}\n", "{b = ".repeat(10_000), "}".repeat(10_000)),
        ),
        (
            "deep.json",
            format!("{{\"a\": {}1{}}}\n", "[".repeat(10_000), "]".repeat(10_000)),
        ),
        (
            "deep.launch.py",
            format!(
                "Node(package='tf2_ros', executable='static_transform_publisher', arguments={}1{})\n",
                "[".repeat(10_000),
                "]".repeat(10_000)
            ),
        ),
    ] {
        let p = write_tmp(&dir, name, &text);
        let t = Instant::now();
        let out = run_audit(&[p.to_str().unwrap(), "--frames"], 20);
        assert_quick(t, 20, name);
        assert_eq!(out.code, Some(2), "{name}: {out:?}");
        assert!(out.stderr.contains(name), "{name}: {out:?}");
    }
}

// ----------------------------------------------------------------------- XML

#[test]
fn xml_nested_deep_does_not_overflow() {
    let dir = tempfile::tempdir().unwrap();
    for depth in [10_000usize, 200_000] {
        for (name, open, close) in [
            ("deep.urdf", "<robot name=\"r\">", "</robot>"),
            ("deep.launch", "<launch>", "</launch>"),
            ("deep.xml", "<root>", "</root>"),
        ] {
            let text = format!(
                "{open}{}{}{close}\n",
                "<a>".repeat(depth),
                "</a>".repeat(depth)
            );
            let p = write_tmp(&dir, name, &text);
            let t = Instant::now();
            let out = run_audit(&[p.to_str().unwrap(), "--frames"], 30);
            assert_quick(t, 30, name);
            assert_eq!(out.code, Some(2), "{name} {depth}: {out:?}");
            assert!(out.stderr.contains(name), "{name}: {out:?}");
            assert!(
                out.stderr.contains("nested") || out.stderr.contains("expected"),
                "{name} {depth}: {}",
                out.stderr
            );
        }
    }
}

#[test]
fn xml_entity_expansion_is_refused() {
    let mut bomb =
        String::from("<?xml version=\"1.0\"?>\n<!DOCTYPE robot [\n  <!ENTITY lol \"lol\">\n");
    bomb.push_str("  <!ENTITY lol1 \"&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;\">\n");
    for i in 2..10 {
        let prev = format!("&lol{};", i - 1);
        bomb.push_str(&format!("  <!ENTITY lol{i} \"{}\">\n", prev.repeat(10)));
    }
    bomb.push_str("]>\n<robot name=\"&lol9;\"><link name=\"a\"/></robot>\n");
    let dir = tempfile::tempdir().unwrap();
    for name in ["bomb.urdf", "bomb.launch", "bomb.xml"] {
        let text = if name == "bomb.urdf" {
            bomb.clone()
        } else {
            bomb.replace(
                "<robot name=\"&lol9;\"><link name=\"a\"/></robot>",
                "<launch><arg name=\"x\" default=\"&lol9;\"/></launch>",
            )
        };
        let t = Instant::now();
        let e = load_str(&text, Path::new(name), &LoadOptions::default())
            .unwrap_err()
            .to_string();
        assert_quick(t, 2, name);
        assert!(e.starts_with(name), "{e}");
        assert!(e.contains("DTD") || e.contains("DOCTYPE"), "{name}: {e}");
        let p = write_tmp(&dir, name, &text);
        let out = run_audit(&[p.to_str().unwrap(), "--frames"], 20);
        assert_eq!(out.code, Some(2), "{out:?}");
        assert!(out.stderr.contains(name), "{out:?}");
    }
}

// ------------------------------------------------------------ big URDF graphs

fn chain_urdf(n: usize) -> String {
    let mut s = String::with_capacity(n * 120);
    s.push_str("<robot name=\"chain\">\n<link name=\"l0\"/>\n");
    for i in 1..=n {
        s.push_str(&format!(
            "<link name=\"l{i}\"/><joint name=\"j{i}\" type=\"fixed\"><parent link=\"l{}\"/><child link=\"l{i}\"/><origin xyz=\"0.001 0 0\" rpy=\"0 0 0.0001\"/></joint>\n",
            i - 1
        ));
    }
    s.push_str("</robot>\n");
    s
}

fn star_urdf(n: usize) -> String {
    let mut s = String::with_capacity(n * 120);
    s.push_str("<robot name=\"star\">\n<link name=\"base\"/>\n");
    for i in 1..=n {
        s.push_str(&format!(
            "<link name=\"l{i}\"/><joint name=\"j{i}\" type=\"fixed\"><parent link=\"base\"/><child link=\"l{i}\"/><origin xyz=\"{i} 0 0\"/></joint>\n"
        ));
    }
    s.push_str("</robot>\n");
    s
}

#[test]
fn urdf_with_100000_links_in_a_chain() {
    let text = chain_urdf(100_000);
    assert!(text.len() < extrinsic_audit::internals::tolerances::DEFAULT_MAX_FILE_SIZE as usize);
    let t = Instant::now();
    let loaded = load_str(&text, Path::new("chain.urdf"), &LoadOptions::default()).unwrap();
    assert_eq!(loaded.edges.len(), 100_000);
    let mut g = FrameGraph::new();
    g.add(loaded).unwrap();
    let c = g.transform("l0", "l100000").unwrap();
    assert_eq!(c.steps.len(), 100_000);
    let d = c.transform.translation();
    assert!(d.iter().all(|x| x.is_finite()));
    let back = g.transform("l100000", "l0").unwrap();
    let id = c.transform.compose(&back.transform);
    assert!(id.translation().norm() < 1e-6, "{id:?}");
    let tree = g.tree();
    assert!(
        tree.len() < 100_000 * 400,
        "tree text is {} bytes",
        tree.len()
    );
    assert_quick(t, 60, "100k chain (debug build)");

    // The binary: the same file, queried end to end and listed.
    let dir = tempfile::tempdir().unwrap();
    let p = write_tmp(&dir, "chain.urdf", &text);
    let out = run_audit(
        &[p.to_str().unwrap(), "--from", "l0", "--to", "l100000"],
        60,
    );
    assert_eq!(out.code, Some(0), "{}", out.stderr);
    assert!(!out.stdout.to_lowercase().contains("nan"), "NaN in report");
    let out = run_audit(&[p.to_str().unwrap(), "--frames"], 60);
    assert_eq!(out.code, Some(0), "{}", out.stderr);
}

#[test]
fn urdf_with_100000_links_in_a_star() {
    let text = star_urdf(100_000);
    let t = Instant::now();
    let loaded = load_str(&text, Path::new("star.urdf"), &LoadOptions::default()).unwrap();
    let mut g = FrameGraph::new();
    g.add(loaded).unwrap();
    let c = g.transform("l1", "l100000").unwrap();
    assert!((c.transform.translation().x - 99_999.0).abs() < 1e-6);
    assert_quick(t, 60, "100k star (debug build)");
    // The typo suggestion over 100k frames stays quick.
    let t = Instant::now();
    let e = g.transform("l1", "l100001x").unwrap_err().to_string();
    assert!(e.contains("unknown frame"), "{e}");
    assert_quick(t, 30, "closest frames over 100k names");
}

#[test]
fn cycle_in_a_long_chain_is_refused_with_a_bounded_message() {
    // l0 -> ... -> l100000 and then l100000 -> l0.
    let mut text = chain_urdf(100_000);
    text = text.replace(
        "<link name=\"l0\"/>",
        "<link name=\"l0\"/><joint name=\"close\" type=\"fixed\"><parent link=\"l100000\"/><child link=\"l0\"/></joint>",
    );
    let t = Instant::now();
    let r = load_str(&text, Path::new("cycle.urdf"), &LoadOptions::default()).and_then(|l| {
        let mut g = FrameGraph::new();
        g.add(l)
    });
    let e = r.unwrap_err().to_string();
    assert_quick(t, 60, "100k cycle");
    assert!(e.contains("cycle"), "{e}");
    assert!(e.starts_with("cycle.urdf"), "{e}");
    assert!(e.len() < 4096, "cycle message is {} bytes", e.len());

    let dir = tempfile::tempdir().unwrap();
    let p = write_tmp(&dir, "cycle.urdf", &text);
    let out = run_audit(&[p.to_str().unwrap(), "--frames"], 60);
    assert_eq!(out.code, Some(2), "{out:?}");
    assert!(out.stderr.contains("cycle.urdf"), "{}", out.stderr);
    assert!(out.stderr.contains("cycle"), "{}", out.stderr);
}

// --------------------------------------------------------------- point files

#[test]
fn point_files_claiming_1e12_points_are_refused_without_allocating() {
    let ply = "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n";
    let pcd = "VERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\nTYPE F F F F F F\nCOUNT 1 1 1 1 1 1\nWIDTH 1000000000000\nHEIGHT 1\nPOINTS 1000000000000\nDATA binary\n";
    let ply_ascii = ply.replace("binary_little_endian", "ascii") + "0 0 0 0 0 1\n";
    let pcd_ascii = pcd.replace("DATA binary", "DATA ascii") + "0 0 0 0 0 1\n";
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in [
        ("claim.ply", ply.to_string()),
        ("claim.pcd", pcd.to_string()),
        ("claim_ascii.ply", ply_ascii),
        ("claim_ascii.pcd", pcd_ascii),
    ] {
        let mut bytes = text.into_bytes();
        bytes.extend_from_slice(&[0u8; 24 * 3]);
        let t = Instant::now();
        let e = parse_points(&bytes).unwrap_err().to_string();
        assert_quick(t, 2, name);
        assert!(
            e.contains("1000000000000") || e.contains("claims") || e.contains("expected"),
            "{name}: {e}"
        );
        let p = dir.path().join(name);
        std::fs::write(&p, &bytes).unwrap();
        let out = run_audit(&["degeneracy", p.to_str().unwrap()], 30);
        assert_eq!(out.code, Some(2), "{name}: {out:?}");
        assert!(out.stderr.contains(name), "{name}: {out:?}");
    }
}

#[test]
fn timeouts_are_real() {
    // The helper kills a child that runs past its time (guards the guards).
    let t = Instant::now();
    let mut c = std::process::Command::new("sleep")
        .arg("30")
        .spawn()
        .unwrap();
    let status = hostile::wait_timeout(&mut c, Duration::from_millis(200));
    assert!(status.is_none());
    assert!(t.elapsed() < Duration::from_secs(10));
}
