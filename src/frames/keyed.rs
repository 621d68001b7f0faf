//! A map from strings to indices that keeps no copy of the strings: each key
//! is kept as its 64-bit hash, and a hash found is confirmed by the caller
//! against the string it leads to (a frame's name, a name's resemblance
//! key), which the caller keeps anyway. A key whose hash an earlier,
//! different key already has is kept whole in a second map (`spill`), so
//! that every answer is that of a map of the strings themselves (issue 29:
//! an owned key per frame was about 50 bytes per link, for a lookup that
//! compares one string either way).

// foldhash: frame names are short and hashed several times per edge; SipHash
// was a tenth of loading a 100,000-link URDF (issue 29). Seeded per process.
use foldhash::HashMap;
use std::hash::BuildHasher;

/// Strings (by hash) to indices; see the module documentation.
#[derive(Debug, Clone, Default)]
pub(crate) struct Keyed {
    hasher: foldhash::fast::RandomState,
    by_hash: HashMap<u64, usize>,
    spill: HashMap<String, usize>,
}

impl Keyed {
    /// The hash of `key` that [`Keyed::get`] and [`Keyed::first_with`] take.
    pub(crate) fn hash(&self, key: &str) -> u64 {
        self.hasher.hash_one(key)
    }

    /// The index recorded for `key` (hash `h`); `is(j)`: whether index `j`'s
    /// string is `key`, asked only when `h` is found.
    pub(crate) fn get(&self, key: &str, h: u64, is: impl FnOnce(usize) -> bool) -> Option<usize> {
        let &j = self.by_hash.get(&h)?;
        if is(j) {
            Some(j)
        } else {
            self.spill.get(key).copied()
        }
    }

    /// The index recorded for `key` (hash `h`), `i` recorded when none was
    /// (then `None`); `is` as for [`Keyed::get`].
    pub(crate) fn first_with(
        &mut self,
        key: &str,
        h: u64,
        i: usize,
        is: impl FnOnce(usize) -> bool,
    ) -> Option<usize> {
        match self.by_hash.get(&h) {
            None => {
                self.by_hash.insert(h, i);
                None
            }
            Some(&j) if is(j) => Some(j),
            Some(_) => match self.spill.get(key) {
                Some(&j) => Some(j),
                None => {
                    self.spill.insert(key.to_string(), i);
                    None
                }
            },
        }
    }

    /// Every key recorded with an index `n` or above forgotten (a graph
    /// undoing a refused source). A key in `spill` was recorded after the
    /// key its hash leads to, so none is left without it.
    pub(crate) fn forget_from(&mut self, n: usize) {
        self.by_hash.retain(|_, i| *i < n);
        self.spill.retain(|_, i| *i < n);
    }
}

/// Frame names, in the order added, in one string (issue 29: a `String`
/// per frame was 24 bytes and an allocation of at least 32).
#[derive(Debug, Clone, Default)]
pub(crate) struct Names {
    text: String,
    /// Where each name ends in `text`.
    ends: Vec<usize>,
}

impl Names {
    /// How many names.
    pub(crate) fn len(&self) -> usize {
        self.ends.len()
    }

    /// Whether there is none.
    pub(crate) fn is_empty(&self) -> bool {
        self.ends.is_empty()
    }

    /// `name` added last.
    pub(crate) fn push(&mut self, name: &str) {
        self.text.push_str(name);
        self.ends.push(self.text.len());
    }

    /// The first `n` names kept.
    pub(crate) fn truncate(&mut self, n: usize) {
        if n < self.ends.len() {
            self.ends.truncate(n);
            self.text.truncate(self.ends.last().copied().unwrap_or(0));
        }
    }

    /// The names in the order added.
    pub(crate) fn iter(&self) -> impl Iterator<Item = &str> + '_ {
        (0..self.len()).map(|i| &self[i])
    }
}

impl std::ops::Index<usize> for Names {
    type Output = str;

    fn index(&self, i: usize) -> &str {
        let start = if i == 0 { 0 } else { self.ends[i - 1] };
        &self.text[start..self.ends[i]]
    }
}

#[cfg(test)]
mod tests {
    use super::{Keyed, Names};

    #[test]
    fn names_in_one_string() {
        let mut n = Names::default();
        for s in ["a", "", "b\u{456}c", "d"] {
            n.push(s);
        }
        assert_eq!(n.iter().collect::<Vec<_>>(), ["a", "", "b\u{456}c", "d"]);
        n.truncate(2);
        assert_eq!((n.len(), &n[0], &n[1]), (2, "a", ""));
        n.push("e");
        assert_eq!(n.iter().collect::<Vec<_>>(), ["a", "", "e"]);
        n.truncate(0);
        assert!(n.is_empty());
    }

    /// Keys whose hashes collide (every hash 0 here) are still told apart:
    /// each key leads to the first index recorded with it, as in a map of
    /// the keys themselves, and forgetting the later indices forgets them.
    #[test]
    fn colliding_hashes_are_told_apart() {
        let keys = ["a", "b", "a", "b", "c", "c", "a"];
        let mut m = Keyed::default();
        let got: Vec<Option<usize>> = (0..keys.len())
            .map(|i| m.first_with(keys[i], 0, i, |j| keys[j] == keys[i]))
            .collect();
        assert_eq!(got, [None, None, Some(0), Some(1), None, Some(4), Some(0)]);
        let get = |m: &Keyed, k: &str| m.get(k, 0, |j| keys[j] == k);
        assert_eq!(
            (get(&m, "a"), get(&m, "b"), get(&m, "c"), get(&m, "d")),
            (Some(0), Some(1), Some(4), None)
        );
        m.forget_from(2);
        assert_eq!(
            (get(&m, "a"), get(&m, "b"), get(&m, "c")),
            (Some(0), Some(1), None)
        );
        m.forget_from(1);
        assert_eq!((get(&m, "a"), get(&m, "b")), (Some(0), None));
        m.forget_from(0);
        assert_eq!(get(&m, "a"), None);
    }

    /// With the real hash, over many keys: the answers of a `HashMap`.
    #[test]
    fn the_answers_of_a_map_of_the_strings() {
        let keys: Vec<String> = (0..5000).map(|i| format!("l{}", i % 3000)).collect();
        let mut m = Keyed::default();
        let mut want = std::collections::HashMap::new();
        for (i, k) in keys.iter().enumerate() {
            let h = m.hash(k);
            let got = m.first_with(k, h, i, |j| keys[j] == *k);
            assert_eq!(got, want.get(k).copied(), "{k}");
            want.entry(k.clone()).or_insert(i);
        }
        for k in ["l0", "l2999", "l3000", "x"] {
            assert_eq!(m.get(k, m.hash(k), |j| keys[j] == k), want.get(k).copied());
        }
    }
}
