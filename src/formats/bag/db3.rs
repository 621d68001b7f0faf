//! rosbag2 sqlite3 storage (`.db3`): table `topics(id, name, type,
//! serialization_format, ...)` and table `messages(id, topic_id, timestamp,
//! data)`, one CDR message per row, `timestamp` the receive time in ns.
//!
//! The database is opened read-only and immutable (no journal, no lock files
//! beside a bag that may sit on a read-only disk); only the rows of the wanted
//! topics are fetched. rosbag2 indexes `messages` by timestamp only, so the
//! query scans the table's leaf pages: payloads larger than a page live in
//! overflow pages that are not read (a 1 GB bag of 1 MiB messages reads
//! ~1.4 MB), but a bag of small messages is read through (356 MB of 1 KiB
//! messages: ~0.3 s).

use super::contents::{Contents, RawMessage};
use super::decode::Encoding;
use crate::diagnostic::{Error, Result};
use rusqlite::{Connection, OpenFlags};
use std::path::Path;

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

/// Read the messages of the topics `wanted` accepts.
pub fn read(path: &Path, wanted: &dyn Fn(&str) -> bool) -> Result<Contents> {
    // Non-UTF-8 paths are read through a lossy URI; refuse rather than open another file.
    if path.to_str().is_none() {
        return Err(
            Error::usage("the .db3 path is not valid UTF-8: rename the file").in_file(path),
        );
    }
    let flags = OpenFlags::SQLITE_OPEN_READ_ONLY
        | OpenFlags::SQLITE_OPEN_URI
        | OpenFlags::SQLITE_OPEN_NO_MUTEX;
    let db = Connection::open_with_flags(uri(path), flags).map_err(|e| db_err(path, "open", e))?;
    let topics = topics(&db).map_err(|e| db_err(path, "table `topics`", e))?;
    let mut out = Contents {
        topics: topics.iter().map(|t| t.1.clone()).collect(),
        messages: Vec::new(),
    };
    let mut stmt = db
        .prepare(
            "SELECT id, timestamp, data FROM messages WHERE topic_id = ?1 ORDER BY timestamp, id",
        )
        .map_err(|e| db_err(path, "table `messages`", e))?;
    for (id, name, type_name, format) in topics.iter().filter(|t| wanted(&t.1)) {
        if format != "cdr" {
            return Err(Error::parse(format!(
                "topic {name}: serialization_format '{format}': expected 'cdr'"
            ))
            .in_file(path));
        }
        let rows = stmt
            .query_map([id], |r| {
                Ok((
                    r.get::<_, i64>(0)?,
                    r.get::<_, i64>(1)?,
                    r.get::<_, Vec<u8>>(2)?,
                ))
            })
            .map_err(|e| db_err(path, "table `messages`", e))?;
        for row in rows {
            let (row_id, ts, data) = row.map_err(|e| db_err(path, "table `messages`", e))?;
            out.messages.push(RawMessage {
                topic: name.clone(),
                type_name: type_name.clone(),
                encoding: Encoding::Cdr,
                time_ns: u64::try_from(ts).unwrap_or(0),
                data,
                file: path.to_path_buf(),
                place: format!("messages row id {row_id}"),
            });
        }
    }
    Ok(out)
}

type TopicRow = (i64, String, String, String);

fn topics(db: &Connection) -> rusqlite::Result<Vec<TopicRow>> {
    let mut stmt =
        db.prepare("SELECT id, name, type, serialization_format FROM topics ORDER BY id")?;
    let rows = stmt.query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?)))?;
    rows.collect()
}
