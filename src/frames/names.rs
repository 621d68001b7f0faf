//! Frame names that look alike. tf2 and the graph compare names byte for
//! byte, so `base_lіnk` (a Cyrillic `і`), `base_link ` (a trailing space),
//! `ｂａｓｅ_link` (full-width letters) and `Base_Link` are four frames, none of
//! them `base_link`: an edge meant for one does not attach to the other, and
//! a calibration silently fails to connect. Each new frame is compared with
//! the frames already in the graph by two resemblance keys:
//!
//! - the name trimmed of white space, in Unicode compatibility form (NFKC),
//!   then reduced to its UTS #39 confusables skeleton (`unicode-security`'s
//!   `skeleton`: NFD, default-ignorable code points such as zero-width spaces
//!   dropped, each character mapped to its prototype: Cyrillic `і` to `i`,
//!   `1` and `I` to `l`, `rn` to `m`);
//! - the same after lower-casing (before the skeleton), so that names that
//!   differ only in case resemble each other too.
//!
//! Two different names with an equal key resemble each other: the later one
//! gets a `confusable-frame-name` warning naming the frame it resembles and
//! how they differ. A name with leading or trailing white space that
//! resembles no frame gets a `padded-frame-name` warning. Both are warnings:
//! the names are kept as written (tf2 would keep them).

use super::keyed::{Keyed, Names};
use unicode_normalization::UnicodeNormalization;
use unicode_security::confusable_detection::skeleton;

/// The two resemblance keys of every frame seen, each to the first frame
/// (its index in the graph) that had it: kept by hash ([`Keyed`]; issue 29:
/// two owned keys per frame were about a hundred bytes per link), a hash
/// found confirmed by the keys of the frame it leads to.
#[derive(Debug, Clone, Default)]
pub struct Resemblance {
    exact: Keyed,
    folded: Keyed,
    /// The new name's keys, and an earlier name's (buffers reused from
    /// frame to frame).
    keys: (String, String),
    other: (String, String),
}

/// What a new name is like.
#[derive(Debug, Clone, PartialEq)]
pub enum Likeness {
    /// Resembles frame `other` (an index into the graph); how they differ.
    Resembles {
        /// The earlier frame's index.
        other: usize,
        /// How the two differ, for the message.
        how: String,
    },
    /// Leading or trailing white space, resembling no other frame.
    Padded,
}

/// The two keys of `name` (exact, folded), written into `out` (cleared).
fn keys(name: &str, out: &mut (String, String)) {
    let name = name.trim();
    out.0.clear();
    out.1.clear();
    if ascii_keys(name, out) {
        return;
    }
    let nfkc: String = name.nfkc().collect();
    out.0.extend(skeleton(&nfkc));
    out.1.extend(skeleton(&nfkc.to_lowercase()));
}

/// The skeleton of each ASCII character, when none holds a combining mark:
/// then an ASCII name's skeleton is theirs joined (NFKC leaves ASCII as it
/// is, and the final NFD has no marks to reorder across characters). Frame
/// names are nearly always ASCII, and a URDF may have 100,000 of them.
/// With it, each character's skeleton when that is one ASCII character
/// (`single`), and whether both the character's and its lower case's are
/// (`plain`).
fn ascii_table() -> Option<&'static AsciiTable> {
    use unicode_normalization::char::canonical_combining_class;
    static TABLE: std::sync::OnceLock<Option<AsciiTable>> = std::sync::OnceLock::new();
    TABLE
        .get_or_init(|| {
            let t: [String; 128] =
                std::array::from_fn(|c| skeleton(&(c as u8 as char).to_string()).collect());
            let starters = t
                .iter()
                .flat_map(|s| s.chars())
                .all(|c| canonical_combining_class(c) == 0);
            // The skeleton's one ASCII byte, else 0 (for a control character, too).
            let one = |c: u8| match t[c as usize].as_bytes() {
                &[s] if s.is_ascii() && s != 0 && c != 0 => s,
                _ => 0,
            };
            let single = std::array::from_fn(|c| one(c as u8));
            let plain = std::array::from_fn(|c| {
                one(c as u8) != 0 && one((c as u8).to_ascii_lowercase()) != 0
            });
            starters.then_some(AsciiTable {
                skeleton: t,
                single,
                plain,
            })
        })
        .as_ref()
}

/// The skeleton of each ASCII character; see [`ascii_table`].
struct AsciiTable {
    skeleton: [String; 128],
    single: [u8; 128],
    plain: [bool; 128],
}

/// The keys of an ASCII name appended to `out`; false (nothing written) for
/// any other name.
fn ascii_keys(name: &str, out: &mut (String, String)) -> bool {
    if !name.is_ascii() {
        return false;
    }
    let Some(t) = ascii_table() else {
        return false;
    };
    if name.bytes().all(|b| t.plain[b as usize]) {
        // A byte per character, not a string appended per character (most
        // names: issue 29).
        let one = |b: u8| char::from(t.single[b as usize]);
        out.0.extend(name.bytes().map(one));
        out.1
            .extend(name.bytes().map(|b| one(b.to_ascii_lowercase())));
        return true;
    }
    let t = &t.skeleton;
    for b in name.bytes() {
        out.0.push_str(&t[b as usize]);
        out.1.push_str(&t[b.to_ascii_lowercase() as usize]);
    }
    true
}

impl Resemblance {
    /// Record frame `i` named `name` (new to the graph); what it resembles
    /// among the frames recorded before (`names` gives their names).
    pub(crate) fn add(&mut self, i: usize, name: &str, names: &Names) -> Option<Likeness> {
        keys(name, &mut self.keys);
        let (he, hf) = (
            self.exact.hash(&self.keys.0),
            self.folded.hash(&self.keys.1),
        );
        // Both keys are recorded (the first frame with each), then the
        // exact key's frame is the answer, else the folded key's. An earlier
        // frame's keys are computed only when its hash is found.
        let (mine, other) = (&self.keys, &mut self.other);
        let exact = self.exact.first_with(&mine.0, he, i, |j| {
            keys(&names[j], other);
            other.0 == mine.0
        });
        let folded = self.folded.first_with(&mine.1, hf, i, |j| {
            keys(&names[j], other);
            other.1 == mine.1
        });
        match exact.or(folded) {
            Some(j) => Some(Likeness::Resembles {
                other: j,
                how: difference(name, &names[j]),
            }),
            None if name.trim() != name => Some(Likeness::Padded),
            None => None,
        }
    }

    /// The frames from `n` on forgotten (a graph undoing a refused source).
    pub fn forget_from(&mut self, n: usize) {
        self.exact.forget_from(n);
        self.folded.forget_from(n);
    }
}

/// How two resembling names differ, most specific first.
fn difference(a: &str, b: &str) -> String {
    if a.trim() == b.trim() {
        return "they differ only by white space at the start or end".into();
    }
    let (na, nb): (String, String) = (a.trim().nfkc().collect(), b.trim().nfkc().collect());
    if na == nb {
        return format!(
            "they are equal in Unicode compatibility form (NFKC) only{}",
            first_difference(a.trim(), b.trim())
        );
    }
    if na.to_lowercase() == nb.to_lowercase() {
        return "they differ only in case".into();
    }
    format!(
        "they look alike (Unicode confusables, UTS #39){}",
        first_difference(&na, &nb)
    )
}

/// `: character N is U+XXXX where the other has U+YYYY` for the first
/// character at which two names differ (by position).
fn first_difference(a: &str, b: &str) -> String {
    let mut ca = a.chars();
    let mut cb = b.chars();
    let mut n = 0;
    loop {
        n += 1;
        match (ca.next(), cb.next()) {
            (Some(x), Some(y)) if x == y => continue,
            (Some(x), Some(y)) => {
                return format!(
                    ": character {n} is U+{:04X} where the other has U+{:04X} '{y}'",
                    x as u32, y as u32
                )
            }
            (Some(x), None) => return format!(": character {n} (U+{:04X}) is extra", x as u32),
            (None, Some(y)) => {
                return format!(": the other has U+{:04X} '{y}' at character {n}", y as u32)
            }
            (None, None) => return String::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn like(earlier: &[&str], name: &str) -> Option<Likeness> {
        let mut r = Resemblance::default();
        let mut names = Names::default();
        for (i, n) in earlier.iter().enumerate() {
            names.push(n);
            r.add(i, n, &names);
        }
        names.push(name);
        r.add(names.len() - 1, name, &names)
    }

    #[test]
    fn look_alikes_resemble_and_distinct_names_do_not() {
        for (a, b) in [
            ("base_link", "base_l\u{456}nk"),
            ("base_link", "base_link "),
            ("base_link", "\u{ff42}ase_link"),
            ("base_link", "Base_Link"),
            ("base_link", "base_\u{200b}link"),
            ("lidar_l", "lidar_I"),
        ] {
            assert!(
                matches!(like(&[a], b), Some(Likeness::Resembles { other: 0, .. })),
                "{a:?} {b:?}"
            );
        }
        for (a, b) in [
            ("base_link", "base_footprint"),
            ("cam0", "cam1"),
            ("lidar", "imu"),
        ] {
            assert_eq!(like(&[a], b), None, "{a:?} {b:?}");
        }
        assert_eq!(like(&["imu"], " lidar"), Some(Likeness::Padded));
    }

    #[test]
    fn ascii_names_take_the_table_and_agree_with_the_skeleton() {
        assert!(
            ascii_table().is_some(),
            "an ASCII character's skeleton has a mark"
        );
        let mut out = (String::from("left over"), String::new());
        let plain = ascii_table().map(|t| t.plain).unwrap();
        // Both paths: the names of plain characters, and all the others.
        let all: String = (0u8..128)
            .map(char::from)
            .filter(char::is_ascii_graphic)
            .collect();
        let own: String = all.chars().filter(|&c| plain[c as usize]).collect();
        assert!(!own.is_empty() && own.len() < all.len(), "{own:?}");
        for name in [
            "base_link",
            "l100000",
            "Cam_0|rn`%\"",
            "a b\tc\u{7f}",
            &own,
            &all,
        ] {
            let full: String = skeleton(name).collect();
            let lower: String = skeleton(&name.to_lowercase()).collect();
            keys(name, &mut out);
            assert_eq!(out, (full, lower), "{name:?}");
        }
        assert!(!ascii_keys("b\u{e4}r", &mut out));
    }

    /// The same answers as maps of the keys as strings (the keys computed
    /// by `skeleton` itself, not the ASCII table), over names that resemble
    /// each other in every way the module lists.
    #[test]
    fn the_same_answers_as_string_keyed_maps() {
        let names = [
            "base_link",
            "Base_Link",
            "base_l\u{456}nk",
            " base_link",
            "cam0",
            "caM0",
            "cam1",
            "lidar_l",
            "lidar_I",
            "lidar_1",
            "\u{ff42}ase_link",
            "imu ",
            "imu",
            "rn",
            "m",
            "M",
            "x\u{200b}y",
            "xy",
        ];
        let mut seen = Names::default();
        let (mut exact, mut folded) = (
            std::collections::HashMap::<String, usize>::new(),
            std::collections::HashMap::<String, usize>::new(),
        );
        let mut r = Resemblance::default();
        for (i, name) in names.iter().enumerate() {
            let nfkc: String = name.trim().nfkc().collect();
            let (e, f): (String, String) = (
                skeleton(&nfkc).collect(),
                skeleton(&nfkc.to_lowercase()).collect(),
            );
            let want = exact.get(&e).or_else(|| folded.get(&f)).copied();
            exact.entry(e).or_insert(i);
            folded.entry(f).or_insert(i);
            seen.push(name);
            let got = match r.add(i, name, &seen) {
                Some(Likeness::Resembles { other, .. }) => Some(other),
                _ => None,
            };
            assert_eq!(got, want, "{name:?}");
        }
    }

    #[test]
    fn the_difference_is_named() {
        let Some(Likeness::Resembles { how, .. }) = like(&["base_link"], "base_l\u{456}nk") else {
            panic!()
        };
        assert!(
            how.contains("character 7 is U+0456 where the other has U+0069 'i'"),
            "{how}"
        );
        let Some(Likeness::Resembles { how, .. }) = like(&["lidar"], "Lidar") else {
            panic!()
        };
        assert_eq!(how, "they differ only in case");
    }
}
