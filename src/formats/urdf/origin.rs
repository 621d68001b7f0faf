//! Numbers as urdfdom reads them, and `<origin>`: its pose (`rpy`, or
//! `quat_xyzw` from URDF 1.1) and the rounding of its numbers as written,
//! from one reading of each attribute. Nothing is allocated unless an error
//! or a warning is raised: a message names its attribute through [`What`],
//! formatted only then.

use super::lines::Lines;
use super::stream::{err_at, El};
use super::version::Version;
use crate::diagnostic::{Code, Location, Result, Warning};
use crate::formats::spec::{locate_warnings, UrdfVersion};
use crate::geometry::uncertainty::{half_units, rounding_covariance, rounding_std};
use crate::geometry::{EdgePrecision, Precision, QuatOrder, Transform};
use std::fmt;

/// A numeric attribute in messages: `joint 'NAME' <TAG ATTR>`.
#[derive(Clone, Copy)]
pub(super) struct What<'n> {
    pub joint: &'n str,
    pub tag: &'n str,
    pub attr: &'n str,
}

impl fmt::Display for What<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "joint '{}' <{} {}>", self.joint, self.tag, self.attr)
    }
}

/// `N` finite numbers separated by ASCII whitespace (a no-break space is no
/// separator for urdfdom), with their texts.
pub(super) fn numbers<'s, const N: usize>(
    s: &'s str,
    what: What,
) -> std::result::Result<([f64; N], [&'s str; N]), String> {
    let (mut parts, mut count) = ([""; N], 0usize);
    for p in s.split_ascii_whitespace() {
        if let Some(slot) = parts.get_mut(count) {
            *slot = p;
        }
        count += 1;
    }
    if count != N {
        return Err(format!(
            "{what}: expected {N} numbers, found {count} ({s:?})"
        ));
    }
    let mut out = [0.0; N];
    for (x, p) in out.iter_mut().zip(parts) {
        *x = parse_f64(p)
            .ok_or_else(|| format!("{what}: expected {N} numbers, found {p:?} in {s:?}"))?;
        if !x.is_finite() {
            return Err(format!("{what}: expected finite numbers, found {p:?}"));
        }
    }
    Ok((out, parts))
}

/// `s` as `str::parse::<f64>` reads it, `None` where it fails: a plain
/// decimal literal (`-0.002`, `12.5`, `3`) is read directly, the rest by
/// `str::parse`.
fn parse_f64(s: &str) -> Option<f64> {
    plain_f64(s.as_bytes()).or_else(|| s.parse().ok())
}

/// A literal `[+-]digits[.digits]` (or `[+-].digits`) whose digits, read
/// as one integer, are at most 2^53 and with at most 22 after the point:
/// that integer and the power of ten are then exact doubles, so their
/// quotient, rounded once by the division, is the correctly rounded value
/// of the literal, the number `str::parse` gives (Clinger's fast path).
/// `None` for anything else (exponents, longer literals, `inf`, ...).
fn plain_f64(b: &[u8]) -> Option<f64> {
    const POW10: [f64; 23] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
        1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
    ];
    let (neg, digits) = match b.first()? {
        b'-' => (true, &b[1..]),
        b'+' => (false, &b[1..]),
        _ => (false, b),
    };
    let (mut w, mut n, mut frac, mut dot) = (0u64, 0usize, 0usize, false);
    for &c in digits {
        match c {
            b'0'..=b'9' => {
                w = w.checked_mul(10)?.checked_add(u64::from(c - b'0'))?;
                n += 1;
                frac += usize::from(dot);
            }
            b'.' if !dot => dot = true,
            _ => return None,
        }
    }
    if n == 0 || w > 1 << 53 || frac >= POW10.len() {
        return None;
    }
    // w is at most 2^53: exact as a double.
    let x = w as f64 / POW10[frac];
    Some(if neg { -x } else { x })
}

/// `N` finite numbers separated by whitespace.
pub(super) fn numbers_attr<const N: usize>(
    s: &str,
    what: What,
) -> std::result::Result<[f64; N], String> {
    numbers::<N>(s, what).map(|(x, _)| x)
}

/// An attribute not written: three zeros.
const ZEROS: ([f64; 3], [&str; 3]) = ([0.0; 3], ["0"; 3]);

/// `<origin xyz rpy>` or, from URDF 1.1, `<origin xyz quat_xyzw>` (both is
/// an error in every version): the pose and the rounding of its numbers.
/// `loc` locates the warnings (made only when one is raised).
pub(super) fn origin(
    idx: &Lines,
    o: &El,
    name: &str,
    version: Version,
    loc: &dyn Fn() -> Location,
    warnings: &mut Vec<Warning>,
) -> Result<(Transform, Precision)> {
    let what = |attr: &'static str| What {
        joint: name,
        tag: "origin",
        attr,
    };
    let read3 = |attr: &'static str| match o.attr(attr) {
        Some(s) => numbers::<3>(s, what(attr)).map_err(|m| err_at(idx, o, m)),
        None => Ok(ZEROS),
    };
    let xyz = read3("xyz")?;
    let rpy = |r: ([f64; 3], [&str; 3])| -> Result<(Transform, Precision)> {
        let t = Transform::from_rpy(r.0, xyz.0).map_err(|e| err_at(idx, o, e.message))?;
        // Kept compact: the covariance is rpy_covariance of these, computed
        // where it is used.
        let u = |texts: &[&str; 3]| half_units(texts).map(rounding_std);
        Ok((t, Precision::rpy(r.0, u(&xyz.1), u(&r.1))))
    };
    match (o.attr("rpy"), o.attr("quat_xyzw")) {
        (Some(_), Some(_)) => Err(err_at(
            idx,
            o,
            format!("joint '{name}' <origin>: expected either rpy or quat_xyzw, found both"),
        )),
        (None, Some(q)) if version.used < UrdfVersion::V1_1 => {
            warnings.push(
                Warning::new(Code::QuatXyzwIgnored, quat_ignored(name, q, version)).at(&loc()),
            );
            rpy(ZEROS)
        }
        (None, Some(q)) => {
            let (q, q_texts) = numbers::<4>(q, what("quat_xyzw")).map_err(|m| err_at(idx, o, m))?;
            let mut ws = Vec::new();
            let t =
                Transform::from_quaternion(q, QuatOrder::Xyzw, xyz.0, &mut ws).map_err(|e| {
                    err_at(
                        idx,
                        o,
                        format!("joint '{name}' <origin quat_xyzw>: {}", e.message),
                    )
                })?;
            if !ws.is_empty() {
                locate_warnings(ws, &loc(), warnings);
            }
            if version.declared.unwrap_or(UrdfVersion::V1_0) < UrdfVersion::V1_1 {
                warnings.push(
                    Warning::new(
                        Code::AssumedConvention,
                        format!(
                            "joint '{name}' <origin quat_xyzw>: applied because of --urdf-version {}; the file {}, so ROS ignores it and runs with the identity rotation",
                            version.used,
                            version.declared_text()
                        ),
                    )
                    .at(&loc()),
                );
            }
            Ok((t, quat_precision(xyz, (q, q_texts))))
        }
        (_, None) => rpy(read3("rpy")?),
    }
}

/// `quat_xyzw` in a file read as URDF 1.0: ROS ignores it.
fn quat_ignored(name: &str, q: &str, version: Version) -> String {
    if version.declared.unwrap_or(UrdfVersion::V1_0) < UrdfVersion::V1_1 {
        format!(
            "joint '{name}' <origin quat_xyzw=\"{q}\">: ignored, as ROS ignores it: the file {} and quat_xyzw exists from URDF 1.1, so urdfdom uses the identity rotation; add version=\"1.1\" to <robot> (or pass --urdf-version 1.1) if the quaternion is meant",
            version.declared_text()
        )
    } else {
        format!(
            "joint '{name}' <origin quat_xyzw=\"{q}\">: ignored because of --urdf-version {}; the file {}, so ROS applies it",
            version.used,
            version.declared_text()
        )
    }
}

/// The rounding of `xyz` and `quat_xyzw` as written (conventions in
/// [`crate::geometry::uncertainty`]): each attribute is one tuple, the
/// covariance carried through the quaternion by finite steps.
fn quat_precision(xyz: ([f64; 3], [&str; 3]), q: ([f64; 4], [&str; 4])) -> Precision {
    let (hd, hq) = (half_units(&xyz.1), half_units(&q.1));
    let params = [xyz.0[0], xyz.0[1], xyz.0[2], q.0[0], q.0[1], q.0[2], q.0[3]];
    let halves = [hd[0], hd[1], hd[2], hq[0], hq[1], hq[2], hq[3]];
    let build = |p: &[f64]| {
        Transform::from_quaternion(
            [p[3], p[4], p[5], p[6]],
            QuatOrder::Xyzw,
            [p[0], p[1], p[2]],
            &mut Vec::new(),
        )
    };
    match rounding_covariance(&params, &halves, build) {
        Ok(c) => EdgePrecision {
            rounding: Some(c),
            user: None,
        }
        .into(),
        Err(_) => Precision::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::{parse_f64, plain_f64};

    /// Bit for bit the double of `str::parse`, or its refusal, on edge
    /// cases and on many pseudo-random literals (lengths 1 to 26, signs,
    /// points anywhere, digit runs that cross 2^53 and 22 decimals).
    #[test]
    fn plain_literals_read_as_str_parse_reads_them() {
        let same = |s: &str| {
            let want = s.parse::<f64>().ok().map(f64::to_bits);
            assert_eq!(parse_f64(s).map(f64::to_bits), want, "{s:?}");
        };
        for s in [
            "0",
            "-0",
            "+0",
            "-0.0",
            "0.",
            ".0",
            "-.5",
            "+.5",
            ".",
            "-",
            "+",
            "",
            "1.",
            "00012.5000",
            "9007199254740992",
            "9007199254740993",
            "-9007199254740993",
            "18446744073709551615",
            "18446744073709551616",
            "0.1",
            "0.2",
            "0.3",
            "0.01",
            "0.002",
            "-0.003",
            "1.7976931348623157",
            "0.0000000000000000000001",
            "0.00000000000000000000001",
            "4.9406564584124654",
            "2.2250738585072014",
            "123456789012345678901234567890",
            "1e5",
            "1E-3",
            "inf",
            "NaN",
            "1..2",
            "1.2.3",
            "--1",
            "+-1",
            "1 ",
            " 1",
            "0x10",
            "1_000",
            "\u{661}",
        ] {
            same(s);
        }
        let mut x: u64 = 0x2545_F491_4F6C_DD1D;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        for _ in 0..200_000 {
            let r = next();
            let len = 1 + (r % 26) as usize;
            let mut s = String::new();
            match (r >> 8) % 4 {
                0 => s.push('-'),
                1 => s.push('+'),
                _ => {}
            }
            let dot = ((r >> 16) % (len as u64 + 2)) as usize;
            for k in 0..len {
                if k == dot {
                    s.push('.');
                }
                // Runs of 9s and 0s cross the limits more often than uniform digits.
                let d = next();
                s.push(match d % 4 {
                    0 => '9',
                    1 => '0',
                    _ => char::from(b'0' + (d >> 8) as u8 % 10),
                });
            }
            same(&s);
        }
        // The fast path was taken where it claims to be.
        assert_eq!(plain_f64(b"-0.003"), Some(-0.003));
        assert_eq!(plain_f64(b"1e3"), None);
    }
}
