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

// foldhash: frame names are short and hashed several times per edge; SipHash
// was a tenth of loading a 100,000-link URDF (issue 29). Seeded per process.
use foldhash::HashMap;
use unicode_normalization::UnicodeNormalization;
use unicode_security::confusable_detection::skeleton;

/// The two resemblance keys of every frame seen, each to the first frame
/// (its index in the graph) that had it.
#[derive(Debug, Clone, Default)]
pub struct Resemblance {
    exact: HashMap<String, usize>,
    folded: HashMap<String, usize>,
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

fn keys(name: &str) -> (String, String) {
    let name = name.trim();
    if let Some(keys) = ascii_keys(name) {
        return keys;
    }
    let nfkc: String = name.nfkc().collect();
    let exact = skeleton(&nfkc).collect();
    let folded = skeleton(&nfkc.to_lowercase()).collect();
    (exact, folded)
}

/// The skeleton of each ASCII character, when none holds a combining mark:
/// then an ASCII name's skeleton is theirs joined (NFKC leaves ASCII as it
/// is, and the final NFD has no marks to reorder across characters). Frame
/// names are nearly always ASCII, and a URDF may have 100,000 of them.
fn ascii_table() -> Option<&'static [String; 128]> {
    use unicode_normalization::char::canonical_combining_class;
    static TABLE: std::sync::OnceLock<Option<[String; 128]>> = std::sync::OnceLock::new();
    TABLE
        .get_or_init(|| {
            let t: [String; 128] =
                std::array::from_fn(|c| skeleton(&(c as u8 as char).to_string()).collect());
            let starters = t
                .iter()
                .flat_map(|s| s.chars())
                .all(|c| canonical_combining_class(c) == 0);
            starters.then_some(t)
        })
        .as_ref()
}

fn ascii_keys(name: &str) -> Option<(String, String)> {
    if !name.is_ascii() {
        return None;
    }
    let t = ascii_table()?;
    let key = |bytes: &mut dyn Iterator<Item = u8>| {
        bytes.map(|b| t[b as usize].as_str()).collect::<String>()
    };
    let exact = key(&mut name.bytes());
    let folded = key(&mut name.bytes().map(|b| b.to_ascii_lowercase()));
    Some((exact, folded))
}

impl Resemblance {
    /// Record frame `i` named `name` (new to the graph); what it resembles
    /// among the frames recorded before (`names` gives their names).
    pub fn add(&mut self, i: usize, name: &str, names: &[String]) -> Option<Likeness> {
        let (exact, folded) = keys(name);
        let other = self
            .exact
            .get(&exact)
            .or_else(|| self.folded.get(&folded))
            .copied();
        self.exact.entry(exact).or_insert(i);
        self.folded.entry(folded).or_insert(i);
        match other {
            Some(j) => Some(Likeness::Resembles {
                other: j,
                how: difference(name, &names[j]),
            }),
            None if name.trim() != name => Some(Likeness::Padded),
            None => None,
        }
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
        let mut names: Vec<String> = Vec::new();
        for (i, n) in earlier.iter().enumerate() {
            names.push(n.to_string());
            r.add(i, n, &names);
        }
        names.push(name.to_string());
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
        for name in ["base_link", "l100000", "Cam_0|rn`%\"", "a b\tc\u{7f}"] {
            let full: String = skeleton(name).collect();
            let lower: String = skeleton(&name.to_lowercase()).collect();
            assert_eq!(ascii_keys(name), Some((full, lower)), "{name:?}");
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
