//! Where two sources of one edge meet, the convention mistake that
//! reconciles them ([`crate::analysis::mistakes`]): the two files of a diff
//! (the chain and each changed edge), and a second source of an edge in one
//! robot of `audit check` (an `audit.toml` group, or a file whose edges
//! close a loop): a disagreement with both values, not "two parents".

use crate::analysis::mistakes::{explain, MistakeTol};
use crate::diagnostic::{Code, Diagnostic, Severity};
use crate::frames::{path_text, Chain, Edge, FrameGraph};
use crate::geometry::Transform;
use crate::report::diff::{DiffToleranceJson, EdgeDiffJson, EdgeStatus};
use crate::report::mistakes::{entries, MistakeJson};

fn tol(t: &DiffToleranceJson) -> MistakeTol {
    MistakeTol {
        translation_mm: t.translation_mm,
        rotation_deg: t.rotation_deg,
    }
}

/// The mistakes of a diff: the chain first (when there is one), then each
/// changed edge (NEW's edge stored the other way round is compared
/// inverted, as the diff does).
pub(super) fn in_diff(
    old: &FrameGraph,
    new: &FrameGraph,
    chains: Option<(&Chain, &Chain)>,
    edges: &[EdgeDiffJson],
    t: &DiffToleranceJson,
) -> Vec<MistakeJson> {
    let tol = tol(t);
    let mut out = Vec::new();
    let mut chain = None;
    if let Some((co, cn)) = chains {
        let name = format!("{} -> {}", co.from, co.to);
        out = entries(
            &name,
            &explain(&co.transform, &cn.transform, &tol),
            "old",
            "new",
        );
        chain = Some(name);
    }
    for e in edges.iter().filter(|e| e.status == EdgeStatus::Changed) {
        let Some(o) = old.parent_edge(&e.child).filter(|o| o.parent == e.parent) else {
            continue;
        };
        let n = if e.reversed {
            new.parent_edge(&e.parent)
                .filter(|n| n.parent == e.child)
                .map(|n| n.transform.inverse())
        } else {
            new.parent_edge(&e.child)
                .filter(|n| n.parent == e.parent)
                .map(|n| n.transform)
        };
        let Some(n) = n else { continue };
        let edge = format!("{} -> {}", e.parent, e.child);
        if chain.as_ref() != Some(&edge) {
            out.extend(entries(
                &edge,
                &explain(&o.transform, &n, &tol),
                "old",
                "new",
            ));
        }
    }
    out
}

fn values(t: &Transform) -> String {
    let d = t.translation();
    let q = t.quaternion_xyzw();
    format!(
        "t = [{:.6}, {:.6}, {:.6}] m, q = [{:.6}, {:.6}, {:.6}, {:.6}]",
        d.x, d.y, d.z, q[0], q[1], q[2], q[3]
    )
}

/// A second source of an edge already in `graph` (its two frames joined by
/// the files read before): `None` when they are not joined yet, or when the
/// two agree within `tol` and the edge is the same pair (the graph's own
/// duplicate rule then warns); otherwise `Some(None)` when they agree (a
/// redundant edge: not added) or `Some(Some(finding))`, an error naming
/// both values, how far apart they are and the mistake that reconciles them.
pub(super) fn second_source(
    graph: &FrameGraph,
    edge: &Edge,
    tol: &MistakeTol,
) -> Option<Option<Diagnostic>> {
    if !(graph.contains(&edge.parent) && graph.contains(&edge.child)) {
        return None;
    }
    let tree = graph.transform(&edge.parent, &edge.child).ok()?;
    let e = explain(&tree.transform, &edge.transform, tol);
    let direct = tree.steps.len() == 1;
    if e.agree {
        return if direct { None } else { Some(None) };
    }
    let first = tree
        .steps
        .first()
        .map(|s| s.edge.provenance.location.to_string())
        .unwrap_or_default();
    let mut message = format!(
        "edge {} -> {} has two sources that disagree by {:.3} mm, {:.4} deg{}: this file ({}) gives {}; the tree {} ({first}) gives {}",
        edge.parent,
        edge.child,
        e.translation_mm,
        e.rotation_deg,
        if direct { "" } else { " (the edge closes a cycle)" },
        edge.provenance.location,
        values(&edge.transform),
        path_text(&tree),
        values(&tree.transform),
    );
    match e.sentence("the tree", "this file") {
        Some(s) => message.push_str(&format!("; {s}")),
        None => message.push_str("; no usual convention mistake reconciles them"),
    }
    Some(Some(
        Diagnostic::new(Code::RedundantEdgeDisagrees, message)
            .with_severity(Severity::Error)
            // At the numbers that disagree: the translation's when it is off.
            .at(&edge
                .provenance
                .value_location(e.translation_mm > tol.translation_mm)),
    ))
}
