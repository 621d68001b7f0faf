//! The MCAP writing both exports share: the file's header, a `json`
//! channel with its `jsonschema` schema, a message, the `/tf` message, and
//! the closing metadata record (see [`super`]'s module docs).

use super::foxglove::{FrameTransform, FrameTransforms, Time};
use crate::diagnostic::{Code, Error, Result};
use crate::document::scene::SceneTransform;
use mcap::records::{MessageHeader, Metadata};
use serde::Serialize;
use std::collections::BTreeMap;
use std::io::{Seek, Write};

/// The topic of the transforms.
pub const TF_TOPIC: &str = "/tf";
/// The name of the metadata record.
pub const METADATA_NAME: &str = "extrinsic-audit";
/// Foxglove's `FrameTransforms` schema (`@foxglove/schemas` 2.1.0), as its
/// file has it.
pub const FRAME_TRANSFORMS: &[u8] =
    include_bytes!("../../../docs/schemas/external/foxglove/FrameTransforms.json");

fn fail(e: mcap::McapError) -> Error {
    Error::new(Code::Io, format!("cannot write MCAP: {e}"))
}

/// A writer with this tool's header: empty profile (not a ROS encoding),
/// the library named, the crate's default zstd chunks and indexes.
pub fn writer<W: Write + Seek>(w: W) -> Result<mcap::Writer<W>> {
    mcap::WriteOptions::new()
        .profile("")
        .library(concat!("extrinsic-audit ", env!("CARGO_PKG_VERSION")))
        .create(w)
        .map_err(fail)
}

/// A new `json` channel on `topic` whose `jsonschema` schema is `schema`
/// (named `name`, its title).
pub fn channel<W: Write + Seek>(
    w: &mut mcap::Writer<W>,
    topic: &str,
    name: &str,
    schema: &[u8],
) -> Result<u16> {
    let sid = w.add_schema(name, "jsonschema", schema).map_err(fail)?;
    w.add_channel(sid, topic, "json", &BTreeMap::new())
        .map_err(fail)
}

/// `msg` as JSON on channel `ch` at `log_time` (ns; also its publish time).
pub fn message<W: Write + Seek, T: Serialize>(
    w: &mut mcap::Writer<W>,
    ch: u16,
    sequence: u32,
    log_time: u64,
    msg: &T,
) -> Result<()> {
    let data = serde_json::to_vec(msg)
        .map_err(|e| Error::new(Code::Io, format!("cannot encode an MCAP message: {e}")))?;
    let header = MessageHeader {
        channel_id: ch,
        sequence,
        log_time,
        publish_time: log_time,
    };
    w.write_to_known_channel(&header, &data).map_err(fail)
}

/// The metadata record (`facts` and the tool), then the summary and the
/// indexes; the writer's sink back.
pub fn finish<W: Write + Seek>(
    mut w: mcap::Writer<W>,
    facts: impl IntoIterator<Item = (String, String)>,
) -> Result<W> {
    let mut facts: BTreeMap<String, String> = facts.into_iter().collect();
    facts.insert(
        "tool".into(),
        format!("audit {}", env!("CARGO_PKG_VERSION")),
    );
    w.write_metadata(&Metadata {
        name: METADATA_NAME.into(),
        metadata: facts,
    })
    .map_err(fail)?;
    w.finish().map_err(fail)?;
    Ok(w.into_inner())
}

/// One `FrameTransforms` of `list`, every transform stamped `at`.
pub fn transforms(list: &[SceneTransform], at: Time) -> FrameTransforms {
    FrameTransforms {
        transforms: list.iter().map(|t| frame_transform(t, at)).collect(),
    }
}

fn frame_transform(t: &SceneTransform, at: Time) -> FrameTransform {
    FrameTransform {
        timestamp: at,
        parent_frame_id: t.parent.clone(),
        child_frame_id: t.child.clone(),
        translation: t.translation_m.into(),
        rotation: t.rotation_xyzw.into(),
    }
}
