//! JSON: the report itself, serialised, in the one envelope every command's
//! JSON has: `schema_version` first, the report's fields, `warnings` last
//! (each a warning's one-line text, as printed on standard error).

use crate::diagnostic::{Code, Error, Result, Warning};
use crate::document::SCHEMA_VERSION;
use serde::Serialize;
use std::io::Write;

mod probe;

/// The report as pretty-printed JSON (a line break at the end); a report
/// with its own `schema_version` or `warnings` keeps them (the check
/// report: version 2, and its warnings listed among its findings).
pub fn render<R: Serialize>(report: &R, warnings: &[Warning]) -> Result<String> {
    let mut out = Vec::new();
    write(report, warnings, &mut out)?;
    String::from_utf8(out).map_err(|e| {
        Error::new(
            Code::Io,
            format!("cannot serialise the report as JSON: {e}"),
        )
    })
}

/// [`render`] written to `out` as it is serialised: a report of a hundred
/// thousand rows is never held as text or as a JSON tree.
pub fn write<R: Serialize>(report: &R, warnings: &[Warning], out: &mut dyn Write) -> Result<()> {
    let err = |e: serde_json::Error| {
        Error::new(
            Code::Io,
            format!("cannot serialise the report as JSON: {e}"),
        )
    };
    let keys = match report.serialize(probe::Keys) {
        Ok(k) => k,
        // A report that is not a plain struct: its keys from its JSON tree.
        Err(_) => match serde_json::to_value(report).map_err(err)? {
            serde_json::Value::Object(m) => Some(m.keys().cloned().collect()),
            _ => None,
        },
    };
    let mut w = std::io::BufWriter::new(out);
    match keys {
        Some(keys) => {
            let has = |k: &str| keys.iter().any(|x| x == k);
            let lines: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
            let envelope = Envelope {
                schema_version: (!has("schema_version")).then_some(SCHEMA_VERSION),
                report,
                warnings: (!has("warnings")).then_some(&lines),
            };
            serde_json::to_writer_pretty(&mut w, &envelope)
        }
        None => serde_json::to_writer_pretty(&mut w, report),
    }
    .map_err(err)?;
    w.write_all(b"\n")
        .and_then(|()| w.flush())
        .map_err(|e| Error::new(Code::Io, format!("cannot write output: {e}")))
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
