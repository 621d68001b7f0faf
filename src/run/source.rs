//! Where a run's scans come from, one at a time: a bag's `PointCloud2` topic
//! ([`BagScans`]), a KITTI sequence or a list of point files ([`FileScans`]).
//! A source only finds and frames the scans (their bytes, time, frame and
//! place); decoding the points is the workers' ([`super::scan`]).
//!
//! A scan's `index` is its place in the run before any selection (the
//! message's index within the topic in file order, the file's in name
//! order); `--start`/`--end` ([`ScanWindow`]) and `--every` select among them.
//! Times are seconds after the run's first scan: a message's `header.stamp`
//! (the time of the sweep, as drivers set it), a KITTI sequence's
//! `times.txt`; a file sequence without either has no times.

use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::formats::bag::{self, decode::Encoding, pointcloud2, BagLimits, Flow, RawMessage};
use std::path::{Path, PathBuf};

/// The `PointCloud2` type names (ROS 2, ROS 1).
pub const POINTCLOUD2_TYPES: &[&str] = &["sensor_msgs/msg/PointCloud2", "sensor_msgs/PointCloud2"];

/// One scan, as a source yields it.
#[derive(Debug, Clone)]
pub struct ScanItem {
    /// Its place in the run (see the module docs).
    pub index: usize,
    /// The file it is in, or the bag's name.
    pub file: PathBuf,
    /// Where in the file (`chunk at byte N`), or the file's name.
    pub place: String,
    /// The sweep's time: `header.stamp` (ns) for a message.
    pub stamp_ns: Option<i128>,
    /// Seconds after the run's first scan.
    pub time_s: Option<f64>,
    /// The scan frame (`header.frame_id`, leading `/` dropped); `None` for
    /// files that name none.
    pub frame_id: Option<String>,
    /// Cells the scan holds (`height * width`; estimated from the size for
    /// files): what the work queue budgets by.
    pub cells: usize,
    /// The bytes to decode.
    pub payload: Payload,
}

/// What a scan's points are read from.
#[derive(Debug, Clone)]
pub enum Payload {
    /// A serialised `sensor_msgs/PointCloud2`.
    Cloud2 {
        /// The message.
        data: Vec<u8>,
        /// Its wire format.
        encoding: Encoding,
    },
    /// A KITTI `.bin` file (float32 x y z intensity).
    KittiBin(PathBuf),
    /// A point file (PCD, PLY, CSV, LAS, LAZ).
    PointFile(PathBuf),
}

/// `--start` / `--end`: a scan index or seconds after the first scan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ScanBound {
    /// A scan index (its place in the run).
    Index(usize),
    /// Seconds after the run's first scan.
    Seconds(f64),
}

impl ScanBound {
    /// `12` (an index) or `12.5s` (seconds).
    pub fn parse(s: &str, flag: &str) -> Result<ScanBound> {
        let t = s.trim();
        if let Some(sec) = t.strip_suffix('s') {
            let v: f64 = sec.trim().parse().map_err(|_| bad(flag, s))?;
            if v.is_finite() && v >= 0.0 {
                return Ok(ScanBound::Seconds(v));
            }
            return Err(bad(flag, s));
        }
        t.parse::<usize>()
            .map(ScanBound::Index)
            .map_err(|_| bad(flag, s))
    }
}

fn bad(flag: &str, s: &str) -> Error {
    Error::usage(format!(
        "{flag}: expected a scan index (`120`) or seconds after the first scan (`12.5s`), found `{s}`"
    ))
}

/// Which scans of a run are analysed: from `start` (kept) to `end` (the first
/// one no longer kept), every `every`-th of those.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanWindow {
    /// The first scan kept.
    pub start: Option<ScanBound>,
    /// The first scan no longer kept.
    pub end: Option<ScanBound>,
    /// Keep every `every`-th scan from the start (1: all).
    pub every: usize,
}

impl Default for ScanWindow {
    fn default() -> Self {
        ScanWindow {
            start: None,
            end: None,
            every: 1,
        }
    }
}

/// Where a scan stands relative to a window.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Place {
    /// Before the start, or between two kept scans.
    Skip,
    /// Kept.
    Keep,
    /// At or past the end: nothing after it is kept.
    Past,
}

impl ScanWindow {
    /// Where the scan `index` at `time_s` stands; `kept` scans are counted
    /// from the start for `every`.
    pub(crate) fn place(
        &self,
        index: usize,
        time_s: Option<f64>,
        started: &mut Option<usize>,
    ) -> Place {
        let reached = |b: ScanBound| match b {
            ScanBound::Index(i) => index >= i,
            ScanBound::Seconds(s) => time_s.is_some_and(|t| t >= s),
        };
        if self.end.is_some_and(reached) {
            return Place::Past;
        }
        if !self.start.is_none_or(reached) {
            return Place::Skip;
        }
        let first = *started.get_or_insert(index);
        if (index - first).is_multiple_of(self.every.max(1)) {
            Place::Keep
        } else {
            Place::Skip
        }
    }

    /// A window given in seconds needs times.
    pub fn needs_times(&self) -> bool {
        matches!(self.start, Some(ScanBound::Seconds(_)))
            || matches!(self.end, Some(ScanBound::Seconds(_)))
    }
}

/// How a source's pass ended.
#[derive(Debug, Default)]
pub struct SourceEnd {
    /// What stopped the read early (a truncated or corrupt file): the scans
    /// before it were handed out.
    pub damage: Option<Error>,
    /// Named warnings about the source (a bag read without its index, ...).
    pub warnings: Vec<Warning>,
}

/// A run's scans, handed out one at a time.
pub trait ScanSource: Send {
    /// What the source reads, for messages (`run.mcap, topic /points`).
    fn describe(&self) -> String;
    /// Hand every scan in the window to `each` (which may stop the pass),
    /// in run order.
    fn scans(&mut self, each: &mut dyn FnMut(ScanItem) -> Result<Flow>) -> Result<SourceEnd>;
}

/// A bag's `PointCloud2` topic (one bag, or the parts of one recording read
/// in order).
pub struct BagScans {
    /// The bags, in order.
    pub bags: Vec<PathBuf>,
    /// The topic.
    pub topic: String,
    /// Which scans.
    pub window: ScanWindow,
    /// Decompression caps.
    pub limits: BagLimits,
}

impl ScanSource for BagScans {
    fn describe(&self) -> String {
        let names: Vec<String> = self.bags.iter().map(|b| b.display().to_string()).collect();
        format!("{}, topic {}", names.join(", "), self.topic)
    }

    fn scans(&mut self, each: &mut dyn FnMut(ScanItem) -> Result<Flow>) -> Result<SourceEnd> {
        let mut end = SourceEnd::default();
        let mut index = 0usize;
        let mut first: Option<i128> = None;
        let mut started = None;
        let topic = self.topic.clone();
        for b in &self.bags {
            let mut stop = false;
            let mut one = |m: RawMessage| -> Result<Flow> {
                let k = index;
                index += 1;
                let item = message_item(k, m, &mut first)?;
                match self.window.place(k, item.time_s, &mut started) {
                    Place::Skip => Ok(Flow::Continue),
                    Place::Past => {
                        stop = true;
                        Ok(Flow::Stop)
                    }
                    Place::Keep => {
                        let f = each(item)?;
                        stop |= f == Flow::Stop;
                        Ok(f)
                    }
                }
            };
            match bag::stream(b, &|t| t == topic, self.limits, &mut one) {
                Ok(listing) => end.warnings.extend(listing.warnings),
                // Damage after scans: reported up to it. A limit (a
                // decompression bomb) is a refusal wherever it is, exit 2.
                Err(e) if index > 0 && !matches!(e.code, Code::Usage | Code::Limit) => {
                    end.damage = Some(e);
                    break;
                }
                Err(e) => return Err(e),
            }
            if stop {
                break;
            }
        }
        Ok(end)
    }
}

/// A message of the topic as a scan: its type checked, its header read
/// (the points are not touched here).
fn message_item(index: usize, m: RawMessage, first: &mut Option<i128>) -> Result<ScanItem> {
    if !m.type_name.is_empty() && !POINTCLOUD2_TYPES.contains(&m.type_name.as_str()) {
        return Err(Error::parse(format!(
            "{} message #{index}: type '{}': expected sensor_msgs/msg/PointCloud2",
            m.topic, m.type_name
        ))
        .in_file(&m.file));
    }
    let head = pointcloud2::decode(&m.data, m.encoding);
    let (stamp, frame, cells) = match &head {
        Ok(c) => (
            Some(c.stamp_ns),
            Some(c.frame_id.trim_start_matches('/').to_string()),
            c.height as usize * c.width as usize,
        ),
        // Decoded again (and the error reported) by the worker.
        Err(_) => (None, None, m.data.len() / 16),
    };
    let t0 = *first.get_or_insert_with(|| stamp.unwrap_or(0));
    Ok(ScanItem {
        index,
        file: m.file,
        place: m.place,
        stamp_ns: stamp,
        time_s: stamp.map(|s| (s - t0) as f64 * 1e-9),
        frame_id: frame,
        cells,
        payload: Payload::Cloud2 {
            data: m.data,
            encoding: m.encoding,
        },
    })
}

/// A sequence of files (KITTI `.bin` files or point files), in the order given.
pub struct FileScans {
    /// The files.
    pub files: Vec<PathBuf>,
    /// Seconds of each file (KITTI `times.txt`), when known.
    pub times: Option<Vec<f64>>,
    /// The scan frame, when named (`--lidar-frame`).
    pub frame_id: Option<String>,
    /// Which scans.
    pub window: ScanWindow,
    /// What the folder or pattern was, for messages.
    pub what: String,
}

impl ScanSource for FileScans {
    fn describe(&self) -> String {
        self.what.clone()
    }

    fn scans(&mut self, each: &mut dyn FnMut(ScanItem) -> Result<Flow>) -> Result<SourceEnd> {
        let mut started = None;
        for (k, f) in self.files.iter().enumerate() {
            let time_s = self.times.as_ref().and_then(|t| t.get(k).copied());
            match self.window.place(k, time_s, &mut started) {
                Place::Skip => continue,
                Place::Past => break,
                Place::Keep => {}
            }
            let kitti = f.extension().is_some_and(|e| e.eq_ignore_ascii_case("bin"));
            let size = crate::input::reported_size(f).unwrap_or(0) as usize;
            let item = ScanItem {
                index: k,
                file: f.clone(),
                place: f
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                stamp_ns: None,
                time_s,
                frame_id: self.frame_id.clone(),
                cells: if kitti { size / 16 } else { size / 12 },
                payload: if kitti {
                    Payload::KittiBin(f.clone())
                } else {
                    Payload::PointFile(f.clone())
                },
            };
            if each(item)? == Flow::Stop {
                break;
            }
        }
        Ok(SourceEnd::default())
    }
}

/// The files of a sequence given as paths: a folder's point files (or its
/// `velodyne/` files) in name order, files as given, a `*`/`?` pattern in the
/// file name expanded in name order.
pub fn sequence_files(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let dir = if p.join("velodyne").is_dir() {
                p.join("velodyne")
            } else {
                p.clone()
            };
            let mut v = list(&dir, &|n| is_scan_file(Path::new(n)))?;
            if v.is_empty() {
                return Err(Error::usage(
                    "expected a run: a bag, a KITTI sequence (velodyne/*.bin) or a folder of point files (.pcd, .ply, .csv, .las, .laz, .bin), found no such file in the folder",
                )
                .in_file(p));
            }
            out.append(&mut v);
        } else if let Some(pattern) = wildcard(p) {
            let dir = p.parent().filter(|d| !d.as_os_str().is_empty());
            let dir = dir.unwrap_or(Path::new("."));
            let mut v = list(dir, &|n| matches(pattern.as_bytes(), n.as_bytes()))?;
            if v.is_empty() {
                return Err(
                    Error::usage(format!("the pattern `{pattern}` matches no file")).in_file(dir),
                );
            }
            out.append(&mut v);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

/// The file-name pattern of `p`, when it has a wildcard and no such file exists.
fn wildcard(p: &Path) -> Option<String> {
    let name = p.file_name()?.to_str()?;
    (name.contains(['*', '?']) && !p.exists()).then(|| name.to_string())
}

/// `*` (any run) and `?` (one byte) matching.
fn matches(p: &[u8], s: &[u8]) -> bool {
    match (p.first(), s.first()) {
        (None, None) => true,
        (Some(b'*'), _) => matches(&p[1..], s) || (!s.is_empty() && matches(p, &s[1..])),
        (Some(b'?'), Some(_)) => matches(&p[1..], &s[1..]),
        (Some(a), Some(b)) if a == b => matches(&p[1..], &s[1..]),
        _ => false,
    }
}

/// The extensions of the files a sequence folder is read for.
fn is_scan_file(p: &Path) -> bool {
    p.extension().is_some_and(|e| {
        let e = e.to_string_lossy().to_ascii_lowercase();
        matches!(e.as_str(), "pcd" | "ply" | "csv" | "las" | "laz" | "bin")
    })
}

/// The regular files of `dir` whose names `keep` takes, in name order.
fn list(dir: &Path, keep: &dyn Fn(&str) -> bool) -> Result<Vec<PathBuf>> {
    let rd = std::fs::read_dir(dir).map_err(|e| Error::io(dir, &e))?;
    let mut v: Vec<PathBuf> = Vec::new();
    for e in rd {
        let e = e.map_err(|e| Error::io(dir, &e))?;
        let name = e.file_name().to_string_lossy().into_owned();
        if keep(&name) && e.path().is_file() {
            v.push(e.path());
        }
    }
    v.sort();
    Ok(v)
}

/// A KITTI `times.txt` (one time in seconds per line, the sequence's order),
/// beside `velodyne/` or beside the files.
pub fn kitti_times(files: &[PathBuf]) -> Result<Option<(PathBuf, Vec<f64>)>> {
    let Some(dir) = files.first().and_then(|f| f.parent()) else {
        return Ok(None);
    };
    let candidates = [dir.join("times.txt"), dir.join("../times.txt")];
    let Some(path) = candidates.into_iter().find(|p| p.is_file()) else {
        return Ok(None);
    };
    let text = crate::input::read_text(&path, 64 << 20, "the times.txt size cap")?;
    let mut v = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if t.is_empty() {
            continue;
        }
        let x: f64 = t.parse().map_err(|_| {
            Error::parse(format!(
                "expected a time in seconds, found `{}`",
                crate::sanitize::quote(t)
            ))
            .at(&Location::at(&path, i + 1, None))
        })?;
        v.push(x);
    }
    Ok(Some((path, v)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_select_by_index_time_and_step() {
        let w = ScanWindow {
            start: Some(ScanBound::Index(2)),
            end: Some(ScanBound::Seconds(0.65)),
            every: 2,
        };
        let mut started = None;
        let got: Vec<Place> = (0..8)
            .map(|k| w.place(k, Some(0.1 * k as f64), &mut started))
            .collect();
        use Place::*;
        assert_eq!(got, [Skip, Skip, Keep, Skip, Keep, Skip, Keep, Past]);
        assert_eq!(
            ScanBound::parse("12.5s", "--start").unwrap(),
            ScanBound::Seconds(12.5)
        );
        assert_eq!(ScanBound::parse("7", "--end").unwrap(), ScanBound::Index(7));
        assert!(ScanBound::parse("-1s", "--end").is_err());
    }

    #[test]
    fn patterns_match_names() {
        assert!(matches(b"*.pcd", b"scan_001.pcd"));
        assert!(matches(b"scan_00?.pcd", b"scan_001.pcd"));
        assert!(!matches(b"*.pcd", b"scan.ply"));
    }
}
