//! The check report (`audit check`): every finding as a diagnostic, and the
//! counts; JSON in `docs/schemas/check.schema.json`.

use super::SCHEMA_VERSION;
use crate::diagnostic::{Diagnostic, Severity};
use crate::render::{Block, Document, Report};
use serde::Serialize;

/// What `audit check` found.
#[derive(Debug, Clone, Serialize)]
pub struct CheckReport {
    /// Always 1.
    pub schema_version: u32,
    /// Files read.
    pub files_checked: usize,
    /// Findings of severity `error` (the gate fails when non-zero).
    pub problems: usize,
    /// Findings of severity `warning`.
    pub warnings: usize,
    /// Every finding, in the order found.
    pub findings: Vec<Diagnostic>,
}

impl CheckReport {
    /// The report over `findings` for `files_checked` files.
    pub fn new(files_checked: usize, findings: Vec<Diagnostic>) -> Self {
        let problems = findings
            .iter()
            .filter(|f| f.severity == Severity::Error)
            .count();
        CheckReport {
            schema_version: SCHEMA_VERSION,
            files_checked,
            problems,
            warnings: findings.len() - problems,
            findings,
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
            plural(self.warnings, "warning")
        )
    }
}

impl Report for CheckReport {
    fn document(&self) -> Document {
        let mut doc = Document::new();
        doc.push(Block::Diagnostics(self.findings.clone()));
        doc.text(self.summary_line());
        doc
    }
}
