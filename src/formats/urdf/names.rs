//! The reader's name lookups (issue 29: memory per link): links by name,
//! joints by name, each a table of `u32` indices into a list the reader keeps
//! anyway, hashed by the names they lead to (5 bytes a slot), where a map of
//! owned-or-borrowed names held each name a second time (33 bytes a slot).
//! Indices and offsets are `u32`: 2^32 links or bytes of URDF are far beyond
//! the memory the tool runs in; one past it (saturated) only finds nothing.

use super::values::decode;
use std::borrow::Cow;
use std::hash::BuildHasher;

/// Indices of names kept elsewhere, found by name (the caller says which
/// name an index has).
struct NameIndex {
    table: hashbrown::HashTable<u32>,
    // foldhash: names are short; SipHash was a tenth of the reading (issue 29).
    hasher: foldhash::fast::RandomState,
}

impl NameIndex {
    fn with_capacity(n: usize) -> Self {
        NameIndex {
            table: hashbrown::HashTable::with_capacity(n),
            hasher: foldhash::fast::RandomState::default(),
        }
    }

    /// The index whose name is `name` (`is(i)`: whether index `i`'s name is).
    fn find(&self, name: &str, is: impl Fn(usize) -> bool) -> Option<usize> {
        let h = self.hasher.hash_one(name);
        self.table.find(h, |&i| is(i as usize)).map(|&i| i as usize)
    }

    /// `i`, named `name`, added (not there yet); `name_of(j)` rehashes the
    /// others when the table grows.
    fn insert<'n>(&mut self, name: &str, i: usize, name_of: impl Fn(usize) -> Cow<'n, str>) {
        let h = self.hasher.hash_one(name);
        let hasher = &self.hasher;
        let i = u32::try_from(i).unwrap_or(u32::MAX);
        self.table
            .insert_unique(h, i, |&j| hasher.hash_one(&*name_of(j as usize)));
    }
}

/// Top-level links in file order (name, start offset), found by name.
pub(super) struct Links<'a> {
    decls: Vec<(Cow<'a, str>, usize)>,
    index: NameIndex,
}

impl<'a> Links<'a> {
    pub(super) fn with_capacity(n: usize) -> Self {
        Links {
            decls: Vec::with_capacity(n),
            index: NameIndex::with_capacity(n),
        }
    }

    /// The start offset of the link named `name`.
    pub(super) fn get(&self, name: &str) -> Option<usize> {
        self.index_of(name).map(|i| self.decls[i].1)
    }

    /// The position in file order of the link named `name`.
    pub(super) fn index_of(&self, name: &str) -> Option<usize> {
        let d = &self.decls;
        self.index
            .find(name, |i| d.get(i).is_some_and(|(n, _)| n == name))
    }

    pub(super) fn contains(&self, name: &str) -> bool {
        self.get(name).is_some()
    }

    /// The link `name` at `start` added (not declared yet: see [`Links::get`]).
    pub(super) fn push(&mut self, name: Cow<'a, str>, start: usize) {
        let d = &self.decls;
        self.index.insert(&name, d.len(), |j| {
            Cow::Borrowed(d.get(j).map_or("", |(n, _)| n.as_ref()))
        });
        self.decls.push((name, start));
    }

    /// The links in file order.
    pub(super) fn decls(&self) -> &[(Cow<'a, str>, usize)] {
        &self.decls
    }
}

/// Joint names, each kept as where its `name` attribute's text is and its
/// joint's line (for "first at line N" and the mimic masters).
pub(super) struct JointNames<'a> {
    text: &'a str,
    /// (offset and length of the attribute's text, line of the joint).
    at: Vec<[u32; 3]>,
    index: NameIndex,
}

impl<'a> JointNames<'a> {
    pub(super) fn with_capacity(text: &'a str, n: usize) -> Self {
        JointNames {
            text,
            at: Vec::with_capacity(n),
            index: NameIndex::with_capacity(n),
        }
    }

    /// The `i`-th name, decoded as XML reads it.
    fn name(text: &'a str, at: &[[u32; 3]], i: usize) -> Cow<'a, str> {
        let raw = at.get(i).and_then(|&[s, l, _]| {
            let s = s as usize;
            text.get(s..s + l as usize)
        });
        raw.and_then(decode).unwrap_or_default()
    }

    /// The line of the joint named `name`.
    pub(super) fn line(&self, name: &str) -> Option<usize> {
        let (t, at) = (self.text, &self.at);
        let i = self.index.find(name, |i| Self::name(t, at, i) == name)?;
        Some(at[i][2] as usize)
    }

    /// The joint named `name` (its attribute's text `raw`, a slice of the
    /// text) at `line` added (not there yet: see [`JointNames::line`]).
    pub(super) fn push(&mut self, name: &str, raw: &str, line: usize) {
        let (t, at) = (self.text, &self.at);
        self.index.insert(name, at.len(), |j| Self::name(t, at, j));
        let u = |x: usize| u32::try_from(x).unwrap_or(u32::MAX);
        let start = (raw.as_ptr() as usize).wrapping_sub(t.as_ptr() as usize);
        self.at.push([u(start), u(raw.len()), u(line)]);
    }
}

#[cfg(test)]
mod tests {
    use super::{JointNames, Links};
    use std::borrow::Cow;

    /// Names found as a map of them would find them, entities decoded.
    #[test]
    fn lookups_are_a_map_s() {
        let text = "<joint name=\"a&amp;b\"/><joint name=\"c\"/>";
        let mut names = JointNames::with_capacity(text, 0);
        names.push("a&b", &text[13..20], 7);
        names.push("c", &text[36..37], 9);
        for _ in 0..100 {
            // Grown past its capacity: the names rehashed.
            assert_eq!(names.line("a&b"), Some(7));
        }
        assert_eq!(names.line("c"), Some(9));
        assert_eq!(names.line("a&amp;b"), None);
        let mut links = Links::with_capacity(1);
        for k in 0..1000 {
            links.push(Cow::Owned(format!("l{k}")), k * 3);
        }
        assert_eq!(links.get("l999"), Some(2997));
        assert!(links.contains("l0") && !links.contains("l1000"));
        assert_eq!(links.index_of("l7"), Some(7));
        assert_eq!(links.decls().len(), 1000);
    }
}
