//! Point files with normals: CSV, PLY (ascii, binary little and big endian) and
//! PCD (ascii, binary).
//!
//! - CSV: `x,y,z,nx,ny,nz[,w]`, with or without a header line. A header names
//!   the columns (`x y z nx ny nz w`; `normal_x`.. and `weight` also accepted) in
//!   any order; without one the columns are positional. Commas, semicolons, tabs
//!   or spaces separate fields; `#` starts a comment line.
//! - PLY: `element vertex` with scalar properties `x y z nx ny nz` (optional `w`
//!   or `weight`), any numeric type. Elements before `vertex` must have scalar
//!   properties only (they are skipped); elements after it are ignored.
//! - PCD (0.7): `FIELDS x y z normal_x normal_y normal_z` (or `nx ny nz`), with
//!   `SIZE`/`TYPE`/`COUNT`, `DATA ascii` or `binary`. `binary_compressed` is
//!   refused (decompress it with `pcl_convert_pcd_ascii_binary`).
//!
//! Checks: a file claiming more points than it holds is an error (pre-allocation
//! is capped, never taken from the header); a zero normal is an error naming the
//! line (or vertex); normals off unit length by more than [`NORMAL_UNIT_TOL`] are
//! renormalised with one `assumed-convention` warning for the file; points with
//! a non-finite coordinate or normal (PCL marks invalid points with NaN) are
//! skipped with a warning; a coordinate beyond [`MAX_COORDINATE`] and a negative
//! or non-finite weight are errors.

use crate::diagnostic::{Error, ErrorKind, Result, Warning, WarningCode};
use crate::tolerances::{
    MAX_COORDINATE, MAX_PCD_COUNT, MAX_POINT_FILE_SIZE, NORMAL_UNIT_TOL, NORMAL_ZERO_TOL,
};
use std::path::Path;

/// Cap on the capacity reserved from a header's point count.
const MAX_PREALLOC: usize = 1 << 20;

/// Which reader was used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointFormat {
    Csv,
    PlyAscii,
    PlyBinaryLittleEndian,
    PlyBinaryBigEndian,
    PcdAscii,
    PcdBinary,
}

impl PointFormat {
    pub fn name(self) -> &'static str {
        match self {
            PointFormat::Csv => "csv",
            PointFormat::PlyAscii => "ply-ascii",
            PointFormat::PlyBinaryLittleEndian => "ply-binary-little-endian",
            PointFormat::PlyBinaryBigEndian => "ply-binary-big-endian",
            PointFormat::PcdAscii => "pcd-ascii",
            PointFormat::PcdBinary => "pcd-binary",
        }
    }
}

/// Points with unit normals and optional weights.
#[derive(Debug, Clone, PartialEq)]
pub struct PointData {
    pub points: Vec<[f64; 3]>,
    pub normals: Vec<[f64; 3]>,
    pub weights: Option<Vec<f64>>,
    pub format: PointFormat,
    pub warnings: Vec<Warning>,
}

/// Read a point file, detecting the format from its content (`ply` magic, a PCD
/// header) and otherwise reading CSV.
pub fn read_points(path: &Path) -> Result<PointData> {
    // Regular files only, reads bounded (issue 12: src/input.rs).
    let bytes = crate::input::read_bytes(path, MAX_POINT_FILE_SIZE, "the point-file size cap")?;
    parse_points(crate::input::strip_bom_bytes(&bytes)).map_err(|e| e.in_file(path))
}

/// Parse a point file held in memory.
pub fn parse_points(bytes: &[u8]) -> Result<PointData> {
    if bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n") {
        return parse_ply(bytes);
    }
    if looks_like_pcd(bytes) {
        return parse_pcd(bytes);
    }
    parse_csv(bytes)
}

fn looks_like_pcd(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(4096)];
    let s = String::from_utf8_lossy(head);
    for line in s.lines() {
        let t = line.trim();
        if t.is_empty() || (t.starts_with('#') && !t.contains(".PCD")) {
            continue;
        }
        if t.starts_with("# .PCD") {
            return true;
        }
        let first = t.split_whitespace().next().unwrap_or("");
        return matches!(first, "VERSION" | "FIELDS");
    }
    false
}

/// The names of the six required roles (x y z and the normal) that `roles`
/// has not found, in order.
fn missing_roles<'a, T>(roles: &[Option<T>], names: [&'a str; 6]) -> Vec<&'a str> {
    names
        .into_iter()
        .zip(roles)
        .filter(|(_, r)| r.is_none())
        .map(|(n, _)| n)
        .collect()
}

/// Collects validated points.
struct Builder {
    points: Vec<[f64; 3]>,
    normals: Vec<[f64; 3]>,
    weights: Option<Vec<f64>>,
    renormalised: usize,
    worst_norm_dev: f64,
    skipped_nonfinite: usize,
}

impl Builder {
    fn new(capacity_hint: usize, weighted: bool) -> Self {
        let cap = capacity_hint.min(MAX_PREALLOC);
        Builder {
            points: Vec::with_capacity(cap),
            normals: Vec::with_capacity(cap),
            weights: if weighted {
                Some(Vec::with_capacity(cap))
            } else {
                None
            },
            renormalised: 0,
            worst_norm_dev: 0.0,
            skipped_nonfinite: 0,
        }
    }

    /// `where_` names the place for errors ("line 12", "vertex 4").
    fn push(&mut self, v: &[f64; 7], where_: &dyn Fn() -> (Option<usize>, String)) -> Result<()> {
        let p = [v[0], v[1], v[2]];
        let mut n = [v[3], v[4], v[5]];
        if !p.iter().chain(n.iter()).all(|x| x.is_finite()) {
            self.skipped_nonfinite += 1;
            return Ok(());
        }
        if let Some(x) = p.iter().find(|x| x.abs() > MAX_COORDINATE) {
            let (line, what) = where_();
            let e = Error::parse(format!(
                "{what}: expected coordinates within +-{MAX_COORDINATE:e}, found {x:e}"
            ));
            return Err(match line {
                Some(l) => e.at_line(l, None),
                None => e,
            });
        }
        // Scaled norm: a normal like [1e200, 0, 0] must not overflow to inf and
        // then normalise to zero.
        let scale = n[0].abs().max(n[1].abs()).max(n[2].abs());
        let norm = if scale > 0.0 {
            let (a, b, c) = (n[0] / scale, n[1] / scale, n[2] / scale);
            scale * (a * a + b * b + c * c).sqrt()
        } else {
            0.0
        };
        if norm < NORMAL_ZERO_TOL {
            let (line, what) = where_();
            let e = Error::parse(format!(
                "{what}: expected a unit normal, found a zero normal [{}, {}, {}]",
                n[0], n[1], n[2]
            ));
            return Err(match line {
                Some(l) => e.at_line(l, None),
                None => e,
            });
        }
        let dev = (norm - 1.0).abs();
        if dev > NORMAL_UNIT_TOL {
            self.renormalised += 1;
            self.worst_norm_dev = self.worst_norm_dev.max(dev);
            n = [n[0] / norm, n[1] / norm, n[2] / norm];
        }
        if let Some(w) = self.weights.as_mut() {
            let wi = v[6];
            if !(wi.is_finite() && wi >= 0.0) {
                let (line, what) = where_();
                let e = Error::parse(format!(
                    "{what}: expected a non-negative finite weight, found {wi}"
                ));
                return Err(match line {
                    Some(l) => e.at_line(l, None),
                    None => e,
                });
            }
            w.push(wi);
        }
        self.points.push(p);
        self.normals.push(n);
        Ok(())
    }

    fn finish(self, format: PointFormat) -> PointData {
        let mut warnings = Vec::new();
        if self.renormalised > 0 {
            warnings.push(Warning::new(
                WarningCode::AssumedConvention,
                format!(
                    "{} normals were not unit length (largest | |n| - 1 | = {:.3e}); renormalised",
                    self.renormalised, self.worst_norm_dev
                ),
            ));
        }
        if self.skipped_nonfinite > 0 {
            warnings.push(Warning::new(
                WarningCode::Ignored,
                format!(
                    "{} points with a non-finite coordinate or normal (NaN marks invalid points in PCL) were skipped",
                    self.skipped_nonfinite
                ),
            ));
        }
        PointData {
            points: self.points,
            normals: self.normals,
            weights: self.weights,
            format,
            warnings,
        }
    }
}

// ---------------------------------------------------------------------------
// CSV
// ---------------------------------------------------------------------------

fn split_fields(line: &str) -> Vec<&str> {
    line.split([',', ';', '\t', ' '])
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .collect()
}

fn column_role(name: &str) -> Option<usize> {
    match name.trim().trim_matches('"').to_ascii_lowercase().as_str() {
        "x" => Some(0),
        "y" => Some(1),
        "z" => Some(2),
        "nx" | "normal_x" => Some(3),
        "ny" | "normal_y" => Some(4),
        "nz" | "normal_z" => Some(5),
        "w" | "weight" => Some(6),
        _ => None,
    }
}

fn parse_csv(bytes: &[u8]) -> Result<PointData> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        Error::parse(format!(
            "CSV: expected UTF-8 text, found invalid bytes at offset {}",
            e.valid_up_to()
        ))
    })?;
    // columns[role] = index in the row; None for absent optional weight.
    let mut columns: Option<[Option<usize>; 7]> = None;
    let mut ncols = 0usize;
    let mut builder: Option<Builder> = None;
    for (i, raw) in text.lines().enumerate() {
        let lineno = i + 1;
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields = split_fields(line);
        if columns.is_none() {
            let numeric = fields.iter().all(|f| f.parse::<f64>().is_ok());
            let mut cols = [None; 7];
            if numeric {
                if fields.len() != 6 && fields.len() != 7 {
                    return Err(Error::parse(format!(
                        "CSV: expected 6 or 7 columns x,y,z,nx,ny,nz[,w], found {}",
                        fields.len()
                    ))
                    .at_line(lineno, None));
                }
                for (k, c) in cols.iter_mut().enumerate().take(fields.len()) {
                    *c = Some(k);
                }
                ncols = fields.len();
            } else {
                for (k, f) in fields.iter().enumerate() {
                    if let Some(role) = column_role(f) {
                        if cols[role].is_some() {
                            return Err(Error::parse(format!(
                                "CSV header: column {f:?} appears twice"
                            ))
                            .at_line(lineno, None));
                        }
                        cols[role] = Some(k);
                    }
                }
                let missing = missing_roles(&cols, ["x", "y", "z", "nx", "ny", "nz"]);
                if !missing.is_empty() {
                    return Err(Error::parse(format!(
                        "CSV header: expected columns x,y,z,nx,ny,nz[,w], missing {} (found {:?})",
                        missing.join(","),
                        fields
                    ))
                    .at_line(lineno, None));
                }
                ncols = fields.len();
                columns = Some(cols);
                builder = Some(Builder::new(text.len() / 40, cols[6].is_some()));
                continue;
            }
            columns = Some(cols);
            builder = Some(Builder::new(text.len() / 40, cols[6].is_some()));
        }
        let (Some(cols), Some(b)) = (columns.as_ref(), builder.as_mut()) else {
            continue;
        };
        if fields.len() != ncols {
            return Err(Error::parse(format!(
                "CSV: expected {ncols} fields, found {}",
                fields.len()
            ))
            .at_line(lineno, None));
        }
        let mut v = [0.0f64; 7];
        for (role, c) in cols.iter().enumerate() {
            if let Some(k) = c {
                let f = fields[*k];
                v[role] = f.parse::<f64>().map_err(|_| {
                    Error::parse(format!(
                        "CSV: expected a number in column {}, found {f:?}",
                        k + 1
                    ))
                    .at_line(lineno, Some(k + 1))
                })?;
            }
        }
        b.push(&v, &|| (Some(lineno), format!("point on line {lineno}")))?;
    }
    match builder {
        Some(b) => Ok(b.finish(PointFormat::Csv)),
        None => Err(Error::parse(
            "CSV: expected rows x,y,z,nx,ny,nz[,w], found no data",
        )),
    }
}

// ---------------------------------------------------------------------------
// Binary scalar types (PLY and PCD)
// ---------------------------------------------------------------------------

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
}

impl Scalar {
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::I64 | Scalar::U64 | Scalar::F64 => 8,
        }
    }
    fn ply(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
    fn pcd(ty: &str, size: usize) -> Option<Scalar> {
        Some(match (ty, size) {
            ("I", 1) => Scalar::I8,
            ("U", 1) => Scalar::U8,
            ("I", 2) => Scalar::I16,
            ("U", 2) => Scalar::U16,
            ("I", 4) => Scalar::I32,
            ("U", 4) => Scalar::U32,
            ("I", 8) => Scalar::I64,
            ("U", 8) => Scalar::U64,
            ("F", 4) => Scalar::F32,
            ("F", 8) => Scalar::F64,
            _ => return None,
        })
    }
    /// Read one value; `b` has at least `size()` bytes.
    fn read(self, b: &[u8], little: bool) -> f64 {
        macro_rules! rd {
            ($t:ty, $n:expr) => {{
                let mut a = [0u8; $n];
                a.copy_from_slice(&b[..$n]);
                if little {
                    <$t>::from_le_bytes(a) as f64
                } else {
                    <$t>::from_be_bytes(a) as f64
                }
            }};
        }
        match self {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => rd!(i16, 2),
            Scalar::U16 => rd!(u16, 2),
            Scalar::I32 => rd!(i32, 4),
            Scalar::U32 => rd!(u32, 4),
            Scalar::I64 => rd!(i64, 8),
            Scalar::U64 => rd!(u64, 8),
            Scalar::F32 => rd!(f32, 4),
            Scalar::F64 => rd!(f64, 8),
        }
    }
}

/// Split off the header: lines up to and including the one `is_end` accepts.
/// Returns the header lines and the byte offset of the data.
fn header_lines(
    bytes: &[u8],
    is_end: &dyn Fn(&str) -> bool,
    what: &str,
) -> Result<(Vec<String>, usize)> {
    let mut lines = Vec::new();
    let mut pos = 0;
    while pos < bytes.len() {
        let end = bytes[pos..]
            .iter()
            .position(|&c| c == b'\n')
            .map(|k| pos + k);
        let Some(end) = end else { break };
        let line = String::from_utf8_lossy(&bytes[pos..end])
            .trim_end_matches('\r')
            .to_string();
        pos = end + 1;
        let done = is_end(&line);
        lines.push(line);
        if done {
            return Ok((lines, pos));
        }
        if lines.len() > 100_000 {
            break;
        }
    }
    Err(Error::parse(format!(
        "{what}: expected the end of the header, found end of file"
    )))
}

// ---------------------------------------------------------------------------
// PLY
// ---------------------------------------------------------------------------

struct PlyElement {
    name: String,
    count: usize,
    /// (name, type); `None` type for a list property.
    props: Vec<(String, Option<Scalar>)>,
    line: usize,
}

fn parse_ply(bytes: &[u8]) -> Result<PointData> {
    let (lines, data_start) = header_lines(bytes, &|l| l.trim() == "end_header", "PLY")?;
    let mut format = None;
    let mut elements: Vec<PlyElement> = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        let lineno = i + 1;
        let t: Vec<&str> = l.split_whitespace().collect();
        match t.first().copied() {
            Some("ply") | Some("comment") | Some("obj_info") | Some("end_header") | None => {}
            Some("format") => {
                format = Some(match t.get(1).copied() {
                    Some("ascii") => PointFormat::PlyAscii,
                    Some("binary_little_endian") => PointFormat::PlyBinaryLittleEndian,
                    Some("binary_big_endian") => PointFormat::PlyBinaryBigEndian,
                    other => {
                        return Err(Error::parse(format!(
                            "PLY: expected format ascii, binary_little_endian or binary_big_endian, found {other:?}"
                        ))
                        .at_line(lineno, None))
                    }
                })
            }
            Some("element") => {
                let (Some(name), Some(count)) = (t.get(1), t.get(2).and_then(|c| c.parse::<usize>().ok())) else {
                    return Err(Error::parse(format!("PLY: expected `element NAME COUNT`, found {l:?}")).at_line(lineno, None));
                };
                elements.push(PlyElement {
                    name: name.to_string(),
                    count,
                    props: Vec::new(),
                    line: lineno,
                });
            }
            Some("property") => {
                let Some(el) = elements.last_mut() else {
                    return Err(Error::parse("PLY: property before any element").at_line(lineno, None));
                };
                if t.get(1) == Some(&"list") {
                    el.props.push((t.get(4).unwrap_or(&"").to_string(), None));
                } else {
                    let (Some(ty), Some(name)) = (t.get(1), t.get(2)) else {
                        return Err(Error::parse(format!("PLY: expected `property TYPE NAME`, found {l:?}")).at_line(lineno, None));
                    };
                    let Some(s) = Scalar::ply(ty) else {
                        return Err(Error::parse(format!("PLY: unknown property type {ty:?}")).at_line(lineno, None));
                    };
                    el.props.push((name.to_string(), Some(s)));
                }
            }
            Some(other) => {
                return Err(Error::parse(format!("PLY: unexpected header line starting with {other:?}")).at_line(lineno, None))
            }
        }
    }
    let Some(format) = format else {
        return Err(Error::parse(
            "PLY: expected a `format` line in the header, found none",
        ));
    };
    let Some(vi) = elements.iter().position(|e| e.name == "vertex") else {
        return Err(Error::parse(
            "PLY: expected an `element vertex`, found none",
        ));
    };
    let vert = &elements[vi];
    let mut roles: [Option<usize>; 7] = [None; 7];
    for (k, (name, ty)) in vert.props.iter().enumerate() {
        if let Some(r) = column_role(name) {
            if ty.is_none() {
                return Err(
                    Error::parse(format!("PLY: vertex property {name:?} is a list"))
                        .at_line(vert.line, None),
                );
            }
            roles[r] = Some(k);
        }
    }
    let missing = missing_roles(&roles, ["x", "y", "z", "nx", "ny", "nz"]);
    if !missing.is_empty() {
        return Err(Error::parse(format!(
            "PLY: expected vertex properties x y z nx ny nz, missing {}",
            missing.join(" ")
        ))
        .at_line(vert.line, None));
    }
    let weighted = roles[6].is_some();
    let n_header = lines.len();
    let data = &bytes[data_start..];
    if format == PointFormat::PlyAscii {
        let text = String::from_utf8_lossy(data);
        let mut it = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        // Skip earlier elements (one line per item).
        for e in &elements[..vi] {
            for _ in 0..e.count {
                if it.next().is_none() {
                    return Err(Error::parse(format!(
                        "PLY: header claims {} `{}` items, the file ends before them",
                        e.count, e.name
                    )));
                }
            }
        }
        let mut b = Builder::new(vert.count, weighted);
        for k in 0..vert.count {
            let Some((li, line)) = it.next() else {
                return Err(Error::parse(format!(
                    "PLY: header claims {} vertices, the file holds {k}",
                    vert.count
                )));
            };
            let lineno = n_header + li + 1;
            let f: Vec<&str> = line.split_whitespace().collect();
            if f.len() < vert.props.len() {
                return Err(Error::parse(format!(
                    "PLY: expected {} values for vertex {k}, found {}",
                    vert.props.len(),
                    f.len()
                ))
                .at_line(lineno, None));
            }
            let mut v = [0.0; 7];
            for (r, c) in roles.iter().enumerate() {
                if let Some(c) = c {
                    v[r] = f[*c].parse::<f64>().map_err(|_| {
                        Error::parse(format!("PLY: expected a number, found {:?}", f[*c]))
                            .at_line(lineno, Some(c + 1))
                    })?;
                }
            }
            b.push(&v, &|| (Some(lineno), format!("vertex {k}")))?;
        }
        return Ok(b.finish(format));
    }
    let little = format == PointFormat::PlyBinaryLittleEndian;
    let mut off = 0usize;
    for e in &elements[..vi] {
        let mut size = 0usize;
        for (name, ty) in &e.props {
            match ty {
                Some(s) => size += s.size(),
                None => {
                    return Err(Error::parse(format!(
                        "PLY: element `{}` before the vertices has a list property {name:?}; only scalar elements can precede vertices",
                        e.name
                    ))
                    .at_line(e.line, None))
                }
            }
        }
        off = size
            .checked_mul(e.count)
            .and_then(|s| s.checked_add(off))
            .filter(|&o| o <= data.len())
            .ok_or_else(|| {
                Error::parse(format!(
                    "PLY: header claims {} `{}` items, the file ends before them",
                    e.count, e.name
                ))
            })?;
    }
    let mut offsets = Vec::new();
    let mut rec = 0usize;
    for (name, ty) in &vert.props {
        let Some(s) = ty else {
            return Err(Error::parse(format!(
                "PLY: vertex property {name:?} is a list; not supported in binary files"
            ))
            .at_line(vert.line, None));
        };
        offsets.push((rec, *s));
        rec += s.size();
    }
    let avail = (data.len() - off) / rec.max(1);
    if avail < vert.count {
        return Err(Error::parse(format!(
            "PLY: header claims {} vertices of {rec} bytes, the file holds {avail}",
            vert.count
        )));
    }
    let mut b = Builder::new(vert.count, weighted);
    for k in 0..vert.count {
        let base = off + k * rec;
        let mut v = [0.0; 7];
        for (r, c) in roles.iter().enumerate() {
            if let Some(c) = c {
                let (o, s) = offsets[*c];
                v[r] = s.read(&data[base + o..], little);
            }
        }
        b.push(&v, &|| {
            (
                None,
                format!("vertex {k} (byte offset {})", data_start + base),
            )
        })?;
    }
    Ok(b.finish(format))
}

// ---------------------------------------------------------------------------
// PCD
// ---------------------------------------------------------------------------

fn pcd_role(name: &str) -> Option<usize> {
    column_role(name)
}

fn parse_pcd(bytes: &[u8]) -> Result<PointData> {
    let (lines, data_start) = header_lines(bytes, &|l| l.trim_start().starts_with("DATA"), "PCD")?;
    let mut fields: Vec<String> = Vec::new();
    let mut sizes: Vec<usize> = Vec::new();
    let mut types: Vec<String> = Vec::new();
    let mut counts: Vec<usize> = Vec::new();
    let mut points: Option<usize> = None;
    let mut width: Option<usize> = None;
    let mut height: Option<usize> = None;
    let mut data_kind = String::new();
    for (i, l) in lines.iter().enumerate() {
        let lineno = i + 1;
        let t: Vec<&str> = l.split_whitespace().collect();
        let nums = |what: &str| -> Result<Vec<usize>> {
            t[1..]
                .iter()
                .map(|x| {
                    x.parse::<usize>().map_err(|_| {
                        Error::parse(format!(
                            "PCD {what}: expected non-negative integers, found {x:?}"
                        ))
                        .at_line(lineno, None)
                    })
                })
                .collect()
        };
        match t.first().copied() {
            None => {}
            Some(s) if s.starts_with('#') => {}
            Some("VERSION") | Some("VIEWPOINT") => {}
            Some("FIELDS") => fields = t[1..].iter().map(|s| s.to_string()).collect(),
            Some("SIZE") => sizes = nums("SIZE")?,
            Some("TYPE") => types = t[1..].iter().map(|s| s.to_string()).collect(),
            Some("COUNT") => counts = nums("COUNT")?,
            Some("WIDTH") => width = nums("WIDTH")?.first().copied(),
            Some("HEIGHT") => height = nums("HEIGHT")?.first().copied(),
            Some("POINTS") => points = nums("POINTS")?.first().copied(),
            Some("DATA") => {
                data_kind = t.get(1).copied().unwrap_or("").to_string();
            }
            Some(other) => {
                return Err(Error::parse(format!(
                    "PCD: unexpected header line starting with {other:?}"
                ))
                .at_line(lineno, None))
            }
        }
    }
    if counts.is_empty() {
        counts = vec![1; fields.len()];
    }
    if fields.is_empty()
        || sizes.len() != fields.len()
        || types.len() != fields.len()
        || counts.len() != fields.len()
    {
        return Err(Error::parse(format!(
            "PCD: expected FIELDS, SIZE, TYPE (and COUNT) of equal length, found {}, {}, {}, {}",
            fields.len(),
            sizes.len(),
            types.len(),
            counts.len()
        )));
    }
    // PCD's COUNT is the number of elements of a field: at least 1. A cap keeps
    // the record arithmetic far from overflow (real descriptors use <= 352).
    if let Some((k, c)) = counts
        .iter()
        .enumerate()
        .find(|(_, c)| **c == 0 || **c > MAX_PCD_COUNT)
    {
        return Err(Error::parse(format!(
            "PCD: field {:?}: expected COUNT between 1 and {MAX_PCD_COUNT}, found {c}",
            fields[k]
        )));
    }
    let n = match (points, width, height) {
        (Some(p), _, _) => p,
        (None, Some(w), Some(h)) => w.saturating_mul(h),
        _ => {
            return Err(Error::parse(
                "PCD: expected POINTS (or WIDTH and HEIGHT) in the header, found neither",
            ))
        }
    };
    let header_len = lines.len();
    let mut scalars = Vec::new();
    for k in 0..fields.len() {
        let Some(s) = Scalar::pcd(&types[k], sizes[k]) else {
            return Err(Error::parse(format!(
                "PCD: field {:?} has TYPE {} SIZE {}, not a supported combination",
                fields[k], types[k], sizes[k]
            )));
        };
        scalars.push(s);
    }
    // Element index (in the flattened token/record list) of each role.
    let mut roles: [Option<(usize, usize)>; 7] = [None; 7]; // (element index, byte offset)
    let mut elem = 0usize;
    let mut byte = 0usize;
    for k in 0..fields.len() {
        if let Some(r) = pcd_role(&fields[k]) {
            roles[r] = Some((elem, byte));
        }
        elem += counts[k];
        byte += counts[k] * sizes[k];
    }
    // Per-element scalar type, for binary reads.
    let missing = missing_roles(&roles, ["x", "y", "z", "normal_x", "normal_y", "normal_z"]);
    if !missing.is_empty() {
        return Err(Error::parse(format!(
            "PCD: expected FIELDS x y z normal_x normal_y normal_z, missing {} (found {})",
            missing.join(" "),
            fields.join(" ")
        )));
    }
    let weighted = roles[6].is_some();
    let role_scalar = |r: usize| -> Scalar {
        let (e, _) = roles[r].unwrap_or((0, 0));
        let mut acc = 0;
        for k in 0..fields.len() {
            if e < acc + counts[k] {
                return scalars[k];
            }
            acc += counts[k];
        }
        Scalar::F32
    };
    let data = &bytes[data_start..];
    match data_kind.as_str() {
        "ascii" => {
            let text = String::from_utf8_lossy(data);
            let mut b = Builder::new(n, weighted);
            let mut it = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty());
            for k in 0..n {
                let Some((li, line)) = it.next() else {
                    return Err(Error::parse(format!("PCD: header claims {n} points, the file holds {k}")));
                };
                let lineno = header_len + li + 1;
                let f: Vec<&str> = line.split_whitespace().collect();
                if f.len() < elem {
                    return Err(Error::parse(format!("PCD: expected {elem} values, found {}", f.len())).at_line(lineno, None));
                }
                let mut v = [0.0; 7];
                for (r, c) in roles.iter().enumerate() {
                    if let Some((e, _)) = c {
                        let tok = f[*e];
                        v[r] = if tok.eq_ignore_ascii_case("nan") {
                            f64::NAN
                        } else {
                            tok.parse::<f64>().map_err(|_| {
                                Error::parse(format!("PCD: expected a number, found {tok:?}")).at_line(lineno, Some(e + 1))
                            })?
                        };
                    }
                }
                b.push(&v, &|| (Some(lineno), format!("point {k}")))?;
            }
            Ok(b.finish(PointFormat::PcdAscii))
        }
        "binary" => {
            let rec = byte;
            let avail = data.len() / rec.max(1);
            if avail < n {
                return Err(Error::parse(format!("PCD: header claims {n} points of {rec} bytes, the file holds {avail}")));
            }
            let mut b = Builder::new(n, weighted);
            for k in 0..n {
                let base = k * rec;
                let mut v = [0.0; 7];
                for (r, c) in roles.iter().enumerate() {
                    if let Some((_, o)) = c {
                        v[r] = role_scalar(r).read(&data[base + o..], true);
                    }
                }
                b.push(&v, &|| (None, format!("point {k} (byte offset {})", data_start + base)))?;
            }
            Ok(b.finish(PointFormat::PcdBinary))
        }
        "binary_compressed" => Err(Error::new(
            ErrorKind::Parse,
            "PCD: DATA binary_compressed is not supported; convert the file to ascii or binary first (e.g. `pcl_convert_pcd_ascii_binary in.pcd out.pcd 1`)",
        )),
        other => Err(Error::parse(format!("PCD: expected DATA ascii, binary or binary_compressed, found {other:?}"))),
    }
}

// ---------------------------------------------------------------------------
// Writers (fixtures, round trips, exporting synthetic scenes)
// ---------------------------------------------------------------------------

/// Encoding for [`write_ply`] and [`write_pcd`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

/// CSV with a header `x,y,z,nx,ny,nz[,w]`, full precision.
pub fn write_csv(points: &[[f64; 3]], normals: &[[f64; 3]], weights: Option<&[f64]>) -> Vec<u8> {
    let mut s = String::from(if weights.is_some() {
        "x,y,z,nx,ny,nz,w\n"
    } else {
        "x,y,z,nx,ny,nz\n"
    });
    for i in 0..points.len().min(normals.len()) {
        let p = points[i];
        let n = normals[i];
        s.push_str(&format!(
            "{:?},{:?},{:?},{:?},{:?},{:?}",
            p[0], p[1], p[2], n[0], n[1], n[2]
        ));
        if let Some(w) = weights {
            s.push_str(&format!(",{:?}", w.get(i).copied().unwrap_or(1.0)));
        }
        s.push('\n');
    }
    s.into_bytes()
}

/// One record per point, `x y z nx ny nz` as doubles: ascii (shortest
/// round-trip text) or binary in the given byte order.
fn write_records(out: &mut Vec<u8>, points: &[[f64; 3]], normals: &[[f64; 3]], enc: Encoding) {
    for (p, n) in points.iter().zip(normals) {
        let vals = [p[0], p[1], p[2], n[0], n[1], n[2]];
        match enc {
            Encoding::Ascii => {
                let line: Vec<String> = vals.iter().map(|v| format!("{v:?}")).collect();
                out.extend_from_slice(line.join(" ").as_bytes());
                out.push(b'\n');
            }
            Encoding::BinaryLittleEndian => vals
                .iter()
                .for_each(|v| out.extend_from_slice(&v.to_le_bytes())),
            Encoding::BinaryBigEndian => vals
                .iter()
                .for_each(|v| out.extend_from_slice(&v.to_be_bytes())),
        }
    }
}

/// PLY with double properties `x y z nx ny nz`.
pub fn write_ply(points: &[[f64; 3]], normals: &[[f64; 3]], enc: Encoding) -> Vec<u8> {
    let n = points.len().min(normals.len());
    let fmt = match enc {
        Encoding::Ascii => "ascii",
        Encoding::BinaryLittleEndian => "binary_little_endian",
        Encoding::BinaryBigEndian => "binary_big_endian",
    };
    let mut out = format!(
        "ply\nformat {fmt} 1.0\ncomment written by extrinsic-audit\nelement vertex {n}\nproperty double x\nproperty double y\nproperty double z\nproperty double nx\nproperty double ny\nproperty double nz\nend_header\n"
    )
    .into_bytes();
    write_records(&mut out, points, normals, enc);
    out
}

/// PCD 0.7 with double fields `x y z normal_x normal_y normal_z` (binary is
/// little endian, as PCL writes it; `BinaryBigEndian` is treated as binary).
pub fn write_pcd(points: &[[f64; 3]], normals: &[[f64; 3]], enc: Encoding) -> Vec<u8> {
    let n = points.len().min(normals.len());
    let data = if enc == Encoding::Ascii {
        "ascii"
    } else {
        "binary"
    };
    let mut out = format!(
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 8 8 8 8 8 8\nTYPE F F F F F F\nCOUNT 1 1 1 1 1 1\nWIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA {data}\n"
    )
    .into_bytes();
    // PCL's binary is little endian.
    let enc = if enc == Encoding::BinaryBigEndian {
        Encoding::BinaryLittleEndian
    } else {
        enc
    };
    write_records(&mut out, points, normals, enc);
    out
}
