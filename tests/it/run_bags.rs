//! The bag class of issue 27 through `audit run`: decompression bombs in
//! each container stop at the documented cap (tolerances.rs
//! MAX_BAG_MESSAGE_BYTES) with an error naming the file, a rosbag2 database
//! with pending WAL frames is refused by name, a `messages` view is refused,
//! a FIFO listed in metadata.yaml is named instead of hanging, and a bag's
//! frames go through the common checks (`--invert` refused by name).

use crate::common::hostile::run_audit;
use std::path::{Path, PathBuf};

const DIR: &str = "tests/fixtures/run";

/// A copy of the fixture folder `name` in `dir`.
fn copy_folder(dir: &Path, name: &str) -> PathBuf {
    let to = dir.join(name);
    std::fs::create_dir(&to).unwrap();
    for e in std::fs::read_dir(Path::new(DIR).join(name)).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
    to
}

/// `n` MiB of zeros, zstd-compressed (a few KiB).
fn zstd_zeros(n: usize) -> Vec<u8> {
    use std::io::Write;
    let mut z = zstd::stream::Encoder::new(Vec::new(), 1).unwrap();
    let mib = vec![0u8; 1 << 20];
    for _ in 0..n {
        z.write_all(&mib).unwrap();
    }
    z.finish().unwrap()
}

/// `audit run ARGS` within 120 s: exit 2, no panic, stderr containing every `want`.
fn refused(args: &[&str], want: &[&str]) -> String {
    let out = run_audit(&[&["run"], args].concat(), 120);
    let err = out.stderr.clone();
    assert_eq!(out.code, Some(2), "{args:?}: {err}");
    for w in want {
        assert!(err.contains(w), "{args:?}: expected {w:?} in {err}");
    }
    err
}

/// Past the block cap, tolerances.rs MAX_BAG_MESSAGE_BYTES (256 MiB), by
/// 16 MiB (MiB): if the cap grows past it the read succeeds and the tests fail.
const BOMB_MIB: usize = 256 + 16;

#[test]
fn an_mcap_chunk_bomb_stops_at_the_block_cap() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("bomb.mcap");
    let mut w = mcap::WriteOptions::new()
        .compression(Some(mcap::Compression::Zstd))
        .chunk_size(Some(u64::MAX))
        .create(std::io::BufWriter::new(std::fs::File::create(&f).unwrap()))
        .unwrap();
    let s = w
        .add_schema("sensor_msgs/msg/PointCloud2", "ros2msg", b"")
        .unwrap();
    let c = w
        .add_channel(s, "/points", "cdr", &Default::default())
        .unwrap();
    let mib = vec![0u8; 1 << 20];
    for k in 0..BOMB_MIB as u32 {
        let h = mcap::records::MessageHeader {
            channel_id: c,
            sequence: k,
            log_time: k as u64,
            publish_time: k as u64,
        };
        w.write_to_known_channel(&h, &mib).unwrap();
    }
    w.finish().unwrap();
    drop(w);
    assert!(std::fs::metadata(&f).unwrap().len() < 4 << 20);
    // Refused from the chunk index's declared length, before decompressing.
    refused(&[f.to_str().unwrap()], &["bomb.mcap", "exceeds limit"]);
}

/// The first /points row of a copied rosbag2 folder replaced by `data`.
fn with_first_scan(db: &Path, data: &[u8]) {
    let c = rusqlite::Connection::open(db).unwrap();
    c.execute(
        "UPDATE messages SET data = ?1 WHERE id = (SELECT m.id FROM messages m JOIN topics t \
         ON m.topic_id = t.id WHERE t.name = '/points' ORDER BY m.timestamp LIMIT 1)",
        [data],
    )
    .unwrap();
}

#[test]
fn a_rosbag2_message_bomb_stops_at_the_block_cap() {
    let dir = tempfile::tempdir().unwrap();
    let bag = copy_folder(dir.path(), "run_message_zstd_db3");
    with_first_scan(&bag.join("run_message_zstd_db3.db3"), &zstd_zeros(BOMB_MIB));
    let err = refused(
        &[bag.to_str().unwrap()],
        &["run_message_zstd_db3", "more than 268435456 bytes"],
    );
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn a_wal_database_with_pending_frames_is_refused_by_name_and_left_alone() {
    let dir = tempfile::tempdir().unwrap();
    let bag = copy_folder(dir.path(), "run_db3");
    let db = bag.join("run_db3.db3");
    let c = rusqlite::Connection::open(&db).unwrap();
    c.pragma_update(None, "journal_mode", "WAL").unwrap();
    c.pragma_update(None, "wal_autocheckpoint", 0).unwrap();
    c.execute("DELETE FROM messages WHERE id % 2 = 0", [])
        .unwrap();
    // The writer is still open (a recording that did not close): frames in -wal.
    let wal = bag.join("run_db3.db3-wal");
    let before = |p: &Path| std::fs::read(p).unwrap();
    let (db0, wal0) = (before(&db), before(&wal));
    assert!(!wal0.is_empty());
    refused(&[bag.to_str().unwrap()], &["run_db3.db3-wal", "WAL"]);
    // Nothing beside the input was touched: the database and its -wal are as they were.
    assert_eq!(before(&db), db0);
    assert_eq!(before(&wal), wal0);
    let names: Vec<_> = std::fs::read_dir(&bag)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 4, "{names:?}"); // metadata, .db3, -wal, -shm
    drop(c);
}

#[test]
fn a_messages_view_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let bag = copy_folder(dir.path(), "run_db3");
    let c = rusqlite::Connection::open(bag.join("run_db3.db3")).unwrap();
    c.execute_batch(
        "ALTER TABLE messages RENAME TO m2; CREATE VIEW messages AS SELECT * FROM m2 ORDER BY random();",
    )
    .unwrap();
    drop(c);
    refused(
        &[bag.to_str().unwrap()],
        &["`messages` is a view, not a table"],
    );
}

#[cfg(unix)]
#[test]
fn a_fifo_listed_in_the_metadata_is_named_not_waited_on() {
    let dir = tempfile::tempdir().unwrap();
    let bag = copy_folder(dir.path(), "run_db3");
    let db = bag.join("run_db3.db3");
    std::fs::remove_file(&db).unwrap();
    let p = std::ffi::CString::new(db.to_str().unwrap()).unwrap();
    // SAFETY: a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(p.as_ptr(), 0o600) }, 0);
    refused(&[bag.to_str().unwrap()], &["run_db3.db3", "a FIFO"]);
}

#[test]
fn invert_is_refused_on_a_bag_by_name() {
    let f = format!("{DIR}/run.mcap");
    let out = run_audit(&[&f, "--invert"], 60);
    let err = &out.stderr;
    assert_eq!(out.code, Some(2), "{err}");
    assert!(
        err.contains("--invert") && err.contains("run.mcap"),
        "{err}"
    );
}
