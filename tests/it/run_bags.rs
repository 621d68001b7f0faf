//! The bag class of issue 27 through `audit run`: decompression bombs in
//! each container stop at the documented cap (tolerances.rs
//! MAX_BAG_MESSAGE_BYTES) with an error naming the file, a rosbag2 database
//! with pending WAL frames is refused by name, a `messages` view is refused,
//! a FIFO listed in metadata.yaml is named instead of hanging, and a bag's
//! frames go through the common checks (`--invert` refused by name).

use crate::common::audit;
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

/// One ROS 1 bag header field, `len name=value` (wiki.ros.org/Bags/Format/2.0).
fn ros1_field(name: &str, v: &[u8]) -> Vec<u8> {
    let mut f = ((name.len() + 1 + v.len()) as u32).to_le_bytes().to_vec();
    f.extend(name.as_bytes());
    f.push(b'=');
    f.extend(v);
    f
}

fn ros1_fields(fields: &[(&str, &[u8])]) -> Vec<u8> {
    fields.iter().flat_map(|(n, v)| ros1_field(n, v)).collect()
}

/// A record: `u32 header_len, header, u32 data_len, data`.
fn ros1_record(fields: &[(&str, &[u8])], data: &[u8]) -> Vec<u8> {
    let h = ros1_fields(fields);
    let mut r = (h.len() as u32).to_le_bytes().to_vec();
    r.extend(&h);
    r.extend((data.len() as u32).to_le_bytes());
    r.extend(data);
    r
}

/// A ROS 1 bag, indexed as `rosbag record` leaves it: the magic, a bag
/// header record padded to 4096 bytes, one chunk (`compression`, declared
/// uncompressed `size`, `data`), then at `index_pos` the /points
/// connection and the chunk's info record (one message).
fn ros1_bag(compression: &str, size: u32, data: &[u8]) -> Vec<u8> {
    const HEADER_RECORD: usize = 4096;
    let chunk_pos = (ros1_magic().len() + HEADER_RECORD) as u64;
    let chunk = ros1_record(
        &[
            ("op", &[0x05]),
            ("compression", compression.as_bytes()),
            ("size", &size.to_le_bytes()),
        ],
        data,
    );
    let index_pos = chunk_pos + chunk.len() as u64;
    let conn_header = ros1_fields(&[
        ("topic", b"/points"),
        ("type", b"sensor_msgs/PointCloud2"),
        ("md5sum", b"1158d486dd51d683ce2f1be655c3c181"),
        ("message_definition", b""),
    ]);
    let zero = [0u8; 8];
    let one = 1u32.to_le_bytes();
    let index_at = index_pos.to_le_bytes();
    let header: [(&str, &[u8]); 4] = [
        ("op", &[0x03]),
        ("index_pos", &index_at),
        ("conn_count", &one),
        ("chunk_count", &one),
    ];
    let pad = vec![b' '; HEADER_RECORD - 8 - ros1_fields(&header).len()];
    let mut bag = ros1_magic().to_vec();
    bag.extend(ros1_record(&header, &pad));
    assert_eq!(bag.len() as u64, chunk_pos);
    bag.extend(chunk);
    let conn = [
        ("op", &[0x07][..]),
        ("conn", &[0; 4]),
        ("topic", b"/points"),
    ];
    bag.extend(ros1_record(&conn, &conn_header));
    let info = [
        ("op", &[0x06][..]),
        ("ver", &one),
        ("chunk_pos", &chunk_pos.to_le_bytes()),
        ("start_time", &zero),
        ("end_time", &zero),
        ("count", &one),
    ];
    bag.extend(ros1_record(&info, &[0, 0, 0, 0, 1, 0, 0, 0]));
    bag
}

fn ros1_magic() -> &'static [u8] {
    b"#ROSBAG V2.0\n"
}

/// `BOMB_MIB` MiB of zeros, bz2: 239 bytes, made by
/// `python3 -c "import bz2; print(bz2.compress(bytes(272 << 20), 9).hex())"`
/// (committed: the crate's pure-Rust bzip2 takes minutes to compress 272
/// MiB in a debug build; Python's libbz2 writes it in 1.5 s).
const BZ2_ZEROS_272_MIB: &str = "425a68393141592653590e09e2df015f8e4000c0000008200030804d4642a025a90a80973141592653590e09e2df015f8e4000c0000008200030804d4642a025a90a80973141592653590e09e2df015f8e4000c0000008200030804d4642a025a90a80973141592653590e09e2df015f8e4000c0000008200030804d4642a025a90a80973141592653590e09e2df015f8e4000c0000008200030804d4642a025a90a80973141592653590e09e2df015f8e4000c0000008200030804d4642a025a90a809731415926535944ece032004b31c000c0020008200030cc0529a6a14523608a291e2ee48a70a121669af3b4";

fn bz2_bomb() -> Vec<u8> {
    let h = BZ2_ZEROS_272_MIB.as_bytes();
    let b: Vec<u8> = h
        .chunks(2)
        .map(|c| u8::from_str_radix(std::str::from_utf8(c).unwrap(), 16).unwrap())
        .collect();
    // What it is: the 272 MiB the test says (checked on the first MiB).
    let mut head = vec![0u8; 1 << 20];
    use std::io::Read;
    bzip2::read::BzDecoder::new(b.as_slice())
        .read_exact(&mut head)
        .unwrap();
    assert!(head.iter().all(|&x| x == 0));
    b
}

/// `BOMB_MIB` MiB of zeros as an LZ4 frame (what ROS 1's roslz4 writes), ~1 MiB.
fn lz4_bomb() -> Vec<u8> {
    use std::io::Write;
    let mut e = lz4::EncoderBuilder::new().build(Vec::new()).unwrap();
    let mib = vec![0u8; 1 << 20];
    for _ in 0..BOMB_MIB {
        e.write_all(&mib).unwrap();
    }
    let (out, r) = e.finish();
    r.unwrap();
    out
}

#[test]
fn ros1_chunk_bombs_stop_at_the_block_cap_bz2_and_lz4() {
    let dir = tempfile::tempdir().unwrap();
    let cap = "268435456";
    for (comp, data) in [("bz2", bz2_bomb()), ("lz4", lz4_bomb())] {
        // A chunk that declares 4 KiB and decompresses past the cap: stopped
        // while decompressing, at most the cap held.
        let f = dir.path().join(format!("lie_{comp}.bag"));
        std::fs::write(&f, ros1_bag(comp, 4096, &data)).unwrap();
        assert!(std::fs::metadata(&f).unwrap().len() < 2 << 20);
        let want =
            format!("ROS 1 bag {comp} chunk at byte 4109: decompresses to more than {cap} bytes");
        let err = refused(&[f.to_str().unwrap()], &[&format!("lie_{comp}.bag"), &want]);
        assert!(!err.contains("panicked"), "{err}");
        // One that declares more than the cap: refused before decompressing.
        let f = dir.path().join(format!("big_{comp}.bag"));
        let size = (BOMB_MIB << 20) as u32;
        std::fs::write(&f, ros1_bag(comp, size, &data)).unwrap();
        let want = format!("chunk of {size} bytes uncompressed: expected at most {cap}");
        refused(&[f.to_str().unwrap()], &[&format!("big_{comp}.bag"), &want]);
    }
}

/// A zstd file of `n` frames, each `BOMB_MIB` MiB of zeros compressed (zstd
/// decoders read concatenated frames as one stream): compressed once.
fn zstd_frames(n: usize) -> Vec<u8> {
    zstd_zeros(BOMB_MIB).repeat(n)
}

#[test]
fn rosbag2_file_compressed_bombs_stop_at_the_file_cap() {
    // Per-file compression (compression_mode file): the split is inflated
    // into a private temporary (a database, or an anonymous file for MCAP)
    // within the file's budget, max(1 GiB, 100x its size): 4 frames of
    // 272 MiB (1088 MiB from ~40 KiB) pass it. TMPDIR is the test's, so
    // what the run leaves there is seen.
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let bomb = zstd_frames(4);
    assert!(bomb.len() < 1 << 20, "{}", bomb.len());
    for inner in ["db3", "mcap"] {
        let bag = copy_folder(dir.path(), "run_file_zstd_db3");
        let split = format!("run_file_zstd_db3.{inner}.zstd");
        std::fs::remove_file(bag.join("run_file_zstd_db3.db3.zstd")).unwrap();
        std::fs::write(bag.join(&split), &bomb).unwrap();
        let meta = std::fs::read_to_string(bag.join("metadata.yaml")).unwrap();
        let meta = meta.replace("run_file_zstd_db3.db3.zstd", &split);
        let meta = if inner == "mcap" {
            meta.replace("storage_identifier: sqlite3", "storage_identifier: mcap")
        } else {
            meta
        };
        std::fs::write(bag.join("metadata.yaml"), meta).unwrap();
        let out = audit()
            .env("TMPDIR", &tmp)
            .args(["run", bag.to_str().unwrap()])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{inner}: {err}");
        assert!(
            err.contains(&split)
                && err.contains("zstd-compressed rosbag2 split (compression_mode file): decompresses to more than 1073741824 bytes"),
            "{inner}: {err}"
        );
        // The temporary is gone: nothing of the gigabyte is left behind.
        let left: Vec<_> = std::fs::read_dir(&tmp).unwrap().collect();
        assert!(left.is_empty(), "{inner}: {left:?}");
        std::fs::remove_dir_all(&bag).unwrap();
    }
}
