//! The data tables of the reports that keep theirs here: the one tidy table
//! each report gives `--format csv` (`crate::render`'s CSV module states the
//! rules and lists every command's layout). Columns are the JSON's keys, a
//! vector split into one column per component with the component before
//! the unit ([`Columns::vector`]: `translation_m` gives `translation_x_m`);
//! where a nested key alone would be ambiguous, its parent's name is
//! prefixed (`screw_kind`), as the other reports' JSON already names it.
//! Values per characteristic length `l` are columns suffixed `_l{l}` (the
//! survey's `band_l1`), `l` as `short` prints it (`1`, `0.5`, `2.85`).
//! The survey's and the spread's tables are in their own modules.

use super::check::CheckReport;
use super::detector::{
    DegeneracyReport, FamilyComparison, FamilyEigen, IntervalJson, SimulateReport, SweepFamilyJson,
    SweepReport, ThresholdReport, TunnelFrameJson, TunnelReport,
};
use super::diff::{DiffReport, EdgeDiffJson};
use super::rig::RigReport;
use crate::diagnostic::Diagnostic;
use crate::document::numbers::short;
use crate::document::{Columns, Table};

/// Components of a 3-vector.
const XYZ: [&str; 3] = ["x", "y", "z"];
/// Components of a quaternion, as `quaternion_xyzw` orders them.
const XYZW: [&str; 4] = ["x", "y", "z", "w"];
/// Components of a URDF `rpy`.
const RPY: [&str; 3] = ["roll", "pitch", "yaw"];
/// The six eigenvalues, ascending, numbered as `audit run`'s CSV numbers
/// them (`lambda1` .. `lambda6`).
const EIGEN: [&str; 6] = ["1", "2", "3", "4", "5", "6"];
/// Twist axes `[omega; t]` of a footprint, as `audit run`'s CSV names them.
const TWIST: [&str; 6] = ["rx", "ry", "rz", "tx", "ty", "tz"];
/// A band's two edges `[s_min^2, s_max^2]`.
const BAND: [&str; 2] = ["low", "high"];

/// `_l{l}` of a characteristic length.
fn at_ell(ell: f64) -> String {
    format!("_l{}", short(ell))
}

impl RigReport {
    /// One row for the chain `from -> to`.
    pub(super) fn data_table(&self) -> Table {
        let mut c = Columns::<RigReport>::new()
            .text("from", |r| r.from.clone())
            .text("to", |r| r.to.clone())
            .vector("translation_m", XYZ, |r| Some(r.transform.translation_m))
            .vector("quaternion_xyzw", XYZW, |r| {
                Some(r.transform.quaternion_xyzw)
            })
            .vector("rpy_rad", RPY, |r| Some(r.transform.rpy_rad))
            .num("lever_arm_m", |r| r.lever_arm_m)
            .num("lever_arm_uncertainty_m", |r| r.lever_arm_uncertainty_m)
            .num("angle_deg", |r| r.rotation.angle_deg)
            .num("angle_uncertainty_rad", |r| {
                r.rotation.angle_uncertainty_rad
            })
            .vector("axis", XYZ, |r| r.rotation.axis)
            .text("screw_kind", |r| r.screw.kind.name().into())
            .num("translation_along_axis_m", |r| {
                r.screw.translation_along_axis_m
            })
            .num("translation_along_axis_uncertainty_m", |r| {
                r.screw.translation_along_axis_uncertainty_m
            })
            .num("pitch_m_per_rad", |r| r.screw.pitch_m_per_rad)
            .num("pitch_uncertainty_m_per_rad", |r| {
                r.screw.pitch_uncertainty_m_per_rad
            })
            .vector("axis_point_m", XYZ, |r| r.screw.axis_point_m)
            .text("pitch_verdict", |r| {
                r.screw.pitch_verdict.map_or("", |v| v.name()).into()
            })
            .num("deciding_uncertainty_m", |r| r.screw.deciding_uncertainty_m)
            .text("uncertainty_source", |r| r.uncertainty.source.name().into())
            .num("sigma_max", |r| r.adjoint.singular_values[0]);
        for (k, cert) in self.certificate.iter().enumerate() {
            let l = at_ell(cert.ell_m);
            c = c
                .num(&format!("delta_eff{l}"), move |r| {
                    r.certificate[k].delta_eff
                })
                .vector(&format!("band{l}"), BAND, move |r| {
                    Some(r.certificate[k].band)
                })
                .vector(&format!("band_uncertainty{l}"), BAND, move |r| {
                    Some(r.certificate[k].band_uncertainty)
                });
        }
        c = c
            .flag("adapted_metric_exists", |r| r.adapted_metric.exists)
            .num("invariance_residual", |r| {
                r.adapted_metric.invariance_residual
            });
        for (k, d) in self.detectors.iter().enumerate() {
            c = c.flag(&format!("invariant_on_rig_{}", d.family.name()), move |r| {
                r.detectors[k].invariant_on_rig
            });
        }
        if let Some(kc) = &self.kappa_check {
            c = c
                .num("kappa", |r| r.kappa_check.as_ref().map(|k| k.kappa))
                .num("lambda", |r| r.kappa_check.as_ref().map(|k| k.lambda))
                .num("ratio", |r| r.kappa_check.as_ref().map(|k| k.ratio));
            for (k, cert) in self.certificate.iter().enumerate().take(kc.certified.len()) {
                c = c.flag(&format!("certified{}", at_ell(cert.ell_m)), move |r| {
                    r.kappa_check.as_ref().map(|x| x.certified[k])
                });
            }
        }
        c.table([self])
    }
}

impl CheckReport {
    /// One row per finding, as the JSON's `findings[i]` (`file` empty and
    /// `line` empty when unknown).
    pub(super) fn data_table(&self) -> Table {
        Columns::<Diagnostic>::new()
            .text("severity", |d| d.severity.name().into())
            .text("code", |d| d.code.name().into())
            .text("file", |d| {
                d.location
                    .file
                    .as_ref()
                    .map(|f| f.to_string_lossy().replace('\\', "/"))
                    .unwrap_or_default()
            })
            .count("line", |d| d.location.line)
            .count("column", |d| d.location.column)
            .text("message", |d| d.message.clone())
            .text("help", |d| d.help.clone().unwrap_or_default())
            .table(&self.findings)
    }
}

impl DiffReport {
    /// One row per edge of either file, as the JSON's `edges[i]` (the
    /// chain's own comparison is in the JSON's `chain`).
    pub(super) fn data_table(&self) -> Table {
        Columns::<EdgeDiffJson>::new()
            .text("parent", |e| e.parent.clone())
            .text("child", |e| e.child.clone())
            .text("status", |e| e.status.name().into())
            .flag("reversed", |e| e.reversed)
            .vector("translation_delta_m", XYZ, |e| e.translation_delta_m)
            .num("translation_change_mm", |e| e.translation_change_mm)
            .num("rotation_change_deg", |e| e.rotation_change_deg)
            .text("old_place", |e| e.old_place.clone().unwrap_or_default())
            .text("new_place", |e| e.new_place.clone().unwrap_or_default())
            .flag("exceeds", |e| e.exceeds)
            .flag("on_chain", |e| e.on_chain)
            .table(&self.edges)
    }
}

impl DegeneracyReport {
    /// One row per family, as the JSON's `families[i]`: its six eigenvalues
    /// (ascending) as `eigenvalues_1` .. `eigenvalues_6`.
    pub(super) fn data_table(&self) -> Table {
        Columns::<FamilyEigen>::new()
            .text("family", |f| f.family.name().into())
            .num("ell_m", |f| f.ell_m)
            .vector("eigenvalues", EIGEN, |f| f.eigenvalues)
            .num("threshold", |f| f.threshold)
            .num("threshold_per_point", |f| f.threshold_per_point)
            .count("degenerate_count", |f| f.degenerate_count)
            .text("error", |f| f.error.clone().unwrap_or_default())
            .table(&self.families)
    }
}

impl SimulateReport {
    /// One row per family, as the JSON's `families[i]`: frame A's values
    /// (`from`) and frame B's (`to`) side by side.
    pub(super) fn data_table(&self) -> Table {
        Columns::<FamilyComparison>::new()
            .text("family", |f| f.family.name().into())
            .num("ell_from_m", |f| f.ell_m[0])
            .num("ell_to_m", |f| f.ell_m[1])
            .num("threshold", |f| f.threshold)
            .vector("eigenvalues_from", EIGEN, |f| Some(f.eigenvalues.from))
            .vector("eigenvalues_to", EIGEN, |f| Some(f.eigenvalues.to))
            .count("degenerate_count_from", |f| f.degenerate_count.from)
            .count("degenerate_count_to", |f| f.degenerate_count.to)
            .flag("decision_changes", |f| f.decision_changes)
            .flags("footprint_from", TWIST, |f| Some(f.footprint.from))
            .flags("footprint_to", TWIST, |f| Some(f.footprint.to))
            .flag("footprint_changes", |f| f.footprint_changes)
            .num("subspace_angle_deg", |f| f.subspace_angle_deg)
            .num("correction_difference_rotation_rad", |f| {
                f.correction_difference.rotation_rad
            })
            .num("correction_difference_translation_m", |f| {
                f.correction_difference.translation_m
            })
            .num("max_eigenvalue_rel_change", |f| f.max_eigenvalue_rel_change)
            .table(&self.families)
    }
}

impl SweepReport {
    /// One row per family, as the JSON's `families[i]`; the changes by arm
    /// as `decision_changes_by_arm_{arm}` (the arm's name, `_` for spaces).
    pub(super) fn data_table(&self) -> Table {
        let mut c = Columns::<SweepFamilyJson>::new()
            .text("family", |f| f.family.name().into())
            .num("ell_m", |f| f.ell_m)
            .num("threshold", |f| f.threshold)
            .count("degenerate_count", |f| f.degenerate_count)
            .count("decision_changes", |f| f.decision_changes)
            .num("decision_change_rate", |f| f.decision_change_rate)
            .vector("decision_change_wilson95", BAND, |f| {
                Some(f.decision_change_wilson95)
            })
            .count("count_changes", |f| f.count_changes)
            .num("count_change_rate", |f| f.count_change_rate)
            .vector("count_change_wilson95", BAND, |f| {
                Some(f.count_change_wilson95)
            });
        for (k, arm) in self.arms.iter().enumerate() {
            // The arm's name as a column: `pure rotation` -> `pure_rotation`.
            let arm = arm.replace([' ', '-'], "_");
            c = c.count(&format!("decision_changes_by_arm_{arm}"), move |f| {
                f.decision_changes_by_arm[k]
            });
        }
        c.num("max_eigenvalue_rel_change", |f| f.max_eigenvalue_rel_change)
            .count("rig_degenerate_count", |f| {
                f.rig.as_ref().map(|r| r.degenerate_count)
            })
            .flag("rig_decision_changes", |f| {
                f.rig.as_ref().map(|r| r.decision_changes)
            })
            .table(&self.families)
    }
}

impl TunnelReport {
    /// One row per frame (`on_axis`, `shifted`), as the JSON's objects of
    /// those names; the rotational twists stay in the JSON (their number
    /// varies).
    pub(super) fn data_table(&self) -> Table {
        let rows = [("on_axis", &self.on_axis), ("shifted", &self.shifted)];
        Columns::<(&str, &TunnelFrameJson)>::new()
            .text("frame", |r| r.0.into())
            .vector("origin_m", XYZ, |r| Some(r.1.origin_m))
            .vector("eigenvalues", EIGEN, |r| Some(r.1.eigenvalues))
            .count("nullity", |r| r.1.nullity)
            .flags("footprint", TWIST, |r| Some(r.1.footprint))
            .flag("footprint_frame_dependent", |r| {
                r.1.footprint_frame_dependent
            })
            .flag("contains_pure_rotation", |r| r.1.contains_pure_rotation)
            .table(&rows)
    }
}

/// An interval's columns `{name}_empty`, `{name}_lo`, `{name}_hi`.
fn interval<'a, T: 'a>(
    c: Columns<'a, T>,
    name: &str,
    g: fn(&T) -> &IntervalJson,
) -> Columns<'a, T> {
    c.flag(&format!("{name}_empty"), move |r| g(r).empty)
        .num(&format!("{name}_lo"), move |r| g(r).lo)
        .num(&format!("{name}_hi"), move |r| g(r).hi)
}

/// A configuration's row of the calibrate-threshold table.
type ConfigRow<'r> = (
    &'r super::detector::FamilyCalibration,
    &'r super::detector::ConfigJson,
);

impl ThresholdReport {
    /// One row per (family, configuration), as the JSON's
    /// `families[i].configurations[j]`: its interval `lo < tau <= hi`, the
    /// same per scene (`corridor_lo`, ...), and the family's intersection.
    pub(super) fn data_table(&self) -> Table {
        let rows: Vec<ConfigRow> = self
            .families
            .iter()
            .flat_map(|f| f.configurations.iter().map(move |c| (f, c)))
            .collect();
        let mut c = Columns::<ConfigRow>::new()
            .text("family", |r| r.0.family.name().into())
            .num("noise_m", |r| r.1.noise_m)
            .num("voxel_m", |r| r.1.voxel_m)
            .count("scenes_reproduced", |r| r.1.scenes_reproduced);
        c = interval(c, "interval", |r| &r.1.interval);
        c = interval(c, "corridor", |r| &r.1.per_scene.corridor);
        c = interval(c, "tunnel", |r| &r.1.per_scene.tunnel);
        c = interval(c, "corner", |r| &r.1.per_scene.corner);
        c = interval(c, "intersection", |r| &r.0.intersection);
        c.num("gap_decades", |r| r.0.gap_decades).table(&rows)
    }
}
