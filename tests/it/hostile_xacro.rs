//! Hostile xacro (issue 27): one test per class of input that crashed, hung
//! or escaped a budget, and the reach of `--confine` (docs/xacro.md). Each
//! runs the binary: exit 2 with the limit named (or the right answer), never
//! a signal (stack overflow), a panic or a run past the time guard.

use crate::common::hostile::{run_audit, write_tmp, Output};

/// A robot whose one joint's x is `x`, after `body` (xacro elements).
fn robot(body: &str, x: &str) -> String {
    format!(
        "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n{body}\n\
         <link name=\"a\"/><link name=\"b\"/>\n<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/>\
         <child link=\"b\"/><origin xyz=\"{x} 0 0\" rpy=\"0 0 0\"/></joint>\n</robot>\n"
    )
}

fn run(text: &str, extra: &[&str]) -> (Output, tempfile::TempDir) {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = write_tmp(&dir, "r.urdf.xacro", text);
    let mut args = vec![p.to_str().expect("utf-8")];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--frames", "--format", "json"]);
    (run_audit(&args, 120), dir)
}

fn refused(text: &str, needle: &str) {
    let (out, _d) = run(text, &[]);
    assert_eq!(out.code, Some(2), "{}", out.stderr);
    assert!(
        out.stderr.contains(needle),
        "expected {needle:?}: {}",
        out.stderr
    );
}

#[test]
fn a_long_lazy_property_chain_is_refused_at_the_property_depth() {
    let n = 100_000;
    let props: String = (0..n)
        .map(|i| {
            format!(
                "<xacro:property name=\"p{i}\" value=\"${{p{}}}\"/>\n",
                i + 1
            )
        })
        .collect();
    let body = format!("{props}<xacro:property name=\"p{n}\" value=\"1\"/>");
    refused(&robot(&body, "${p0}"), "150");
}

#[test]
fn a_long_operator_chain_is_evaluated_flat() {
    let chain = vec!["0.001"; 100_000].join("+");
    let (out, _d) = run(&robot("", &format!("${{{chain}}}")), &[]);
    assert_eq!(out.code, Some(0), "{}", out.stderr);
    let v: serde_json::Value = serde_json::from_str(&out.stdout).expect("json");
    let x = v["edges"][0]["translation_m"][0].as_f64().expect("x");
    assert!((x - 100.0).abs() < 1e-6, "{x}");
}

#[test]
fn deep_parentheses_are_refused_at_the_expression_depth() {
    let e = format!("{}1{}", "(".repeat(50_000), ")".repeat(50_000));
    refused(&robot("", &format!("${{{e}}}")), "100");
}

#[test]
fn deeply_nested_xacro_if_is_refused_at_the_element_depth() {
    let n = 100_000;
    let body = format!(
        "{}<link name=\"c\"/>{}",
        "<xacro:if value=\"1\">".repeat(n),
        "</xacro:if>".repeat(n)
    );
    refused(&robot(&body, "0"), "500");
}

#[test]
fn shared_nested_lists_stop_within_the_work_budget() {
    // A thousand references to one list, nested five deep: 10^15 items to
    // print in a few hundred bytes of source.
    let mut body = String::from("<xacro:property name=\"l0\" value=\"${[0]*1000}\"/>\n");
    for i in 1..5 {
        body += &format!(
            "<xacro:property name=\"l{i}\" value=\"${{[l{}]*1000}}\"/>\n",
            i - 1
        );
    }
    let t = std::time::Instant::now();
    refused(&robot(&body, "${len(str(l4))}"), "cap");
    crate::common::hostile::assert_quick(t, 12, "shared nested lists");
}

#[test]
fn list_repetition_and_doubling_are_capped() {
    refused(&robot("", "${len([0]*10**9)}"), "1000000");
    let mut body = String::from("<xacro:property name=\"l0\" value=\"${[0]}\"/>\n");
    for i in 1..=40 {
        body += &format!(
            "<xacro:property name=\"l{i}\" value=\"${{l{0}+l{0}}}\"/>\n",
            i - 1
        );
    }
    refused(&robot(&body, "${len(l40)}"), "1000000");
}

/// `--confine`: an include, a load_yaml file and a `$(find)` package outside
/// the directory are refused; inside, read; the environment is not read.
#[test]
fn confine_keeps_every_read_below_the_directory() {
    let outside = tempfile::tempdir().expect("tempdir");
    write_tmp(&outside, "inc.xacro", "<robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\"><xacro:property name=\"v\" value=\"1\"/></robot>");
    write_tmp(&outside, "v.yaml", "x: 1\n");
    write_tmp(
        &outside,
        "package.xml",
        "<package><name>far_pkg</name></package>",
    );
    let o = outside.path().display().to_string();
    let inside = tempfile::tempdir().expect("tempdir");
    let conf = inside.path().to_str().expect("utf-8").to_string();
    let cases = [
        (
            format!("<xacro:include filename=\"{o}/inc.xacro\"/>"),
            "0".to_string(),
        ),
        (
            String::new(),
            format!("${{xacro.load_yaml('{o}/v.yaml')['x']}}"),
        ),
        (String::new(), "$(find far_pkg)".to_string()),
        (String::new(), "$(env HOME)".to_string()),
    ];
    for (body, x) in &cases {
        let p = write_tmp(&inside, "r.urdf.xacro", &robot(body, x));
        let out = run_audit(
            &[
                p.to_str().unwrap(),
                "--confine",
                &conf,
                "--package-path",
                &o,
                "--frames",
            ],
            120,
        );
        assert_eq!(out.code, Some(2), "{x}: {}", out.stderr);
        assert!(out.stderr.contains("--confine"), "{x}: {}", out.stderr);
        // Without --confine the same file reads (but for $(find): a path).
        let out = run_audit(
            &[p.to_str().unwrap(), "--package-path", &o, "--frames"],
            120,
        );
        assert!(!out.stderr.contains("--confine"), "{}", out.stderr);
    }
    // The input itself outside.
    let p = write_tmp(&outside, "r.urdf.xacro", &robot("", "0"));
    let out = run_audit(&[p.to_str().unwrap(), "--confine", &conf, "--frames"], 120);
    assert_eq!(out.code, Some(2), "{}", out.stderr);
    // Inside: read.
    write_tmp(&inside, "inc.xacro", "<robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\"><xacro:property name=\"v\" value=\"0.5\"/></robot>");
    let p = write_tmp(
        &inside,
        "r.urdf.xacro",
        &robot("<xacro:include filename=\"inc.xacro\"/>", "${v}"),
    );
    let out = run_audit(
        &[
            p.to_str().unwrap(),
            "--confine",
            &conf,
            "--frames",
            "--format",
            "json",
        ],
        120,
    );
    assert_eq!(out.code, Some(0), "{}", out.stderr);
    assert!(out.stdout.contains("0.5"), "{}", out.stdout);
}

/// `check` on a folder with a robot and a macro-only file: a note, not an
/// error; two copies of a package: a duplicate-package warning naming both.
#[test]
fn check_notes_macro_only_files_and_names_duplicate_packages() {
    let d = tempfile::tempdir().expect("tempdir");
    let macros = "<robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<xacro:macro name=\"sensor\" params=\"parent\"><link name=\"s\"/></xacro:macro>\n</robot>\n";
    write_tmp(&d, "sensor.urdf.xacro", macros);
    for copy in ["one", "two"] {
        std::fs::create_dir_all(d.path().join("pkgs").join(copy)).expect("mkdir");
        std::fs::write(
            d.path().join("pkgs").join(copy).join("package.xml"),
            "<package><name>twin</name></package>",
        )
        .expect("write");
    }
    let robot_ok = robot("", "${len('$(find twin)') * 0}");
    write_tmp(&d, "robot.urdf.xacro", &robot_ok);
    let pp = d.path().join("pkgs");
    let out = run_audit(
        &[
            "check",
            d.path().to_str().unwrap(),
            "--package-path",
            pp.to_str().unwrap(),
        ],
        120,
    );
    assert_eq!(out.code, Some(0), "{}\n{}", out.stdout, out.stderr);
    let all = format!("{}{}", out.stdout, out.stderr);
    assert!(
        all.contains("note:") && all.contains("defines only macros (sensor)"),
        "{all}"
    );
    assert!(
        all.contains("duplicate-package") || all.contains("2 packages named twin"),
        "{all}"
    );
    assert!(all.contains("one") && all.contains("two"), "{all}");
}

#[test]
fn a_character_that_is_no_letter_is_refused_not_looped_on() {
    // Found by `fuzz/run.sh 300 xacro` (fuzz/regressions/xacro/): a
    // non-ASCII character that is not alphanumeric (`€`, and the U+FFFD a
    // lossy decoding leaves) entered the name branch of the expression
    // lexer, matched nothing and pushed empty names without moving: 2 GB in
    // 20 s. Python: "invalid character".
    for ch in ["€", "\u{fffd}", "[x * 2 for \u{fffd} 2]"] {
        refused(&robot("", &format!("${{{ch}}}")), "unexpected character");
    }
    // A letter outside ASCII is still a name, as in Python.
    refused(&robot("", "${é}"), "name 'é' is not defined");
    // The fuzzer's input itself, decoded as the fuzz target decodes it.
    let raw =
        std::fs::read("fuzz/regressions/xacro/timeout-765420b09e17ef9a19c65bf1dda1056f70c34bac")
            .unwrap();
    refused(&String::from_utf8_lossy(&raw[1..]), "unexpected character");
}
