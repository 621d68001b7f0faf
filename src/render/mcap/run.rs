//! `audit run --format mcap --output FILE.mcap`: the run timeline as an
//! MCAP file, streamed as the scans finish (memory does not grow with the
//! run).
//!
//! | topic | schema | messages |
//! |---|---|---|
//! | `/tf` | `foxglove.FrameTransforms` (Foxglove's) | one, at the first scan's time: the run's transforms and the rig frames |
//! | `/audit/run` | `extrinsic_audit.RunScan` (`docs/schemas/mcap/RunScan.json`) | one per scan (or pair), in run order |
//!
//! A `RunScan` is the scan's JSON line (`--jsonl`), field for field, less
//! its null fields, with a `timestamp`: Foxglove's plot panel draws any of its numbers
//! against time (`/audit/run.frames[:]{frame=="base_link"}.families[:]{family=="point_displacement"}.eigenvalues[0]`).
//!
//! # Time
//!
//! A message's log time (and publish time, and `timestamp`) is the scan's
//! `header.stamp` (ns since the Unix epoch) when it has one; otherwise its
//! `time_s` (KITTI's `times.txt`: seconds from the sequence's start); otherwise
//! its index in seconds (a folder of point files has no time). The metadata's
//! `log_time` names the rule each message followed as the first did.

use super::foxglove::Time;
use super::write::{channel, finish, message, transforms, writer, FRAME_TRANSFORMS, TF_TOPIC};
use crate::diagnostic::{Code, Error, Result};
use crate::document::scene::SceneTransform;
use crate::report::run::ScanRecord;
use std::io::{Seek, Write};

/// The topic of the per-scan messages.
pub const RUN_TOPIC: &str = "/audit/run";
/// This tool's schema of a per-scan message (JSON Schema 2020-12).
const RUN_SCAN: &[u8] = include_bytes!("../../../docs/schemas/mcap/RunScan.json");
const RUN_SCAN_NAME: &str = "extrinsic_audit.RunScan";

/// One `/audit/run` message: the JSON line without its nulls (Foxglove's
/// JSON-schema reader takes one `type` per field, never `null`), and its
/// time.
fn run_scan(r: &ScanRecord, at: Time) -> Result<serde_json::Value> {
    let encode = |e: serde_json::Error| Error::new(Code::Io, format!("cannot encode a scan: {e}"));
    let mut v = serde_json::to_value(r).map_err(encode)?;
    drop_nulls(&mut v);
    if let serde_json::Value::Object(m) = &mut v {
        m.insert(
            "timestamp".into(),
            serde_json::to_value(at).map_err(encode)?,
        );
    }
    Ok(v)
}

/// Every `null` member of every object removed (nulls in arrays stay: a
/// non-finite eigenvalue is then refused by the schema, never hidden).
fn drop_nulls(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Object(m) => {
            m.retain(|_, x| !x.is_null());
            m.values_mut().for_each(drop_nulls);
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(drop_nulls),
        _ => {}
    }
}

/// Which time a message got (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum TimeBase {
    Stamp,
    RunTime,
    Index,
}

impl TimeBase {
    fn name(self) -> &'static str {
        match self {
            TimeBase::Stamp => "header.stamp",
            TimeBase::RunTime => "time_s",
            TimeBase::Index => "index",
        }
    }
}

/// The log time (ns) of `r` and the rule that gave it.
fn log_time(r: &ScanRecord) -> (u64, TimeBase) {
    if let Some(ns) = r.stamp_ns.and_then(|t| u64::try_from(t).ok()) {
        return (ns, TimeBase::Stamp);
    }
    if let Some(t) = r.time_s.filter(|t| t.is_finite() && *t >= 0.0) {
        // At most 2^64 ns (584 years) from the start.
        return (
            (t * 1e9).round().min(u64::MAX as f64) as u64,
            TimeBase::RunTime,
        );
    }
    let s = u64::try_from(r.index).unwrap_or(u64::MAX);
    (s.saturating_mul(1_000_000_000), TimeBase::Index)
}

fn time(ns: u64) -> Time {
    // Past 2106 (u32 seconds) a stamp is held at the largest Time.
    let sec = u32::try_from(ns / 1_000_000_000).unwrap_or(u32::MAX);
    Time {
        sec,
        nsec: (ns % 1_000_000_000) as u32,
    }
}

/// The MCAP file of a run, written as the records come.
pub struct RunMcap<W: Write + Seek> {
    w: mcap::Writer<W>,
    scans: u16,
    sequence: u32,
    /// The transforms, written with the first scan (at its time).
    pending_tf: Option<Vec<SceneTransform>>,
    base: Option<TimeBase>,
}

impl<W: Write + Seek> RunMcap<W> {
    /// Start the file on `sink`.
    pub fn new(sink: W) -> Result<Self> {
        let mut w = writer(sink)?;
        let scans = channel(&mut w, RUN_TOPIC, RUN_SCAN_NAME, RUN_SCAN)?;
        Ok(RunMcap {
            w,
            scans,
            sequence: 0,
            pending_tf: None,
            base: None,
        })
    }

    /// The run's transforms (before the first record; none: no `/tf`).
    pub fn transforms(&mut self, list: Vec<SceneTransform>) {
        self.pending_tf = (!list.is_empty()).then_some(list);
    }

    /// One record.
    pub fn record(&mut self, r: &ScanRecord) -> Result<()> {
        let (ns, base) = log_time(r);
        let at = time(ns);
        if let Some(tf) = self.pending_tf.take() {
            if let Some(t) = tf.iter().find(|t| !finite(t)) {
                return Err(Error::invalid(format!(
                    "--format mcap: transform {} -> {} holds a non-finite number, which JSON cannot carry",
                    t.parent, t.child
                )));
            }
            let ch = channel(
                &mut self.w,
                TF_TOPIC,
                "foxglove.FrameTransforms",
                FRAME_TRANSFORMS,
            )?;
            message(&mut self.w, ch, 0, ns, &transforms(&tf, at))?;
        }
        self.base.get_or_insert(base);
        message(
            &mut self.w,
            self.scans,
            self.sequence,
            ns,
            &run_scan(r, at)?,
        )?;
        self.sequence = self.sequence.wrapping_add(1);
        Ok(())
    }

    /// The metadata record (`facts`, and `log_time`), the indexes; the sink.
    pub fn finish(self, facts: Vec<(String, String)>) -> Result<W> {
        let base = self.base.map_or("none", TimeBase::name);
        let facts = facts
            .into_iter()
            .chain([("log_time".to_string(), base.to_string())]);
        finish(self.w, facts)
    }
}

fn finite(t: &SceneTransform) -> bool {
    t.translation_m
        .iter()
        .chain(&t.rotation_xyzw)
        .all(|x| x.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::run::RunUnit;

    fn record(index: usize, time_s: Option<f64>, stamp_ns: Option<i64>) -> ScanRecord {
        ScanRecord {
            schema_version: 1,
            unit: RunUnit::Scans,
            index,
            time_s,
            stamp_ns,
            frame_id: None,
            place: String::new(),
            status: "ok",
            reason: None,
            message: None,
            cells: None,
            nonfinite: None,
            points: None,
            normals: None,
            pair: None,
            frames: Vec::new(),
            warnings: Vec::new(),
        }
    }

    #[test]
    fn a_scan_is_at_its_stamp_else_its_run_time_else_its_index() {
        let r = record(3, Some(0.25), Some(1_700_000_000_123_456_789));
        assert_eq!(log_time(&r), (1_700_000_000_123_456_789, TimeBase::Stamp));
        assert_eq!(
            time(1_700_000_000_123_456_789),
            Time {
                sec: 1_700_000_000,
                nsec: 123_456_789
            }
        );
        let r = record(3, Some(0.25), None);
        assert_eq!(log_time(&r), (250_000_000, TimeBase::RunTime));
        // A stamp before 1970 cannot be a log time: the run time is used.
        let r = record(3, Some(0.25), Some(-5));
        assert_eq!(log_time(&r), (250_000_000, TimeBase::RunTime));
        let r = record(3, None, None);
        assert_eq!(log_time(&r), (3_000_000_000, TimeBase::Index));
        let r = record(3, Some(f64::NAN), None);
        assert_eq!(log_time(&r).1, TimeBase::Index);
    }
}
