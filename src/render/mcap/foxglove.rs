//! Foxglove's messages as their JSON schemas (`@foxglove/schemas` 2.1.0,
//! docs/schemas/external/foxglove/) define them: every field the schemas
//! require, enums as integers, times as `{sec, nsec}`, binary data in
//! standard padded base64. Field names are the schemas'; only what the
//! scene writes is here.

use serde::Serialize;

/// `time` and `duration`: seconds and nanoseconds (`nsec` below 1e9).
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq, Default)]
pub struct Time {
    pub sec: u32,
    pub nsec: u32,
}

/// `foxglove.Vector3` and `foxglove.Point3`.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Xyz {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

impl From<[f64; 3]> for Xyz {
    fn from(v: [f64; 3]) -> Self {
        Xyz {
            x: v[0],
            y: v[1],
            z: v[2],
        }
    }
}

/// `foxglove.Quaternion`.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Quaternion {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub w: f64,
}

impl From<[f64; 4]> for Quaternion {
    fn from(q: [f64; 4]) -> Self {
        Quaternion {
            x: q[0],
            y: q[1],
            z: q[2],
            w: q[3],
        }
    }
}

/// `foxglove.Pose`.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Pose {
    pub position: Xyz,
    pub orientation: Quaternion,
}

impl Pose {
    /// At `p`, rotated by `q` (`[x, y, z, w]`).
    pub fn new(p: [f64; 3], q: [f64; 4]) -> Self {
        Pose {
            position: p.into(),
            orientation: q.into(),
        }
    }

    /// The frame's own origin and axes.
    pub fn identity() -> Self {
        Pose::new([0.0; 3], [0.0, 0.0, 0.0, 1.0])
    }
}

/// `foxglove.Color`, each channel in `[0, 1]`.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Color {
    pub r: f64,
    pub g: f64,
    pub b: f64,
    pub a: f64,
}

/// `foxglove.FrameTransform`: the pose of `child_frame_id` in
/// `parent_frame_id`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FrameTransform {
    pub timestamp: Time,
    pub parent_frame_id: String,
    pub child_frame_id: String,
    pub translation: Xyz,
    pub rotation: Quaternion,
}

/// `foxglove.FrameTransforms`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FrameTransforms {
    pub transforms: Vec<FrameTransform>,
}

/// `foxglove.KeyValuePair`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct KeyValuePair {
    pub key: String,
    pub value: String,
}

/// `foxglove.ArrowPrimitive`: along the pose's +x from its position.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ArrowPrimitive {
    pub pose: Pose,
    pub shaft_length: f64,
    pub shaft_diameter: f64,
    pub head_length: f64,
    pub head_diameter: f64,
    pub color: Color,
}

/// `foxglove.LineType`: `LINE_STRIP`.
pub const LINE_STRIP: u8 = 0;

/// `foxglove.LinePrimitive`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct LinePrimitive {
    #[serde(rename = "type")]
    pub kind: u8,
    pub pose: Pose,
    /// Pixels when `scale_invariant`, metres otherwise.
    pub thickness: f64,
    pub scale_invariant: bool,
    pub points: Vec<Xyz>,
    pub color: Color,
    /// Per-vertex colours (none: `color` for all).
    pub colors: Vec<Color>,
    /// Vertex indices (none: every point in order).
    pub indices: Vec<u32>,
}

/// `foxglove.TextPrimitive`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct TextPrimitive {
    pub pose: Pose,
    pub billboard: bool,
    /// Pixels when `scale_invariant`, metres otherwise.
    pub font_size: f64,
    pub scale_invariant: bool,
    pub color: Color,
    pub text: String,
}

/// An empty array of a primitive the scene never draws (the schema requires
/// each array).
pub type Unused = [(); 0];

/// `foxglove.SceneEntity`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SceneEntity {
    pub timestamp: Time,
    pub frame_id: String,
    pub id: String,
    /// `{0, 0}`: shown until replaced.
    pub lifetime: Time,
    pub frame_locked: bool,
    pub metadata: Vec<KeyValuePair>,
    pub arrows: Vec<ArrowPrimitive>,
    pub cubes: Unused,
    pub spheres: Unused,
    pub cylinders: Unused,
    pub lines: Vec<LinePrimitive>,
    pub triangles: Unused,
    pub texts: Vec<TextPrimitive>,
    pub models: Unused,
}

/// `foxglove.SceneUpdate`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SceneUpdate {
    pub deletions: Unused,
    pub entities: Vec<SceneEntity>,
}

/// `foxglove.NumericType`: `FLOAT32`.
pub const FLOAT32: u8 = 7;

/// `foxglove.PackedElementField`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct PackedElementField {
    pub name: String,
    /// Bytes from the start of a point.
    pub offset: u32,
    #[serde(rename = "type")]
    pub kind: u8,
}

/// `foxglove.PointCloud`: `point_stride` bytes per point, little-endian.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct PointCloud {
    pub timestamp: Time,
    pub frame_id: String,
    /// Where the points' origin sits in `frame_id`.
    pub pose: Pose,
    pub point_stride: u32,
    pub fields: Vec<PackedElementField>,
    /// Base64 (standard alphabet, padded).
    pub data: String,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enums_are_integers_and_unused_arrays_are_empty() {
        let f = PackedElementField {
            name: "x".into(),
            offset: 0,
            kind: FLOAT32,
        };
        assert_eq!(
            serde_json::to_string(&f).unwrap(),
            r#"{"name":"x","offset":0,"type":7}"#
        );
        let u = SceneUpdate {
            deletions: [],
            entities: vec![],
        };
        assert_eq!(
            serde_json::to_string(&u).unwrap(),
            r#"{"deletions":[],"entities":[]}"#
        );
    }
}
