//! The `version` attribute of `<robot>`, read exactly as urdfdom reads it
//! (ROS's parser: `URDFVersion` in urdf_parser.h and the range check in
//! model.cpp; urdfdom 6.0, measured with its `check_urdf` build by the
//! conformance suite).
//!
//! Form: no attribute is 1.0. Otherwise the text is split at every `.`, a
//! trailing empty piece dropped (urdfdom_headers' `split_string`), and exactly
//! two pieces must remain, each a C `strtol` integer: optional leading
//! whitespace and sign, at least one digit, nothing after, not negative. So
//! `"1.0"`, `"01.1"`, `" 1.0"`, `"+1.0"`, `"1.-0"` and even `"1.0."` are 1.0 or
//! 1.1, while `"1"`, `"1.0.0"`, `"1."`, `".1"`, `"a.b"`, `"1.0 "` and `""` are
//! refused. Range: versions 1.0 to 1.2 are read (urdfdom 5.1 read up to 1.1,
//! 6.0 up to 1.2); anything else is refused, as urdfdom refuses it. `strtol` saturates at the `long` range and urdfdom keeps
//! the low 32 bits of the result; both are reproduced.
//!
//! Meaning: `quat_xyzw` on `<origin>` exists from 1.1; a 1.0 file's
//! `quat_xyzw` is ignored by ROS (see `read.rs`). From 1.2 a revolute or
//! prismatic `<limit>` needs `lower` and `upper` and no longer `effort` and
//! `velocity`.

use std::fmt;

/// A URDF version `major.minor`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct UrdfVersion {
    /// The number before the dot.
    pub major: u32,
    /// The number after the dot.
    pub minor: u32,
}

impl UrdfVersion {
    /// URDF 1.0: the default when `<robot>` declares none.
    pub const V1_0: UrdfVersion = UrdfVersion { major: 1, minor: 0 };
    /// URDF 1.1: adds `quat_xyzw` on `<origin>`.
    pub const V1_1: UrdfVersion = UrdfVersion { major: 1, minor: 1 };
    /// URDF 1.2: `<limit>` rules change (see the module documentation).
    pub const V1_2: UrdfVersion = UrdfVersion { major: 1, minor: 2 };

    /// Parse a version as urdfdom does, form and range: the error says what
    /// urdfdom objects to.
    pub fn parse(text: &str) -> Result<UrdfVersion, String> {
        let v = Self::parse_form(text)?;
        if v < Self::V1_0 || v > Self::V1_2 {
            return Err(format!(
                "URDF version {v} (written {text:?}): expected 1.0, 1.1 or 1.2, the versions ROS (urdfdom 6.0) reads"
            ));
        }
        Ok(v)
    }

    /// The `x.y` form alone, without the range check.
    fn parse_form(text: &str) -> Result<UrdfVersion, String> {
        let mut pieces: Vec<&str> = text.split('.').collect();
        // urdfdom_headers' split_string keeps empty pieces except a last one.
        if pieces.last().is_some_and(|p| p.is_empty()) {
            pieces.pop();
        }
        let [major, minor] = pieces[..] else {
            return Err(format!(
                "version {text:?}: expected the form x.y (two integers separated by one dot, e.g. \"1.0\")"
            ));
        };
        Ok(UrdfVersion {
            major: strtol_unsigned(major, text)?,
            minor: strtol_unsigned(minor, text)?,
        })
    }
}

/// One field as urdfdom's `strToUnsigned`: `strtol` base 10 over the whole
/// piece, refused when blank, without digits, with trailing text or negative.
fn strtol_unsigned(piece: &str, text: &str) -> Result<u32, String> {
    if piece.is_empty() {
        return Err(format!(
            "version {text:?}: one of the fields is blank; expected the form x.y"
        ));
    }
    // C isspace: space, \t, \n, \v, \f, \r.
    let rest = piece.trim_start_matches([' ', '\t', '\n', '\u{b}', '\u{c}', '\r']);
    let (negative, rest) = match rest.as_bytes().first() {
        Some(b'-') => (true, &rest[1..]),
        Some(b'+') => (false, &rest[1..]),
        _ => (false, rest),
    };
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    if digits == 0 {
        return Err(format!(
            "version {text:?}: field {piece:?} is not an integer; expected the form x.y"
        ));
    }
    if digits != rest.len() {
        return Err(format!(
            "version {text:?}: extra characters after the number in field {piece:?}; expected the form x.y"
        ));
    }
    // strtol saturates at the range of a 64-bit long.
    let magnitude = rest[..digits].bytes().fold(0i128, |acc, d| {
        (acc * 10 + i128::from(d - b'0')).min(i128::from(i64::MAX) + 1)
    });
    let value = if negative {
        (-magnitude).max(i128::from(i64::MIN))
    } else {
        magnitude.min(i128::from(i64::MAX))
    };
    if value < 0 {
        return Err(format!(
            "version {text:?}: field {piece:?} is negative; expected non-negative integers"
        ));
    }
    // urdfdom stores the long in a uint32_t: the low 32 bits.
    Ok((value as u64 & u64::from(u32::MAX)) as u32)
}

impl fmt::Display for UrdfVersion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{}", self.major, self.minor)
    }
}

impl std::str::FromStr for UrdfVersion {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        UrdfVersion::parse(s)
    }
}

#[cfg(test)]
mod tests {
    use super::UrdfVersion;

    fn v(major: u32, minor: u32) -> Result<UrdfVersion, String> {
        Ok(UrdfVersion { major, minor })
    }

    /// The strings of urdfdom's urdf_version_test.cpp and what it expects.
    #[test]
    fn urdfdom_version_class_cases() {
        assert_eq!(UrdfVersion::parse("1.0"), v(1, 0));
        for (s, why) in [
            ("1.0.0", "form x.y"),
            ("1.", "form x.y"),
            (".1", "blank"),
            ("-1.0", "negative"),
            ("1.-1", "negative"),
            ("abc", "form x.y"),
            ("a.c", "not an integer"),
            ("1.c", "not an integer"),
            ("1.0~pre6", "extra characters"),
            ("foo", "form x.y"),
            ("1", "form x.y"),
        ] {
            let e = UrdfVersion::parse(s).expect_err(s);
            assert!(e.contains(why), "{s}: {e}");
        }
        // Well formed, out of range.
        for s in ["2.0", "0.9", "1.3"] {
            assert!(UrdfVersion::parse(s)
                .expect_err(s)
                .contains("1.0, 1.1 or 1.2"));
        }
        assert_eq!(UrdfVersion::parse("1.2"), v(1, 2));
    }

    /// Consequences of strtol and split_string that the tests do not spell out.
    #[test]
    fn strtol_and_split_quirks() {
        assert_eq!(UrdfVersion::parse("01.01"), v(1, 1));
        assert_eq!(UrdfVersion::parse(" 1.\t0"), v(1, 0));
        assert_eq!(UrdfVersion::parse("+1.+1"), v(1, 1));
        assert_eq!(UrdfVersion::parse("1.-0"), v(1, 0));
        assert_eq!(UrdfVersion::parse("1.0."), v(1, 0));
        assert_eq!(UrdfVersion::parse("4294967297.1"), v(1, 1));
        assert!(UrdfVersion::parse("").is_err());
        assert!(UrdfVersion::parse("1.0 ").is_err());
        assert!(UrdfVersion::parse("1..0").is_err());
        assert!(UrdfVersion::parse("99999999999999999999.0").is_err());
        assert!(UrdfVersion::parse("-99999999999999999999.0").is_err());
    }
}
