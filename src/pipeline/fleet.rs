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
use std::collections::HashMap;
use std::path::Path;

use super::walk::Found;

/// `Member::file` of a location kept in `Fleet::elsewhere` (this bit set,
/// its index in the others).
const ELSEWHERE: u32 = 1 << 31;

/// One vehicle's calibration of one pair, in 72 bytes and no allocation
/// (issue 29: 100,000 vehicles): the pair an index in the fleet's pairs, the
/// place the walk's file index and the line and column (0: none), the
/// transform as stored (rebuilt, the same bits, where the findings need it).
struct Member {
    quaternion_xyzw: [f64; 4],
    translation_m: [f64; 3],
    pair: u32,
    file: u32,
    line: u32,
    column: u32,
}

/// Every checked pair of every vehicle, in the walk's order.
#[derive(Default)]
pub(super) struct Fleet {
    /// The frame pairs, each once, in the order first checked.
    pairs: Vec<(String, String)>,
    index: HashMap<(String, String), u32>,
    members: Vec<Member>,
    /// The locations no walk index names (a manifest's robot's files, an
    /// included file's line).
    elsewhere: Vec<Location>,
}

fn transform(q: [f64; 4], t: [f64; 3]) -> Option<Transform> {
    Transform::from_quaternion(q, QuatOrder::Xyzw, t, &mut Vec::new()).ok()
}

impl Fleet {
    /// A fleet with room for `n` members (one per walked file: one pair each).
    pub(super) fn with_capacity(n: usize) -> Fleet {
        Fleet {
            members: Vec::with_capacity(n),
            ..Fleet::default()
        }
    }

    /// The member a checked pair of `file` (the walk's `walk`-th file, when
    /// it is one) gives, when its stored transform reads back.
    pub(super) fn add(
        &mut self,
        walk: Option<usize>,
        file: &Path,
        at: Option<&Location>,
        p: &BaselinePair,
    ) {
        let t = &p.transform;
        if transform(t.quaternion_xyzw, t.translation_m).is_none() {
            return;
        }
        let key = (t.parent.clone(), t.child.clone());
        let pair = match self.index.get(&key) {
            Some(&k) => k,
            None => {
                let k = self.pairs.len() as u32;
                self.pairs.push(key.clone());
                self.index.insert(key, k);
                k
            }
        };
        // 0 stands for no line (a line is 1-based): a line 0 is kept elsewhere.
        let small = |x: Option<usize>| match x {
            None => Some(0),
            Some(0) => None,
            Some(v) => u32::try_from(v).ok(),
        };
        let own = at.is_none_or(|a| a.file.is_none());
        let compact = match (walk, at) {
            (Some(w), _) if own && w < ELSEWHERE as usize => {
                let (line, column) =
                    at.map_or((Some(0), Some(0)), |a| (small(a.line), small(a.column)));
                line.zip(column).map(|(l, c)| (w as u32, l, c))
            }
            _ => None,
        };
        let (file, line, column) = compact.unwrap_or_else(|| {
            // The pair's line (its last edge) is kept without the file: add it.
            let mut at = at.cloned().unwrap_or_default();
            if at.file.is_none() {
                at.file = Some(file.into());
            }
            self.elsewhere.push(at);
            (ELSEWHERE | (self.elsewhere.len() - 1) as u32, 0, 0)
        });
        self.members.push(Member {
            quaternion_xyzw: t.quaternion_xyzw,
            translation_m: t.translation_m,
            pair,
            file,
            line,
            column,
        });
    }

    /// Where `m` was read: a walked file's line, or one of the others.
    fn location(&self, m: &Member, files: &[Found]) -> Location {
        if m.file & ELSEWHERE != 0 {
            return self.elsewhere[(m.file & !ELSEWHERE) as usize].clone();
        }
        let some = |x: u32| (x != 0).then_some(x as usize);
        Location {
            file: Some(files[m.file as usize].path.as_path().into()),
            line: some(m.line),
            column: some(m.column),
        }
    }
}

fn vec3(v: [f64; 3], decimals: usize) -> String {
    format!(
        "[{:.decimals$}, {:.decimals$}, {:.decimals$}]",
        v[0], v[1], v[2]
    )
}

/// The findings: per frame pair with two calibrations or more, each one
/// beyond `tol` from the pair's fleet mean; `files` the walk's files the
/// members name.
pub(super) fn findings(fleet: &Fleet, tol: &DriftTolerances, files: &[Found]) -> Vec<Diagnostic> {
    // The members of each pair, in the walk's order (one pass, not one per pair).
    let mut groups: Vec<Vec<&Member>> = (0..fleet.pairs.len()).map(|_| Vec::new()).collect();
    for m in &fleet.members {
        groups[m.pair as usize].push(m);
    }
    let mtol = MistakeTol {
        translation_mm: tol.translation_m * 1e3,
        rotation_deg: tol.rotation_deg,
    };
    let mut out = Vec::new();
    for ((from, to), group) in fleet.pairs.iter().zip(groups) {
        if group.len() < 2 {
            continue;
        }
        // Each member's transform read back again where it is needed (the
        // same bits: it read back when added) rather than held.
        let at = |i: usize| {
            let m: &Member = group[i];
            transform(m.quaternion_xyzw, m.translation_m).unwrap_or_default()
        };
        let Ok((mean, _)) = spread::mean_by(group.len(), at) else {
            continue;
        };
        // The outliers as `audit spread` finds them; each deviation is
        // computed again where it is needed rather than held (112 bytes a
        // vehicle).
        let (rf, tf): (Vec<[f64; 3]>, Vec<[f64; 3]>) = (0..group.len())
            .map(|i| {
                let d = spread::deviation(&mean, &at(i));
                (d.rotation_from_deg, d.translation_from_mm)
            })
            .unzip();
        let flagged = spread::outliers(&rf, &tf).flagged;
        drop((rf, tf));
        for (i, m) in group.iter().enumerate() {
            let t = at(i);
            let d = spread::deviation(&mean, &t);
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
            if flagged.binary_search(&i).is_ok() {
                msg.push_str("; an outlier by the robust rule");
            }
            if let Some(why) =
                explain(&mean, &t, &mtol).sentence("the fleet mean", "this calibration")
            {
                msg.push_str(&format!("; {why}"));
            }
            out.push(Diagnostic::new(Code::FleetDeviation, msg).at(&fleet.location(m, files)));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_member_is_small() {
        assert!(std::mem::size_of::<Member>() <= 80);
    }
}
