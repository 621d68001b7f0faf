//! MCAP files (ROS 2 `ros2 bag record -s mcap`, Foxglove, and ROS 1 messages in
//! MCAP): read with the `mcap` crate's sans-I/O readers over a seekable file, so
//! the file is never read whole.
//!
//! With a summary section (every finished MCAP writer leaves one): the channels
//! come from it, and only the chunks whose message index names a wanted channel
//! are read and decompressed (`IndexedReader` with `include_topics`), one at a
//! time, in file order (the order the recorder wrote; log-time order would
//! hold every chunk whose time range overlaps at once). Without a summary (an
//! unfinished recording, a truncated file): the file is streamed once from the
//! start; a truncation then surfaces as an error at its offset, after the
//! messages before it were handed out.
//!
//! Every chunk counts against the file's decompression budget
//! ([`super::inflate::Budget`]) before it is decompressed, and the `mcap`
//! crate refuses a chunk larger than the block cap (its record length limit).

use super::contents::{add_topic, Flow, RawMessage, TopicInfo};
use super::decode::Encoding;
use super::inflate::Budget;
use super::progress::Progress;
use crate::diagnostic::{Error, Result};
use crate::formats::spec::ReadBlock;
use mcap::records::{MessageHeader, Record};
use mcap::sans_io::indexed_reader::{
    IndexedReadEvent, IndexedReader, IndexedReaderOptions, ReadOrder,
};
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

/// Hand the messages of the topics `wanted` accepts from `file` (`size`
/// bytes, at its start), read from `path`, to `each` in file order; every
/// topic of the file.
pub fn stream<R: ReadBlock>(
    file: R,
    size: u64,
    path: &Path,
    wanted: &dyn Fn(&str) -> bool,
    budget: &mut Budget,
    each: &mut dyn FnMut(RawMessage) -> Result<Flow>,
) -> Result<Vec<TopicInfo>> {
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
        Ok(Some(s)) if !s.chunk_indexes.is_empty() => {
            indexed(path, &mut file, &s, (wanted, budget), each)
        }
        _ => linear(path, &mut file, size, (wanted, budget), each),
    }
}

fn summary<R: ReadBlock>(
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

/// Every topic of the summary, with its message count when the summary has
/// statistics.
fn summary_topics(s: &mcap::Summary, channels: &HashMap<u16, ChannelInfo>) -> Vec<TopicInfo> {
    let counts = s.stats.as_ref().map(|st| &st.channel_message_counts);
    let mut topics = Vec::new();
    let mut ids: Vec<&u16> = channels.keys().collect();
    ids.sort();
    for id in ids {
        let c = &channels[id];
        add_topic(
            &mut topics,
            TopicInfo {
                name: c.topic.clone(),
                type_name: c.schema.clone(),
                count: counts.map(|m| m.get(id).copied().unwrap_or(0)),
            },
        );
    }
    topics.sort();
    topics
}

type Wanted<'a> = (&'a dyn Fn(&str) -> bool, &'a mut Budget);

fn indexed<R: ReadBlock>(
    path: &Path,
    file: &mut BufReader<R>,
    s: &mcap::Summary,
    (wanted, budget): Wanted,
    each: &mut dyn FnMut(RawMessage) -> Result<Flow>,
) -> Result<Vec<TopicInfo>> {
    let channels: HashMap<u16, ChannelInfo> = s
        .channels
        .iter()
        .map(|(id, c)| (*id, channel_info(c)))
        .collect();
    let topics = summary_topics(s, &channels);
    let want: BTreeSet<String> = topics
        .iter()
        .map(|t| t.name.clone())
        .filter(|t| wanted(t))
        .collect();
    if want.is_empty() {
        return Ok(topics);
    }
    let mut opts = IndexedReaderOptions::new()
        .include_topics(want.clone())
        .with_order(ReadOrder::File);
    opts.record_length_limit = Some(budget.limits.block_bytes);
    let ids: BTreeSet<u16> = channels
        .iter()
        .filter(|(_, c)| want.contains(&c.topic))
        .map(|(id, _)| *id)
        .collect();
    let todo: Vec<&mcap::records::ChunkIndex> = s
        .chunk_indexes
        .iter()
        .filter(|c| {
            c.message_index_offsets.is_empty()
                || c.message_index_offsets.keys().any(|k| ids.contains(k))
        })
        .collect();
    // Decompressed sizes by where the chunk's data starts (the read request).
    let sizes: HashMap<u64, u64> = todo
        .iter()
        .filter_map(|c| Some((c.compressed_data_offset().ok()?, c.uncompressed_size)))
        .collect();
    let total: u64 = todo.iter().map(|c| c.compressed_size).sum();
    let mut progress = Progress::new(path, total);
    let mut done = 0u64;
    let mut r = IndexedReader::new_with_options(s, opts).map_err(|e| mcap_err(path, "index", e))?;
    let mut buf = Vec::new();
    let mut chunk_at = 0u64;
    while let Some(ev) = r.next_event() {
        match ev.map_err(|e| mcap_err(path, &format!("chunk at byte {chunk_at}"), e))? {
            IndexedReadEvent::ReadChunkRequest { offset, length } => {
                chunk_at = offset;
                budget.take(
                    sizes.get(&offset).copied().unwrap_or(length as u64),
                    &format!("MCAP chunk at byte {offset}"),
                )?;
                // The seek empties the BufReader, so the chunk is read from
                // the file itself, into spare capacity (ReadBlock).
                let ok = file.seek(SeekFrom::Start(offset)).is_ok()
                    && file.get_mut().read_block(length, &mut buf).is_ok();
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
                if each(m)? == Flow::Stop {
                    break;
                }
            }
        }
    }
    Ok(topics)
}

/// Stream the whole file: for MCAPs without a summary.
fn linear<R: ReadBlock>(
    path: &Path,
    file: &mut BufReader<R>,
    size: u64,
    (wanted, budget): Wanted,
    each: &mut dyn FnMut(RawMessage) -> Result<Flow>,
) -> Result<Vec<TopicInfo>> {
    file.seek(SeekFrom::Start(0))
        .map_err(|e| Error::io(path, &e))?;
    let mut r = LinearReader::new_with_options(
        LinearReaderOptions::default().with_record_length_limit(budget.limits.block_bytes),
    );
    let mut schemas: HashMap<u16, String> = HashMap::new();
    let mut channels: HashMap<u16, ChannelInfo> = HashMap::new();
    let mut counts: HashMap<u16, u64> = HashMap::new();
    let mut fed = 0u64;
    let mut progress = Progress::new(path, size);
    let topics = |channels: &HashMap<u16, ChannelInfo>, counts: &HashMap<u16, u64>| {
        let mut v = Vec::new();
        for (id, c) in channels {
            let t = TopicInfo {
                name: c.topic.clone(),
                type_name: c.schema.clone(),
                count: Some(counts.get(id).copied().unwrap_or(0)),
            };
            add_topic(&mut v, t);
        }
        v.sort();
        v
    };
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
                budget.take(data.len() as u64, "MCAP records")?;
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
                            *counts.entry(header.channel_id).or_default() += 1;
                            if wanted(&ch.topic) {
                                let place = format!("record before byte {fed}");
                                if each(raw(path, ch, &header, &data, place)?)? == Flow::Stop {
                                    return Ok(topics(&channels, &counts));
                                }
                            }
                        }
                    }
                    _ => {}
                }
            }
        }
    }
    Ok(topics(&channels, &counts))
}
