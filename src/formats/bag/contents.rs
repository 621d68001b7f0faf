//! What a container reader yields: every topic the container holds, and the
//! messages of the wanted topics, still serialised.

use super::decode::Encoding;
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

/// What a container yields: every topic it has, and the wanted messages.
#[derive(Debug, Clone, Default)]
pub struct Contents {
    /// Every topic the container holds.
    pub topics: Vec<String>,
    /// The messages of the wanted topics.
    pub messages: Vec<RawMessage>,
}
