//! A 3D scene: named frames joined by transforms, shapes drawn in those
//! frames, and point clouds with per-point fields. What `--format mcap`
//! writes for Foxglove (`render::mcap`), filled by the rig report, the frame
//! tree and `audit degeneracy` (a scan or a pair).
//!
//! # Conventions
//!
//! - A [`SceneTransform`] is the pose of `child` in `parent`,
//!   `p_parent = R p_child + d` (the tool's `T` for `parent -> child`, and
//!   TF's and Foxglove's `FrameTransform`), `R` as a unit quaternion
//!   `[x, y, z, w]`.
//! - Every coordinate is in metres, in the frame of the entity or cloud
//!   that holds it.
//! - Times are nanoseconds since the Unix epoch; a scene that has no time (a
//!   rig, a frame tree, a point file) is at 0.
//! - Colours are named by role ([`Paint`]); the renderer picks them.
//! - Every number must be finite: the renderer refuses a scene that is not
//!   (JSON has no NaN).
//!
//! Text is as the report has it (frame names from files included): the
//! renderer encodes it for its format.

/// The scene.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Scene {
    /// Facts about the whole scene, `(key, value)`: the command, the frames
    /// asked for, the queried chain.
    pub metadata: Vec<(String, String)>,
    /// Transforms between frames (at most one parent per child).
    pub transforms: Vec<SceneTransform>,
    /// Shapes, grouped into entities.
    pub entities: Vec<Entity>,
    /// Point clouds.
    pub clouds: Vec<PointCloud>,
}

/// The pose of `child` in `parent`.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneTransform {
    /// The parent frame.
    pub parent: String,
    /// The child frame.
    pub child: String,
    /// `d` (m): the child's origin in parent coordinates.
    pub translation_m: [f64; 3],
    /// `R` as a unit quaternion `[x, y, z, w]`.
    pub rotation_xyzw: [f64; 4],
}

/// A named group of shapes in one frame (one thing the scene shows: a screw
/// axis, a lever arm, a frame's axes), with facts about it.
#[derive(Debug, Clone, PartialEq)]
pub struct Entity {
    /// Unique in the scene (`screw_axis`, `axes/base_link`, ...).
    pub id: String,
    /// The frame its coordinates are in.
    pub frame: String,
    /// What it draws.
    pub shapes: Vec<Shape>,
    /// `(key, value)` facts (numbers at full precision, as text).
    pub metadata: Vec<(String, String)>,
}

/// One shape.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A polyline through `points` (at least two).
    Line {
        /// The vertices, in order.
        points: Vec<[f64; 3]>,
        /// Its role.
        paint: Paint,
    },
    /// An arrow from `from` to `from + along` (its tip), the vector given
    /// (not the tip) so that its direction keeps every digit far from the
    /// origin.
    Arrow {
        /// The tail.
        from: [f64; 3],
        /// Tail to tip.
        along: [f64; 3],
        /// Its role.
        paint: Paint,
    },
    /// A label that faces the viewer.
    Text {
        /// Where it is anchored.
        at: [f64; 3],
        /// What it says.
        text: String,
        /// Its role.
        paint: Paint,
    },
}

/// What a shape shows, for the renderer's colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Paint {
    /// A frame's x axis (red, as in RViz and Foxglove).
    AxisX,
    /// A frame's y axis (green).
    AxisY,
    /// A frame's z axis (blue).
    AxisZ,
    /// A rig's screw axis.
    Screw,
    /// A lever arm.
    LeverArm,
    /// An edge of the queried chain.
    Chain,
    /// A degenerate direction of a scan.
    Degenerate,
    /// A label.
    Label,
}

/// A point cloud: points with named per-point fields.
#[derive(Debug, Clone, PartialEq)]
pub struct PointCloud {
    /// Its name: the renderer's topic is made from it (`points`,
    /// `target_points`).
    pub name: String,
    /// The frame the points are in.
    pub frame: String,
    /// A point near the cloud (its centroid): the points are written as
    /// offsets from it, so that map or UTM coordinates keep their digits.
    pub origin_m: [f64; 3],
    /// The points, in `frame` (m).
    pub points_m: Vec<[f64; 3]>,
    /// Per-point fields, `(name, one value per point)`.
    pub fields: Vec<(String, Vec<f64>)>,
}

impl Entity {
    /// An entity without shapes.
    pub fn new(id: impl Into<String>, frame: impl Into<String>) -> Self {
        Entity {
            id: id.into(),
            frame: frame.into(),
            shapes: Vec::new(),
            metadata: Vec::new(),
        }
    }

    /// The axes of `frame`: arrows of `length` m along x, y and z from its
    /// origin, and its name at the origin; id `axes/FRAME`.
    pub fn axes(frame: &str, length: f64) -> Self {
        let mut e = Entity::new(format!("axes/{frame}"), frame);
        for (k, paint) in [Paint::AxisX, Paint::AxisY, Paint::AxisZ]
            .into_iter()
            .enumerate()
        {
            let mut along = [0.0; 3];
            along[k] = length;
            e.shapes.push(Shape::Arrow {
                from: [0.0; 3],
                along,
                paint,
            });
        }
        e.shapes.push(Shape::Text {
            at: [0.0; 3],
            text: frame.to_string(),
            paint: Paint::Label,
        });
        e
    }

    /// Add a fact.
    pub fn fact(&mut self, key: &str, value: impl ToString) -> &mut Self {
        self.metadata.push((key.to_string(), value.to_string()));
        self
    }
}

/// The shortest drawn frame axis (m): visible beside a sensor a few
/// centimetres from its body frame.
pub const MIN_AXIS_M: f64 = 0.1;

/// The length of a frame's drawn axes in a scene whose longest distance is
/// `extent_m`: a fifth of it, at least [`MIN_AXIS_M`].
pub fn axis_length(extent_m: f64) -> f64 {
    (0.2 * extent_m).max(MIN_AXIS_M)
}

/// The segment of the line through `point` along the unit `axis` that is
/// centred on the line's point nearest `near`, `2 half_length` long: an axis
/// drawn where the scene is, not at the foot of the origin.
pub fn axis_segment(
    point: [f64; 3],
    axis: [f64; 3],
    near: [f64; 3],
    half_length: f64,
) -> [[f64; 3]; 2] {
    let along: f64 = (0..3).map(|k| (near[k] - point[k]) * axis[k]).sum();
    let c: [f64; 3] = std::array::from_fn(|k| point[k] + along * axis[k]);
    [
        std::array::from_fn(|k| c[k] - half_length * axis[k]),
        std::array::from_fn(|k| c[k] + half_length * axis[k]),
    ]
}

impl Scene {
    /// Every number of the scene is finite; otherwise the first that is not,
    /// named (`transform base -> lidar`, `entity screw_axis`, `cloud points`).
    pub fn non_finite(&self) -> Option<String> {
        let bad = |v: &[f64]| v.iter().any(|x| !x.is_finite());
        for t in &self.transforms {
            if bad(&t.translation_m) || bad(&t.rotation_xyzw) {
                return Some(format!("transform {} -> {}", t.parent, t.child));
            }
        }
        for e in &self.entities {
            let shape_bad = e.shapes.iter().any(|s| match s {
                Shape::Line { points, .. } => points.iter().any(|p| bad(p)),
                Shape::Arrow { from, along, .. } => bad(from) || bad(along),
                Shape::Text { at, .. } => bad(at),
            });
            if shape_bad {
                return Some(format!("entity {}", e.id));
            }
        }
        for c in &self.clouds {
            if bad(&c.origin_m)
                || c.points_m.iter().any(|p| bad(p))
                || c.fields.iter().any(|(_, v)| bad(v))
            {
                return Some(format!("cloud {}", c.name));
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_axis_segment_is_centred_where_the_scene_is() {
        // The z axis through (1, 0, 0), seen from (5, 5, 3): centred at (1, 0, 3).
        let [a, b] = axis_segment([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [5.0, 5.0, 3.0], 2.0);
        assert_eq!(a, [1.0, 0.0, 1.0]);
        assert_eq!(b, [1.0, 0.0, 5.0]);
    }

    #[test]
    fn frame_axes_are_red_green_blue_arrows_and_a_name() {
        let e = Entity::axes("lidar", 0.5);
        assert_eq!(e.id, "axes/lidar");
        assert_eq!(e.frame, "lidar");
        let tips: Vec<[f64; 3]> = e
            .shapes
            .iter()
            .filter_map(|s| match s {
                Shape::Arrow { along, .. } => Some(*along),
                _ => None,
            })
            .collect();
        assert_eq!(
            tips,
            [[0.5, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 0.5]].to_vec()
        );
        assert!(matches!(&e.shapes[3], Shape::Text { text, .. } if text == "lidar"));
    }

    #[test]
    fn a_non_finite_number_is_named() {
        let mut s = Scene::default();
        assert_eq!(s.non_finite(), None);
        s.clouds.push(PointCloud {
            name: "points".into(),
            frame: "scan".into(),
            origin_m: [0.0; 3],
            points_m: vec![[0.0, 0.0, 0.0]],
            fields: vec![("weakest_share".into(), vec![f64::NAN])],
        });
        assert_eq!(s.non_finite().as_deref(), Some("cloud points"));
        s.transforms.push(SceneTransform {
            parent: "a".into(),
            child: "b".into(),
            translation_m: [f64::INFINITY, 0.0, 0.0],
            rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
        });
        assert_eq!(s.non_finite().as_deref(), Some("transform a -> b"));
    }
}
