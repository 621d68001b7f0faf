//! What every YAML dialect shares: the documents read (with the advice for
//! OpenCV files that are not YAML), and `--key NAME`, which reads one key
//! (a dotted path `a.b.c`, or `NAME[i]` for the i-th of stacked 4x4
//! matrices) in any YAML or JSON file, whichever shape it holds (see
//! `yaml_shapes`); frames from a `T_A_B` / `A_T_B` name or Kalibr's
//! `camN.T_cam_imu`; a name that gives neither the frames nor the direction
//! is read only with `--assume DIRECTION:PARENT,CHILD` (refused without).

use super::calib_shapes::assumed;
use super::spec::{Assume, Confidence, LoadOptions, Parsed};
use super::yaml::{self, Node, Value};
use super::yaml_shapes::{
    err_at, frames_from_key, kalibr_frames, kalibr_imu, matrix_edge, MATRIX_YAML_ID,
};
use crate::diagnostic::{Error, Result};
use std::path::Path;

/// The keys are present: the level every YAML dialect sniffs at.
pub(crate) fn keys(present: bool) -> Option<Confidence> {
    present.then_some(Confidence::Keys)
}

/// A YAML dialect's `FormatSpec`: its id, whether `--key` applies, its
/// sniffer, its reader of the parsed documents, its description.
macro_rules! yaml_dialect {
    ($name:ident, $id:expr, $keyed:literal, $sniff:expr, $read:expr, $desc:literal) => {
        #[doc = $desc]
        pub const $name: $crate::formats::spec::FormatSpec = $crate::formats::spec::FormatSpec {
            id: $id,
            description: $desc,
            extensions: &[],
            walk: &[".yaml", ".yml"],
            magic: &[],
            sniff: $sniff,
            parse: |input, opts| {
                $crate::formats::yaml_keyed::parse_with(
                    $read,
                    $keyed,
                    input.text()?,
                    input.path(),
                    opts,
                )
            },
            checked: true,
        };
    };
}
pub(crate) use yaml_dialect;

pub(crate) type DocsParser = fn(&[Node], &str, &Path) -> Result<Parsed>;

/// Parse YAML text with one dialect's reader; `--key` reads one key instead
/// (except in tf_static dumps, whose keys are not transforms).
pub(crate) fn parse_with(
    read: DocsParser,
    keyed: bool,
    text: &str,
    path: &Path,
    opts: &LoadOptions,
) -> Result<Parsed> {
    let docs = yaml::parse_documents_shared(text).map_err(|e| explain_yaml_error(e, text))?;
    // A JSON file read by a YAML dialect keeps JSON's rule on keys.
    if super::json::is_json(text) {
        super::json::refuse_duplicate_keys(&docs)?;
    }
    if let (Some(key), true) = (&opts.key, keyed) {
        return parse_keyed(&docs, key, text, path, opts.assume.as_ref());
    }
    read(&docs, text, path)
}

fn explain_yaml_error(e: Error, text: &str) -> Error {
    if text.contains("!!opencv-matrix") || text.trim_start().starts_with("%YAML:") {
        let msg = format!(
            "{} (OpenCV FileStorage file that is not valid YAML: write each matrix as `KEY: !!opencv-matrix` with `rows`, `cols`, `dt`, `data` indented alike and comments after `#`; or copy the one matrix you need into a file of its own and pass --key NAME)",
            e.message
        );
        Error { message: msg, ..e }
    } else {
        e
    }
}

fn find_key<'a>(n: &'a Node, key: &str, out: &mut Vec<(&'a Node, &'a Node)>) {
    match &n.value {
        Value::Map(m) => {
            for (k, v) in m {
                if k.as_str().as_deref() == Some(key) {
                    out.push((k, v));
                }
                find_key(v, key, out);
            }
        }
        Value::Seq(s) => {
            for v in s {
                find_key(v, key, out);
            }
        }
        _ => {}
    }
}

/// `--key NAME`: one key anywhere (or a dotted path from the top).
pub fn parse_keyed(
    docs: &[Node],
    key: &str,
    text: &str,
    path: &Path,
    assume: Option<&Assume>,
) -> Result<Parsed> {
    // `NAME[i]`: the i-th of stacked 4x4 matrices under NAME.
    let (key, index) = match key.strip_suffix(']').and_then(|k| k.rsplit_once('[')) {
        Some((k, i)) => match i.trim().parse::<usize>() {
            Ok(i) => (k, Some(i)),
            Err(_) => {
                return Err(Error::usage(format!(
                    "--key {key}: expected NAME or NAME[i] with i a number, found [{i}]"
                )))
            }
        },
        None => (key, None),
    };
    let (k, v) = find_one_key(docs, key)?;
    let picked;
    let v = match index {
        None => v,
        Some(i) => {
            picked = stacked_matrix(v, key, i)?;
            &picked
        }
    };
    let last = key.rsplit('.').next().unwrap_or(key);
    let mut out = Parsed::default();
    // Kalibr `camN.T_cam_imu`: frames named from the block (camN, imu).
    let block = key.rsplit('.').nth(1);
    let imu = kalibr_imu(docs);
    let kalibr = block.and_then(|cam| kalibr_frames(cam, last, imu));
    let named = kalibr.or_else(|| frames_from_key(last));
    let frames = match (&named, assume) {
        (Some(f), _) => f.clone(),
        (None, Some(Assume { frames: Some(f), .. })) => f.clone(),
        (None, Some(a)) => {
            return Err(Error::usage(format!(
                "--key {key}: the name does not say which frames (T_A_B or A_T_B): expected {}:PARENT,CHILD",
                a.flag()
            )))
        }
        (None, None) => {
            return Err(err_at(
                k,
                format!("--key {key}: the name says neither the frames nor the direction (T_A_B or A_T_B would): pass --assume child-in-parent:PARENT,CHILD (the value is the pose of CHILD in PARENT) or --assume parent-in-child:PARENT,CHILD"),
            ))
        }
    };
    let label = match index {
        Some(i) => format!("{key}[{i}]"),
        None => key.to_string(),
    };
    let e = matrix_edge(
        MATRIX_YAML_ID,
        &label,
        frames,
        (k, v),
        text,
        path,
        &mut out.warnings,
    )?;
    // A name that gives no frames gives no direction either: --assume does.
    out.edges.push(match (named, assume) {
        (None, Some(a)) => assumed(a, e),
        _ => e,
    });
    Ok(out)
}

/// The value under a dotted path (`a.b.c`) in one document.
fn dotted<'a>(d: &'a Node, key: &str) -> Option<(&'a Node, &'a Node)> {
    let parts: Vec<&str> = key.split('.').collect();
    let mut cur = d;
    let mut hit = None;
    for (i, p) in parts.iter().enumerate() {
        let (k, v) = cur
            .entries()
            .iter()
            .rev()
            .find(|(k, _)| k.as_str().as_deref() == Some(*p))?;
        if i + 1 == parts.len() {
            hit = Some((k, v));
        }
        cur = v;
    }
    hit
}

/// The one value of `key` (a dotted path, or a key anywhere); several equal
/// values are one, different ones are an error naming their lines.
fn find_one_key<'a>(docs: &'a [Node], key: &str) -> Result<(&'a Node, &'a Node)> {
    let mut found: Vec<(&Node, &Node)> = Vec::new();
    for d in docs {
        if key.contains('.') {
            found.extend(dotted(d, key));
        }
        if found.is_empty() {
            find_key(d, key, &mut found);
        }
    }
    if found.is_empty() {
        let names: Vec<String> = docs
            .iter()
            .flat_map(|d| d.entries().iter().filter_map(|(k, _)| k.as_str()))
            .map(|s| s.to_string())
            .collect();
        return Err(Error::parse(format!(
            "--key {key}: no such key in this file; top-level keys: {}",
            names.join(", ")
        )));
    }
    if found.len() > 1 && !found.windows(2).all(|w| w[0].1.value == w[1].1.value) {
        return Err(err_at(
            found[1].0,
            format!(
                "--key {key}: the key appears {} times with different values (lines {}): the file is ambiguous; copy the right one into a file of its own",
                found.len(),
                found.iter().map(|(k, _)| k.line.to_string()).collect::<Vec<_>>().join(", ")
            ),
        ));
    }
    Ok(found[0])
}

/// The `i`-th of stacked 4x4 matrices under `key`, as its top 3x4 (stacked
/// files use the (4,4) entry as a flag).
fn stacked_matrix(v: &Node, key: &str, i: usize) -> Result<Node> {
    let nums = v.numbers(key)?;
    let count = nums.len() / 16;
    if nums.len() % 16 != 0 || i >= count {
        return Err(err_at(
            v,
            format!(
                "--key {key}[{i}]: expected at least {} stacked 4x4 matrices (16 numbers each), found {} numbers",
                i + 1,
                nums.len()
            ),
        ));
    }
    let b = &nums[16 * i..16 * (i + 1)];
    if !(b[12] == 0.0 && b[13] == 0.0 && b[14] == 0.0 && (b[15] == 0.0 || b[15] == 1.0)) {
        return Err(err_at(
            v,
            format!(
                "--key {key}[{i}]: expected bottom row [0, 0, 0, 1] (or SLICT's [0, 0, 0, 0] flag), found [{}, {}, {}, {}]",
                b[12], b[13], b[14], b[15]
            ),
        ));
    }
    Ok(Node {
        value: Value::Seq(
            nums[16 * i..16 * i + 12]
                .iter()
                .map(|x| Node {
                    value: Value::Num(*x),
                    line: v.line,
                    column: v.column,
                })
                .collect(),
        ),
        line: v.line,
        column: v.column,
    })
}
