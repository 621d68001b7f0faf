//! Which container a bag is: an MCAP file, a rosbag2 sqlite3 `.db3`, a ROS 1
//! `.bag`, or a rosbag2 folder. A container is recognised by its magic bytes,
//! else by its extension; a folder by its `metadata.yaml`.

use super::{db3, mcap_file};
use crate::formats::spec::Input;
use std::path::Path;

/// The first bytes of a ROS 1 bag, whatever its version (`#ROSBAG V2.0`).
pub(super) const ROS1_MAGIC: &[u8] = b"#ROSBAG";

/// The magic bytes of the containers.
pub(super) const MAGIC: &[&[u8]] = &[mcap_file::MAGIC, db3::MAGIC, ROS1_MAGIC];

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Container {
    Mcap,
    Db3,
    Ros1,
    Folder,
}

pub(super) fn magic_of(head: &[u8]) -> Option<Container> {
    if head.starts_with(mcap_file::MAGIC) {
        Some(Container::Mcap)
    } else if head.starts_with(db3::MAGIC) {
        Some(Container::Db3)
    } else if head.starts_with(ROS1_MAGIC) {
        Some(Container::Ros1)
    } else {
        None
    }
}

fn by_extension(ext: &str) -> Option<Container> {
    match ext {
        "mcap" => Some(Container::Mcap),
        "db3" => Some(Container::Db3),
        "bag" => Some(Container::Ros1),
        _ => None,
    }
}

/// The container `input` is: a folder with `metadata.yaml`, a file by its
/// magic bytes, else by its extension.
pub(super) fn container(input: &Input) -> Option<Container> {
    if input.is_folder() {
        return input
            .folder_holds("metadata.yaml")
            .then_some(Container::Folder);
    }
    magic_of(input.head()).or_else(|| by_extension(input.ext()))
}

/// [`container`] of the file or folder at `path` (one that cannot be opened
/// by its extension alone).
pub(super) fn container_at(path: &Path) -> Option<Container> {
    match Input::peek(path) {
        Some(input) => container(&input),
        None => by_extension(
            &path
                .extension()
                .map(|e| e.to_string_lossy().to_ascii_lowercase())
                .unwrap_or_default(),
        ),
    }
}
