//! Issue 12: messages are bounded. A value quoted from a file is shortened
//! (head and tail kept, with the count of what was cut), and no message is
//! longer than the backstop however many values it quotes.

use crate::common::hostile::{run_audit, write_tmp};

#[test]
fn a_five_megabyte_value_is_quoted_shortened_with_the_count_cut() {
    let d = tempfile::tempdir().unwrap();
    let long = "x".repeat(5_000_000);
    let p = write_tmp(
        &d,
        "big.txt",
        &format!("ros2 run tf2_ros static_transform_publisher 0 0 {long} 0 0 0 a b\n"),
    );
    let o = run_audit(&[p.to_str().unwrap()], 20);
    assert_eq!(o.code, Some(2), "{}", &o.stderr[..o.stderr.len().min(500)]);
    assert!(o.stderr.len() < 400, "{} bytes", o.stderr.len());
    assert!(
        o.stderr.contains("...[4999880 characters cut]..."),
        "{}",
        o.stderr
    );
    assert!(o.stderr.contains("big.txt:1:1"), "{}", o.stderr);

    let p = write_tmp(
        &d,
        "big.yaml",
        &format!("mapping:\n  extrinsic_T: [0, 0, \"{long}\"]\n  extrinsic_R: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n"),
    );
    let o = run_audit(&[p.to_str().unwrap()], 20);
    assert_eq!(o.code, Some(2));
    assert!(o.stderr.len() < 400, "{} bytes", o.stderr.len());
    assert!(o.stderr.contains("characters cut"), "{}", o.stderr);
}

#[test]
fn a_million_column_csv_header_gives_a_bounded_message() {
    let d = tempfile::tempdir().unwrap();
    let header: Vec<String> = (0..1_000_000).map(|i| format!("c{i}")).collect();
    let p = write_tmp(&d, "wide.csv", &format!("{}\n1,2,3\n", header.join(",")));
    let o = run_audit(&["degeneracy", p.to_str().unwrap()], 20);
    assert_eq!(o.code, Some(2));
    let max = extrinsic_audit::internals::tolerances::MAX_MESSAGE_CHARS;
    assert!(o.stderr.len() < max + 200, "{} bytes", o.stderr.len());
    let head: String = o.stderr.chars().take(300).collect();
    assert!(o.stderr.contains("wide.csv:1"), "{head}");
    // The streaming reader refuses the line by its length; a message that
    // quotes the columns must say how much it cut.
    let quoted = o.stderr.contains("\"c0\"");
    assert!(!quoted || o.stderr.contains("characters cut]..."), "{head}");
}
