//! SARIF 2.1.0 (the format GitHub code scanning uploads): one run of the tool
//! `extrinsic-audit`, one rule per diagnostic code that occurs (its id the
//! code's name, its description the code's doc), one result per diagnostic
//! (level `error` or `warning`, the file as a relative URI reference, the line
//! and column as the region). Validated in the tests against the published
//! schema (docs/schemas/external/).

use crate::diagnostic::{Code, Diagnostic, Severity};
use crate::document::{Block, Document};
use serde_json::{json, Value};

/// Render a document's diagnostics as a SARIF log (the other blocks have no
/// place in SARIF).
pub fn render(doc: &Document) -> String {
    let diags: Vec<&Diagnostic> = doc
        .blocks
        .iter()
        .filter_map(|b| match b {
            Block::Diagnostics(ds) => Some(ds.iter()),
            _ => None,
        })
        .flatten()
        .collect();
    let mut codes: Vec<Code> = diags.iter().map(|d| d.code).collect();
    codes.sort();
    codes.dedup();
    let rules: Vec<Value> = codes.iter().map(|c| rule(*c)).collect();
    let results: Vec<Value> = diags
        .iter()
        .map(|d| result(d, codes.iter().position(|c| *c == d.code).unwrap_or(0)))
        .collect();
    let log = json!({
        "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
        "version": "2.1.0",
        "runs": [{
            "tool": {"driver": {
                "name": "extrinsic-audit",
                "version": env!("CARGO_PKG_VERSION"),
                "rules": rules,
            }},
            "columnKind": "unicodeCodePoints",
            "results": results,
        }],
    });
    // A `Value` always serialises.
    let mut s = serde_json::to_string_pretty(&log).unwrap_or_default();
    s.push('\n');
    s
}

fn level(s: Severity) -> &'static str {
    match s {
        Severity::Error => "error",
        Severity::Warning => "warning",
    }
}

fn rule(c: Code) -> Value {
    json!({
        "id": c.name(),
        "name": c.name(),
        "shortDescription": {"text": c.description()},
        "defaultConfiguration": {"level": level(c.default_severity())},
    })
}

fn result(d: &Diagnostic, rule_index: usize) -> Value {
    let mut r = json!({
        "ruleId": d.code.name(),
        "ruleIndex": rule_index,
        "level": level(d.severity),
        "message": {"text": match &d.help {
            Some(h) => format!("{} ({h})", d.message),
            None => d.message.clone(),
        }},
    });
    if let Some(f) = &d.location.file {
        let mut phys = json!({"artifactLocation": {"uri": uri(&f.to_string_lossy())}});
        if let Some(l) = d.location.line.filter(|l| *l >= 1) {
            let mut region = json!({"startLine": l});
            if let Some(c) = d.location.column.filter(|c| *c >= 1) {
                region["startColumn"] = json!(c);
            }
            phys["region"] = region;
        }
        r["locations"] = json!([{"physicalLocation": phys}]);
    }
    r
}

/// A path as a URI reference: `/`-separated, relative paths stay relative,
/// absolute ones become `file://` URIs; every byte outside the unreserved set
/// and `/` is percent-encoded.
pub fn uri(path: &str) -> String {
    let p = path.replace('\\', "/");
    let mut out = String::new();
    if p.starts_with('/') {
        out.push_str("file://");
    }
    for b in p.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~/".contains(&b) {
            out.push(b as char);
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}
