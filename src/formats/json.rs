//! JSON, read as the JSON formats read it: serde_json checks the syntax (a
//! JSON error is reported as JSON, at its line and column), then the YAML
//! reader parses it (YAML 1.2 holds JSON, and the reader keeps each node's
//! line for provenance).
//!
//! A key given twice in one object is refused, as the YAML formats refuse a
//! duplicated key they read: RFC 8259 (section 4) leaves the meaning of such
//! an object to the reader, and readers differ (Python's `json`, jq and
//! serde_json keep the last value, a reader that stops at the first match
//! keeps the first), so no answer would be the one every tool gives.

use crate::diagnostic::{Error, Result};
use crate::formats::yaml::{self, Node, Value};
use std::collections::HashMap;

/// The documents of a JSON file, read by the YAML reader (which keeps each
/// node's line) after serde_json has checked the syntax, so a JSON error is
/// reported as JSON, at its line and column; a key given twice in one object
/// is an error naming both lines. Shared by the JSON formats.
pub(crate) fn json_documents(text: &str) -> Result<Vec<yaml::Node>> {
    if let Err(e) = serde_json::from_str::<serde::de::IgnoredAny>(text) {
        let msg = e.to_string();
        let msg = msg.split(" at line ").next().unwrap_or("").to_string();
        return Err(Error::parse(format!("not valid JSON: {msg}"))
            .at_line(e.line().max(1), Some(e.column().max(1))));
    }
    // JSON allows tabs where YAML forbids them in indentation.
    let docs = yaml::parse_documents(&text.replace('\t', " "))?;
    refuse_duplicate_keys(&docs)?;
    Ok(docs)
}

/// Whether `text` is a JSON object or array (what a YAML dialect reading a
/// `.json` file is given): then its keys are held to the JSON rule.
pub(crate) fn is_json(text: &str) -> bool {
    text.trim_start().starts_with(['{', '['])
        && serde_json::from_str::<serde::de::IgnoredAny>(text).is_ok()
}

/// A key given twice in one object, anywhere in `docs`: an error at the
/// second occurrence naming the line and column of both (the earliest such
/// pair in the file). Nesting is bounded by the YAML reader's depth limit.
pub(crate) fn refuse_duplicate_keys(docs: &[Node]) -> Result<()> {
    let mut todo: Vec<&Node> = docs.iter().collect();
    let mut earliest: Option<(&Node, &Node)> = None;
    while let Some(n) = todo.pop() {
        match &n.value {
            Value::Map(entries) => {
                let mut seen: HashMap<String, &Node> = HashMap::with_capacity(entries.len());
                for (k, v) in entries {
                    let name = k.as_str().unwrap_or_default();
                    if let Some(first) = seen.insert(name, k) {
                        if earliest.is_none_or(|(_, e)| (k.line, k.column) < (e.line, e.column)) {
                            earliest = Some((first, k));
                        }
                    }
                    todo.push(v);
                }
            }
            Value::Seq(items) => todo.extend(items),
            _ => {}
        }
    }
    let Some((first, again)) = earliest else {
        return Ok(());
    };
    Err(Error::parse(format!(
        "key \"{}\" given twice in one object (line {}, column {} and line {}, column {}): expected each key once (JSON readers disagree on which value counts)",
        crate::sanitize::quote(&again.as_str().unwrap_or_default()),
        first.line,
        first.column,
        again.line,
        again.column
    ))
    .at_line(again.line.max(1), Some(again.column.max(1))))
}
