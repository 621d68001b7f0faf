//! ROS 1 bags (format 2.0, `#ROSBAG V2.0`), read after the format
//! specification (wiki.ros.org/Bags/Format/2.0) by a reader of our own: the
//! `rosbag` crate maps the whole file and is not defensive about corrupt
//! lengths.
//!
//! Layout: magic, a bag header record (`op=03`: `index_pos`, `conn_count`,
//! `chunk_count`), chunks (`op=05`, compression `none`/`bz2`/`lz4`, holding
//! connection `op=07` and message data `op=02` records), each followed by its
//! index data (`op=04`), then at `index_pos` the connection records and chunk
//! info records (`op=06`: chunk position and per-connection message counts).
//! A record is `u32 header_len, header, u32 data_len, data`; a header is fields
//! `u32 len, name=value`. All integers little-endian.
//!
//! Only the index section and the chunks whose chunk info counts a message on
//! a wanted connection are read, one chunk at a time, in file order; a chunk
//! is decompressed in pieces, capped ([`super::inflate::Budget`]). A bag
//! without an index (still recording, or cut short) is refused with the
//! advice to run `rosbag reindex`, unless the caller asks to recover: then it
//! is read from the start, chunk after chunk, and the messages of every
//! complete chunk are handed out before the damage is reported (what
//! `rosbag reindex` itself recovers).

use super::contents::{add_topic, Flow, RawMessage, TopicInfo, Wanted};
use super::decode::Encoding;
use super::inflate::Budget;
use super::progress::Progress;
use crate::bytes::{read_at, Endian, Reader};
use crate::diagnostic::{Error, Result};
use crate::formats::spec::ReadBlock;
use std::collections::{BTreeMap, BTreeSet};
use std::io::SeekFrom;
use std::path::Path;

/// The 13 bytes a ROS 1 bag (format 2.0) starts with.
pub const MAGIC: &[u8; 13] = b"#ROSBAG V2.0\n";

const OP_MSG_DATA: u8 = 0x02;
const OP_BAG_HEADER: u8 = 0x03;
const OP_CHUNK: u8 = 0x05;
const OP_CHUNK_INFO: u8 = 0x06;
const OP_CONNECTION: u8 = 0x07;

/// Largest record header or data block read whole: a chunk's compressed data
/// or the index section ([`crate::tolerances::MAX_BAG_MESSAGE_BYTES`]).
const MAX_BLOCK: usize = crate::tolerances::MAX_BAG_MESSAGE_BYTES;

/// One record: header fields and data, with the offset it starts at.
struct Record {
    at: u64,
    fields: Vec<(String, Vec<u8>)>,
    data: Vec<u8>,
}

impl Record {
    fn field(&self, name: &str) -> Option<&[u8]> {
        self.fields
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }

    fn op(&self) -> Option<u8> {
        self.field("op").and_then(|v| v.first().copied())
    }

    fn err(&self, path: &Path, msg: impl std::fmt::Display) -> Error {
        Error::parse(format!("ROS 1 bag record at byte {}: {msg}", self.at)).in_file(path)
    }

    fn u32(&self, path: &Path, name: &str) -> Result<u32> {
        match self.field(name) {
            Some(v) if v.len() == 4 => Ok(le32(v)),
            other => Err(self.err(
                path,
                format!(
                    "field `{name}`: expected 4 bytes, found {}",
                    describe(other)
                ),
            )),
        }
    }

    fn u64(&self, path: &Path, name: &str) -> Result<u64> {
        match self.field(name) {
            Some(v) if v.len() == 8 => Ok(read_at(v, 0, Endian::Little).unwrap_or_default()),
            other => Err(self.err(
                path,
                format!(
                    "field `{name}`: expected 8 bytes, found {}",
                    describe(other)
                ),
            )),
        }
    }

    fn text(&self, path: &Path, name: &str) -> Result<String> {
        let v = self
            .field(name)
            .ok_or_else(|| self.err(path, format!("expected a field `{name}`, found none")))?;
        String::from_utf8(v.to_vec())
            .map_err(|_| self.err(path, format!("field `{name}`: expected UTF-8 text")))
    }
}

fn describe(v: Option<&[u8]>) -> String {
    match v {
        Some(v) => format!("{} bytes", v.len()),
        None => "no such field".into(),
    }
}

/// The little-endian `u32` that starts `b` (0 when `b` is shorter: the
/// callers give it four bytes).
fn le32(b: &[u8]) -> u32 {
    read_at(b, 0, Endian::Little).unwrap_or_default()
}

/// Split a record header into `name=value` fields.
fn fields(h: &[u8]) -> std::result::Result<Vec<(String, Vec<u8>)>, String> {
    let mut out = Vec::new();
    let mut i = 0usize;
    while i < h.len() {
        let Ok(len) = read_at::<u32>(h, i, Endian::Little) else {
            return Err(format!(
                "header byte {i}: expected a 4-byte field length, found the end of the header"
            ));
        };
        let len = len as usize;
        let body = h.get(i + 4..).and_then(|r| r.get(..len)).ok_or_else(|| {
            format!("header byte {i}: field of length {len} runs past the end of the header")
        })?;
        let eq = body
            .iter()
            .position(|&b| b == b'=')
            .ok_or_else(|| format!("header byte {i}: expected `name=value`, found no `=`"))?;
        out.push((
            String::from_utf8_lossy(&body[..eq]).into_owned(),
            body[eq + 1..].to_vec(),
        ));
        i += 4 + len;
    }
    Ok(out)
}

/// Reads length-prefixed blocks from a slice (a decompressed chunk) or a file.
trait Source {
    fn pos(&self) -> u64;
    fn len(&self) -> u64;
    fn read_exact_at(&mut self, n: usize) -> std::io::Result<Vec<u8>>;
}

struct FileSource<R> {
    file: R,
    pos: u64,
    len: u64,
}

impl<R: ReadBlock> Source for FileSource<R> {
    fn pos(&self) -> u64 {
        self.pos
    }
    fn len(&self) -> u64 {
        self.len
    }
    fn read_exact_at(&mut self, n: usize) -> std::io::Result<Vec<u8>> {
        let mut v = Vec::new();
        self.file.seek(SeekFrom::Start(self.pos))?;
        self.file.read_block(n, &mut v)?;
        self.pos += n as u64;
        Ok(v)
    }
}

impl Source for Reader<'_> {
    fn pos(&self) -> u64 {
        Reader::pos(self) as u64
    }
    fn len(&self) -> u64 {
        Reader::len(self) as u64
    }
    fn read_exact_at(&mut self, n: usize) -> std::io::Result<Vec<u8>> {
        let v = self
            .take(n)
            .map_err(|_| std::io::ErrorKind::UnexpectedEof)?;
        Ok(v.to_vec())
    }
}

/// Read one length-prefixed block of at most the bytes left and the record limit.
fn block(src: &mut dyn Source, what: &str, within: &str) -> std::result::Result<Vec<u8>, String> {
    let at = src.pos();
    let left = src.len().saturating_sub(at);
    let n = src
        .read_exact_at(4)
        .map_err(|_| format!("byte {at}: expected a 4-byte {what} length, found the end of the {within} ({left} bytes left)"))?;
    let n = u64::from(le32(&n));
    let left = src.len().saturating_sub(at + 4);
    if n > left || n > MAX_BLOCK as u64 {
        return Err(format!(
            "byte {at}: {what} length {n}: expected at most the {left} bytes left in the {within} (truncated or corrupt?)"
        ));
    }
    src.read_exact_at(n as usize)
        .map_err(|e| format!("byte {at}: reading {what} of {n} bytes: {e}"))
}

fn record(src: &mut dyn Source, within: &str) -> std::result::Result<Record, String> {
    let at = src.pos();
    let header = block(src, "record header", within)?;
    let fields = fields(&header).map_err(|e| format!("record at byte {at}: {e}"))?;
    let data = block(src, "record data", within)?;
    Ok(Record { at, fields, data })
}

/// A connection: its topic and message type.
struct Conn {
    topic: String,
    type_name: String,
}

/// How a read went: every topic, and what it had to work around.
pub struct Ros1Read {
    /// Every topic (from the index, or from the chunks read).
    pub topics: Vec<TopicInfo>,
    /// Set when the bag had no usable index and was read from the start.
    pub recovered: Option<String>,
}

/// Hand the messages of the topics `wanted` accepts from `file` (`len`
/// bytes), read from `path`, to `each` in file order. `recover`: a bag
/// without a usable index is read from the start instead of refused.
pub fn stream<R: ReadBlock>(
    file: R,
    len: u64,
    path: &Path,
    (wanted, budget, recover): (Wanted, &mut Budget, bool),
    each: &mut dyn FnMut(RawMessage) -> Result<Flow>,
) -> Result<Ros1Read> {
    let mut src = FileSource { file, pos: 0, len };
    let perr = |e: String| Error::parse(format!("ROS 1 bag: {e}")).in_file(path);
    let magic = src.read_exact_at(MAGIC.len()).unwrap_or_default();
    if magic != MAGIC {
        let v1 = magic.starts_with(b"#ROSBAG V1");
        return Err(Error::parse(if v1 {
            "ROS 1 bag format 1.x: expected format 2.0 (`rosbag fix` converts it)".to_string()
        } else {
            format!(
                "expected the ROS 1 bag magic `#ROSBAG V2.0` at byte 0, found {:?}",
                String::from_utf8_lossy(&magic)
            )
        })
        .in_file(path));
    }
    let hdr = record(&mut src, "file").map_err(perr)?;
    if hdr.op() != Some(OP_BAG_HEADER) {
        return Err(hdr.err(path, "expected the bag header record (op=03)"));
    }
    let first = src.pos;
    match index(path, &mut src, &hdr, wanted) {
        Ok((topics, todo, conns, want)) => {
            let per_chunk = len / (todo.len().max(1) as u64);
            let mut progress = Progress::new(path, per_chunk * todo.len() as u64);
            for (i, chunk_pos) in todo.into_iter().enumerate() {
                progress.update(per_chunk * i as u64);
                let mut c = ChunkRead {
                    path,
                    conns: Conns::Index(&conns, &want),
                    budget: &mut *budget,
                };
                if read_chunk(&mut src, chunk_pos, &mut c, each)? == Flow::Stop {
                    break;
                }
            }
            Ok(Ros1Read {
                topics,
                recovered: None,
            })
        }
        Err(e) if recover => {
            let note = format!("{} Read from the start instead.", e.message);
            let topics = linear(path, &mut src, first, (wanted, budget), each)?;
            Ok(Ros1Read {
                topics,
                recovered: Some(note),
            })
        }
        Err(e) => Err(e),
    }
}

type Index = (Vec<TopicInfo>, Vec<u64>, BTreeMap<u32, Conn>, BTreeSet<u32>);

/// The index section: every topic with its count, the positions of the
/// chunks holding a wanted connection (in file order), the connections and
/// the wanted ones.
fn index<R: ReadBlock>(
    path: &Path,
    src: &mut FileSource<R>,
    hdr: &Record,
    wanted: &dyn Fn(&str) -> bool,
) -> Result<Index> {
    let perr = |e: String| Error::parse(format!("ROS 1 bag: {e}")).in_file(path);
    let len = src.len;
    let index_pos = hdr.u64(path, "index_pos")?;
    let conn_count = hdr.u32(path, "conn_count")?;
    let chunk_count = hdr.u32(path, "chunk_count")?;
    if index_pos == 0 || index_pos >= len {
        return Err(hdr.err(
            path,
            format!("index_pos {index_pos}: expected an index inside the {len}-byte file (a bag still recording or cut short; `rosbag reindex` rebuilds the index)"),
        ));
    }
    // The index section runs to the end of the file: one read, then parsed in
    // memory (a few dozen bytes per chunk).
    let index_len = len - index_pos;
    if index_len > MAX_BLOCK as u64 {
        return Err(hdr.err(path, format!("index section of {index_len} bytes at index_pos {index_pos}: expected at most {MAX_BLOCK}")));
    }
    src.pos = index_pos;
    let index = src
        .read_exact_at(index_len as usize)
        .map_err(|e| Error::io(path, &e))?;
    let mut isrc = Reader::new(&index, Endian::Little);
    let mut conns: BTreeMap<u32, Conn> = BTreeMap::new();
    let mut chunks: Vec<ChunkInfo> = Vec::new();
    while isrc.left() > 0 {
        let mut r = record(&mut isrc, "index section").map_err(|e| {
            perr(format!(
                "index section at byte {index_pos}: {e} (offsets within the section; a bag cut short? `rosbag reindex` rebuilds the index)"
            ))
        })?;
        r.at += index_pos;
        match r.op() {
            Some(OP_CONNECTION) => {
                let id = r.u32(path, "conn")?;
                let conn = connection(path, &r)?;
                conns.insert(id, conn);
            }
            Some(OP_CHUNK_INFO) => chunks.push(chunk_info(path, &r)?),
            _ => {}
        }
    }
    if conns.len() != conn_count as usize || chunks.len() != chunk_count as usize {
        return Err(hdr.err(path, format!(
            "expected {conn_count} connections and {chunk_count} chunk infos in the index, found {} and {} (truncated or corrupt?)",
            conns.len(), chunks.len()
        )));
    }
    let want: BTreeSet<u32> = conns
        .iter()
        .filter(|(_, c)| wanted(&c.topic))
        .map(|(id, _)| *id)
        .collect();
    let mut counts: BTreeMap<u32, u64> = BTreeMap::new();
    for c in &chunks {
        for (id, n) in &c.counts {
            *counts.entry(*id).or_default() += u64::from(*n);
        }
    }
    let mut topics = Vec::new();
    for (id, c) in &conns {
        let t = TopicInfo {
            name: c.topic.clone(),
            type_name: c.type_name.clone(),
            count: Some(counts.get(id).copied().unwrap_or(0)),
        };
        add_topic(&mut topics, t);
    }
    topics.sort();
    let mut todo: Vec<u64> = chunks
        .into_iter()
        .filter(|c| c.counts.iter().any(|(id, _)| want.contains(id)))
        .map(|c| c.pos)
        .collect();
    todo.sort_unstable();
    Ok((topics, todo, conns, want))
}

/// A bag without a usable index, read from `first` (after the bag header)
/// record by record: connections as they come, the messages of each chunk.
/// The first record that does not read is the damage: an error, after the
/// messages before it were handed out.
fn linear<R: ReadBlock>(
    path: &Path,
    src: &mut FileSource<R>,
    first: u64,
    (wanted, budget): (&dyn Fn(&str) -> bool, &mut Budget),
    each: &mut dyn FnMut(RawMessage) -> Result<Flow>,
) -> Result<Vec<TopicInfo>> {
    let mut conns: BTreeMap<u32, Conn> = BTreeMap::new();
    let mut counts: BTreeMap<u32, u64> = BTreeMap::new();
    src.pos = first;
    let mut progress = Progress::new(path, src.len);
    while src.pos < src.len {
        progress.update(src.pos);
        let at = src.pos;
        let r = record(src, "file").map_err(|e| {
            Error::parse(format!(
                "ROS 1 bag without an index, read from the start: {e}; the messages before byte {at} were read"
            ))
            .in_file(path)
        })?;
        match r.op() {
            Some(OP_CHUNK) => {
                let mut c = ChunkRead {
                    path,
                    conns: Conns::Linear(&mut conns, &mut counts, wanted),
                    budget: &mut *budget,
                };
                if chunk_messages(&r, at, &mut c, each)? == Flow::Stop {
                    break;
                }
            }
            Some(OP_CONNECTION) => {
                let id = r.u32(path, "conn")?;
                let conn = connection(path, &r)?;
                conns.entry(id).or_insert(conn);
            }
            _ => {}
        }
    }
    let mut topics = Vec::new();
    for (id, c) in &conns {
        let t = TopicInfo {
            name: c.topic.clone(),
            type_name: c.type_name.clone(),
            count: Some(counts.get(id).copied().unwrap_or(0)),
        };
        add_topic(&mut topics, t);
    }
    topics.sort();
    Ok(topics)
}

fn connection(path: &Path, r: &Record) -> Result<Conn> {
    let topic = r.text(path, "topic")?;
    let inner = fields(&r.data).map_err(|e| r.err(path, format!("connection header: {e}")))?;
    let type_name = inner
        .iter()
        .find(|(n, _)| n == "type")
        .map(|(_, v)| String::from_utf8_lossy(v).into_owned())
        .unwrap_or_default();
    Ok(Conn { topic, type_name })
}

/// A chunk info record: where the chunk is, and its message count per
/// connection.
struct ChunkInfo {
    pos: u64,
    counts: Vec<(u32, u32)>,
}

fn chunk_info(path: &Path, r: &Record) -> Result<ChunkInfo> {
    let pos = r.u64(path, "chunk_pos")?;
    let count = r.u32(path, "count")? as usize;
    if r.data.len() != count.saturating_mul(8) {
        return Err(r.err(
            path,
            format!(
                "chunk info: expected {count} entries of 8 bytes, found {} bytes",
                r.data.len()
            ),
        ));
    }
    let counts = r
        .data
        .chunks_exact(8)
        .map(|e| (le32(&e[..4]), le32(&e[4..])))
        .filter(|(_, n)| *n > 0)
        .collect();
    Ok(ChunkInfo { pos, counts })
}

/// The connections a chunk's messages are matched against.
enum Conns<'a> {
    /// From the index, with the wanted ones.
    Index(&'a BTreeMap<u32, Conn>, &'a BTreeSet<u32>),
    /// Learnt from the chunks as they come (no index), with the message
    /// count per connection and the topic filter.
    Linear(
        &'a mut BTreeMap<u32, Conn>,
        &'a mut BTreeMap<u32, u64>,
        &'a dyn Fn(&str) -> bool,
    ),
}

impl Conns<'_> {
    fn connection(&mut self, id: u32, conn: Conn) {
        if let Conns::Linear(conns, ..) = self {
            conns.entry(id).or_insert(conn);
        }
    }

    /// The connection of a message when its topic is wanted.
    fn wanted(&mut self, id: u32) -> Option<&Conn> {
        match self {
            Conns::Index(conns, want) => conns.get(&id).filter(|_| want.contains(&id)),
            Conns::Linear(conns, counts, wanted) => {
                let c = conns.get(&id)?;
                *counts.entry(id).or_default() += 1;
                wanted(&c.topic).then_some(c)
            }
        }
    }
}

/// What reading a chunk needs.
struct ChunkRead<'a, 'c> {
    path: &'a Path,
    conns: Conns<'c>,
    budget: &'a mut Budget,
}

/// A chunk's records, decompressed in pieces within the block cap and the
/// file's budget; the declared `size` must match.
fn decompress(path: &Path, r: &Record, budget: &mut Budget) -> Result<Vec<u8>> {
    let comp = r.text(path, "compression")?;
    let size = r.u32(path, "size")? as usize;
    let cap = budget.limits.block_bytes;
    if size > cap {
        return Err(Error::limit(format!(
            "ROS 1 bag record at byte {}: chunk of {size} bytes uncompressed: expected at most {cap}",
            r.at
        ))
        .in_file(path));
    }
    let what = format!("ROS 1 bag {comp} chunk at byte {}", r.at);
    let out = match comp.as_str() {
        "none" => return Ok(r.data.clone()),
        "bz2" => budget.inflate(bzip2::read::BzDecoder::new(r.data.as_slice()), &what)?,
        "lz4" => {
            let d = lz4::Decoder::new(r.data.as_slice())
                .map_err(|e| r.err(path, format!("lz4 chunk: cannot decompress: {e}")))?;
            budget.inflate(d, &what)?
        }
        other => {
            return Err(r.err(
                path,
                format!("chunk compression '{other}': expected none, bz2 or lz4"),
            ))
        }
    };
    if out.len() != size {
        return Err(r.err(
            path,
            format!(
                "{comp} chunk: expected {size} bytes uncompressed, found {}",
                out.len()
            ),
        ));
    }
    Ok(out)
}

fn read_chunk<R: ReadBlock>(
    src: &mut FileSource<R>,
    chunk_pos: u64,
    c: &mut ChunkRead,
    each: &mut dyn FnMut(RawMessage) -> Result<Flow>,
) -> Result<Flow> {
    let path = c.path;
    src.pos = chunk_pos;
    let r = record(src, "file").map_err(|e| {
        Error::parse(format!("ROS 1 bag chunk at byte {chunk_pos}: {e}")).in_file(path)
    })?;
    if r.op() != Some(OP_CHUNK) {
        return Err(r.err(
            path,
            "expected a chunk record (op=05), as the chunk info says",
        ));
    }
    chunk_messages(&r, chunk_pos, c, each)
}

/// The messages of the chunk record `r` (at `chunk_pos`) on wanted
/// connections, in order.
fn chunk_messages(
    r: &Record,
    chunk_pos: u64,
    c: &mut ChunkRead,
    each: &mut dyn FnMut(RawMessage) -> Result<Flow>,
) -> Result<Flow> {
    let path = c.path;
    let data = decompress(path, r, c.budget)?;
    let mut inner = Reader::new(&data, Endian::Little);
    let inside = |e: String| r.err(path, format!("inside the chunk: {e}"));
    while inner.left() > 0 {
        let m = record(&mut inner, "chunk").map_err(inside)?;
        match m.op() {
            Some(OP_CONNECTION) => {
                let id = m.u32(path, "conn").map_err(|e| inside(e.message))?;
                let conn = connection(path, &m).map_err(|e| inside(e.message))?;
                c.conns.connection(id, conn);
                continue;
            }
            Some(OP_MSG_DATA) => {}
            _ => continue,
        }
        let conn = m.u32(path, "conn").map_err(|e| inside(e.message))?;
        let Some(cn) = c.conns.wanted(conn) else {
            continue;
        };
        let (topic, type_name) = (cn.topic.clone(), cn.type_name.clone());
        let t = m.u64(path, "time").map_err(|e| inside(e.message))?;
        let (sec, nsec) = (t & 0xffff_ffff, t >> 32);
        let msg = RawMessage {
            topic,
            type_name,
            encoding: Encoding::Ros1,
            time_ns: sec * 1_000_000_000 + nsec,
            data: m.data,
            file: path.to_path_buf(),
            place: format!("chunk at byte {chunk_pos}, record at chunk byte {}", m.at),
        };
        if each(msg)? == Flow::Stop {
            return Ok(Flow::Stop);
        }
    }
    Ok(Flow::Continue)
}
