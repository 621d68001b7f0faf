//! The Python reader (launch.py files, roslaunch `$(eval ...)`) cannot be
//! made to exhaust memory: each input here, generated, would have grown
//! without bound before the limits of `tolerances.rs` (`MAX_PY_STR_BYTES`,
//! `MAX_PY_ITEMS`, `MAX_PY_WORK_BYTES`) and must be refused naming its line.
//! Run under `ulimit -v 4000000` while changing the reader, so a regression
//! fails instead of swapping the machine.

use extrinsic_audit::internals::formats::load_str;
use extrinsic_audit::{Code, Error};
use extrinsic_audit::{Format, LoadOptions};
use std::path::Path;

fn read_as(format: &str, text: &str) -> Result<usize, Error> {
    let mut o = LoadOptions::default();
    o.format = Some(Format::from_name(format).unwrap());
    load_str(text, Path::new("hostile.launch.py"), &o).map(|l| l.edges.len())
}

/// `text` read as launch.py is refused at `line` with `want` in the message.
fn refused(text: &str, line: usize, want: &str) -> Error {
    let e = read_as("launch-py", text).expect_err("a hostile file is refused");
    assert!(e.message.contains(want), "{}", e.message);
    assert_eq!(e.location.line, Some(line), "{}", e.message);
    assert_eq!(
        e.location.file.as_deref(),
        Some(Path::new("hostile.launch.py"))
    );
    e
}

#[test]
fn indented_text_read_as_launch_py_is_refused_not_looped() {
    // The cause of the 22 GB test run: a tf_static YAML dump read as
    // launch.py. Its indented lines open no block; the statement loop stood
    // still on the indent and pushed statements until memory ran out.
    let yaml = "transforms:\n- header:\n    stamp:\n      sec: 1\n".repeat(3);
    let e = refused(&yaml, 3, "unexpected indent");
    assert_eq!(e.code, Code::Parse);
    // Inside a block, an indent that opens nothing.
    refused("if a:\n    b = 1\n        c = 2\n", 3, "unexpected indent");
}

#[test]
fn string_doubling_in_a_loop_is_refused() {
    // A rebound name is unknown to the reader; a list's last item is not.
    let py = "l = ['ab']\nfor i in range(64):\n    l.append(l[-1] + l[-1])\n";
    let e = refused(py, 3, "more than 1048576");
    assert_eq!(e.code, Code::Limit);
}

#[test]
fn appending_a_big_string_in_a_loop_is_refused_by_the_work_budget() {
    // Each string is under the cap; 100000 copies of it (100 GB) are not.
    let py = "s = 'x' * 1000000\nl = []\nfor i in range(100000):\n    l.append(s)\n";
    let e = refused(py, 4, "exceed 268435456 bytes in all");
    assert_eq!(e.code, Code::Limit);
}

#[test]
fn nested_comprehensions_are_refused_by_the_work_budget() {
    // 10^10 ints, each list under the item cap.
    let py = "x = [[i for i in range(100000)] for j in range(100000)]\n";
    refused(py, 1, "exceed 268435456 bytes in all");
}

#[test]
fn padding_and_replacing_past_the_string_cap_are_refused() {
    for (py, what) in [
        (
            "x = '1'.zfill(10 ** 12)\n",
            "str.zfill() would make a string of 1000000000000 bytes",
        ),
        (
            "x = '{:999999999999}'.format(1)\n",
            "format spec \"999999999999\"",
        ),
        ("x = f'{1.0:.999999999f}'\n", "999999999 bytes"),
        (
            "x = ('x' * 1000000).replace('x', 'yy')\n",
            "str.replace() would make a string of 2000000 bytes",
        ),
        ("x = ('x' * 1000000).replace('', 'y')\n", "str.replace()"),
        (
            "x = '-'.join(['x' * 600000, 'y' * 600000])\n",
            "str.join() would make a string of 1200001 bytes",
        ),
        (
            "x = list(range(100001))\n",
            "range() would make 100001 items",
        ),
        (
            "x = sum([list(range(90000)), list(range(90000))], [])\n",
            "sum() would make 180000 items",
        ),
    ] {
        let e = refused(py, 1, what);
        assert_eq!(e.code, Code::Limit, "{py}");
    }
}

#[test]
fn a_list_holding_itself_is_printed_and_compared_without_recursing() {
    // Before: str(l) and l == l recursed until the stack overflowed.
    let py = "l = []\nl.append(l)\ns = str(l)\nt = l == l\nx = 'ab' * 10 ** 7\n";
    refused(
        py,
        5,
        "string repetition would make a string of 20000000 bytes",
    );
}

#[test]
fn range_counts_as_python() {
    // CPython: len(range(0, 10, 3)) == 4, len(range(10, 0, -3)) == 4; the
    // reader counted 3 (floor instead of ceiling) before.
    let py = "n = [i for i in range(0, 10, 3)] + [i for i in range(10, 0, -3)]\n\
              x = 'a' * (len(n) * 600000)\n";
    refused(
        py,
        2,
        "string repetition would make a string of 4800000 bytes",
    );
}

#[test]
fn roslaunch_eval_concatenation_past_the_cap_is_refused() {
    let xml = "<launch>\n<node if=\"$(eval len('ab' * 500000 + 'cd' * 500000) > 0)\" \
               pkg=\"tf2_ros\" type=\"static_transform_publisher\" name=\"n\" \
               args=\"0 0 0 0 0 0 a b\"/>\n</launch>\n";
    let e = read_as("launch-xml", xml).expect_err("refused");
    assert!(e.message.contains("more than 1048576"), "{}", e.message);
    assert_eq!(e.location.line, Some(2), "{}", e.message);
}

/// A static_transform_publisher Node whose child frame is `child`.
fn stp_node(child: &str) -> String {
    format!(
        "Node(package='tf2_ros', executable='static_transform_publisher', \
         arguments=['0', '0', '1', '0', '0', '0', 'base', {child}])\n"
    )
}

#[test]
fn values_nested_past_the_depth_cap_are_refused_by_name() {
    // 10^5 levels built in a loop (the cap, tolerances.rs MAX_PY_VALUE_DEPTH,
    // is 100): lists, tuples and dicts, each refused where the value that
    // passes 100 levels is evaluated, line 3. Tuples and dicts were copied
    // whole at each step before (quadratic: still running after a minute),
    // and printing or comparing a 10^5-deep value recursed 10^5 frames.
    let want = "a value nested more than 100 levels deep";
    for (seed, wrap) in [
        ("[]", "[l[-1]]"),
        ("()", "(l[-1],)"),
        ("{}", "{'k': l[-1]}"),
    ] {
        let py = format!(
            "l = [{seed}]\nfor i in range(100000):\n    l.append({wrap})\nx = str(l[-1]) + {}",
            stp_node("'lidar'")
        );
        let e = refused(&py, 3, want);
        assert_eq!(e.code, Code::Limit, "{wrap}");
    }
    // From a literal the parser's nesting limit refuses first, by name.
    let deep = format!("x = {}{}\n", "[".repeat(100_000), "]".repeat(100_000));
    refused(&deep, 1, "nested more than 32 deep");
    // The boundary: `l` is 100 deep after 98 steps (accepted, the Node
    // read), 101 after 99: refused where the append makes it, line 3, naming
    // the call (it was refused only where `l` was next evaluated, line 4).
    let at = |n: usize| {
        format!(
            "l = [[]]\nfor i in range({n}):\n    l.append([l[-1]])\nx = l\n{}",
            stp_node("'lidar'")
        )
    };
    assert_eq!(read_as("launch-py", &at(98)).expect("100 levels"), 1);
    let e = refused(&at(99), 3, want);
    assert!(e.message.contains("list.append()"), "{}", e.message);
    // A list holding itself is cyclic, not deep: read as CPython does.
    let cyc = format!(
        "a = []\na.append(a)\nc = 'lidar' if str(a) == '[[...]]' else 'x'\n{}",
        stp_node("c")
    );
    assert_eq!(read_as("launch-py", &cyc).expect("a cyclic list"), 1);
}

/// A list made deep by appending into a list another list already holds:
/// `a.append(b)` over the pairs of 99,000 fresh lists chains them 99,000
/// deep while every value evaluated is one level deep. The chain's root,
/// evaluated, is refused by name (the measure stops past the cap) and the
/// file's values are dropped without recursion (a value.rs unit test drops
/// a million levels on a small stack).
#[test]
fn a_list_deepened_through_its_holder_is_refused_where_it_is_evaluated() {
    let chain = "cs = [[] for i in range(99000)]\nfor a, b in zip(cs, cs[1:]):\n    a.append(b)\n";
    let text = format!("{chain}{}", stp_node("'lidar'"));
    assert_eq!(read_as("launch-py", &text).expect("never evaluated"), 1);
    let text = format!("{chain}x = str(cs[0])\n{}", stp_node("x"));
    let e = refused(&text, 4, "a value nested more than 100 levels deep");
    assert_eq!(e.code, Code::Limit);
}

#[test]
fn a_character_that_is_no_letter_is_refused_not_looped_on() {
    // The xacro lexer's fault (found by fuzzing), here too: `€` stopped the
    // name lexer without moving it (900 MB in 10 s).
    for py in [
        "x = €\n",
        "x = [1, \u{fffd}]\n",
        "def f():\n    return 1 + ¤\n",
    ] {
        let e = read_as("launch-py", py).expect_err("refused");
        assert!(
            e.message.contains("invalid character"),
            "{py:?}: {}",
            e.message
        );
    }
    assert_eq!(
        read_as("launch-py", &format!("é = 'lidar'\n{}", stp_node("é"))).unwrap(),
        1
    );
}

/// Fuzz finding 16 (pyexpr, FUZZING.md): a backslash before a character
/// beyond ASCII in a plain string (`'\é'`, `"\\\u{fffd}"`) stepped two bytes,
/// into the character, and the next slice of the text panicked. Python
/// keeps an unknown escape as written (`'\é'` is two characters), so the
/// file reads, and the string's length says the character came whole.
#[test]
fn an_unknown_escape_of_a_non_ascii_character_is_kept_whole() {
    for ch in ['é', '\u{fffd}', '漢', '🦀'] {
        let py = format!(
            "s = '\\{ch}'\nif len(s) == 2 and s[1] == '{ch}':\n    {}",
            stp_node("'lidar'")
        );
        assert_eq!(read_as("launch-py", &py).expect("read"), 1, "{ch}");
        // Triple-quoted too, and the rest of the line read on from there.
        let py = format!(
            "s = \"\"\"a\\{ch}b\"\"\"\nif s == 'a\\\\{ch}b':\n    {}",
            stp_node("'lidar'")
        );
        assert_eq!(read_as("launch-py", &py).expect("read"), 1, "{ch}");
    }
}

/// Escapes as Python reads them (checked with CPython 3.11): octal takes up
/// to three digits (`'\012'` is a line feed, `'\1a'` is chr(1) + 'a', `\0`
/// a NUL), compared here with the same characters written as hex escapes;
/// `\x+1` is refused, as Python refuses it (`from_str_radix` took the sign).
#[test]
fn octal_and_hex_escapes_read_as_python_reads_them() {
    for (lit, cond) in [
        (r"'\012'", r"s == '\n'"),
        (r"'\0'", r"s == '\x00'"),
        (r"'\101\102'", "s == 'AB'"),
        (r"'\1a'", r"len(s) == 2 and s == '\x01a'"),
        (r"'\7777'", r"s == '\u01ff7'"),
        (r"'\x41'", "s == 'A'"),
    ] {
        let py = format!("s = {lit}\nif {cond}:\n    {}", stp_node("'lidar'"));
        assert_eq!(read_as("launch-py", &py).expect("read"), 1, "{lit}");
    }
    refused(
        &format!("s = '\\x+1'\n{}", stp_node("'lidar'")),
        1,
        "escape",
    );
}
