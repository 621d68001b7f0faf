//! `audit degeneracy` in 3D (`--format mcap`). Frames: [`SCAN_FRAME`], the
//! point file's own, and [`BODY_FRAME`], the report's (`--shift`,
//! `--rotate-rpy`: its pose in the scan frame; the identity without them);
//! for a pair, [`TARGET_FRAME`], the target file's, with the scan (source)
//! frame at the initial guess in it. Then:
//!
//! - `points` (scan frame): the points `H` and `M` were assembled from (a
//!   pair's: the matched source points), each with `weakest_share`, its share
//!   of the weakest point-displacement direction (`w_i (a_i . v)^2 / v^T H v`,
//!   adding up to 1 over every point; 0 for every point when no point
//!   constrains that direction); `target_points` (target frame) for a pair;
//! - `degenerate/K` (body frame), one per basis twist of the degenerate
//!   subspace: a rotation's axis as a line through the cloud (centred on the
//!   axis point nearest the centroid, [`DEGENERATE_HALF_LENGTH_FACTOR`] RMS
//!   radii each way), labelled with its pitch and eigenvalue; a translation
//!   as an arrow from the centroid along its direction;
//! - `axes/scan`, `axes/body`: the two frames' axes.
//!
//! The numbers are the JSON report's: the entities' metadata carries them at
//! full precision, and the scene's metadata the point-displacement
//! eigenvalues.

use super::detector::DegeneracyReport;
use crate::analysis::Family;
use crate::document::numbers::sci;
use crate::document::scene::{
    axis_length, axis_segment, Entity, Paint, PointCloud, SceneTransform, Shape,
};
use crate::document::Scene;

/// The point file's frame in the scene.
pub const SCAN_FRAME: &str = "scan";
/// The report's frame (`--shift`, `--rotate-rpy`) in the scene.
pub const BODY_FRAME: &str = "body";
/// A pair's target frame in the scene.
pub const TARGET_FRAME: &str = "target";

/// Each half of a drawn degenerate axis, in RMS radii of the cloud.
pub const DEGENERATE_HALF_LENGTH_FACTOR: f64 = 2.0;

fn exact(x: f64) -> String {
    format!("{x:?}")
}

fn exact_list(v: &[f64]) -> String {
    format!(
        "[{}]",
        v.iter().map(|&x| exact(x)).collect::<Vec<_>>().join(", ")
    )
}

impl DegeneracyReport {
    /// The scan or pair as a 3D scene (see the module docs).
    pub fn scene(&self) -> Scene {
        let sd = &self.scene;
        let mut s = Scene::default();
        if let Some((d, q)) = sd.guess {
            s.transforms.push(SceneTransform {
                parent: TARGET_FRAME.into(),
                child: SCAN_FRAME.into(),
                translation_m: d,
                rotation_xyzw: q,
            });
        }
        s.transforms.push(SceneTransform {
            parent: SCAN_FRAME.into(),
            child: BODY_FRAME.into(),
            translation_m: self.frame.translation_m,
            rotation_xyzw: sd.frame_xyzw,
        });
        s.metadata.extend([
            ("report".to_string(), "degeneracy".to_string()),
            ("points".to_string(), self.points.to_string()),
            ("weakest_eigenvalue".to_string(), exact(sd.weakest.1)),
            ("weakest_twist".to_string(), exact_list(&sd.weakest.0)),
        ]);
        if let Some(e) = self
            .families
            .iter()
            .find(|f| f.family == Family::PointDisplacement)
            .and_then(|f| f.eigenvalues)
        {
            s.metadata
                .push(("point_displacement_eigenvalues".into(), exact_list(&e)));
        }
        let extent = sd.rms_radius_m;
        for (k, sub) in self.degenerate_subspace.iter().enumerate() {
            s.entities.push(self.degenerate_entity(k, sub, extent));
        }
        let axis = axis_length(extent);
        s.entities.push(Entity::axes(SCAN_FRAME, axis));
        s.entities.push(Entity::axes(BODY_FRAME, axis));
        if let Some(c) = &sd.cloud {
            s.metadata.extend([
                ("cloud_points_drawn".to_string(), c.points_m.len().to_string()),
                ("cloud_stride".to_string(), c.stride.to_string()),
                (
                    "weakest_share".to_string(),
                    match c.shares {
                        Some(_) => "each point's share of v^T H v along the weakest point-displacement direction (sum 1 over every point)".to_string(),
                        None => "0 for every point: no point constrains the weakest direction".to_string(),
                    },
                ),
            ]);
            let share = c
                .shares
                .clone()
                .unwrap_or_else(|| vec![0.0; c.points_m.len()]);
            s.clouds.push(cloud(
                "points",
                SCAN_FRAME,
                &c.points_m,
                vec![("weakest_share".into(), share)],
            ));
            if let Some(t) = &c.target_m {
                s.clouds
                    .push(cloud("target_points", TARGET_FRAME, t, Vec::new()));
            }
        }
        s
    }

    /// `degenerate/K`: basis twist `k` of the degenerate subspace as a
    /// screw axis or a translation arrow, through the cloud.
    fn degenerate_entity(
        &self,
        k: usize,
        sub: &super::detector::SubspaceJson,
        extent: f64,
    ) -> Entity {
        let c = self.scene.centroid_m;
        let half = DEGENERATE_HALF_LENGTH_FACTOR * extent.max(f64::MIN_POSITIVE);
        let sc = &sub.screw;
        let mut e = Entity::new(format!("degenerate/{k}"), BODY_FRAME);
        e.fact("kind", sc.kind)
            .fact("eigenvalue", exact(sub.eigenvalue))
            .fact("twist", exact_list(&sub.twist));
        match (sc.axis, sc.axis_point_m, sc.direction) {
            (Some(axis), Some(point), _) => {
                let [a, b] = axis_segment(point, axis, c, half);
                let pitch = sc.pitch_m_per_rad.unwrap_or(0.0);
                e.shapes.push(Shape::Line {
                    points: vec![a, b],
                    paint: Paint::Degenerate,
                });
                e.shapes.push(Shape::Text {
                    at: b,
                    text: format!(
                        "degenerate screw {k}: pitch {} m/rad, eigenvalue {}",
                        sci(pitch, 3),
                        sci(sub.eigenvalue, 3)
                    ),
                    paint: Paint::Degenerate,
                });
                e.fact("axis", exact_list(&axis))
                    .fact("axis_point_m", exact_list(&point))
                    .fact("pitch_m_per_rad", exact(pitch));
            }
            (_, _, Some(dir)) => {
                let along = dir.map(|x| half * x);
                let tip: [f64; 3] = std::array::from_fn(|i| c[i] + along[i]);
                e.shapes.push(Shape::Arrow {
                    from: c,
                    along,
                    paint: Paint::Degenerate,
                });
                e.shapes.push(Shape::Text {
                    at: tip,
                    text: format!(
                        "degenerate translation {k}: eigenvalue {}",
                        sci(sub.eigenvalue, 3)
                    ),
                    paint: Paint::Degenerate,
                });
                e.fact("direction", exact_list(&dir));
            }
            _ => {}
        }
        e
    }
}

/// A cloud about its points' mean.
fn cloud(
    name: &str,
    frame: &str,
    points: &[[f64; 3]],
    fields: Vec<(String, Vec<f64>)>,
) -> PointCloud {
    let n = points.len().max(1) as f64;
    let origin = std::array::from_fn(|k| points.iter().map(|p| p[k]).sum::<f64>() / n);
    PointCloud {
        name: name.into(),
        frame: frame.into(),
        origin_m: origin,
        points_m: points.to_vec(),
        fields,
    }
}
