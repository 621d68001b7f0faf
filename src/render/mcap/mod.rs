//! `--format mcap`: a document's [`Scene`] as an MCAP file that Foxglove
//! (and Lichtblick) open, written with the `mcap` crate.
//!
//! # What the file holds
//!
//! | topic | schema (Foxglove's, `jsonschema`) | messages |
//! |---|---|---|
//! | `/tf` | `foxglove.FrameTransforms` | one, every transform of the scene |
//! | `/audit/scene` | `foxglove.SceneUpdate` | one, every entity |
//! | `/audit/<name>` | `foxglove.PointCloud` | one per cloud (`/audit/points`, `/audit/target_points`) |
//!
//! and one metadata record, `extrinsic-audit`, with the scene's facts (the
//! tool's version among them). A topic with nothing to say is not written.
//!
//! # Encoding
//!
//! Channels are `json` with `jsonschema` schemas (the MCAP registry's
//! well-known encodings): the schema's name is its `title` and its data is
//! Foxglove's own schema file, byte for byte (docs/schemas/external/foxglove/,
//! where SOURCES.md names the package, version, sha256 and licence). Messages
//! are UTF-8 JSON of [`foxglove`]'s types. A scene holding a non-finite
//! number is refused (JSON has no NaN: serde_json would write `null`, which
//! the schemas reject). The scene has no time: every message is at 0 (log
//! time, publish time and stamps), so the file is the same bytes for the same
//! scene. Chunks are zstd-compressed (the crate's default) with the usual
//! indexes and statistics; the profile is empty (not a ROS encoding).
//!
//! # Drawing
//!
//! Lines and labels keep their size on screen (`scale_invariant`: pixels);
//! arrows, which have no such mode, scale with their length. Point clouds
//! put their origin in the message's `pose` and their points as `FLOAT32`
//! offsets from it (x, y, z, then each field), so coordinates far from the
//! frame's origin keep millimetres.

mod foxglove;
mod run;
mod write;

pub use run::{RunMcap, RUN_TOPIC};
use write::{channel, finish, message, transforms, writer, FRAME_TRANSFORMS, TF_TOPIC};

use crate::diagnostic::{Error, Result};
use crate::document::scene::{Entity, Paint, PointCloud, Scene, Shape};
use base64::Engine as _;
use foxglove::{
    ArrowPrimitive, Color, KeyValuePair, LinePrimitive, PackedElementField, Pose, SceneEntity,
    SceneUpdate, TextPrimitive, Time, FLOAT32, LINE_STRIP,
};
use serde::Serialize;
use std::io::Cursor;

/// The topic of the entities.
pub const SCENE_TOPIC: &str = "/audit/scene";
/// Point clouds are on `CLOUD_TOPIC_PREFIX` + their name.
pub const CLOUD_TOPIC_PREFIX: &str = "/audit/";

/// Foxglove's schemas (`@foxglove/schemas` 2.1.0), as their files have them.
const SCENE_UPDATE: &[u8] =
    include_bytes!("../../../docs/schemas/external/foxglove/SceneUpdate.json");
const POINT_CLOUD: &[u8] =
    include_bytes!("../../../docs/schemas/external/foxglove/PointCloud.json");

/// Line width on screen (px).
const LINE_PX: f64 = 3.0;
/// Label size on screen (px).
const FONT_PX: f64 = 14.0;
/// An arrow's head length, head diameter and shaft diameter as fractions of
/// its length.
const ARROW_HEAD: f64 = 0.2;
const ARROW_HEAD_WIDTH: f64 = 0.08;
const ARROW_SHAFT_WIDTH: f64 = 0.03;

/// The scene as the bytes of an MCAP file.
pub fn write(scene: &Scene) -> Result<Vec<u8>> {
    if let Some(what) = scene.non_finite() {
        return Err(Error::invalid(format!(
            "--format mcap: {what} holds a non-finite number, which JSON cannot carry"
        )));
    }
    let mut w = writer(Cursor::new(Vec::new()))?;
    let mut out = Out { w: &mut w };
    if !scene.transforms.is_empty() {
        let msg = transforms(&scene.transforms, Time::default());
        out.one(TF_TOPIC, "foxglove.FrameTransforms", FRAME_TRANSFORMS, &msg)?;
    }
    if !scene.entities.is_empty() {
        let msg = SceneUpdate {
            deletions: [],
            entities: scene.entities.iter().map(entity).collect(),
        };
        out.one(SCENE_TOPIC, "foxglove.SceneUpdate", SCENE_UPDATE, &msg)?;
    }
    for c in &scene.clouds {
        let topic = format!("{CLOUD_TOPIC_PREFIX}{}", c.name);
        out.one(&topic, "foxglove.PointCloud", POINT_CLOUD, &point_cloud(c))?;
    }
    Ok(finish(w, scene.metadata.iter().cloned())?.into_inner())
}

/// The writer of a scene, one message per topic at time 0.
struct Out<'a> {
    w: &'a mut mcap::Writer<Cursor<Vec<u8>>>,
}

impl Out<'_> {
    fn one<T: Serialize>(&mut self, topic: &str, name: &str, schema: &[u8], msg: &T) -> Result<()> {
        let ch = channel(self.w, topic, name, schema)?;
        message(self.w, ch, 0, 0, msg)
    }
}

/// The colour of a role: the frame axes as RViz and Foxglove draw them.
fn color(p: Paint) -> Color {
    let (r, g, b) = match p {
        Paint::AxisX => (0.9, 0.1, 0.1),
        Paint::AxisY => (0.1, 0.8, 0.1),
        Paint::AxisZ => (0.15, 0.35, 1.0),
        Paint::Screw => (1.0, 0.55, 0.0),
        Paint::LeverArm => (1.0, 0.9, 0.2),
        Paint::Chain => (0.85, 0.3, 0.95),
        Paint::Degenerate => (0.0, 0.85, 0.9),
        Paint::Label => (1.0, 1.0, 1.0),
    };
    Color { r, g, b, a: 1.0 }
}

/// The rotation `[x, y, z, w]` that takes +x onto the unit vector `u`: the
/// shortest one, `q ~ [x cross u, 1 + x . u]`, when `u` leans toward +x;
/// otherwise the one that takes +x onto `-u` (the same formula, stable
/// there) after a half-turn about z, `q ~ [u_z, 0, 1 - u_x, u_y]`, so that
/// no digit is lost near `u = -x` (the half-turn itself at `u = -x`).
pub fn rotation_from_x(u: [f64; 3]) -> [f64; 4] {
    let q = if u[0] >= 0.0 {
        [0.0, -u[2], u[1], 1.0 + u[0]]
    } else {
        [u[2], 0.0, 1.0 - u[0], u[1]]
    };
    let n = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    q.map(|c| c / n)
}

/// An arrow from `from` along `d`; none when `d` is zero.
fn arrow(from: [f64; 3], d: [f64; 3], paint: Paint) -> Option<ArrowPrimitive> {
    let len = d.iter().map(|c| c * c).sum::<f64>().sqrt();
    if len.is_nan() || len <= 0.0 {
        return None;
    }
    let head = ARROW_HEAD * len;
    Some(ArrowPrimitive {
        pose: Pose::new(from, rotation_from_x(d.map(|c| c / len))),
        shaft_length: len - head,
        shaft_diameter: ARROW_SHAFT_WIDTH * len,
        head_length: head,
        head_diameter: ARROW_HEAD_WIDTH * len,
        color: color(paint),
    })
}

fn entity(e: &Entity) -> SceneEntity {
    let mut out = SceneEntity {
        timestamp: Time::default(),
        frame_id: e.frame.clone(),
        id: e.id.clone(),
        lifetime: Time::default(),
        frame_locked: true,
        metadata: e
            .metadata
            .iter()
            .map(|(key, value)| KeyValuePair {
                key: key.clone(),
                value: value.clone(),
            })
            .collect(),
        arrows: Vec::new(),
        cubes: [],
        spheres: [],
        cylinders: [],
        lines: Vec::new(),
        triangles: [],
        texts: Vec::new(),
        models: [],
    };
    for s in &e.shapes {
        match s {
            Shape::Line { points, paint } => out.lines.push(LinePrimitive {
                kind: LINE_STRIP,
                pose: Pose::identity(),
                thickness: LINE_PX,
                scale_invariant: true,
                points: points.iter().map(|&p| p.into()).collect(),
                color: color(*paint),
                colors: Vec::new(),
                indices: Vec::new(),
            }),
            Shape::Arrow { from, along, paint } => out.arrows.extend(arrow(*from, *along, *paint)),
            Shape::Text { at, text, paint } => out.texts.push(TextPrimitive {
                pose: Pose::new(*at, [0.0, 0.0, 0.0, 1.0]),
                billboard: true,
                font_size: FONT_PX,
                scale_invariant: true,
                color: color(*paint),
                text: text.clone(),
            }),
        }
    }
    out
}

/// A cloud as `FLOAT32` x, y, z offsets from its origin, then its fields.
fn point_cloud(c: &PointCloud) -> foxglove::PointCloud {
    let names = ["x", "y", "z"]
        .into_iter()
        .map(str::to_string)
        .chain(c.fields.iter().map(|(n, _)| n.clone()));
    let fields: Vec<PackedElementField> = names
        .enumerate()
        .map(|(i, name)| PackedElementField {
            name,
            offset: 4 * i as u32,
            kind: FLOAT32,
        })
        .collect();
    let stride = 4 * fields.len();
    let mut raw = Vec::with_capacity(stride * c.points_m.len());
    for (i, p) in c.points_m.iter().enumerate() {
        for (x, o) in p.iter().zip(&c.origin_m) {
            raw.extend_from_slice(&((x - o) as f32).to_le_bytes());
        }
        for (_, v) in &c.fields {
            let x = v.get(i).copied().unwrap_or(0.0);
            raw.extend_from_slice(&(x as f32).to_le_bytes());
        }
    }
    foxglove::PointCloud {
        timestamp: Time::default(),
        frame_id: c.frame.clone(),
        pose: Pose::new(c.origin_m, [0.0, 0.0, 0.0, 1.0]),
        point_stride: stride as u32,
        fields,
        data: base64::engine::general_purpose::STANDARD.encode(raw),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::scene::SceneTransform;

    /// `q` applied to `v`.
    fn rotate(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
        let r = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            q[3], q[0], q[1], q[2],
        ));
        let w = r * nalgebra::Vector3::from(v);
        [w.x, w.y, w.z]
    }

    #[test]
    fn an_arrow_turns_x_onto_its_direction_including_minus_x() {
        let s = 0.5f64.sqrt();
        for u in [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, -1.0],
            [-1.0, 0.0, 0.0],
            [s, -s, 0.0],
            [-1.0, 1e-9, 0.0],
        ] {
            let n = u.iter().map(|c: &f64| c * c).sum::<f64>().sqrt();
            let u = u.map(|c| c / n);
            let q = rotation_from_x(u);
            let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
            assert!((norm - 1.0).abs() < 1e-15, "{u:?}: |q| = {norm}");
            let x = rotate(q, [1.0, 0.0, 0.0]);
            for k in 0..3 {
                assert!((x[k] - u[k]).abs() < 1e-12, "{u:?} -> {x:?}");
            }
        }
        assert_eq!(rotation_from_x([-1.0, 0.0, 0.0]), [0.0, 0.0, 1.0, 0.0]);
    }

    #[test]
    fn an_arrow_has_its_length_and_none_when_empty() {
        let a = arrow([1.0, 2.0, 3.0], [0.0, 0.0, 2.0], Paint::LeverArm).unwrap();
        assert_eq!(a.shaft_length + a.head_length, 2.0);
        assert_eq!(a.pose.position, [1.0, 2.0, 3.0].into());
        assert!(arrow([1.0; 3], [0.0; 3], Paint::LeverArm).is_none());
    }

    #[test]
    fn a_cloud_is_float32_offsets_from_its_origin_then_its_fields() {
        let c = PointCloud {
            name: "points".into(),
            frame: "scan".into(),
            origin_m: [500_000.0, 4_000_000.0, 10.0],
            points_m: vec![
                [500_000.25, 4_000_000.5, 10.0],
                [499_999.0, 4_000_001.0, 9.0],
            ],
            fields: vec![("weakest_share".into(), vec![0.75, 0.25])],
        };
        let m = point_cloud(&c);
        assert_eq!(m.point_stride, 16);
        let names: Vec<&str> = m.fields.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(names, ["x", "y", "z", "weakest_share"]);
        let raw = base64::engine::general_purpose::STANDARD
            .decode(&m.data)
            .unwrap();
        let f: Vec<f32> = raw
            .chunks(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        assert_eq!(f, [0.25, 0.5, 0.0, 0.75, -1.0, 1.0, -1.0, 0.25]);
    }

    #[test]
    fn a_non_finite_scene_is_refused_by_name() {
        let mut s = Scene::default();
        s.transforms.push(SceneTransform {
            parent: "base".into(),
            child: "lidar".into(),
            translation_m: [f64::NAN, 0.0, 0.0],
            rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
        });
        let e = write(&s).unwrap_err();
        assert!(e.to_string().contains("transform base -> lidar"), "{e}");
    }

    #[test]
    fn the_same_scene_gives_the_same_bytes() {
        let mut s = Scene::default();
        s.transforms.push(SceneTransform {
            parent: "base".into(),
            child: "lidar".into(),
            translation_m: [0.1, 0.0, 0.4],
            rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
        });
        s.entities.push(Entity::axes("lidar", 0.2));
        let a = write(&s).unwrap();
        assert_eq!(a, write(&s).unwrap());
        assert!(a.starts_with(b"\x89MCAP0\r\n"));
    }
}
