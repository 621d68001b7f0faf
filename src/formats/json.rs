//! JSON, read as the JSON formats read it: serde_json checks the syntax (a
//! JSON error is reported as JSON, at its line and column), then the YAML
//! reader parses it (YAML 1.2 holds JSON, and the reader keeps each node's
//! line for provenance).

use crate::diagnostic::{Error, Result};
use crate::formats::yaml;

/// The documents of a JSON file, read by the YAML reader (which keeps each
/// node's line) after serde_json has checked the syntax, so a JSON error is
/// reported as JSON, at its line and column. Shared by the JSON formats.
pub(crate) fn json_documents(text: &str) -> Result<Vec<yaml::Node>> {
    if let Err(e) = serde_json::from_str::<serde_json::Value>(text) {
        let msg = e.to_string();
        let msg = msg.split(" at line ").next().unwrap_or("").to_string();
        return Err(Error::parse(format!("not valid JSON: {msg}"))
            .at_line(e.line().max(1), Some(e.column().max(1))));
    }
    // JSON allows tabs where YAML forbids them in indentation.
    yaml::parse_documents(&text.replace('\t', " "))
}
