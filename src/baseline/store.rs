//! A baseline held compactly: what `check` compares and writes, for fleets of
//! any size.
//!
//! Each file's record is kept as numbers and indices into a table of names
//! (frame names and screw kinds repeat across a fleet: `base_link`, `imu`,
//! `lidar`), its edges and pairs in two shared arrays, its key in one entry
//! of a sorted array: about 200 bytes per file of one edge and one pair, and
//! no allocation per file but its key. A record is rebuilt as a
//! [`BaselineFile`] only where a comparison needs its names.

use super::record::{BaselineFile, BaselinePair, BaselineTransform};
use std::collections::HashMap;
use std::sync::Arc;

#[derive(Debug, Clone, Copy, PartialEq)]
struct Transform {
    parent: u32,
    child: u32,
    translation_m: [f64; 3],
    quaternion_xyzw: [f64; 4],
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Pair {
    transform: Transform,
    lever_arm_m: f64,
    screw_kind: u32,
    zero_pitch: bool,
    adapted_metric_exists: bool,
    declared: bool,
}

#[derive(Debug, Clone)]
struct Entry {
    key: Box<str>,
    edges: (u32, u32),
    pairs: (u32, u32),
}

/// Records by key, compactly (see the module doc).
#[derive(Debug, Clone)]
pub struct Store {
    names: Vec<Arc<str>>,
    index: HashMap<Arc<str>, u32>,
    edges: Vec<Transform>,
    pairs: Vec<Pair>,
    entries: Vec<Entry>,
    /// `entries` sorted by key with no key twice ([`Store::finish`]).
    sorted: bool,
}

fn range(start: usize, end: usize) -> (u32, u32) {
    // More than 4e9 edges would need 256 GiB: the size caps stop far below.
    (start as u32, end as u32)
}

impl Default for Store {
    fn default() -> Self {
        Store {
            names: Vec::new(),
            index: HashMap::new(),
            edges: Vec::new(),
            pairs: Vec::new(),
            entries: Vec::new(),
            sorted: true,
        }
    }
}

impl Store {
    /// An empty store.
    pub fn new() -> Self {
        Store::default()
    }

    fn name(&mut self, s: &str) -> u32 {
        if let Some(&i) = self.index.get(s) {
            return i;
        }
        let i = self.names.len() as u32;
        let a: Arc<str> = Arc::from(s);
        self.names.push(a.clone());
        self.index.insert(a, i);
        i
    }

    fn transform(&mut self, t: &BaselineTransform) -> Transform {
        Transform {
            parent: self.name(&t.parent),
            child: self.name(&t.child),
            translation_m: t.translation_m,
            quaternion_xyzw: t.quaternion_xyzw,
        }
    }

    /// Add `key`'s record. Keys may come in any order; [`Store::finish`]
    /// sorts them before any look-up.
    pub fn insert(&mut self, key: &str, rec: &BaselineFile) {
        let e0 = self.edges.len();
        for e in &rec.edges {
            let t = self.transform(e);
            self.edges.push(t);
        }
        let p0 = self.pairs.len();
        for p in &rec.pairs {
            let pair = Pair {
                transform: self.transform(&p.transform),
                lever_arm_m: p.lever_arm_m,
                screw_kind: self.name(&p.screw_kind),
                zero_pitch: p.zero_pitch,
                adapted_metric_exists: p.adapted_metric_exists,
                declared: p.declared,
            };
            self.pairs.push(pair);
        }
        if self.entries.last().is_some_and(|last| *last.key >= *key) {
            self.sorted = false;
        }
        self.entries.push(Entry {
            key: key.into(),
            edges: range(e0, self.edges.len()),
            pairs: range(p0, self.pairs.len()),
        });
    }

    /// Sort by key; the first key given twice when there is one (the store
    /// is then unusable: the caller refuses the baseline).
    pub fn finish(&mut self) -> Option<String> {
        if !self.sorted {
            self.entries.sort_by(|a, b| a.key.cmp(&b.key));
            self.sorted = true;
        }
        self.entries
            .windows(2)
            .find(|w| w[0].key == w[1].key)
            .map(|w| w[0].key.to_string())
    }

    /// How many files.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// The index of `key` (after [`Store::finish`]).
    pub fn find(&self, key: &str) -> Option<usize> {
        debug_assert!(self.sorted);
        self.entries.binary_search_by(|e| (*e.key).cmp(key)).ok()
    }

    /// The key of entry `i`.
    pub fn key(&self, i: usize) -> &str {
        &self.entries[i].key
    }

    fn stored(&self, t: &Transform) -> BaselineTransform {
        BaselineTransform {
            parent: self.names[t.parent as usize].to_string(),
            child: self.names[t.child as usize].to_string(),
            translation_m: t.translation_m,
            quaternion_xyzw: t.quaternion_xyzw,
        }
    }

    /// Entry `i`'s record, rebuilt.
    pub fn record(&self, i: usize) -> BaselineFile {
        let e = &self.entries[i];
        let edges = self.edges[e.edges.0 as usize..e.edges.1 as usize]
            .iter()
            .map(|t| self.stored(t))
            .collect();
        let pairs = self.pairs[e.pairs.0 as usize..e.pairs.1 as usize]
            .iter()
            .map(|p| BaselinePair {
                transform: self.stored(&p.transform),
                lever_arm_m: p.lever_arm_m,
                screw_kind: self.names[p.screw_kind as usize].to_string(),
                zero_pitch: p.zero_pitch,
                adapted_metric_exists: p.adapted_metric_exists,
                declared: p.declared,
            })
            .collect();
        BaselineFile { edges, pairs }
    }

    fn same_transform(&self, t: &Transform, b: &BaselineTransform) -> bool {
        *self.names[t.parent as usize] == *b.parent
            && *self.names[t.child as usize] == *b.child
            && t.translation_m == b.translation_m
            && t.quaternion_xyzw == b.quaternion_xyzw
    }

    /// Whether entry `i` holds exactly `rec` (no record rebuilt).
    pub fn holds(&self, i: usize, rec: &BaselineFile) -> bool {
        let e = &self.entries[i];
        let edges = &self.edges[e.edges.0 as usize..e.edges.1 as usize];
        let pairs = &self.pairs[e.pairs.0 as usize..e.pairs.1 as usize];
        edges.len() == rec.edges.len()
            && pairs.len() == rec.pairs.len()
            && edges
                .iter()
                .zip(&rec.edges)
                .all(|(t, b)| self.same_transform(t, b))
            && pairs.iter().zip(&rec.pairs).all(|(p, b)| {
                self.same_transform(&p.transform, &b.transform)
                    && p.lever_arm_m == b.lever_arm_m
                    && *self.names[p.screw_kind as usize] == *b.screw_kind
                    && p.zero_pitch == b.zero_pitch
                    && p.adapted_metric_exists == b.adapted_metric_exists
                    && p.declared == b.declared
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(parent: &str, x: f64, kind: &str) -> BaselineFile {
        let t = BaselineTransform {
            parent: parent.into(),
            child: "lidar".into(),
            translation_m: [x, 0.5, -0.25],
            quaternion_xyzw: [0.0, 0.0, 0.6, 0.8],
        };
        BaselineFile {
            edges: vec![t.clone()],
            pairs: vec![BaselinePair {
                transform: t,
                lever_arm_m: 1.25,
                screw_kind: kind.into(),
                zero_pitch: false,
                adapted_metric_exists: false,
                declared: true,
            }],
        }
    }

    #[test]
    fn records_come_back_as_given_in_key_order() {
        let mut s = Store::new();
        s.insert("b.toml", &rec("imu", 0.1, "general"));
        s.insert("a.toml", &rec("base_link", 0.2, "zero_pitch"));
        assert_eq!(s.finish(), None);
        assert_eq!((s.key(0), s.key(1)), ("a.toml", "b.toml"));
        let i = s.find("b.toml").unwrap();
        assert_eq!(s.record(i), rec("imu", 0.1, "general"));
        assert!(s.holds(i, &rec("imu", 0.1, "general")));
        assert!(!s.holds(i, &rec("imu", 0.1 + 1e-12, "general")));
        assert!(!s.holds(i, &rec("imu", 0.1, "zero_pitch")));
        assert_eq!(s.find("c.toml"), None);
    }

    #[test]
    fn a_key_given_twice_is_named() {
        let mut s = Store::new();
        s.insert("a.toml", &rec("imu", 0.1, "general"));
        s.insert("b.toml", &rec("imu", 0.1, "general"));
        s.insert("a.toml", &rec("imu", 0.3, "general"));
        assert_eq!(s.finish().as_deref(), Some("a.toml"));
    }
}
