//! Where two sources of one edge meet, the convention mistake that
//! reconciles them ([`crate::analysis::mistakes`]): the two files of a diff
//! (the chain and each changed edge).

use crate::analysis::mistakes::{explain, MistakeTol};
use crate::frames::{Chain, FrameGraph};
use crate::report::diff::{DiffToleranceJson, EdgeDiffJson, EdgeStatus};
use crate::report::mistakes::{entries, MistakeJson};

fn tol(t: &DiffToleranceJson) -> MistakeTol {
    MistakeTol {
        translation_mm: t.translation_mm,
        rotation_deg: t.rotation_deg,
    }
}

/// The mistakes of a diff: the chain first, then each changed edge (NEW's
/// edge stored the other way round is compared inverted, as the diff does).
pub(super) fn in_diff(
    old: &FrameGraph,
    new: &FrameGraph,
    co: &Chain,
    cn: &Chain,
    edges: &[EdgeDiffJson],
    t: &DiffToleranceJson,
) -> Vec<MistakeJson> {
    let tol = tol(t);
    let chain = format!("{} -> {}", co.from, co.to);
    let mut out = entries(
        &chain,
        &explain(&co.transform, &cn.transform, &tol),
        "old",
        "new",
    );
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
        if edge != chain {
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
