//! JSON: the report itself, serialised, in the one envelope every command's
//! JSON has: `schema_version` first, the report's fields, `warnings` last
//! (each a warning's one-line text, as printed on standard error).

use crate::diagnostic::{Code, Error, Result, Warning};
use crate::document::SCHEMA_VERSION;
use serde::Serialize;

/// The report as pretty-printed JSON (a line break at the end); a report
/// with its own `schema_version` or `warnings` keeps them (the check
/// report: version 2, and its warnings listed among its findings).
pub fn render<R: Serialize>(report: &R, warnings: &[Warning]) -> Result<String> {
    let err = |e: serde_json::Error| {
        Error::new(
            Code::Io,
            format!("cannot serialise the report as JSON: {e}"),
        )
    };
    let value = serde_json::to_value(report).map_err(err)?;
    let has = |k: &str| value.as_object().is_some_and(|o| o.contains_key(k));
    let lines: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    let envelope = Envelope {
        schema_version: (!has("schema_version")).then_some(SCHEMA_VERSION),
        report,
        warnings: (!has("warnings")).then_some(&lines),
    };
    let mut s = if value.is_object() {
        serde_json::to_string_pretty(&envelope)
    } else {
        serde_json::to_string_pretty(report)
    }
    .map_err(err)?;
    s.push('\n');
    Ok(s)
}

#[derive(Serialize)]
struct Envelope<'a, R: Serialize> {
    #[serde(skip_serializing_if = "Option::is_none")]
    schema_version: Option<u32>,
    #[serde(flatten)]
    report: &'a R,
    #[serde(skip_serializing_if = "Option::is_none")]
    warnings: Option<&'a Vec<String>>,
}
