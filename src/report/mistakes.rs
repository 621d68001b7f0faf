//! The convention mistakes named in a report (`audit diff`, `audit check`):
//! one entry per mistake that reconciles two sources of one edge or chain
//! (the candidates and the rule: [`crate::analysis::mistakes`]).

use crate::analysis::mistakes::{Direction, Explanation};
use serde::Serialize;

/// The lines a text report prints: per edge, each mistake once (a mistake
/// that is its own reverse, such as `inverse`, is found both ways), with
/// "ambiguous" when several fit.
pub fn lines(entries: &[MistakeJson]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut edges: Vec<&str> = entries.iter().map(|m| m.edge.as_str()).collect();
    edges.dedup();
    for edge in edges {
        let mut seen: Vec<&str> = Vec::new();
        let mut said: Vec<&str> = Vec::new();
        for m in entries.iter().filter(|m| m.edge == edge) {
            if !seen.contains(&m.mistake) {
                seen.push(m.mistake);
                said.push(&m.sentence);
            }
        }
        let ambiguous = if said.len() > 1 { "ambiguous: " } else { "" };
        out.push(format!("{edge}: {ambiguous}{}", said.join("; or ")));
    }
    out
}

/// `mistakes[i]`: one mistake that reconciles two sources.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct MistakeJson {
    /// What the two sources give: `from -> to` (the chain) or `parent -> child`.
    pub edge: String,
    /// The candidate's name (`inverse`, `rotation_transposed`, ...).
    pub mistake: &'static str,
    /// Which source is the other misread: `second_from_first` (in a diff the
    /// new file read from the old) or `first_from_second`.
    pub direction: Direction,
    /// Translation residual after the mistake is undone (mm).
    pub residual_mm: f64,
    /// Rotation residual (deg).
    pub residual_deg: f64,
    /// The sentence ("new equals old inverted (parent and child swapped;
    /// residual 0.019 mm, 0.0010 deg)").
    pub sentence: String,
}

/// The entries of one explanation, for `edge`, the sources named `first`
/// and `second`.
pub fn entries(edge: &str, e: &Explanation, first: &str, second: &str) -> Vec<MistakeJson> {
    e.mistakes
        .iter()
        .map(|f| MistakeJson {
            edge: edge.to_string(),
            mistake: f.mistake,
            direction: f.direction,
            residual_mm: f.residual_mm,
            residual_deg: f.residual_deg,
            sentence: f.sentence(first, second),
        })
        .collect()
}
