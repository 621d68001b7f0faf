//! Reading and writing a baseline as a stream: a baseline of a fleet (about
//! 1 KB of JSON per file, 100 MB for 100,000 files) is never held as text or
//! as a JSON tree. Reading hands each entry, checked, to the caller as it is
//! parsed; writing serialises entries one at a time, byte for byte what
//! `serde_json::to_string_pretty` of the whole `Baseline` writes.
//!
//! Both sides keep to `MAX_BASELINE_FILE_SIZE`: what the tool writes, it
//! reads (a write that would pass the cap is an error, nothing written).

use super::key::decode_key;
#[cfg(test)]
use super::record::Baseline;
use super::record::{validate_file, BaselineFile};
use crate::diagnostic::{Error, Result};
use crate::tolerances::MAX_BASELINE_FILE_SIZE;
use serde::de::{self, DeserializeSeed, IgnoredAny, MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::cell::RefCell;
use std::fmt;
use std::io::{BufReader, Write};
use std::path::Path;

/// What the size cap is called in messages.
const CAP_NAME: &str = "the baseline size cap, MAX_BASELINE_FILE_SIZE";

/// What went wrong inside the parse, kept apart from serde's error (which
/// carries only text): the entry errors name the entry as [`super::read_store`]
/// always has.
enum Failure {
    Entry(String),
}

struct Files<'a, F> {
    each: &'a mut F,
    failure: &'a RefCell<Option<Failure>>,
}

impl<'de, F: FnMut(String, BaselineFile)> Visitor<'de> for Files<'_, F> {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an object of per-file records")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> std::result::Result<(), A::Error> {
        while let Some(key) = map.next_key::<String>()? {
            // Each entry through a small JSON tree, so that a malformed one is
            // named as it always was (serde's message without a position).
            let v: serde_json::Value = map.next_value()?;
            let fail = |what: String| {
                *self.failure.borrow_mut() = Some(Failure::Entry(what));
                de::Error::custom("entry")
            };
            let rec = BaselineFile::deserialize(&v)
                .map_err(|e| fail(format!("baseline entry files[{key:?}]: {e}")))?;
            validate_file(&key, &rec).map_err(fail)?;
            if decode_key(&key).is_none() {
                return Err(fail(format!(
                    "baseline entry files[{key:?}]: expected a key written by --write-baseline (`%` followed by two hex digits)"
                )));
            }
            (self.each)(key, rec);
        }
        Ok(())
    }
}

impl<'de, F: FnMut(String, BaselineFile)> DeserializeSeed<'de> for Files<'_, F> {
    type Value = ();
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> std::result::Result<(), D::Error> {
        d.deserialize_map(self)
    }
}

/// The top level: `schema_version` (kept as JSON, for the message) and
/// whether `files` was there; other keys are skipped. Not an object: `None`.
struct Top<'a, F> {
    files: Files<'a, F>,
}

type TopSeen = Option<(Option<serde_json::Value>, bool)>;

impl<'de, F: FnMut(String, BaselineFile)> Visitor<'de> for Top<'_, F> {
    type Value = TopSeen;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a baseline object")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> std::result::Result<TopSeen, A::Error> {
        let (mut version, mut files) = (None, false);
        let mut seed = Some(self.files);
        while let Some(key) = map.next_key::<String>()? {
            match key.as_str() {
                "schema_version" => version = Some(map.next_value::<serde_json::Value>()?),
                "files" => match seed.take() {
                    Some(s) => {
                        map.next_value_seed(s)?;
                        files = true;
                    }
                    None => return Err(de::Error::custom("`files` given twice")),
                },
                _ => {
                    map.next_value::<IgnoredAny>()?;
                }
            }
        }
        Ok(Some((version, files)))
    }
    // Any other JSON value: not a baseline (said below, as before).
    fn visit_bool<E: de::Error>(self, _: bool) -> std::result::Result<TopSeen, E> {
        Ok(None)
    }
    fn visit_i64<E: de::Error>(self, _: i64) -> std::result::Result<TopSeen, E> {
        Ok(None)
    }
    fn visit_u64<E: de::Error>(self, _: u64) -> std::result::Result<TopSeen, E> {
        Ok(None)
    }
    fn visit_f64<E: de::Error>(self, _: f64) -> std::result::Result<TopSeen, E> {
        Ok(None)
    }
    fn visit_str<E: de::Error>(self, _: &str) -> std::result::Result<TopSeen, E> {
        Ok(None)
    }
    fn visit_unit<E: de::Error>(self) -> std::result::Result<TopSeen, E> {
        Ok(None)
    }
    fn visit_seq<A: de::SeqAccess<'de>>(self, mut s: A) -> std::result::Result<TopSeen, A::Error> {
        while s.next_element::<IgnoredAny>()?.is_some() {}
        Ok(None)
    }
}

/// Open `path` for a streamed read within the cap (a FIFO or device is
/// refused, as every read of the tool refuses it).
fn open_capped(path: &Path) -> Result<impl std::io::Read> {
    let (f, len) = crate::input::open_stream(path)?;
    if len > MAX_BASELINE_FILE_SIZE {
        return Err(Error::limit(format!(
            "file is {len} bytes: expected at most {MAX_BASELINE_FILE_SIZE} bytes ({CAP_NAME})"
        ))
        .in_file(path));
    }
    Ok(BufReader::with_capacity(
        1 << 16,
        crate::input::Capped::new(f, MAX_BASELINE_FILE_SIZE),
    ))
}

fn not_a_baseline(path: &Path, e: &serde_json::Error) -> Error {
    Error::parse(format!(
        "expected a baseline written by `audit check --write-baseline`, found: {e}"
    ))
    .in_file(path)
    .at_line(e.line(), Some(e.column()))
}

/// Read the baseline at `path`, each entry handed to `each` (key, record) as
/// it is parsed and checked. Refused as [`super::read_store`] says; the entries
/// already handed on are then to be dropped by the caller.
pub fn read_each(path: &Path, mut each: impl FnMut(String, BaselineFile)) -> Result<()> {
    let failure = RefCell::new(None);
    let mut de = serde_json::Deserializer::from_reader(open_capped(path)?);
    let top = Top {
        files: Files {
            each: &mut each,
            failure: &failure,
        },
    };
    let seen = de::Deserializer::deserialize_any(&mut de, top).and_then(|s| de.end().map(|()| s));
    let bad = |what: String| Error::invalid(what).in_file(path);
    let seen = match (seen, failure.into_inner()) {
        (_, Some(Failure::Entry(what))) => return Err(bad(what)),
        (Err(e), None) if e.is_io() => return Err(Error::io(path, &std::io::Error::other(e))),
        (Err(e), None) => return Err(not_a_baseline(path, &e)),
        (Ok(s), None) => s,
    };
    let (version, files) = seen.unwrap_or((None, false));
    if version.as_ref().and_then(|v| v.as_u64()) != Some(1) {
        return Err(bad(format!(
            "expected baseline schema_version 1, found {}",
            version
                .map(|x| x.to_string())
                .unwrap_or_else(|| "none".into())
        )));
    }
    if !files {
        return Err(bad(
            "expected `files`: an object of per-file records, found none".into(),
        ));
    }
    Ok(())
}

/// Whether `path` parses as a baseline's top level (an object with
/// `schema_version` and `files`), read as a stream with nothing kept.
pub fn looks_like_baseline(path: &Path) -> bool {
    let Ok(r) = open_capped(path) else {
        return false;
    };
    struct Keys;
    impl<'de> Visitor<'de> for Keys {
        type Value = bool;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str("an object")
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> std::result::Result<bool, A::Error> {
            let (mut v, mut f) = (false, false);
            while let Some(k) = map.next_key::<String>()? {
                v |= k == "schema_version";
                f |= k == "files";
                map.next_value::<IgnoredAny>()?;
            }
            Ok(v && f)
        }
    }
    let mut de = serde_json::Deserializer::from_reader(r);
    matches!(
        de::Deserializer::deserialize_map(&mut de, Keys).and_then(|b| de.end().map(|()| b)),
        Ok(true)
    )
}

/// A map serialised from an iterator, taken once.
struct Lazy<I>(RefCell<Option<I>>);

impl<'a, I: Iterator<Item = (&'a str, BaselineFile)>> Serialize for Lazy<I> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        let it = self
            .0
            .borrow_mut()
            .take()
            .ok_or_else(|| serde::ser::Error::custom("serialised twice"))?;
        s.collect_map(it)
    }
}

/// The baseline's top level, its files from an iterator.
struct Out<I> {
    schema_version: u32,
    files: Lazy<I>,
}

impl<'a, I: Iterator<Item = (&'a str, BaselineFile)>> Serialize for Out<I> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut st = s.serialize_struct("Baseline", 2)?;
        st.serialize_field("schema_version", &self.schema_version)?;
        st.serialize_field("files", &self.files)?;
        st.end()
    }
}

/// Counts what goes through, and fails past the read cap.
struct Counted<'w> {
    inner: &'w mut dyn Write,
    n: u64,
}

impl Write for Counted<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.n += buf.len() as u64;
        if self.n > MAX_BASELINE_FILE_SIZE {
            return Err(std::io::Error::other(format!(
                "the baseline would be more than {MAX_BASELINE_FILE_SIZE} bytes ({CAP_NAME}): it could not be read back; nothing written"
            )));
        }
        self.inner.write_all(buf)?;
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

/// Write a baseline of `files` (sorted by key, each key once) to `w`: the
/// text of `serde_json::to_string_pretty` of the `Baseline`, and a newline.
pub fn write_to<'a>(
    w: &mut dyn Write,
    files: impl Iterator<Item = (&'a str, BaselineFile)>,
) -> std::io::Result<()> {
    let mut c = Counted { inner: w, n: 0 };
    let out = Out {
        schema_version: 1,
        files: Lazy(RefCell::new(Some(files))),
    };
    serde_json::to_writer_pretty(&mut c, &out).map_err(std::io::Error::other)?;
    c.write_all(b"\n")
}

/// The whole of a `Baseline` written as [`write_to`] writes it (what the
/// tests compare the streamed text with).
#[cfg(test)]
pub fn write_baseline_to(w: &mut dyn Write, b: &Baseline) -> std::io::Result<()> {
    write_to(w, b.files.iter().map(|(k, v)| (k.as_str(), v.clone())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::baseline::{BaselinePair, BaselineTransform};
    use std::collections::BTreeMap;

    #[test]
    fn streamed_text_is_the_pretty_text_of_the_whole() {
        let t = BaselineTransform {
            parent: "imu".into(),
            child: "lidar".into(),
            translation_m: [0.1, -0.2, 1e-17],
            quaternion_xyzw: [0.0, 0.0, 0.0, 1.0],
        };
        let rec = BaselineFile {
            edges: vec![t.clone()],
            pairs: vec![BaselinePair {
                transform: t,
                lever_arm_m: 0.2236,
                screw_kind: "pure_translation".into(),
                zero_pitch: false,
                adapted_metric_exists: false,
                declared: true,
            }],
        };
        for files in [
            BTreeMap::new(),
            BTreeMap::from([
                ("a%25b.toml".to_string(), rec.clone()),
                ("d/c.toml".to_string(), BaselineFile::default()),
            ]),
        ] {
            let b = Baseline {
                schema_version: 1,
                files,
            };
            let mut want = serde_json::to_string_pretty(&b).unwrap();
            want.push('\n');
            let mut got = Vec::new();
            write_baseline_to(&mut got, &b).unwrap();
            assert_eq!(String::from_utf8(got).unwrap(), want);
        }
    }
}
