//! `sensor_msgs/PointCloud2`, in both wire formats, and its points.
//!
//! The message (sensor_msgs `PointCloud2.msg`): `Header header`, `uint32
//! height`, `uint32 width`, `PointField[] fields` (`string name`, `uint32
//! offset`, `uint8 datatype`, `uint32 count`), `bool is_bigendian`, `uint32
//! point_step`, `uint32 row_step`, `uint8[] data`, `bool is_dense`. Point `(r,
//! c)` of the `height x width` grid starts at byte `r * row_step + c *
//! point_step` of `data`; a field's value at `offset` within the point, of
//! type `datatype` (`PointField.msg`: INT8=1, UINT8=2, INT16=3, UINT16=4,
//! INT32=5, UINT32=6, FLOAT32=7, FLOAT64=8), in the byte order
//! `is_bigendian` gives (as `sensor_msgs::PointCloud2Iterator` and
//! `pcl::fromROSMsg` read them).
//!
//! What is read: `x`, `y`, `z` (each of count 1, any datatype: an integer
//! field is the coordinate in metres as it is, PointCloud2 has no scale) and,
//! when all three exist, `normal_x`, `normal_y`, `normal_z`; every other field
//! is ignored. A point whose coordinates (or, when read, normal) are not all
//! finite is dropped and counted (NaN marks a no-return in organised clouds).
//! Checked before anything is read, in this order: every field's datatype is
//! one of the eight and its bytes end within `point_step`; `x`, `y` and `z`
//! exist with count 1; then an empty grid (`height` or `width` 0) is empty;
//! `row_step >= width * point_step`; `data` holds `(height - 1) * row_step +
//! width * point_step` bytes (more is allowed and reported).

use super::decode::{Cursor, Encoding};

/// One `sensor_msgs/PointField`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PointField {
    /// Field name (`x`, `intensity`, ...).
    pub name: String,
    /// Byte offset within a point.
    pub offset: u32,
    /// `PointField` datatype code (1-8).
    pub datatype: u8,
    /// Number of elements.
    pub count: u32,
}

/// A decoded `PointCloud2`, its `data` borrowed from the message.
#[derive(Debug, Clone)]
pub struct PointCloud2<'a> {
    /// `header.stamp` (ns; negative before 1970).
    pub stamp_ns: i128,
    /// `header.frame_id`.
    pub frame_id: String,
    /// Rows (1 for an unorganised cloud).
    pub height: u32,
    /// Points per row.
    pub width: u32,
    /// The fields.
    pub fields: Vec<PointField>,
    /// Byte order of the values.
    pub is_bigendian: bool,
    /// Bytes per point.
    pub point_step: u32,
    /// Bytes per row.
    pub row_step: u32,
    /// The point bytes.
    pub data: &'a [u8],
    /// The publisher's claim that no point is invalid (not relied on).
    pub is_dense: bool,
}

/// Decode a `sensor_msgs/PointCloud2` (the data stays in `data`).
pub fn decode(data: &[u8], enc: Encoding) -> Result<PointCloud2<'_>, String> {
    let mut c = Cursor::new(data, enc)?;
    let (stamp_ns, frame_id) = c.header(enc)?;
    let height = c.u32("height")?;
    let width = c.u32("width")?;
    let at = c.pos();
    let n = c.u32("fields count")? as usize;
    // A PointField takes at least 13 bytes (name length, offset, datatype, count).
    if n > c.left() / 13 {
        return Err(format!(
            "byte {at}: fields count {n}: expected at most {} in the {} bytes left",
            c.left() / 13,
            c.left()
        ));
    }
    let mut fields = Vec::with_capacity(n);
    for i in 0..n {
        let name = c.string(&format!("fields[{i}].name"))?;
        let offset = c.u32(&format!("fields[{i}].offset"))?;
        let datatype = c.u8(&format!("fields[{i}].datatype"))?;
        let count = c.u32(&format!("fields[{i}].count"))?;
        fields.push(PointField {
            name,
            offset,
            datatype,
            count,
        });
    }
    let is_bigendian = c.u8("is_bigendian")? != 0;
    let point_step = c.u32("point_step")?;
    let row_step = c.u32("row_step")?;
    let at = c.pos();
    let len = c.u32("data length")? as usize;
    if len > c.left() {
        return Err(format!(
            "byte {at}: data of {len} bytes: expected at most the {} bytes left in the message",
            c.left()
        ));
    }
    let bytes = c.take(len, "data")?;
    let is_dense = c.u8("is_dense")? != 0;
    c.finish()?;
    Ok(PointCloud2 {
        stamp_ns,
        frame_id,
        height,
        width,
        fields,
        is_bigendian,
        point_step,
        row_step,
        data: bytes,
        is_dense,
    })
}

/// A field's value type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Kind {
    fn of(datatype: u8) -> Option<Kind> {
        Some(match datatype {
            1 => Kind::I8,
            2 => Kind::U8,
            3 => Kind::I16,
            4 => Kind::U16,
            5 => Kind::I32,
            6 => Kind::U32,
            7 => Kind::F32,
            8 => Kind::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Kind::I8 | Kind::U8 => 1,
            Kind::I16 | Kind::U16 => 2,
            Kind::I32 | Kind::U32 | Kind::F32 => 4,
            Kind::F64 => 8,
        }
    }

    fn is_float(self) -> bool {
        matches!(self, Kind::F32 | Kind::F64)
    }
}

/// Where one value is read from a point, and how.
#[derive(Debug, Clone, Copy)]
struct Slot {
    offset: usize,
    kind: Kind,
}

impl Slot {
    /// The value at this slot of the point starting at `p` (in bounds: the
    /// layout checks guarantee it).
    #[inline(always)]
    fn read(self, b: &[u8], p: usize, big: bool) -> f64 {
        let i = p + self.offset;
        macro_rules! get {
            ($t:ty, $n:expr) => {{
                let mut a = [0u8; $n];
                a.copy_from_slice(&b[i..i + $n]);
                if big {
                    <$t>::from_be_bytes(a)
                } else {
                    <$t>::from_le_bytes(a)
                }
            }};
        }
        match self.kind {
            Kind::F32 => f64::from(get!(f32, 4)),
            Kind::F64 => get!(f64, 8),
            Kind::I8 => f64::from(b[i] as i8),
            Kind::U8 => f64::from(b[i]),
            Kind::I16 => f64::from(get!(i16, 2)),
            Kind::U16 => f64::from(get!(u16, 2)),
            Kind::I32 => f64::from(get!(i32, 4)),
            Kind::U32 => f64::from(get!(u32, 4)),
        }
    }
}

/// The values at three slots of the point starting at `p`.
#[inline(always)]
fn read3(s: &[Slot; 3], b: &[u8], p: usize, big: bool) -> [f64; 3] {
    [
        s[0].read(b, p, big),
        s[1].read(b, p, big),
        s[2].read(b, p, big),
    ]
}

/// A cloud's points as read.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Points {
    /// Points with finite coordinates (and normals, when read).
    pub points: Vec<[f64; 3]>,
    /// Their normals, when the cloud has `normal_x`, `normal_y`, `normal_z`
    /// and they were asked for.
    pub normals: Option<Vec<[f64; 3]>>,
    /// Cells of the grid (`height * width`).
    pub cells: usize,
    /// Cells dropped for a non-finite coordinate or normal.
    pub nonfinite: usize,
    /// `x`, `y` or `z` is an integer field (taken as metres as it is).
    pub integer_xyz: bool,
    /// Bytes of `data` past the last point.
    pub extra_bytes: usize,
    /// The cloud has all three normal fields.
    pub has_normals: bool,
}

/// What is wrong with a cloud, or that it is empty.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CloudError {
    /// `height` or `width` is 0.
    Empty,
    /// More cells than the caller takes.
    TooLarge(usize),
    /// The fields or steps contradict each other or the data.
    Invalid(String),
}

impl PointCloud2<'_> {
    fn slot(&self, name: &str) -> Option<(Slot, u32)> {
        let f = self.fields.iter().find(|f| f.name == name)?;
        let kind = Kind::of(f.datatype)?;
        Some((
            Slot {
                offset: f.offset as usize,
                kind,
            },
            f.count,
        ))
    }

    /// The checks of the module docs; the `x y z` slots and, when present,
    /// the normal slots.
    fn layout(&self, max_cells: usize) -> Result<([Slot; 3], Option<[Slot; 3]>), CloudError> {
        let step = self.point_step as u64;
        for f in &self.fields {
            let kind = Kind::of(f.datatype).ok_or_else(|| {
                CloudError::Invalid(format!(
                    "field {}: datatype {} is none of PointField's 1-8",
                    crate::sanitize::quote(&f.name),
                    f.datatype
                ))
            })?;
            let bytes = kind.size() as u64 * u64::from(f.count.max(1));
            if u64::from(f.offset) + bytes > step {
                return Err(CloudError::Invalid(format!(
                    "field {}: offset {} + {bytes} bytes exceeds point_step {step}",
                    crate::sanitize::quote(&f.name),
                    f.offset
                )));
            }
        }
        let mut xyz = [Slot {
            offset: 0,
            kind: Kind::F32,
        }; 3];
        for (k, c) in ["x", "y", "z"].into_iter().enumerate() {
            let (s, count) = self
                .slot(c)
                .ok_or_else(|| CloudError::Invalid(format!("no field {c}")))?;
            if count != 1 {
                return Err(CloudError::Invalid(format!(
                    "field {c}: count {count}, expected 1"
                )));
            }
            xyz[k] = s;
        }
        let normals = ["normal_x", "normal_y", "normal_z"].map(|n| self.slot(n).map(|(s, _)| s));
        let normals = match normals {
            [Some(a), Some(b), Some(c)] => Some([a, b, c]),
            _ => None,
        };
        let (h, w) = (self.height as u64, self.width as u64);
        if h * w == 0 {
            return Err(CloudError::Empty);
        }
        if h * w > max_cells as u64 {
            return Err(CloudError::TooLarge((h * w) as usize));
        }
        let rs = self.row_step as u64;
        if rs < w * step {
            return Err(CloudError::Invalid(format!(
                "row_step {rs} < width {w} * point_step {step}"
            )));
        }
        let need = (h - 1) * rs + w * step;
        if (self.data.len() as u64) < need {
            return Err(CloudError::Invalid(format!(
                "data holds {} bytes, height/width/steps need {need}",
                self.data.len()
            )));
        }
        Ok((xyz, normals))
    }

    /// The points (and normals when `with_normals` and present), at most
    /// `max_cells` cells (see the module docs).
    pub fn points(&self, with_normals: bool, max_cells: usize) -> Result<Points, CloudError> {
        let (xyz, nslots) = self.layout(max_cells)?;
        let big = self.is_bigendian;
        let (h, w) = (self.height as usize, self.width as usize);
        let (rs, step) = (self.row_step as usize, self.point_step as usize);
        let cells = h * w;
        let used = nslots.filter(|_| with_normals);
        let mut points = Vec::with_capacity(cells);
        let mut normals = used.map(|_| Vec::with_capacity(cells));
        let b = self.data;
        for r in 0..h {
            for c in 0..w {
                let p = r * rs + c * step;
                // Three reads written out: `array::map` made the read an
                // out-of-line closure call per value (53 M of five 128k
                // scans' instructions).
                let q = read3(&xyz, b, p, big);
                if !(q[0].is_finite() && q[1].is_finite() && q[2].is_finite()) {
                    continue;
                }
                if let (Some(ns), Some(out)) = (used, normals.as_mut()) {
                    let n = read3(&ns, b, p, big);
                    if !(n[0].is_finite() && n[1].is_finite() && n[2].is_finite()) {
                        continue;
                    }
                    out.push(n);
                }
                points.push(q);
            }
        }
        let need = (h - 1) * rs + w * step;
        Ok(Points {
            nonfinite: cells - points.len(),
            points,
            normals,
            cells,
            integer_xyz: xyz.iter().any(|s| !s.kind.is_float()),
            extra_bytes: b.len() - need,
            has_normals: nslots.is_some(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A CDR PointCloud2 (little-endian) of `pts` as float32 x y z at point_step 16.
    fn cloud(pts: &[[f32; 3]], h: u32, w: u32, big: bool) -> Vec<u8> {
        let mut m = vec![0, 1, 0, 0];
        m.extend(5i32.to_le_bytes());
        m.extend(7u32.to_le_bytes());
        m.extend(6u32.to_le_bytes());
        m.extend(b"lidar\0");
        m.resize(m.len().next_multiple_of(4), 0);
        m.extend(h.to_le_bytes());
        m.extend(w.to_le_bytes());
        m.extend(3u32.to_le_bytes());
        for (k, n) in ["x", "y", "z"].iter().enumerate() {
            while (m.len() - 4) % 4 != 0 {
                m.push(0);
            }
            m.extend(2u32.to_le_bytes());
            m.extend(n.as_bytes());
            m.push(0);
            while (m.len() - 4) % 4 != 0 {
                m.push(0);
            }
            m.extend((4 * k as u32).to_le_bytes());
            m.push(7);
            while (m.len() - 4) % 4 != 0 {
                m.push(0);
            }
            m.extend(1u32.to_le_bytes());
        }
        m.push(u8::from(big));
        while (m.len() - 4) % 4 != 0 {
            m.push(0);
        }
        m.extend(16u32.to_le_bytes());
        m.extend((16 * w).to_le_bytes());
        m.extend((16 * pts.len() as u32).to_le_bytes());
        for p in pts {
            for v in p {
                m.extend(if big {
                    v.to_be_bytes()
                } else {
                    v.to_le_bytes()
                });
            }
            m.extend([0xff; 4]);
        }
        m.push(1);
        m
    }

    #[test]
    fn reads_points_in_either_byte_order_and_drops_nan() {
        let pts = [[1.0, 2.0, 3.0], [f32::NAN, 0.0, 0.0], [-1.5, 0.25, 8.0]];
        for big in [false, true] {
            let m = cloud(&pts, 1, 3, big);
            let c = decode(&m, Encoding::Cdr).unwrap();
            assert_eq!((c.stamp_ns, c.frame_id.as_str()), (5_000_000_007, "lidar"));
            let p = c.points(true, 100).unwrap();
            assert_eq!(p.points, vec![[1.0, 2.0, 3.0], [-1.5, 0.25, 8.0]]);
            assert_eq!((p.cells, p.nonfinite, p.normals), (3, 1, None));
        }
    }

    #[test]
    fn steps_that_lie_are_refused_and_empty_grids_named() {
        let m = cloud(&[[1.0, 2.0, 3.0]], 1, 2, false);
        let c = decode(&m, Encoding::Cdr).unwrap();
        assert_eq!(
            c.points(false, 100),
            Err(CloudError::Invalid(
                "data holds 16 bytes, height/width/steps need 32".into()
            ))
        );
        let m = cloud(&[], 0, 5, false);
        let c = decode(&m, Encoding::Cdr).unwrap();
        assert_eq!(c.points(false, 100), Err(CloudError::Empty));
        let m = cloud(&[[1.0, 2.0, 3.0]; 4], 2, 2, false);
        let c = decode(&m, Encoding::Cdr).unwrap();
        assert_eq!(c.points(false, 3), Err(CloudError::TooLarge(4)));
    }

    #[test]
    fn a_huge_field_count_is_refused_before_allocating() {
        let mut m = cloud(&[], 1, 1, false);
        let at = 4 + 4 + 4 + 4 + 6 + 2 + 4 + 4;
        m[at..at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
        let e = decode(&m, Encoding::Cdr).unwrap_err();
        assert!(e.contains("fields count 4294967295"), "{e}");
    }
}
