//! The check report (`audit check`): every finding as a diagnostic, and the
//! counts; JSON in `docs/schemas/check.schema.json`.

use crate::diagnostic::{Diagnostic, Severity};
use crate::document::{Block, Document, Report};
use serde::Serialize;

/// Version of the check report's JSON: 2 since `warnings` became the array of
/// warning lines every other report carries (it was their count in 1).
pub const CHECK_SCHEMA_VERSION: u32 = 2;

/// What `audit check` found.
#[derive(Debug, Clone, Serialize)]
pub struct CheckReport {
    /// `CHECK_SCHEMA_VERSION`.
    pub schema_version: u32,
    /// Files read.
    pub files_checked: usize,
    /// Findings of severity `error` (the gate fails when non-zero).
    pub problems: usize,
    /// Findings of severity `warning`, one line each (`warning[code]: file:line:
    /// message`), as in every report's JSON; the findings hold them in full.
    pub warnings: Vec<String>,
    /// Every finding, in the order found.
    pub findings: Vec<Diagnostic>,
    /// What `--write-baseline` changed (`null` when no baseline was written).
    pub baseline_written: Option<BaselineChanges>,
    /// Files read but not checked on their own, and why (an xacro file that
    /// only defines macros: an include), one line each; never a problem.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
}

/// What `--write-baseline` changed, by baseline key.
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
pub struct BaselineChanges {
    /// The baseline written.
    pub path: String,
    /// Entries of files new to the baseline.
    pub added: Vec<String>,
    /// Entries dropped (`--prune`: files not checked this run).
    pub removed: Vec<String>,
    /// Entries whose record changed.
    pub updated: Vec<String>,
    /// Entries checked and unchanged.
    pub unchanged: usize,
}

impl BaselineChanges {
    /// `wrote baseline P: A added, R removed, U updated, N unchanged`, then one
    /// line per changed entry.
    pub fn lines(&self) -> String {
        let mut s = format!(
            "wrote baseline {}: {} added, {} removed, {} updated, {} unchanged",
            self.path,
            self.added.len(),
            self.removed.len(),
            self.updated.len(),
            self.unchanged
        );
        for (what, keys) in [
            ("added", &self.added),
            ("removed", &self.removed),
            ("updated", &self.updated),
        ] {
            for k in keys {
                s.push_str(&format!("\n  {what}: {k}"));
            }
        }
        s
    }
}

impl CheckReport {
    /// The report over `findings` for `files_checked` files.
    pub fn new(files_checked: usize, findings: Vec<Diagnostic>) -> Self {
        let problems = findings
            .iter()
            .filter(|f| f.severity == Severity::Error)
            .count();
        let warnings = findings
            .iter()
            .filter(|f| f.severity == Severity::Warning)
            .map(|f| f.to_string())
            .collect();
        CheckReport {
            schema_version: CHECK_SCHEMA_VERSION,
            files_checked,
            problems,
            warnings,
            findings,
            baseline_written: None,
            notes: Vec::new(),
        }
    }

    /// 0 when clean, 1 when a finding of severity `error` was made.
    pub fn exit_code(&self) -> i32 {
        i32::from(self.problems > 0)
    }

    /// `checked N files: P problems, W warnings`.
    pub fn summary_line(&self) -> String {
        let plural = |n: usize, w: &str| format!("{n} {w}{}", if n == 1 { "" } else { "s" });
        format!(
            "checked {}: {}, {}",
            plural(self.files_checked, "file"),
            plural(self.problems, "problem"),
            plural(self.warnings.len(), "warning")
        )
    }
}

impl Report for CheckReport {
    fn document(&self) -> Document {
        let mut doc = Document::new();
        let verdict = if self.problems == 0 {
            "audit check: passed"
        } else {
            "audit check: FAILED"
        };
        doc.push(Block::Headline {
            text: verdict.to_string(),
            good: self.problems == 0,
        });
        doc.push(Block::Diagnostics(self.findings.clone()));
        if !self.notes.is_empty() {
            let lines: Vec<String> = self.notes.iter().map(|n| format!("note: {n}")).collect();
            doc.text(lines.join("\n"));
        }
        doc.text(self.summary_line());
        if let Some(b) = &self.baseline_written {
            doc.text(b.lines());
        }
        doc.table(self.data_table());
        doc
    }
}
