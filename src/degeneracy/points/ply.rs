//! PLY: ascii, binary little and big endian.

use super::binary::{decode_records, Layout, Run, Scalar};
use super::check::{Checker, Stats};
use super::record::{column_role, missing_roles, PointFormat, Sink};
use super::source::{header_lines, Source};
use crate::bytes::Endian;
use crate::diagnostic::{Error, Result};
use crate::tolerances::MAX_POINT_RECORD_BYTES;
use std::io::Read;

struct PlyElement {
    name: String,
    count: usize,
    /// (name, type); `None` type for a list property.
    props: Vec<(String, Option<Scalar>)>,
    /// (count type, item type) of each list property (`None` for a scalar).
    lists: Vec<Option<(Scalar, Scalar)>>,
    /// Header line of each property (for a duplicate's message).
    prop_lines: Vec<usize>,
    line: usize,
}

/// What the header says.
pub(super) struct Header {
    pub format: PointFormat,
    elements: Vec<PlyElement>,
    /// Index of the `vertex` element.
    vi: usize,
    /// Property index of each role.
    roles: [Option<usize>; 7],
}

impl Header {
    pub fn count(&self) -> usize {
        self.elements[self.vi].count
    }
    fn weighted(&self) -> bool {
        self.roles[6].is_some()
    }
}

fn header_line(
    t: &[&str],
    l: &str,
    lineno: usize,
    format: &mut Option<PointFormat>,
    elements: &mut Vec<PlyElement>,
) -> Result<()> {
    match t.first().copied() {
        Some("ply") | Some("comment") | Some("obj_info") | Some("end_header") | None => {}
        Some("format") => {
            *format = Some(match t.get(1).copied() {
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
                lists: Vec::new(),
                prop_lines: Vec::new(),
                line: lineno,
            });
        }
        Some("property") => {
            let Some(el) = elements.last_mut() else {
                return Err(Error::parse("PLY: property before any element").at_line(lineno, None));
            };
            let mut list = None;
            let (name, ty) = if t.get(1) == Some(&"list") {
                list = Some(list_types(t, l, lineno)?);
                (t.get(4).unwrap_or(&"").to_string(), None)
            } else {
                let (Some(ty), Some(name)) = (t.get(1), t.get(2)) else {
                    return Err(Error::parse(format!("PLY: expected `property TYPE NAME`, found {l:?}")).at_line(lineno, None));
                };
                let Some(s) = Scalar::ply(ty) else {
                    return Err(Error::parse(format!("PLY: unknown property type {ty:?}")).at_line(lineno, None));
                };
                (name.to_string(), Some(s))
            };
            // A second declaration would silently win over the first (issue 12).
            if let Some(k) = el.props.iter().position(|(n, _)| *n == name) {
                return Err(Error::parse(format!(
                    "PLY: element `{}` declares property {name:?} twice, at header lines {} and {lineno}",
                    el.name, el.prop_lines[k]
                ))
                .at_line(lineno, None));
            }
            el.props.push((name, ty));
            el.lists.push(list);
            el.prop_lines.push(lineno);
        }
        Some(other) => {
            return Err(Error::parse(format!("PLY: unexpected header line starting with {other:?}")).at_line(lineno, None))
        }
    }
    Ok(())
}

/// The (count, item) types of `property list COUNT ITEM NAME`: the count an
/// integer type.
fn list_types(t: &[&str], l: &str, lineno: usize) -> Result<(Scalar, Scalar)> {
    let (Some(c), Some(i), Some(_)) = (t.get(2), t.get(3), t.get(4)) else {
        return Err(Error::parse(format!(
            "PLY: expected `property list COUNT_TYPE ITEM_TYPE NAME`, found {l:?}"
        ))
        .at_line(lineno, None));
    };
    match (Scalar::ply(c), Scalar::ply(i)) {
        (Some(Scalar::F32 | Scalar::F64), _) => Err(Error::parse(format!(
            "PLY: expected an integer list count type, found {c:?}"
        ))
        .at_line(lineno, None)),
        (Some(c), Some(i)) => Ok((c, i)),
        _ => {
            Err(Error::parse(format!("PLY: unknown list types {c:?} {i:?}")).at_line(lineno, None))
        }
    }
}

pub(super) fn read_header<R: Read>(src: &mut Source<R>, xyz_only: bool) -> Result<Header> {
    let lines = header_lines(src, &|l| l.trim() == "end_header", "PLY")?;
    let mut format = None;
    let mut elements: Vec<PlyElement> = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        let t: Vec<&str> = l.split_whitespace().collect();
        header_line(&t, l, i + 1, &mut format, &mut elements)?;
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
    let missing = missing_roles(&roles, ["x", "y", "z", "nx", "ny", "nz"], xyz_only);
    if !missing.is_empty() {
        return Err(Error::parse(format!(
            "PLY: expected vertex properties x y z nx ny nz, missing {}",
            missing.join(" ")
        ))
        .at_line(vert.line, None));
    }
    Ok(Header {
        format,
        elements,
        vi,
        roles,
    })
}

/// Decode the data after the header into `sink`.
pub(super) fn body<R: Read, S: Sink>(
    src: &mut Source<R>,
    h: &Header,
    sink: &mut S,
) -> Result<(PointFormat, Stats)> {
    let mut ck = Checker::new(sink, h.weighted(), h.count());
    if h.format == PointFormat::PlyAscii {
        ascii(src, h, &mut ck)?;
    } else {
        let (_, layout) = binary_plan(h)?;
        for e in &h.elements[..h.vi] {
            let bytes = element_bytes(e)?;
            if src.skip(bytes)? < bytes {
                return Err(ends_before(e));
            }
        }
        decode_records(src, &layout, &run(h, 0, h.count()), &mut ck)?;
        binary_tail(src, h, layout.rec)?;
    }
    Ok((h.format, ck.stats))
}

/// Bytes of the elements after the vertices, when all are scalar (a list
/// element, e.g. faces, has no fixed size: `None`, and the end is not checked).
pub(super) fn tail_bytes(h: &Header) -> Option<u64> {
    h.elements[h.vi + 1..]
        .iter()
        .try_fold(0u64, |acc, e| acc.checked_add(element_bytes(e).ok()?))
}

/// After the vertices of a binary file: the later elements, then nothing (a
/// header that claims fewer vertices than the file holds is an error).
fn binary_tail<R: Read>(src: &mut Source<R>, h: &Header, rec: usize) -> Result<()> {
    let Some(tail) = tail_bytes(h) else {
        return list_tail(src, h);
    };
    let got = src.skip(tail)?;
    if got < tail {
        let e = h.elements[h.vi + 1..].iter().last();
        return Err(e.map_or_else(|| ends_before(&h.elements[h.vi]), ends_before));
    }
    let at = src.offset();
    if src.has_more()? {
        let extra = src.skip(u64::MAX)?;
        return Err(run(h, 0, h.count()).excess(rec, extra, at));
    }
    Ok(())
}

/// After the vertices of a binary file whose later elements have list
/// properties (faces): each item read by its declared types, each list by
/// its own count, then nothing (issue 12).
pub(super) fn list_tail<R: Read>(src: &mut Source<R>, h: &Header) -> Result<()> {
    let endian = Endian::little_if(h.format == PointFormat::PlyBinaryLittleEndian);
    for e in &h.elements[h.vi + 1..] {
        for k in 0..e.count {
            for ((name, ty), list) in e.props.iter().zip(&e.lists) {
                let bytes = match (ty, list) {
                    (Some(s), _) => s.size() as u64,
                    (None, Some((c, item))) => {
                        let n = read_scalar(src, *c, endian).ok_or_else(|| ends_in(e, k))?;
                        if !(n >= 0.0 && n <= u32::MAX as f64) {
                            return Err(Error::parse(format!(
                                "PLY: `{}` item {k}: expected a list length for {name:?}, found {n}",
                                e.name
                            ))
                            .at_line(e.line, None));
                        }
                        n as u64 * item.size() as u64
                    }
                    (None, None) => 0,
                };
                if src.skip(bytes)? < bytes {
                    return Err(ends_in(e, k));
                }
            }
        }
    }
    let at = src.offset();
    if src.has_more()? {
        let extra = src.skip(u64::MAX)?;
        let last = h.elements.last().map_or("vertex", |e| e.name.as_str());
        return Err(Error::parse(format!(
            "PLY: the file holds {extra} more bytes after the header's last element `{last}` (from byte offset {at}); expected the counts to match the data"
        )));
    }
    Ok(())
}

fn read_scalar<R: Read>(src: &mut Source<R>, s: Scalar, endian: Endian) -> Option<f64> {
    src.fill(s.size()).ok()?;
    let v = s.read(src.data(), 0, endian)?;
    src.consume(s.size());
    Some(v)
}

/// A later element cut short at item `k`.
fn ends_in(e: &PlyElement, k: usize) -> Error {
    Error::parse(format!(
        "PLY: header claims {} `{}` items, the file ends in item {k}",
        e.count, e.name
    ))
    .at_line(e.line, None)
}

/// The records `first .. first + count` of the vertex element.
pub(super) fn run(h: &Header, first: usize, count: usize) -> Run {
    Run {
        first,
        count,
        total: h.count(),
        names: ["PLY", "vertex", "vertices"],
        line: h.elements[h.vi].line,
    }
}

fn ends_before(e: &PlyElement) -> Error {
    Error::parse(format!(
        "PLY: header claims {} `{}` items, the file ends before them",
        e.count, e.name
    ))
}

/// Bytes of an element before the vertices (scalar properties only).
fn element_bytes(e: &PlyElement) -> Result<u64> {
    let mut size = 0u64;
    for (name, ty) in &e.props {
        match ty {
            Some(s) => size += s.size() as u64,
            None => {
                return Err(Error::parse(format!(
                    "PLY: element `{}` before the vertices has a list property {name:?}; only scalar elements can precede vertices",
                    e.name
                ))
                .at_line(e.line, None))
            }
        }
    }
    size.checked_mul(e.count as u64)
        .ok_or_else(|| ends_before(e))
}

fn ascii<R: Read, S: Sink>(src: &mut Source<R>, h: &Header, ck: &mut Checker<S>) -> Result<()> {
    let mut line = Vec::new();
    // The next non-empty data line, with its line number.
    let mut next = |src: &mut Source<R>| -> Result<Option<(usize, String)>> {
        loop {
            if src.read_line(&mut line)?.is_none() {
                return Ok(None);
            }
            let l = String::from_utf8_lossy(&line);
            if !l.trim().is_empty() {
                return Ok(Some((src.lines(), l.into_owned())));
            }
        }
    };
    // Skip earlier elements (one line per item).
    for e in &h.elements[..h.vi] {
        for _ in 0..e.count {
            if next(src)?.is_none() {
                return Err(Error::parse(format!(
                    "PLY: header claims {} `{}` items, the file ends before them",
                    e.count, e.name
                )));
            }
        }
    }
    let nprops = h.elements[h.vi].props.len();
    for k in 0..h.count() {
        let Some((lineno, line)) = next(src)? else {
            let vline = h.elements[h.vi].line;
            return Err(Error::parse(format!(
                "PLY: header line {vline} claims {} vertices, the file holds {k}",
                h.count()
            ))
            .at_line(vline, None));
        };
        let f: Vec<&str> = line.split_whitespace().collect();
        if f.len() < nprops {
            return Err(Error::parse(format!(
                "PLY: expected {nprops} values for vertex {k}, found {}",
                f.len()
            ))
            .at_line(lineno, None));
        }
        // Without normal properties (a raw scan) the normal is a placeholder +z.
        let mut v = [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0];
        for (r, c) in h.roles.iter().enumerate() {
            if let Some(c) = c {
                v[r] = f[*c].parse::<f64>().map_err(|_| {
                    Error::parse(format!("PLY: expected a number, found {:?}", f[*c]))
                        .at_line(lineno, Some(c + 1))
                })?;
            }
        }
        ck.record(&v)
            .map_err(|f| f.error(format!("vertex {k}"), Some(lineno)))?;
    }
    ascii_tail(src, h, &mut next)
}

/// The next non-empty data line, with its line number.
type NextLine<'a, R> = dyn FnMut(&mut Source<R>) -> Result<Option<(usize, String)>> + 'a;

/// After the vertices of an ascii file: one line per item of the later
/// elements, then nothing but blank lines.
fn ascii_tail<R: Read>(src: &mut Source<R>, h: &Header, next: &mut NextLine<'_, R>) -> Result<()> {
    for e in &h.elements[h.vi + 1..] {
        for _ in 0..e.count {
            if next(src)?.is_none() {
                return Err(ends_before(e).at_line(e.line, None));
            }
        }
    }
    if let Some(extra) = src.next_nonblank()? {
        let vert = &h.elements[h.vi];
        let later: usize = h.elements[h.vi + 1..].iter().map(|e| e.count).sum();
        return Err(Error::parse(format!(
            "PLY: header line {} claims {} vertices ({later} items of later elements), the file holds more: line {extra} is past them; expected the count to match the data",
            vert.line, vert.count
        ))
        .at_line(extra, None));
    }
    Ok(())
}

/// For a binary file: the bytes of the elements before the vertices, and the
/// vertex record layout.
pub(super) fn binary_plan(h: &Header) -> Result<(u64, Layout)> {
    let mut skip = 0u64;
    for e in &h.elements[..h.vi] {
        skip = element_bytes(e)?
            .checked_add(skip)
            .ok_or_else(|| ends_before(e))?;
    }
    let vert = &h.elements[h.vi];
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
    if rec > MAX_POINT_RECORD_BYTES {
        return Err(Error::limit(format!(
            "PLY: expected vertex records of at most {MAX_POINT_RECORD_BYTES} bytes, found {rec}"
        ))
        .at_line(vert.line, None));
    }
    let mut roles = [None; 7];
    for (r, c) in h.roles.iter().enumerate() {
        roles[r] = c.and_then(|c| offsets.get(c).copied());
    }
    Ok((
        skip,
        Layout {
            rec: rec.max(1),
            roles,
            endian: Endian::little_if(h.format == PointFormat::PlyBinaryLittleEndian),
        },
    ))
}
