//! `audit FILE --frames --format text|json|dot|mermaid|svg`: the pictures hold
//! every frame and every edge of the file, the chain is marked, the JSON
//! validates against docs/schemas/frames.schema.json, and hostile frame names
//! are escaped in each format (the SVG stays well-formed XML, the DOT a single
//! quoted string per name).

use crate::common::{audit, run_cli};
use serde_json::Value;
use std::collections::BTreeSet;

/// ANYmal C, the whole real description (every link and joint), from the
/// test-data folder; `None` where absent.
fn anymal() -> Option<String> {
    let p = crate::common::testdata::file(crate::common::testdata::ANYMAL_C)?;
    Some(p.to_str().unwrap().to_string())
}

fn frames(anymal: &str, args: &[&str], format: &str) -> String {
    let mut a = vec![anymal, "--frames", "--format", format];
    a.extend_from_slice(args);
    let (code, out, err) = run_cli(&a);
    assert_eq!(code, 0, "{a:?}: {err}");
    out
}

/// Frame and edge names of the JSON, the reference the pictures are held to.
fn json_of(file: &str, extra: &[&str]) -> Value {
    let mut a = vec![file, "--frames", "--format", "json"];
    a.extend_from_slice(extra);
    let (code, out, err) = run_cli(&a);
    assert_eq!(code, 0, "{err}");
    serde_json::from_str(&out).expect("JSON")
}

fn names(v: &Value) -> BTreeSet<String> {
    v["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["name"].as_str().unwrap().to_string())
        .collect()
}

/// The URDF's own link names, read with roxmltree (not through audit).
fn urdf_links(path: &str) -> BTreeSet<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    doc.descendants()
        .filter(|n| n.has_tag_name("link"))
        .map(|n| n.attribute("name").unwrap().to_string())
        .collect()
}

fn validator() -> jsonschema::Validator {
    let path = format!(
        "{}/docs/schemas/frames.schema.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let s: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    jsonschema::validator_for(&s).expect("schema")
}

#[test]
fn json_lists_every_link_and_marks_the_chain() {
    let Some(anymal) = anymal() else { return };
    let anymal = anymal.as_str();
    let v = json_of(anymal, &["--from", "base", "--to", "lidar"]);
    let errors: Vec<String> = validator().iter_errors(&v).map(|e| e.to_string()).collect();
    assert!(errors.is_empty(), "{errors:#?}");
    assert_eq!(v["schema_version"], 1);
    assert_eq!(names(&v), urdf_links(anymal));
    assert_eq!(v["edges"].as_array().unwrap().len(), names(&v).len() - 1);
    assert_eq!(
        v["chain"]["path"],
        serde_json::json!(["base", "lidar_cage", "lidar"])
    );
    let on: Vec<&Value> = v["edges"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["on_chain"] == true)
        .collect();
    assert_eq!(on.len(), 2);
    // anymal_c.urdf:666 <origin rpy="0 0 0" xyz="-0.364 0.0 0.0735"/> and
    // :692 <origin rpy="0.0 0.0 -1.57079632679" xyz="0.0 0.0 0.0687"/>.
    assert_eq!(on[0]["child"], "lidar_cage");
    assert_eq!(
        on[0]["translation_m"],
        serde_json::json!([-0.364, 0.0, 0.0735])
    );
    assert_eq!(on[0]["line"], 666);
    assert_eq!(on[1]["child"], "lidar");
    let yaw = on[1]["rpy_deg"][2].as_f64().unwrap();
    assert!(
        (yaw - "-1.57079632679".parse::<f64>().unwrap().to_degrees()).abs() < 1e-9,
        "{yaw}"
    );
    assert!((on[1]["angle_deg"].as_f64().unwrap() - 90.0).abs() < 1e-6);
    assert_eq!(on[1]["joint_type"], "fixed");
    // Without a chain: null, and nothing marked.
    let v = json_of(anymal, &[]);
    assert!(validator().is_valid(&v));
    assert!(v["chain"].is_null());
    assert!(v["frames"]
        .as_array()
        .unwrap()
        .iter()
        .all(|f| f["on_chain"] == false));
    // A parent is listed before its children.
    let order: Vec<&str> = v["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["name"].as_str().unwrap())
        .collect();
    for f in v["frames"].as_array().unwrap() {
        if let Some(p) = f["parent"].as_str() {
            let (pi, ci) = (
                order.iter().position(|n| *n == p).unwrap(),
                order.iter().position(|n| *n == f["name"]).unwrap(),
            );
            assert!(pi < ci, "{p} after its child");
        }
    }
}

#[test]
fn movable_joints_are_labelled_with_their_type() {
    let Some(anymal) = anymal() else { return };
    let anymal = anymal.as_str();
    let v = json_of(anymal, &[]);
    let hfe = v["edges"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["joint_name"] == "LF_HFE")
        .expect("LF_HFE joint");
    assert_eq!(hfe["joint_type"], "revolute");
    let dot = frames(anymal, &[], "dot");
    assert!(dot.contains("revolute joint LF_HFE"), "{dot}");
}

/// The DOT statements: (node ids and labels, edges as id pairs), parsed with
/// a small reader of the subset the tool writes (quoted strings with `\"`
/// and `\\` escapes); anything else in the text fails the test.
/// DOT nodes (id, label) and edges (from id, to id, highlighted).
type DotGraph = (Vec<(String, String)>, Vec<(String, String, bool)>);

fn parse_dot(dot: &str) -> DotGraph {
    let mut lines = dot.lines();
    assert_eq!(lines.next(), Some("digraph frames {"));
    assert_eq!(dot.lines().last(), Some("}"));
    let unquote = |s: &str| -> (String, usize) {
        assert!(s.starts_with('"'), "{s}");
        let mut out = String::new();
        let mut it = s.char_indices().skip(1);
        while let Some((i, c)) = it.next() {
            match c {
                '\\' => out.push(it.next().unwrap().1),
                '"' => return (out, i + 1),
                c => out.push(c),
            }
        }
        panic!("unterminated string in {s}")
    };
    let (mut nodes, mut edges) = (vec![], vec![]);
    for l in dot.lines().skip(1) {
        let l = l.trim();
        if l == "}"
            || l.starts_with("rankdir")
            || l.starts_with("node [")
            || l.starts_with("edge [")
        {
            continue;
        }
        assert!(l.ends_with("];"), "{l}");
        let (head, attrs) = l.split_once(" [").unwrap();
        let attrs = attrs.strip_prefix("label=").expect("label first");
        let (label, end) = unquote(attrs);
        let rest = &attrs[end..];
        assert!(rest == "];" || rest.starts_with(", color="), "{rest}");
        match head.split_once(" -> ") {
            Some((a, b)) => edges.push((a.to_string(), b.to_string(), rest != "];")),
            None => nodes.push((head.to_string(), label)),
        }
    }
    (nodes, edges)
}

#[test]
fn dot_parses_and_holds_every_frame_and_edge() {
    let Some(anymal) = anymal() else { return };
    let anymal = anymal.as_str();
    let dot = frames(anymal, &["--from", "base", "--to", "lidar"], "dot");
    let (nodes, edges) = parse_dot(&dot);
    let labels: BTreeSet<String> = nodes.iter().map(|n| n.1.clone()).collect();
    assert_eq!(labels, urdf_links(anymal));
    assert_eq!(edges.len(), nodes.len() - 1);
    let ids: BTreeSet<&str> = nodes.iter().map(|n| n.0.as_str()).collect();
    assert!(edges
        .iter()
        .all(|e| ids.contains(e.0.as_str()) && ids.contains(e.1.as_str())));
    assert_eq!(
        edges.iter().filter(|e| e.2).count(),
        2,
        "chain edges marked"
    );
    graphviz_accepts(&dot, nodes.len(), edges.len());
}

/// Graphviz reads the text without a complaint and lays out as many nodes and
/// edges as the parse above found (`dot -Tplain`); skipped (with a note)
/// where Graphviz is not installed.
fn graphviz_accepts(dot: &str, nodes: usize, edges: usize) {
    use std::io::Write;
    let child = std::process::Command::new("dot")
        .arg("-Tplain")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn();
    let Ok(mut child) = child else {
        eprintln!("note: Graphviz `dot` not installed; the Graphviz half of this test is skipped");
        return;
    };
    child
        .stdin
        .take()
        .unwrap()
        .write_all(dot.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && err.trim().is_empty(), "dot: {err}");
    let plain = String::from_utf8(out.stdout).unwrap();
    let count = |kind: &str| plain.lines().filter(|l| l.starts_with(kind)).count();
    assert_eq!((count("node "), count("edge ")), (nodes, edges), "{plain}");
}

/// The text of every `<g class="frame">` of the tool's SVG.
fn svg_frames(svg: &str) -> Vec<String> {
    let doc = roxmltree::Document::parse(svg).expect("well-formed XML");
    assert!(doc.root_element().has_tag_name("svg"));
    doc.descendants()
        .filter(|n| n.attribute("class") == Some("frame"))
        .map(|g| {
            g.descendants()
                .filter(|t| t.has_tag_name("text"))
                .filter_map(|t| t.text())
                .collect::<String>()
        })
        .collect()
}

#[test]
fn svg_is_xml_with_every_frame_and_the_chain_in_red() {
    let Some(anymal) = anymal() else { return };
    let anymal = anymal.as_str();
    let svg = frames(anymal, &["--from", "base", "--to", "lidar"], "svg");
    let drawn: BTreeSet<String> = svg_frames(&svg).into_iter().collect();
    assert_eq!(drawn, urdf_links(anymal));
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let red: BTreeSet<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text") && n.attribute("fill") == Some("#c0392b"))
        .filter(|n| n.parent().and_then(|p| p.attribute("class")) == Some("frame"))
        .filter_map(|n| n.text())
        .collect();
    assert_eq!(red, BTreeSet::from(["base", "lidar_cage", "lidar"]));
    let edge_labels = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("edge"))
        .count();
    assert_eq!(edge_labels, urdf_links(anymal).len() - 1);
}

#[test]
fn mermaid_and_markdown_hold_every_frame() {
    let Some(anymal) = anymal() else { return };
    let anymal = anymal.as_str();
    let m = frames(anymal, &["--from", "base", "--to", "lidar"], "mermaid");
    assert!(m.starts_with("flowchart LR\n"));
    let nodes = m
        .lines()
        .filter(|l| l.trim_start().starts_with('n') && l.contains("[\""))
        .count();
    let links = m.lines().filter(|l| l.contains(" -->|\"")).count();
    assert_eq!(nodes, urdf_links(anymal).len());
    assert_eq!(links, nodes - 1);
    assert!(m.contains("class n0,") && m.contains("linkStyle "), "{m}");
    let md = frames(anymal, &[], "markdown");
    assert!(md.starts_with("```mermaid\nflowchart LR\n") && md.ends_with("```\n"));
}

#[test]
fn pictures_need_frames_and_frames_refuse_report_only_formats() {
    let anymal = "tests/fixtures/urdf/anymal_c_lidar.urdf";
    let (code, _, err) = run_cli(&[anymal, "--from", "base", "--to", "lidar", "--format", "svg"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("draws the frame tree (`audit FILE... --frames`)"),
        "{err}"
    );
    let (code, _, err) = run_cli(&[anymal, "--frames", "--format", "sarif"]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = run_cli(&[anymal, "--frames", "--from", "base"]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = run_cli(&[anymal, "--frames", "--from", "base", "--to", "nowhere"]);
    assert_eq!(code, 2, "{err}");
}

/// A URDF whose link names carry markup, quotes, DOT label escapes, Mermaid
/// syntax and an escape character.
const HOSTILE: [&str; 5] = [
    "a\"b",
    "<script>&x</script>",
    "back\\N\\l",
    "x]-->|y|z;#q",
    "rtl\u{202e}txt",
];

fn hostile_urdf(dir: &tempfile::TempDir) -> String {
    let esc = |s: &str| {
        s.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
            .replace('"', "&quot;")
    };
    let mut x = String::from("<robot name=\"r\"><link name=\"root\"/>\n");
    for (i, n) in HOSTILE.iter().enumerate() {
        x.push_str(&format!(
            "<link name=\"{0}\"/><joint name=\"j{i}\" type=\"fixed\"><parent link=\"root\"/><child link=\"{0}\"/><origin xyz=\"{i} 0 0\"/></joint>\n",
            esc(n)
        ));
    }
    x.push_str("</robot>\n");
    let p = dir.path().join("hostile.urdf");
    std::fs::write(&p, x).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn hostile_names_are_escaped_in_every_picture() {
    let dir = tempfile::tempdir().unwrap();
    let f = hostile_urdf(&dir);
    let out = |format: &str| {
        let o = audit()
            .args([&f, "--frames", "--format", format])
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{format}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        String::from_utf8(o.stdout).unwrap()
    };
    // The bidi override is shown as text (`\u{202e}`), never written raw.
    let shown = |n: &str| n.replace('\u{202e}', "\\u{202e}");
    let mut expected: BTreeSet<String> = HOSTILE.iter().map(|n| shown(n)).collect();
    expected.insert("root".into());
    for format in ["dot", "mermaid", "svg", "json"] {
        let o = out(format);
        if format == "json" {
            // JSON stays exact: serde escapes, the names round-trip.
            let v: Value = serde_json::from_str(&o).unwrap();
            let mut raw: BTreeSet<String> = HOSTILE.iter().map(|s| s.to_string()).collect();
            raw.insert("root".into());
            assert_eq!(names(&v), raw);
            continue;
        }
        assert!(!o.contains('\u{202e}'), "{format}: raw bidi override");
        match format {
            "svg" => assert_eq!(
                svg_frames(&o).into_iter().collect::<BTreeSet<_>>(),
                expected
            ),
            "dot" => {
                let (nodes, edges) = parse_dot(&o);
                graphviz_accepts(&o, nodes.len(), edges.len());
                let labels: BTreeSet<String> = nodes.into_iter().map(|n| n.1).collect();
                assert_eq!(labels, expected);
                assert_eq!(edges.len(), HOSTILE.len());
            }
            _ => {
                // Mermaid: each name only as entity codes inside its quotes.
                for l in o.lines().skip(1).filter(|l| l.contains("[\"")) {
                    let inner = l.split_once("[\"").unwrap().1.strip_suffix("\"]").unwrap();
                    assert!(
                        !inner.contains(['"', '<', '>', '|', ';', '\\']) || inner.contains('#'),
                        "{l}"
                    );
                    assert!(
                        !inner.contains('"') && !inner.contains('<') && !inner.contains('|'),
                        "{l}"
                    );
                }
                assert!(
                    o.contains("a#34;b") && o.contains("#60;script#62;#38;x"),
                    "{o}"
                );
            }
        }
    }
}

/// The `(child, xyz, rpy)` of every top-level joint of a URDF written one
/// element a line (`<origin rpy=".." xyz=".."/>` before `<child link=".."/>`),
/// read from its text: the numbers the tree must print, taken from the file
/// rather than from the tool.
fn joint_origins(path: &str) -> Vec<(String, [f64; 3], [f64; 3])> {
    let attr = |line: &str, name: &str| -> Option<String> {
        let at = line.find(&format!("{name}=\""))? + name.len() + 2;
        Some(line[at..at + line[at..].find('"')?].to_string())
    };
    let three = |s: String| -> [f64; 3] {
        let v: Vec<f64> = s.split_whitespace().map(|x| x.parse().unwrap()).collect();
        [v[0], v[1], v[2]]
    };
    let text = std::fs::read_to_string(path).unwrap();
    let (mut out, mut origin, mut top) = (Vec::new(), None, true);
    for line in text.lines().map(str::trim) {
        // Joints inside a <transmission> are not edges.
        if line.starts_with("<transmission") {
            top = false;
        } else if line.starts_with("</transmission") {
            top = true;
        } else if top && line.starts_with("<origin") {
            origin = Some((
                three(attr(line, "xyz").unwrap()),
                three(attr(line, "rpy").unwrap()),
            ));
        } else if let (true, true, Some((xyz, rpy))) = (top, line.starts_with("<child"), origin) {
            out.push((attr(line, "link").unwrap(), xyz, rpy));
            origin = None;
        }
    }
    out
}

/// The numbers of `label [a, b, c] unit` in a line.
fn vector_after(line: &str, label: &str) -> [f64; 3] {
    let start = line.find(&format!("{label} [")).unwrap() + label.len() + 2;
    let end = start + line[start..].find(']').unwrap();
    let v: Vec<f64> = line[start..end]
        .split(", ")
        .map(|x| x.parse().unwrap())
        .collect();
    [v[0], v[1], v[2]]
}

/// Issue 33: the text tree labels each edge with its translation (m) and
/// roll-pitch-yaw (deg), as the pictures do: checked against the numbers the
/// URDF itself writes, for every joint not at gimbal lock (|pitch| < 80 deg,
/// where rpy is unique), angles compared modulo 360 deg.
#[test]
fn the_text_tree_labels_each_edge_with_translation_and_rpy() {
    let urdf = "tests/fixtures/urdf/husky_kinematics.urdf";
    let (code, out, err) = run_cli(&[urdf, "--frames", "--format", "text"]);
    assert_eq!(code, 0, "{err}");
    let joints = joint_origins(urdf);
    assert!(joints.len() > 20, "{joints:?}");
    let mut checked = 0;
    for (child, xyz, rpy) in &joints {
        let line = out
            .lines()
            .find(|l| l.contains(&format!("── {child}  [")))
            .unwrap_or_else(|| panic!("no line for {child}:\n{out}"));
        let got = vector_after(line, "xyz");
        for k in 0..3 {
            assert!((got[k] - xyz[k]).abs() <= 0.5e-4 + 1e-12, "{child}: {line}");
        }
        assert!(line.ends_with(" deg"), "{line}");
        if rpy[1].to_degrees().abs() >= 80.0 {
            continue;
        }
        let got = vector_after(line, "rpy");
        for k in 0..3 {
            let d = (got[k] - rpy[k].to_degrees()).rem_euclid(360.0);
            assert!(
                d.min(360.0 - d) <= 0.5e-3 + 1e-9,
                "{child}: {line} against {rpy:?} rad"
            );
        }
        checked += 1;
    }
    assert!(checked > 20, "{checked}");
}
