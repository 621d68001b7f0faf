//! The reader's name lookups (issue 29: memory per link): the top-level
//! links (by name: their start offsets, and their order) and the joints (by
//! name: their lines). A name is kept as where its attribute's text is in
//! the file (decoded again when asked for: [`Named::name`]), and found
//! through a table of `u32` indices hashed by the names they lead to (5
//! bytes a slot), where a map and a list of `Cow` names held each name twice
//! (33 bytes a slot and 32 an entry). Indices and offsets are `u32`: 2^32
//! links or bytes of URDF are far beyond the memory the tool runs in; one
//! past it (saturated) only finds nothing.

use super::values::decode;
use std::borrow::Cow;
use std::hash::BuildHasher;

/// Names in the order added, each with a number (a link's start offset, a
/// joint's line), found by name.
pub(super) struct Named<'a> {
    text: &'a str,
    /// Offset and length of the name's attribute text, and its number.
    at: Vec<[u32; 3]>,
    table: hashbrown::HashTable<u32>,
    // foldhash: names are short; SipHash was a tenth of the reading (issue 29).
    hasher: foldhash::fast::RandomState,
}

/// Top-level links: start offsets.
pub(super) type Links<'a> = Named<'a>;

/// Joints: lines.
pub(super) type JointNames<'a> = Named<'a>;

fn to_u32(x: usize) -> u32 {
    u32::try_from(x).unwrap_or(u32::MAX)
}

impl<'a> Named<'a> {
    /// Room for `n` names of `text`.
    pub(super) fn with_capacity(text: &'a str, n: usize) -> Self {
        Named {
            text,
            at: Vec::with_capacity(n),
            table: hashbrown::HashTable::with_capacity(n),
            hasher: foldhash::fast::RandomState::default(),
        }
    }

    /// The `i`-th name, decoded as XML reads it.
    fn name_in(text: &'a str, at: &[[u32; 3]], i: usize) -> Cow<'a, str> {
        let raw = at.get(i).and_then(|&[s, l, _]| {
            let s = s as usize;
            text.get(s..s.checked_add(l as usize)?)
        });
        match raw {
            // Names are short: a byte loop, where `decode`'s search for four
            // characters costs more than the name (a lookup compares one).
            Some(r) if !r.bytes().any(|b| matches!(b, b'&' | b'\t' | b'\n' | b'\r')) => {
                Cow::Borrowed(r)
            }
            _ => raw.and_then(decode).unwrap_or_default(),
        }
    }

    /// The `i`-th name.
    pub(super) fn name(&self, i: usize) -> Cow<'a, str> {
        Self::name_in(self.text, &self.at, i)
    }

    /// The position (order added) of the name `name`.
    pub(super) fn index_of(&self, name: &str) -> Option<usize> {
        let h = self.hasher.hash_one(name);
        let (t, at) = (self.text, &self.at);
        let i = self
            .table
            .find(h, |&i| Self::name_in(t, at, i as usize) == name)?;
        Some(*i as usize)
    }

    /// The number of the name `name`.
    pub(super) fn get(&self, name: &str) -> Option<usize> {
        self.index_of(name).map(|i| self.at[i][2] as usize)
    }

    pub(super) fn contains(&self, name: &str) -> bool {
        self.index_of(name).is_some()
    }

    /// `name` (not there yet: see [`Named::get`]), written `raw` (a slice
    /// of the text), with its number, added last.
    pub(super) fn push(&mut self, name: &str, raw: &str, number: usize) {
        let h = self.hasher.hash_one(name);
        let (t, at, hasher) = (self.text, &self.at, &self.hasher);
        self.table.insert_unique(h, to_u32(at.len()), |&j| {
            hasher.hash_one(&*Self::name_in(t, at, j as usize))
        });
        let start = (raw.as_ptr() as usize).wrapping_sub(t.as_ptr() as usize);
        self.at
            .push([to_u32(start), to_u32(raw.len()), to_u32(number)]);
    }

    /// How many names.
    pub(super) fn len(&self) -> usize {
        self.at.len()
    }

    /// The names and their numbers, in the order added.
    pub(super) fn iter(&self) -> impl Iterator<Item = (Cow<'a, str>, usize)> + '_ {
        (0..self.len()).map(|i| (self.name(i), self.at[i][2] as usize))
    }
}

#[cfg(test)]
mod tests {
    use super::Named;

    /// Names found as a map of them would find them, entities decoded.
    #[test]
    fn lookups_are_a_map_s() {
        let text = "<joint name=\"a&amp;b\"/><joint name=\"c\"/>";
        let mut names = Named::with_capacity(text, 0);
        names.push("a&b", &text[13..20], 7);
        names.push("c", &text[36..37], 9);
        for _ in 0..100 {
            assert_eq!(names.get("a&b"), Some(7));
        }
        assert_eq!(names.get("c"), Some(9));
        assert_eq!(names.get("a&amp;b"), None);
        assert_eq!(names.name(0), "a&b");
        let text: String = (0..1000)
            .map(|k| format!("<link name=\"l{k}\"/>"))
            .collect();
        // Grown past its capacity: the names rehashed.
        let mut links = Named::with_capacity(&text, 1);
        let mut rest = &text[..];
        for k in 0..1000 {
            let s = rest.find("=\"").unwrap() + 2;
            let e = s + rest[s..].find('"').unwrap();
            let raw = &rest[s..e];
            links.push(raw, raw, k * 3);
            rest = &rest[e..];
        }
        assert_eq!(links.get("l999"), Some(2997));
        assert!(links.contains("l0") && !links.contains("l1000"));
        assert_eq!(links.index_of("l7"), Some(7));
        assert_eq!(links.len(), 1000);
        assert_eq!(links.iter().nth(5).unwrap(), ("l5".into(), 15));
    }
}
