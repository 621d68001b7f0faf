//! rosbag2 sqlite3 storage (`.db3`): table `topics(id, name, type,
//! serialization_format, ...)` and table `messages(id, topic_id, timestamp,
//! data)`, one CDR message per row, `timestamp` the receive time in ns
//! (rosbag2_storage_sqlite3, `sqlite_storage.cpp`).
//!
//! The database is opened read-only and immutable (no journal, no lock or
//! `-shm` file beside a bag that may sit on a read-only disk), after checks
//! that make that safe (issue 27):
//!
//! - a special file (FIFO, device, directory) is refused before SQLite opens
//!   it (opening a FIFO would block);
//! - a database in WAL mode whose `-wal` file holds frames, or one with a
//!   non-empty rollback `-journal`, is refused by name: an immutable read
//!   ignores both and would silently give the older contents (rosbag2 records
//!   in WAL mode; a recording that did not close leaves its last messages in
//!   the `-wal` file). Reading them needs SQLite to write a `-shm` file beside
//!   the input, which this tool never does; the message says how to
//!   checkpoint a copy;
//! - `topics` and `messages` must be tables, not views (a recursive view
//!   makes every query run away);
//! - SQLite's memory is capped (a hard heap limit, an in-memory temporary
//!   store, a small page cache), so no query can fill the disk or the memory.
//!
//! Rows are read in row-id order (insertion, i.e. recording order) with the
//! length of their data, then each wanted row's data is fetched by its id:
//! the scan reads the table's leaf pages, never the overflow pages of the
//! rows not wanted (a 1 GB bag of 1 MiB messages reads ~1.4 MB), and no
//! sort is needed. A message's data is checked against the block cap before
//! it is fetched, and, in a bag compressed per message, decompressed within
//! the file's budget.

use super::contents::{Flow, RawMessage, TopicInfo, Wanted};
use super::decode::Encoding;
use super::inflate::Budget;
use crate::diagnostic::{Error, Result};
use crate::tolerances::{MAX_SQLITE_CACHE_KIB, MAX_SQLITE_HEAP_BYTES};
use rusqlite::{Connection, OpenFlags};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The 16 bytes an SQLite database starts with.
pub const MAGIC: &[u8; 16] = b"SQLite format 3\0";

fn db_err(path: &Path, what: &str, e: rusqlite::Error) -> Error {
    Error::parse(format!(
        "rosbag2 sqlite3 {what}: {e} (expected a rosbag2 .db3 with tables `topics` and `messages`; a truncated or corrupt database?)"
    ))
    .in_file(path)
}

/// `file:` URI for `path`, with the characters URIs reserve escaped.
fn uri(path: &Path) -> String {
    let mut s = String::from("file:");
    for b in path.to_string_lossy().bytes() {
        match b {
            b'%' | b'?' | b'#' => s.push_str(&format!("%{b:02X}")),
            _ => s.push(char::from(b)),
        }
    }
    s.push_str("?immutable=1");
    s
}

/// `path` with `suffix` appended to its file name (`x.db3-wal`).
fn beside(path: &Path, suffix: &str) -> PathBuf {
    let mut s = path.as_os_str().to_os_string();
    s.push(suffix);
    PathBuf::from(s)
}

/// A database whose latest contents are not all in the main file: WAL mode
/// with frames in its `-wal` file, or a hot rollback journal. An immutable
/// read would silently miss them.
fn pending_writes(path: &Path, head: &[u8]) -> Result<()> {
    let nonempty = |p: &Path| std::fs::metadata(p).is_ok_and(|m| m.len() > 0);
    // Bytes 18 and 19: file format write and read versions, 2 in WAL mode.
    let wal_mode = head.get(18..20) == Some(&[2, 2]);
    let wal = beside(path, "-wal");
    let journal = beside(path, "-journal");
    let file = path.file_name().map(|n| n.to_string_lossy().into_owned());
    let file = file.unwrap_or_default();
    let how = format!(
        "checkpoint a copy first: cp {file}* /tmp/ && sqlite3 /tmp/{file} 'PRAGMA wal_checkpoint(TRUNCATE);', then read /tmp/{file}"
    );
    if nonempty(&wal) {
        let mode = if wal_mode { "in WAL mode" } else { "" };
        return Err(Error::parse(format!(
            "rosbag2 sqlite3 database {mode} with uncommitted frames in {} (a recording that did not close): reading the .db3 alone would give older contents, and reading the -wal needs SQLite to write beside the input; {how}",
            wal.display()
        ))
        .in_file(path));
    }
    if nonempty(&journal) {
        return Err(Error::parse(format!(
            "rosbag2 sqlite3 database with a hot rollback journal {} (a write that did not finish): the .db3 alone may be inconsistent; open a copy with sqlite3 to roll it back first",
            journal.display()
        ))
        .in_file(path));
    }
    Ok(())
}

/// Cap SQLite's memory for every connection of the process (a hard heap
/// limit), before the first connection.
fn cap_sqlite_memory() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // SAFETY: sets a process-wide limit; no pointer is passed.
        unsafe {
            rusqlite::ffi::sqlite3_hard_heap_limit64(MAX_SQLITE_HEAP_BYTES);
        }
    });
}

/// Open `path` read-only and immutable after the checks of the module docs.
/// SQLite opens a file lazily: the first statement opens it, so a caller
/// may remove the file's name right after this returns.
pub(super) fn open(path: &Path) -> Result<Connection> {
    // Non-UTF-8 paths are read through a lossy URI; refuse rather than open another file.
    if path.to_str().is_none() {
        return Err(
            Error::usage("the .db3 path is not valid UTF-8: rename the file").in_file(path),
        );
    }
    // A FIFO, a device or a directory is refused here, before SQLite blocks on it.
    let file = crate::input::open_regular(path)?;
    let head = crate::input::head_of(&file, 100).map_err(|e| Error::io(path, &e))?;
    drop(file);
    pending_writes(path, &head)?;
    cap_sqlite_memory();
    let flags = OpenFlags::SQLITE_OPEN_READ_ONLY
        | OpenFlags::SQLITE_OPEN_URI
        | OpenFlags::SQLITE_OPEN_NO_MUTEX;
    let db = Connection::open_with_flags(uri(path), flags).map_err(|e| db_err(path, "open", e))?;
    db.execute_batch(&format!(
        "PRAGMA temp_store = MEMORY; PRAGMA cache_size = -{MAX_SQLITE_CACHE_KIB};"
    ))
    .map_err(|e| db_err(path, "settings", e))?;
    real_tables(&db).map_err(|e| match e {
        Some(e) => e.in_file(path),
        None => db_err(path, "schema", rusqlite::Error::InvalidQuery),
    })?;
    Ok(db)
}

/// `topics` and `messages` are tables (not views, not missing).
fn real_tables(db: &Connection) -> std::result::Result<(), Option<Error>> {
    for name in ["topics", "messages"] {
        let kind: Option<String> = db
            .query_row(
                "SELECT type FROM sqlite_master WHERE name = ?1",
                [name],
                |r| r.get(0),
            )
            .map(Some)
            .or_else(|e| match e {
                rusqlite::Error::QueryReturnedNoRows => Ok(None),
                e => Err(Some(Error::parse(format!(
                    "rosbag2 sqlite3 schema: {e} (a truncated or corrupt database?)"
                )))),
            })?;
        match kind.as_deref() {
            Some("table") => {}
            other => {
                return Err(Some(Error::parse(format!(
                    "rosbag2 sqlite3: `{name}` is {}: expected rosbag2's table `{name}`",
                    other.map_or("missing".to_string(), |k| format!("a {k}, not a table"))
                ))))
            }
        }
    }
    Ok(())
}

/// A topic row: name, type, serialization format.
type TopicRow = (String, String, String);

fn topics(db: &Connection) -> rusqlite::Result<BTreeMap<i64, TopicRow>> {
    let mut stmt = db.prepare("SELECT id, name, type, serialization_format FROM topics")?;
    let rows = stmt.query_map([], |r| Ok((r.get(0)?, (r.get(1)?, r.get(2)?, r.get(3)?))))?;
    rows.collect()
}

/// Hand the messages of the topics `wanted` accepts to `each`, in row-id
/// order; `compressed`: each message's data is one zstd frame (rosbag2
/// `compression_mode: message`). `path` names the file in messages.
pub fn stream(
    db: &Connection,
    path: &Path,
    (wanted, budget, compressed): (Wanted, &mut Budget, bool),
    each: &mut dyn FnMut(RawMessage) -> Result<Flow>,
) -> Result<Vec<TopicInfo>> {
    let topics = topics(db).map_err(|e| db_err(path, "table `topics`", e))?;
    let mut list: Vec<TopicInfo> = topics
        .values()
        .map(|(name, type_name, _)| TopicInfo {
            name: name.clone(),
            type_name: type_name.clone(),
            count: None,
        })
        .collect();
    list.sort();
    let want: BTreeMap<i64, &TopicRow> = topics
        .iter()
        .filter(|(_, t)| wanted(&t.0))
        .map(|(id, t)| (*id, t))
        .collect();
    for (name, _, format) in want.values() {
        if format != "cdr" {
            return Err(Error::parse(format!(
                "topic {name}: serialization_format '{format}': expected 'cdr'"
            ))
            .in_file(path));
        }
    }
    if want.is_empty() {
        return Ok(list);
    }
    let msg_err = |e| db_err(path, "table `messages`", e);
    let mut rows = db
        .prepare("SELECT rowid, topic_id, timestamp, length(data) FROM messages ORDER BY rowid")
        .map_err(msg_err)?;
    let mut data = db
        .prepare("SELECT data FROM messages WHERE rowid = ?1")
        .map_err(msg_err)?;
    let mut q = rows.query([]).map_err(msg_err)?;
    while let Some(r) = q.next().map_err(msg_err)? {
        let col = |k: usize| r.get::<_, i64>(k).map_err(msg_err);
        let (row_id, topic_id, ts, len) = (col(0)?, col(1)?, col(2)?, col(3)?);
        let Some((name, type_name, _)) = want.get(&topic_id) else {
            continue;
        };
        let place = format!("messages row id {row_id}");
        let cap = budget.limits.block_bytes;
        if len < 0 || len as u64 > cap as u64 {
            return Err(Error::limit(format!(
                "{name} message ({place}): {len} bytes: expected at most {cap}"
            ))
            .in_file(path));
        }
        let bytes: Vec<u8> = data.query_row([row_id], |r| r.get(0)).map_err(msg_err)?;
        let bytes = if compressed {
            let what = format!("{name} message ({place}): expected zstd-compressed bytes (compression_mode message)");
            let d = zstd::stream::read::Decoder::new(bytes.as_slice())
                .map_err(|e| Error::parse(format!("{what}: {e}")).in_file(path))?;
            budget.inflate(d, &what)?
        } else {
            bytes
        };
        let m = RawMessage {
            topic: name.clone(),
            type_name: type_name.clone(),
            encoding: Encoding::Cdr,
            time_ns: u64::try_from(ts).unwrap_or(0),
            data: bytes,
            file: path.to_path_buf(),
            place,
        };
        if each(m)? == Flow::Stop {
            break;
        }
    }
    Ok(list)
}
