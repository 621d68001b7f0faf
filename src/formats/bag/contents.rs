//! What a container reader yields: every topic the container holds, and the
//! messages of the wanted topics, still serialised, one at a time
//! ([`Flow`] says whether to go on) or collected ([`Contents`]).

use super::decode::Encoding;
use super::inflate::BagLimits;
use crate::diagnostic::Warning;
use std::path::PathBuf;

/// One message of a wanted topic, as a container yields it.
#[derive(Debug, Clone)]
pub struct RawMessage {
    /// The topic it was recorded on.
    pub topic: String,
    /// The message type as the container names it (`tf2_msgs/msg/TFMessage`,
    /// `tf2_msgs/TFMessage`); empty when it names none.
    pub type_name: String,
    /// How its bytes are serialised.
    pub encoding: Encoding,
    /// Log (receive) time, ns since the epoch.
    pub time_ns: u64,
    /// The serialised message.
    pub data: Vec<u8>,
    /// The file it was read from.
    pub file: PathBuf,
    /// Where in the file: `chunk at byte N`, `messages row id N`.
    pub place: String,
}

/// A topic of a container, from its index (or, without one, from a pass
/// over the file).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct TopicInfo {
    /// Its name as recorded.
    pub name: String,
    /// The message type as the container names it (empty when it names none).
    pub type_name: String,
    /// Messages on it, when the index counts them.
    pub count: Option<u64>,
}

/// What a message callback tells the reader.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    /// Hand out the next message.
    Continue,
    /// Stop reading (the rest is not wanted).
    Stop,
}

/// What a container yields: every topic it has, and the wanted messages.
#[derive(Debug, Clone, Default)]
pub struct Contents {
    /// Every topic the container holds.
    pub topics: Vec<String>,
    /// The messages of the wanted topics.
    pub messages: Vec<RawMessage>,
}

/// Add `t` to `topics` unless a topic of that name is there (first seen wins).
pub(super) fn add_topic(topics: &mut Vec<TopicInfo>, t: TopicInfo) {
    match topics.iter_mut().find(|o| o.name == t.name) {
        Some(o) => {
            if let (Some(a), Some(b)) = (o.count, t.count) {
                o.count = Some(a + b);
            }
        }
        None => topics.push(t),
    }
}

/// Which topics a reader hands out.
pub(super) type Wanted<'a> = &'a dyn Fn(&str) -> bool;

/// How a streamed read went: every topic of the container, and the named
/// warnings of what it worked around (a ROS 1 bag without an index read
/// from the start).
#[derive(Debug, Clone, Default)]
pub struct Listing {
    /// Every topic, sorted by name.
    pub topics: Vec<TopicInfo>,
    /// What the read worked around.
    pub warnings: Vec<Warning>,
}

/// How a read is asked for.
#[derive(Clone, Copy)]
pub struct Ask<'a> {
    /// Which topics' messages are handed out.
    pub wanted: &'a dyn Fn(&str) -> bool,
    /// The decompression caps.
    pub limits: BagLimits,
    /// Read a ROS 1 bag without a usable index from the start instead of
    /// refusing it.
    pub recover: bool,
}
