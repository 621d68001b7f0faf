//! Message decoders for the message types a bag is read for:
//! `tf2_msgs/TFMessage`, `std_msgs/String`, `rcl_interfaces/msg/ParameterEvent`
//! and the pose of `nav_msgs/Odometry` (`sensor_msgs/PointCloud2`: in
//! [`super::pointcloud2`], on this module's cursor), in both wire formats.
//!
//! - ROS 2 CDR (XCDR1, `PLAIN_CDR`): a 4-byte encapsulation header (`00 01`
//!   little-endian, `00 00` big-endian, then two option bytes); every primitive is
//!   aligned to its size counted from the end of that header; a string is a
//!   `u32` length that counts its NUL terminator, then the bytes and the NUL; a
//!   sequence is a `u32` count then the elements.
//! - ROS 1: little-endian, no alignment; a string is a `u32` length (no NUL);
//!   `Header` starts with a `u32 seq`; `time` is `u32 sec, u32 nsec`.
//!
//! `TransformStamped` = `Header header, string child_frame_id, Transform
//! transform` with `Transform` = `Vector3 translation` (x y z) then `Quaternion
//! rotation` (x y z w), all `float64`. The transform is the pose of
//! `child_frame_id` in `header.frame_id`.
//!
//! Errors are strings naming the byte offset in the message; the caller adds
//! the bag, topic and message. Counts and lengths are checked against the bytes
//! left before anything is allocated, so a corrupt count cannot exhaust memory.

/// The serialization a container declares for a topic.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// ROS 2 CDR (`cdr` in MCAP and rosbag2 sqlite3).
    Cdr,
    /// ROS 1 serialization (`.bag` files, `ros1` in MCAP).
    Ros1,
}

/// One `geometry_msgs/TransformStamped`.
#[derive(Debug, Clone, PartialEq)]
pub struct TfRecord {
    /// `header.frame_id`.
    pub parent: String,
    /// `child_frame_id`.
    pub child: String,
    /// `transform.translation` (m): the child's origin in the parent.
    pub translation: [f64; 3],
    /// x, y, z, w.
    pub rotation: [f64; 4],
    /// `header.stamp` in nanoseconds (sec * 1e9 + nsec, negative before 1970).
    pub stamp_ns: i128,
}

use crate::bytes::{Endian, Primitive, Reader};

/// A lower bound on the size of an encoded `TransformStamped` (seven doubles,
/// the stamp and two string lengths: 72 bytes; ROS 1 adds `seq`, CDR the NULs),
/// to bound a sequence count by the bytes left.
const MIN_TRANSFORM_BYTES: usize = 56 + 8 + 4 + 4;

/// A message cursor: the shared byte reader, with CDR's alignment on top.
pub(super) struct Cursor<'a> {
    r: Reader<'a>,
    /// Where alignment is counted from (after the CDR header); `None`: no alignment.
    align_origin: Option<usize>,
}

impl<'a> Cursor<'a> {
    pub(super) fn new(data: &'a [u8], enc: Encoding) -> Result<Self, String> {
        match enc {
            Encoding::Ros1 => Ok(Cursor {
                r: Reader::new(data, Endian::Little),
                align_origin: None,
            }),
            Encoding::Cdr => {
                let endian = match data.get(..2) {
                    Some([0, 1]) => Endian::Little,
                    Some([0, 0]) => Endian::Big,
                    Some(h) => {
                        return Err(format!(
                        "CDR encapsulation header {:02x} {:02x}: expected 00 01 (CDR little-endian) or 00 00 (big-endian); XCDR2 is not supported",
                        h[0], h[1]
                    ))
                    }
                    None => {
                        return Err(format!(
                        "message of {} bytes: expected at least a 4-byte CDR encapsulation header",
                        data.len()
                    ))
                    }
                };
                if data.len() < 4 {
                    return Err(format!(
                        "message of {} bytes: expected at least a 4-byte CDR encapsulation header",
                        data.len()
                    ));
                }
                let mut r = Reader::new(data, endian);
                r.seek(4);
                Ok(Cursor {
                    r,
                    align_origin: Some(4),
                })
            }
        }
    }

    pub(super) fn pos(&self) -> usize {
        self.r.pos()
    }

    pub(super) fn left(&self) -> usize {
        self.r.left()
    }

    /// CDR aligns a primitive of `n` bytes (1, 2, 4 or 8) to `n`, counted from
    /// the end of the header.
    fn align(&mut self, n: usize) {
        if let Some(o) = self.align_origin {
            let pos = self.r.pos();
            let rel = pos.saturating_sub(o);
            self.r.seek(pos.saturating_add((n - rel % n) % n));
        }
    }

    fn short(&self, what: &str, n: usize) -> String {
        format!(
            "byte {}: expected {what} ({n} bytes), found the end of the {}-byte message",
            self.r.pos(),
            self.r.len()
        )
    }

    /// A primitive of `n` bytes (1, 2, 4 or 8), aligned.
    pub(super) fn prim(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        self.align(n);
        self.take(n, what)
    }

    pub(super) fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        let r = self.r.take(n);
        r.map_err(|_| self.short(what, n))
    }

    /// A field of type `T`, aligned.
    fn field<T: Primitive>(&mut self, what: &str) -> Result<T, String> {
        self.align(T::SIZE);
        let r = self.r.read::<T>();
        r.map_err(|_| self.short(what, T::SIZE))
    }

    pub(super) fn u32(&mut self, what: &str) -> Result<u32, String> {
        self.field(what)
    }

    pub(super) fn u8(&mut self, what: &str) -> Result<u8, String> {
        self.field(what)
    }

    /// Skip a sequence of `elem`-byte primitives.
    fn skip_seq(&mut self, elem: usize, what: &str) -> Result<(), String> {
        let at = self.pos();
        let n = self.u32(what)? as usize;
        if n > self.left() / elem {
            return Err(format!(
                "byte {at}: {what} count {n}: expected at most {} in the {} bytes left",
                self.left() / elem,
                self.left()
            ));
        }
        for _ in 0..n {
            self.prim(elem, what)?;
        }
        Ok(())
    }

    pub(super) fn i32(&mut self, what: &str) -> Result<i32, String> {
        self.field(what)
    }

    pub(super) fn f64(&mut self, what: &str) -> Result<f64, String> {
        self.field(what)
    }

    pub(super) fn string(&mut self, what: &str) -> Result<String, String> {
        let at = self.pos();
        let n = self.u32(what)? as usize;
        if n > self.left() {
            return Err(format!(
                "byte {at}: {what} of length {n}: expected at most the {} bytes left in the message",
                self.left()
            ));
        }
        let raw = self.take(n, what)?;
        let body = match self.align_origin {
            // CDR counts the NUL terminator.
            Some(_) => match raw.split_last() {
                Some((0, b)) => b,
                _ => {
                    return Err(format!(
                        "byte {at}: {what}: expected a NUL-terminated CDR string, found none"
                    ))
                }
            },
            None => raw,
        };
        String::from_utf8(body.to_vec())
            .map_err(|_| format!("byte {at}: {what}: expected UTF-8 text, found invalid bytes"))
    }

    pub(super) fn finish(&self) -> Result<(), String> {
        // CDR may pad to a multiple of 4 at the end; anything more is a wrong type.
        let slack = if self.align_origin.is_some() { 3 } else { 0 };
        if self.left() > slack {
            return Err(format!(
                "{} bytes left after the message ended at byte {}: expected none (is the topic's type right?)",
                self.left(),
                self.pos()
            ));
        }
        Ok(())
    }
}

fn transform(c: &mut Cursor, enc: Encoding) -> Result<TfRecord, String> {
    let (stamp_ns, parent) = c.header(enc)?;
    let child = c.string("child_frame_id")?;
    let mut translation = [0.0; 3];
    for (v, n) in translation.iter_mut().zip(["x", "y", "z"]) {
        *v = c.f64(&format!("transform.translation.{n}"))?;
    }
    let mut rotation = [0.0; 4];
    for (v, n) in rotation.iter_mut().zip(["x", "y", "z", "w"]) {
        *v = c.f64(&format!("transform.rotation.{n}"))?;
    }
    Ok(TfRecord {
        parent,
        child,
        translation,
        rotation,
        stamp_ns,
    })
}

impl Cursor<'_> {
    /// A ROS `Header`: the stamp (ns; negative before 1970) and `frame_id`
    /// (ROS 1 adds `seq` first).
    pub(super) fn header(&mut self, enc: Encoding) -> Result<(i128, String), String> {
        let (sec, nsec) = match enc {
            Encoding::Ros1 => {
                self.u32("header.seq")?;
                (
                    i64::from(self.u32("header.stamp.sec")?),
                    self.u32("header.stamp.nsec")?,
                )
            }
            Encoding::Cdr => (
                i64::from(self.i32("header.stamp.sec")?),
                self.u32("header.stamp.nanosec")?,
            ),
        };
        let frame = self.string("header.frame_id")?;
        Ok((i128::from(sec) * 1_000_000_000 + i128::from(nsec), frame))
    }
}

/// One `nav_msgs/Odometry`'s pose: `pose.pose` is the pose of
/// `child_frame_id` in `header.frame_id` (the REP 105 `odom -> base_link`
/// motion), position x y z then orientation x y z w.
#[derive(Debug, Clone, PartialEq)]
pub struct OdometryPose {
    /// `header.stamp` (ns).
    pub stamp_ns: i128,
    /// `header.frame_id`.
    pub parent: String,
    /// `child_frame_id`.
    pub child: String,
    /// Position (m).
    pub translation: [f64; 3],
    /// Orientation x, y, z, w.
    pub rotation: [f64; 4],
}

/// Decode the pose of a `nav_msgs/Odometry` (the covariances and the twist
/// after it are not read).
pub fn odometry(data: &[u8], enc: Encoding) -> Result<OdometryPose, String> {
    let mut c = Cursor::new(data, enc)?;
    let (stamp_ns, parent) = c.header(enc)?;
    let child = c.string("child_frame_id")?;
    let mut translation = [0.0; 3];
    for (v, n) in translation.iter_mut().zip(["x", "y", "z"]) {
        *v = c.f64(&format!("pose.pose.position.{n}"))?;
    }
    let mut rotation = [0.0; 4];
    for (v, n) in rotation.iter_mut().zip(["x", "y", "z", "w"]) {
        *v = c.f64(&format!("pose.pose.orientation.{n}"))?;
    }
    // pose.covariance (36), twist.twist (6), twist.covariance (36) doubles.
    for k in 0..78 {
        c.f64(&format!("double {k} after the pose"))?;
    }
    c.finish()?;
    Ok(OdometryPose {
        stamp_ns,
        parent,
        child,
        translation,
        rotation,
    })
}

/// Decode a `tf2_msgs/TFMessage`.
pub fn tf_message(data: &[u8], enc: Encoding) -> Result<Vec<TfRecord>, String> {
    let mut c = Cursor::new(data, enc)?;
    let n = c.u32("transforms count")? as usize;
    if n > c.left() / MIN_TRANSFORM_BYTES {
        return Err(format!(
            "transforms count {n}: expected at most {} in the {} bytes left",
            c.left() / MIN_TRANSFORM_BYTES,
            c.left()
        ));
    }
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        out.push(transform(&mut c, enc).map_err(|e| format!("transforms[{i}]: {e}"))?);
    }
    c.finish()?;
    Ok(out)
}

/// `rcl_interfaces/msg/ParameterValue` type of a string parameter.
const PARAMETER_STRING: u8 = 4;

/// One parameter of a `rcl_interfaces/msg/Parameter` list: its name and, for a
/// string parameter, its value.
fn parameter(c: &mut Cursor) -> Result<(String, Option<String>), String> {
    let name = c.string("parameter name")?;
    let kind = c.u8("value.type")?;
    c.u8("value.bool_value")?;
    c.prim(8, "value.integer_value")?;
    c.f64("value.double_value")?;
    let text = c.string("value.string_value")?;
    c.skip_seq(1, "value.byte_array_value")?;
    c.skip_seq(1, "value.bool_array_value")?;
    c.skip_seq(8, "value.integer_array_value")?;
    c.skip_seq(8, "value.double_array_value")?;
    let at = c.pos();
    let n = c.u32("value.string_array_value count")? as usize;
    if n > c.left() / 4 {
        return Err(format!(
            "byte {at}: string_array_value count {n}: expected at most {}",
            c.left() / 4
        ));
    }
    for _ in 0..n {
        c.string("value.string_array_value[]")?;
    }
    Ok((name, (kind == PARAMETER_STRING).then_some(text)))
}

/// The string parameters a ROS 2 `rcl_interfaces/msg/ParameterEvent` (CDR)
/// sets (new or changed): `(node, name, value)`.
pub fn parameter_event(data: &[u8]) -> Result<Vec<(String, String, String)>, String> {
    let mut c = Cursor::new(data, Encoding::Cdr)?;
    c.i32("stamp.sec")?;
    c.u32("stamp.nanosec")?;
    let node = c.string("node")?;
    let mut out = Vec::new();
    for list in ["new_parameters", "changed_parameters", "deleted_parameters"] {
        let at = c.pos();
        let n = c.u32(list)? as usize;
        // A parameter takes at least 40 bytes (name, type, scalars, lengths).
        if n > c.left() / 40 {
            return Err(format!(
                "byte {at}: {list} count {n}: expected at most {} in the {} bytes left",
                c.left() / 40,
                c.left()
            ));
        }
        for i in 0..n {
            let (name, value) = parameter(&mut c).map_err(|e| format!("{list}[{i}]: {e}"))?;
            if let (Some(v), false) = (value, list == "deleted_parameters") {
                out.push((node.clone(), name, v));
            }
        }
    }
    c.finish()?;
    Ok(out)
}

/// Decode a `std_msgs/String`.
pub fn string_message(data: &[u8], enc: Encoding) -> Result<String, String> {
    let mut c = Cursor::new(data, enc)?;
    let s = c.string("data")?;
    c.finish()?;
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cdr_string_counts_its_nul() {
        let msg = [0, 1, 0, 0, 3, 0, 0, 0, b'h', b'i', 0, 0];
        assert_eq!(string_message(&msg, Encoding::Cdr).unwrap(), "hi");
    }

    #[test]
    fn cdr_big_endian_and_alignment_after_the_header() {
        // 00 00: big-endian. One transform: stamp, "a", "b", then the doubles
        // aligned to 8 counted from byte 4.
        let mut m = vec![0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 7, 0, 0, 0, 9];
        m.extend([0, 0, 0, 2, b'a', 0, 0, 0, 0, 0, 0, 2, b'b', 0]);
        m.resize(36, 0); // pad: byte 30 -> 36 (32 past the header)
        for v in [1.5f64, -2.0, 0.25, 0.0, 0.0, 0.0, 1.0] {
            m.extend(v.to_be_bytes());
        }
        let t = tf_message(&m, Encoding::Cdr).unwrap();
        assert_eq!(t.len(), 1);
        assert_eq!((t[0].parent.as_str(), t[0].child.as_str()), ("a", "b"));
        assert_eq!(t[0].translation, [1.5, -2.0, 0.25]);
        assert_eq!(t[0].rotation, [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(t[0].stamp_ns, 7_000_000_009);
    }

    #[test]
    fn xcdr2_is_refused_by_name() {
        let e = string_message(&[0, 7, 0, 0, 1, 0, 0, 0, 0], Encoding::Cdr).unwrap_err();
        assert!(e.contains("XCDR2 is not supported"), "{e}");
    }

    #[test]
    fn ros1_string_has_no_nul() {
        let msg = [2, 0, 0, 0, b'h', b'i'];
        assert_eq!(string_message(&msg, Encoding::Ros1).unwrap(), "hi");
    }

    #[test]
    fn huge_counts_are_refused_before_allocating() {
        let msg = [0, 1, 0, 0, 0xff, 0xff, 0xff, 0xff];
        let e = tf_message(&msg, Encoding::Cdr).unwrap_err();
        assert!(e.contains("transforms count 4294967295"), "{e}");
        let e = string_message(&[0xff, 0xff, 0xff, 0x7f], Encoding::Ros1).unwrap_err();
        assert!(e.contains("expected at most the 0 bytes"), "{e}");
    }

    #[test]
    fn truncated_transform_names_the_field_and_offset() {
        // One transform: the stamp, then a frame_id length past the end.
        let mut msg = vec![0, 1, 0, 0, 1, 0, 0, 0, 5, 0, 0, 0, 0, 0, 0, 0, 200, 0, 0, 0];
        msg.resize(100, 0);
        let e = tf_message(&msg, Encoding::Cdr).unwrap_err();
        assert!(
            e.starts_with("transforms[0]: byte 16: header.frame_id of length 200"),
            "{e}"
        );
    }
}
