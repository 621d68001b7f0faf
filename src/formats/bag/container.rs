//! The wanted messages streamed from a bag, whichever container it is
//! ([`super::kind`]): an MCAP file, a rosbag2 sqlite3 `.db3`, a ROS 1 `.bag`
//! (each read through its own index: [`super::mcap_file`], [`super::db3`],
//! [`super::ros1`]), or a rosbag2 folder ([`super::folder`]).
//!
//! Messages come one at a time, in file order; the transform reader collects
//! those of its few topics ([`read`]), a run streams its clouds ([`stream`]).

use super::contents::{Ask, Contents, Flow, Listing, RawMessage};
use super::inflate::{BagLimits, Budget};
use super::kind::{container, Container};
use super::{db3, folder, mcap_file, ros1};
use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::spec::Input;
use crate::tolerances::MAX_BAG_KEPT_BYTES;
use std::io::Write;

/// The messages of the topics `wanted` accepts, from the container `input`
/// is, collected (at most [`MAX_BAG_KEPT_BYTES`] of them).
pub(super) fn read(input: &Input, wanted: &dyn Fn(&str) -> bool) -> Result<Contents> {
    let mut messages = Vec::new();
    let mut kept = 0usize;
    let ask = Ask {
        wanted,
        limits: BagLimits::default(),
        recover: false,
    };
    let listing = stream(input, ask, &mut |m: RawMessage| {
        kept = kept.saturating_add(m.data.len());
        if kept > MAX_BAG_KEPT_BYTES {
            return Err(Error::limit(format!(
                "the messages of the transform and description topics take more than {MAX_BAG_KEPT_BYTES} bytes (the last: {} at {}): expected a few MiB",
                m.topic, m.place
            ))
            .in_file(&m.file));
        }
        messages.push(m);
        Ok(Flow::Continue)
    })?;
    Ok(Contents {
        topics: listing.topics.into_iter().map(|t| t.name).collect(),
        messages,
    })
}

/// Hand the wanted messages of the container `input` is to `each`, in file
/// order (split after split for a folder).
pub(super) fn stream(
    input: &Input,
    ask: Ask,
    each: &mut dyn FnMut(RawMessage) -> Result<Flow>,
) -> Result<Listing> {
    let path = input.path();
    match container(input) {
        Some(Container::Mcap) => {
            let (stream, len) = input.stream()?;
            let mut budget = Budget::new(path, len, ask.limits);
            let topics = mcap_file::stream(stream, len, path, ask.wanted, &mut budget, each)?;
            Ok(Listing {
                topics,
                warnings: Vec::new(),
            })
        }
        Some(Container::Db3) => stream_db3(input, ask, each),
        Some(Container::Ros1) => {
            let (stream, len) = input.stream()?;
            let mut budget = Budget::new(path, len, ask.limits);
            let r = ros1::stream(stream, len, path, (ask.wanted, &mut budget, ask.recover), each)?;
            let warnings = r
                .recovered
                .map(|note| Warning::new(Code::Ignored, note).at(&Location::file(path)))
                .into_iter()
                .collect();
            Ok(Listing {
                topics: r.topics,
                warnings,
            })
        }
        Some(Container::Folder) => folder::stream(path, ask, each),
        None => Err(Error::parse(
            "expected a bag (.mcap, .db3, .bag, or a rosbag2 folder with metadata.yaml), found none of them",
        )
        .in_file(path)),
    }
}

/// A `.db3` file, or bytes held in memory (written to a private temporary
/// database first: SQLite reads a database from a file).
fn stream_db3(
    input: &Input,
    ask: Ask,
    each: &mut dyn FnMut(RawMessage) -> Result<Flow>,
) -> Result<Listing> {
    let path = input.path();
    let db = match input.file_on_disk() {
        Some(p) => db3::open(p)?,
        None => {
            let bytes = input.bytes()?;
            folder::TempDb::write(path, |f| {
                f.write_all(bytes).map_err(|e| Error::io(path, &e))
            })?
            .open(path)?
        }
    };
    let len = crate::input::reported_size(path).unwrap_or(0);
    let mut budget = Budget::new(path, len, ask.limits);
    let topics = db3::stream(&db, path, (ask.wanted, &mut budget, false), each)?;
    Ok(Listing {
        topics,
        warnings: Vec::new(),
    })
}
