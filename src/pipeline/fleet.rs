//! `audit check --fleet-tolerance LENGTH,ANGLE`: the checked frame pairs of many
//! robots (one calibration file per vehicle) compared with their fleet mean
//! ([`crate::analysis::spread`]: the chordal rotation mean, the arithmetic
//! translation mean); a finding per vehicle whose pair deviates from it
//! beyond the tolerance, naming the convention mistake when one reconciles
//! it with the mean.

use crate::analysis::mistakes::{explain, MistakeTol};
use crate::analysis::spread;
use crate::baseline::{BaselinePair, DriftTolerances};
use crate::diagnostic::{Code, Diagnostic, Location};
use crate::geometry::{QuatOrder, Transform};
use std::path::Path;

/// One vehicle's calibration of one pair.
pub(super) struct Member {
    from: String,
    to: String,
    at: Location,
    transform: Transform,
}

/// The member a checked pair gives, when its stored transform reads back.
pub(super) fn member(file: &Path, at: Option<&Location>, p: &BaselinePair) -> Option<Member> {
    let t = &p.transform;
    let transform = Transform::from_quaternion(
        t.quaternion_xyzw,
        QuatOrder::Xyzw,
        t.translation_m,
        &mut Vec::new(),
    )
    .ok()?;
    // The pair's line (its last edge) is kept without the file: add it.
    let mut at = at.cloned().unwrap_or_default();
    if at.file.is_none() {
        at.file = Some(file.into());
    }
    Some(Member {
        from: t.parent.clone(),
        to: t.child.clone(),
        at,
        transform,
    })
}

fn vec3(v: [f64; 3], decimals: usize) -> String {
    format!(
        "[{:.decimals$}, {:.decimals$}, {:.decimals$}]",
        v[0], v[1], v[2]
    )
}

/// The findings: per frame pair with two calibrations or more, each one
/// beyond `tol` from the pair's fleet mean.
pub(super) fn findings(members: &[Member], tol: &DriftTolerances) -> Vec<Diagnostic> {
    let mut pairs: Vec<(&str, &str)> = Vec::new();
    for m in members {
        if !pairs.contains(&(m.from.as_str(), m.to.as_str())) {
            pairs.push((&m.from, &m.to));
        }
    }
    let mtol = MistakeTol {
        translation_mm: tol.translation_m * 1e3,
        rotation_deg: tol.rotation_deg,
    };
    let mut out = Vec::new();
    for (from, to) in pairs {
        let group: Vec<&Member> = members
            .iter()
            .filter(|m| m.from == from && m.to == to)
            .collect();
        if group.len() < 2 {
            continue;
        }
        let ts: Vec<Transform> = group.iter().map(|m| m.transform).collect();
        let Ok(s) = spread::spread(&ts) else { continue };
        for (i, (m, d)) in group.iter().zip(&s.deviations).enumerate() {
            if d.distance_mm <= mtol.translation_mm && d.angle_deg <= mtol.rotation_deg {
                continue;
            }
            let mut msg = format!(
                "{from} -> {to} deviates from the fleet mean of {} calibrations by {:.3} mm, {:.4} deg (tolerance {} mm, {} deg): translation {} mm, rotation {} deg (from-frame axes)",
                group.len(),
                d.distance_mm,
                d.angle_deg,
                mtol.translation_mm,
                mtol.rotation_deg,
                vec3(d.translation_from_mm, 3),
                vec3(d.rotation_from_deg, 4),
            );
            if s.outliers.flagged.contains(&i) {
                msg.push_str("; an outlier by the robust rule");
            }
            if let Some(why) =
                explain(&s.mean, &m.transform, &mtol).sentence("the fleet mean", "this calibration")
            {
                msg.push_str(&format!("; {why}"));
            }
            out.push(Diagnostic::new(Code::FleetDeviation, msg).at(&m.at));
        }
    }
    out
}
