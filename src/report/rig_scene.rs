//! The rig report in 3D (`--format mcap`): the frame tree's transforms (every
//! edge of the graph when the report carries the tree, else the one
//! `from -> to` transform), then in frame `from`:
//!
//! - `lever_arm`: an arrow from the origin of `from` to the origin of `to`
//!   (`d`), none when `||d||` is within `LENGTH_ZERO_TOL`; its label gives
//!   `||d||` and the certificate band at the first characteristic length;
//! - `screw_axis`: the line through the axis point along the rotation axis,
//!   centred on the axis point nearest the middle of the lever arm and
//!   [`SCREW_AXIS_HALF_LENGTH_FACTOR`] times the scene long each way, labelled
//!   with `h` and the pitch; a rotation-free transform has a label that says
//!   why there is no axis;
//! - `axes/FROM`, `axes/TO`: the two frames' axes (x red, y green, z blue).
//!
//! Each entity's metadata carries its numbers at full precision (as the JSON
//! report has them); the scene's metadata names the queried chain.

use super::rig::RigReport;
use crate::document::numbers::{degrees, metres, ratio, short};
use crate::document::scene::{axis_length, axis_segment, Entity, Paint, SceneTransform, Shape};
use crate::document::Scene;
use crate::geometry::ScrewKind;
use crate::tolerances::LENGTH_ZERO_TOL;

/// Each half of the drawn screw axis, in units of the scene's extent
/// (`max(||d||, 0.5 m)`): the axis reaches well past both frames.
pub const SCREW_AXIS_HALF_LENGTH_FACTOR: f64 = 1.5;

/// The smallest extent of a rig's scene (m), so that a sensor at the body
/// origin still gets an axis one can see.
const MIN_EXTENT_M: f64 = 0.5;

/// A number at full precision for entity metadata (`Debug`: the shortest
/// text that reads back as the same `f64`).
fn exact(x: f64) -> String {
    format!("{x:?}")
}

fn exact3(v: &[f64; 3]) -> String {
    format!("[{}]", v.map(exact).join(", "))
}

impl RigReport {
    /// The rig as a 3D scene (see the module docs).
    pub fn scene(&self) -> Scene {
        let mut s = match &self.tree {
            Some(t) => t.scene(),
            None => {
                let mut s = Scene::default();
                s.transforms.push(SceneTransform {
                    parent: self.from.clone(),
                    child: self.to.clone(),
                    translation_m: self.transform.translation_m,
                    rotation_xyzw: self.transform.quaternion_xyzw,
                });
                s.metadata.extend([
                    ("from".into(), self.from.clone()),
                    ("to".into(), self.to.clone()),
                ]);
                s
            }
        };
        s.metadata.push(("report".into(), "rig".into()));
        s.metadata
            .push(("lever_arm_m".into(), exact(self.lever_arm_m)));
        s.metadata
            .push(("screw_kind".into(), self.screw.kind.name().into()));
        // Foxglove draws the two frames' axes from the tree: these replace
        // any the tree drew, at the rig's own scale.
        s.entities.retain(|e| !e.id.starts_with("axes/"));
        let extent = self.lever_arm_m.max(MIN_EXTENT_M);
        s.entities.extend(self.lever_arm_entity());
        s.entities.push(self.screw_entity(extent));
        let axis = axis_length(self.lever_arm_m);
        s.entities.push(Entity::axes(&self.from, axis));
        if self.to != self.from {
            s.entities.push(Entity::axes(&self.to, axis));
        }
        s
    }

    /// `lever_arm`: the arrow to the origin of `to`, labelled; none for a
    /// zero lever arm.
    fn lever_arm_entity(&self) -> Option<Entity> {
        if self.lever_arm_m <= LENGTH_ZERO_TOL {
            return None;
        }
        let d = self.transform.translation_m;
        let mut e = Entity::new("lever_arm", &self.from);
        e.shapes.push(Shape::Arrow {
            from: [0.0; 3],
            along: d,
            paint: Paint::LeverArm,
        });
        let mut text = format!("lever arm {} m", metres(self.lever_arm_m));
        if let Some(c) = self.certificate.first() {
            text.push_str(&format!(
                "\nband at l = {} m: [{}, {}]",
                short(c.ell_m),
                ratio(c.band[0]),
                ratio(c.band[1])
            ));
            e.fact("band_ell_m", exact(c.ell_m)).fact(
                "band",
                format!("[{}, {}]", exact(c.band[0]), exact(c.band[1])),
            );
        }
        e.shapes.push(Shape::Text {
            at: d.map(|x| 0.5 * x),
            text,
            paint: Paint::LeverArm,
        });
        e.fact("lever_arm_m", exact(self.lever_arm_m))
            .fact("translation_m", exact3(&d));
        Some(e)
    }

    /// `screw_axis`: the axis line and its label, or the label alone when
    /// the transform has no rotation.
    fn screw_entity(&self, extent: f64) -> Entity {
        let sc = &self.screw;
        let mut e = Entity::new("screw_axis", &self.from);
        e.fact("kind", sc.kind.name());
        let (axis, point) = match (self.rotation.axis, sc.axis_point_m) {
            (Some(a), Some(q)) if matches!(sc.kind, ScrewKind::ZeroPitch | ScrewKind::General) => {
                (a, q)
            }
            _ => {
                let why = match sc.kind {
                    ScrewKind::Identity => "identity: no screw axis",
                    _ => "no rotation (pure translation): no screw axis",
                };
                e.shapes.push(Shape::Text {
                    at: [0.0; 3],
                    text: why.into(),
                    paint: Paint::Screw,
                });
                return e;
            }
        };
        let mid = self.transform.translation_m.map(|x| 0.5 * x);
        let [a, b] = axis_segment(point, axis, mid, SCREW_AXIS_HALF_LENGTH_FACTOR * extent);
        e.shapes.push(Shape::Line {
            points: vec![a, b],
            paint: Paint::Screw,
        });
        let h = sc.translation_along_axis_m.unwrap_or(0.0);
        let pitch = sc.pitch_m_per_rad.unwrap_or(0.0);
        let verdict = sc.pitch_verdict.map_or("", |v| v.name());
        let judged = match verdict {
            "" => String::new(),
            v => format!(" (pitch {v})"),
        };
        e.shapes.push(Shape::Text {
            at: b,
            text: format!(
                "screw axis: h = {} m, pitch = {} m/rad{judged}, {} deg",
                short(h),
                short(pitch),
                degrees(self.rotation.angle_deg)
            ),
            paint: Paint::Screw,
        });
        e.fact("h_m", exact(h))
            .fact("pitch_m_per_rad", exact(pitch))
            .fact("axis", exact3(&axis))
            .fact("axis_point_m", exact3(&point))
            .fact("angle_rad", exact(self.rotation.angle_rad))
            .fact("pitch_verdict", verdict);
        e
    }
}
