//! MCAP files (ROS 2 `ros2 bag record -s mcap`, Foxglove, and ROS 1 messages in
//! MCAP): read with the `mcap` crate's sans-I/O readers over a seekable file, so
//! the file is never read whole.
//!
//! With a summary section (every finished MCAP writer leaves one): the channels
//! come from it, and only the chunks whose message index names a wanted channel
//! are read and decompressed (`IndexedReader` with `include_topics`). Without a
//! summary (an unfinished recording, a truncated file): the file is streamed
//! once from the start; a truncation then surfaces as an error at its offset.

use super::contents::{Contents, RawMessage};
use super::decode::Encoding;
use super::progress::Progress;
use crate::diagnostic::{Error, Result};
use crate::tolerances::MAX_BAG_RECORD_BYTES;
use mcap::records::{MessageHeader, Record};
use mcap::sans_io::indexed_reader::{IndexedReadEvent, IndexedReader, IndexedReaderOptions};
use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};
use mcap::sans_io::summary_reader::{SummaryReadEvent, SummaryReader, SummaryReaderOptions};
use std::collections::{BTreeSet, HashMap};
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::Path;

/// The 8 bytes every MCAP file starts with.
pub const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

fn mcap_err(path: &Path, what: &str, e: impl std::fmt::Display) -> Error {
    Error::parse(format!("MCAP {what}: {e}")).in_file(path)
}

/// Topic, encoding and schema name of one channel.
#[derive(Clone)]
struct ChannelInfo {
    topic: String,
    encoding: String,
    schema: String,
}

/// Read the messages of the topics `wanted` accepts from `file` (`size`
/// bytes, at its start), read from `path`.
pub fn read<R: Read + Seek>(
    file: R,
    size: u64,
    path: &Path,
    wanted: &dyn Fn(&str) -> bool,
) -> Result<Contents> {
    // The summary reader asks for records a few bytes at a time: buffer them.
    let mut file = BufReader::with_capacity(1 << 16, file);
    let mut head = [0u8; 8];
    if size < 8 || file.read_exact(&mut head).is_err() || &head != MAGIC {
        return Err(Error::parse(format!(
            "expected the MCAP magic bytes 89 4D 43 41 50 30 0D 0A at byte 0, found a {size}-byte file without them"
        ))
        .in_file(path));
    }
    match summary(&mut file, size) {
        Ok(Some(s)) if !s.chunk_indexes.is_empty() => indexed(path, &mut file, &s, wanted),
        _ => linear(path, &mut file, size, wanted),
    }
}

fn summary<R: Read + Seek>(
    file: &mut BufReader<R>,
    size: u64,
) -> mcap::McapResult<Option<mcap::Summary>> {
    let mut r =
        SummaryReader::new_with_options(SummaryReaderOptions::default().with_file_size(size));
    while let Some(ev) = r.next_event() {
        match ev? {
            SummaryReadEvent::ReadRequest(n) => {
                let got = file.read(r.insert(n))?;
                r.notify_read(got);
            }
            SummaryReadEvent::SeekRequest(to) => {
                let at = file.seek(to)?;
                r.notify_seeked(at);
            }
        }
    }
    Ok(r.finish())
}

fn channel_info(c: &mcap::Channel) -> ChannelInfo {
    ChannelInfo {
        topic: c.topic.clone(),
        encoding: c.message_encoding.clone(),
        schema: c
            .schema
            .as_ref()
            .map(|s| s.name.clone())
            .unwrap_or_default(),
    }
}

fn encoding(path: &Path, ch: &ChannelInfo) -> Result<Encoding> {
    match ch.encoding.as_str() {
        "cdr" => Ok(Encoding::Cdr),
        "ros1" => Ok(Encoding::Ros1),
        other => Err(Error::parse(format!(
            "topic {}: message encoding '{other}': expected 'cdr' (ROS 2) or 'ros1'",
            ch.topic
        ))
        .in_file(path)),
    }
}

fn raw(
    path: &Path,
    ch: &ChannelInfo,
    header: &MessageHeader,
    data: &[u8],
    place: String,
) -> Result<RawMessage> {
    Ok(RawMessage {
        topic: ch.topic.clone(),
        type_name: ch.schema.clone(),
        encoding: encoding(path, ch)?,
        time_ns: header.log_time,
        data: data.to_vec(),
        file: path.to_path_buf(),
        place,
    })
}

fn indexed<R: Read + Seek>(
    path: &Path,
    file: &mut BufReader<R>,
    s: &mcap::Summary,
    wanted: &dyn Fn(&str) -> bool,
) -> Result<Contents> {
    let channels: HashMap<u16, ChannelInfo> = s
        .channels
        .iter()
        .map(|(id, c)| (*id, channel_info(c)))
        .collect();
    let topics: BTreeSet<String> = channels.values().map(|c| c.topic.clone()).collect();
    let want: BTreeSet<String> = topics.iter().filter(|t| wanted(t)).cloned().collect();
    let mut out = Contents {
        topics: topics.into_iter().collect(),
        messages: Vec::new(),
    };
    if want.is_empty() {
        return Ok(out);
    }
    let mut opts = IndexedReaderOptions::new().include_topics(want.clone());
    opts.record_length_limit = Some(MAX_BAG_RECORD_BYTES);
    let ids: BTreeSet<u16> = channels
        .iter()
        .filter(|(_, c)| want.contains(&c.topic))
        .map(|(id, _)| *id)
        .collect();
    let total: u64 = s
        .chunk_indexes
        .iter()
        .filter(|c| {
            c.message_index_offsets.is_empty()
                || c.message_index_offsets.keys().any(|k| ids.contains(k))
        })
        .map(|c| c.compressed_size)
        .sum();
    let mut progress = Progress::new(path, total);
    let mut done = 0u64;
    let mut r = IndexedReader::new_with_options(s, opts).map_err(|e| mcap_err(path, "index", e))?;
    let mut buf = Vec::new();
    let mut chunk_at = 0u64;
    while let Some(ev) = r.next_event() {
        match ev.map_err(|e| mcap_err(path, &format!("chunk at byte {chunk_at}"), e))? {
            IndexedReadEvent::ReadChunkRequest { offset, length } => {
                chunk_at = offset;
                buf.resize(length, 0);
                let ok =
                    file.seek(SeekFrom::Start(offset)).is_ok() && file.read_exact(&mut buf).is_ok();
                if !ok {
                    return Err(Error::parse(format!(
                        "MCAP chunk data at byte {offset}, {length} bytes: expected inside the file, found the end of the file first (truncated?)"
                    ))
                    .in_file(path));
                }
                done += length as u64;
                progress.update(done);
                r.insert_chunk_record_data(offset, &buf)
                    .map_err(|e| mcap_err(path, &format!("chunk at byte {offset}"), e))?;
            }
            IndexedReadEvent::Message { header, data } => {
                let Some(ch) = channels.get(&header.channel_id) else {
                    return Err(mcap_err(
                        path,
                        &format!("chunk at byte {chunk_at}"),
                        format!(
                            "message on channel {} that the summary does not list",
                            header.channel_id
                        ),
                    ));
                };
                let m = raw(path, ch, &header, data, format!("chunk at byte {chunk_at}"))?;
                out.messages.push(m);
            }
        }
    }
    Ok(out)
}

/// Stream the whole file: for MCAPs without a summary.
fn linear<R: Read + Seek>(
    path: &Path,
    file: &mut BufReader<R>,
    size: u64,
    wanted: &dyn Fn(&str) -> bool,
) -> Result<Contents> {
    file.seek(SeekFrom::Start(0))
        .map_err(|e| Error::io(path, &e))?;
    let mut r = LinearReader::new_with_options(
        LinearReaderOptions::default().with_record_length_limit(MAX_BAG_RECORD_BYTES),
    );
    let mut schemas: HashMap<u16, String> = HashMap::new();
    let mut channels: HashMap<u16, ChannelInfo> = HashMap::new();
    let mut messages = Vec::new();
    let mut fed = 0u64;
    let mut progress = Progress::new(path, size);
    while let Some(ev) = r.next_event() {
        let at = |e| {
            mcap_err(
                path,
                "(no readable summary section: read from the start)",
                format!("{e}, at byte {fed} of {size} (truncated or corrupt?)"),
            )
        };
        match ev.map_err(at)? {
            LinearReadEvent::ReadRequest(n) => {
                let got = file.read(r.insert(n)).map_err(|e| Error::io(path, &e))?;
                fed += got as u64;
                progress.update(fed);
                r.notify_read(got);
            }
            LinearReadEvent::Record { data, opcode } => {
                let rec = mcap::parse_record(opcode, data).map_err(|e| {
                    mcap_err(path, &format!("record 0x{opcode:02x} before byte {fed}"), e)
                })?;
                match rec {
                    Record::Schema { header, .. } => {
                        schemas.insert(header.id, header.name);
                    }
                    Record::Channel(c) => {
                        let info = ChannelInfo {
                            topic: c.topic,
                            encoding: c.message_encoding,
                            schema: schemas.get(&c.schema_id).cloned().unwrap_or_default(),
                        };
                        channels.insert(c.id, info);
                    }
                    Record::Message { header, data } => {
                        if let Some(ch) = channels.get(&header.channel_id) {
                            if wanted(&ch.topic) {
                                let place = format!("record before byte {fed}");
                                messages.push(raw(path, ch, &header, &data, place)?);
                            }
                        }
                    }
                    _ => {}
                }
            }
        }
    }
    let topics: BTreeSet<String> = channels.values().map(|c| c.topic.clone()).collect();
    Ok(Contents {
        topics: topics.into_iter().collect(),
        messages,
    })
}
