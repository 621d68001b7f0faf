//! One-character edits at pseudo-random places, for the differential tests
//! of the fast readers (`formats::toml_subset`, `formats::yaml_subset`)
//! against the crates they stand in for: a fixed-seed LCG, so every run
//! tries the same edits.

/// The edit stream: each [`Edits::edit`] deletes the character at a random
/// place or inserts one of the given strings there.
pub(crate) struct Edits {
    seed: u64,
}

impl Edits {
    pub(crate) fn new() -> Edits {
        Edits {
            seed: 0x9e37_79b9_7f4a_7c15,
        }
    }

    /// A pseudo-random number below `n` (0 for `n` = 0).
    fn next(&mut self, n: usize) -> usize {
        self.seed = self
            .seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.seed >> 33) as usize % n.max(1)
    }

    /// `t` with one edit: one time in three the character at a random place
    /// deleted, else one of `inserts` inserted there.
    pub(crate) fn edit(&mut self, t: &str, inserts: &[&str]) -> String {
        let mut at = self.next(t.len());
        while !t.is_char_boundary(at) {
            at -= 1;
        }
        let mut v = t.to_string();
        match self.next(3) {
            0 => {
                let end = t[at..].chars().next().map_or(at, |c| at + c.len_utf8());
                v.replace_range(at..end, "");
            }
            _ => v.insert_str(at, inserts[self.next(inserts.len())]),
        }
        v
    }
}
