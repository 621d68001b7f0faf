//! The one byte reader of the binary formats: bounded reads of fixed-size
//! fields, little-endian unless a format says otherwise, that return a typed
//! [`Short`] instead of panicking or reading past the end (after gimli's
//! `Reader` and mcap's record reader). Arrow IPC tables, ROS 1 bag records,
//! CDR and ROS 1 messages, PLY and PCD records and the LAS header are all read
//! through it; each format words its own message from the [`Short`].
//!
//! Two ways in: a [`Reader`], a cursor that moves past what it reads (records
//! and messages), and [`read_at`] / [`get_at`], reads at an offset (layouts
//! that point into a buffer: flatbuffer tables, the LAS header, a record's
//! fields).
//!
//! Magic bytes that more than one module tests for live here too
//! ([`LAS_MAGIC`], [`PLY_MAGICS`], [`looks_like_pcd`]): the point readers
//! decode point clouds, the formats refuse them naming the command that reads
//! them.

/// The first bytes of every LAS and LAZ file (ASPRS LAS 1.0 to 1.4, "File
/// Signature").
pub const LAS_MAGIC: &[u8; 4] = b"LASF";

/// The first line of every PLY file (the magic `ply`, with a Unix or DOS line
/// end; Paul Bourke's PLY description).
pub const PLY_MAGICS: [&[u8]; 2] = [b"ply\n", b"ply\r\n"];

/// Whether a text head is a PCD header: its first line that is not blank or
/// a plain comment is `# .PCD ...`, or starts with `VERSION` or `FIELDS` (PCL's
/// PCD file format: the header's first entries).
pub fn looks_like_pcd(head: &[u8]) -> bool {
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

/// The byte order of multi-byte fields.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Endian {
    /// Least significant byte first (x86, ARM as used, most formats here).
    Little,
    /// Most significant byte first (big-endian PLY, CDR `00 00`).
    Big,
}

impl Endian {
    /// `Little` when `little`, else `Big`.
    pub fn little_if(little: bool) -> Endian {
        if little {
            Endian::Little
        } else {
            Endian::Big
        }
    }
}

/// A read that wanted more bytes than there are: it started at byte `at`,
/// wanted `wanted` bytes and found `left`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Short {
    /// Where the read started.
    pub at: usize,
    /// How many bytes it wanted.
    pub wanted: usize,
    /// How many bytes there were from `at` to the end.
    pub left: usize,
}

/// A fixed-size field type: an integer or a float.
pub trait Primitive: Sized + Copy {
    /// Its size in bytes.
    const SIZE: usize;
    /// The value of the first [`Primitive::SIZE`] bytes of `b`, which has at
    /// least that many (the callers below check it).
    fn decode(b: &[u8], endian: Endian) -> Self;
}

macro_rules! fields {
    ($($t:ty),*) => {$(
        impl Primitive for $t {
            const SIZE: usize = std::mem::size_of::<$t>();
            #[inline(always)]
            fn decode(b: &[u8], endian: Endian) -> Self {
                let mut a = [0u8; std::mem::size_of::<$t>()];
                a.copy_from_slice(&b[..std::mem::size_of::<$t>()]);
                match endian {
                    Endian::Little => <$t>::from_le_bytes(a),
                    Endian::Big => <$t>::from_be_bytes(a),
                }
            }
        }
    )*};
}

fields!(u8, i8, u16, i16, u32, i32, u64, i64, f32, f64);

/// The `len` bytes of `b` from `at`.
#[inline(always)]
pub fn slice_at(b: &[u8], at: usize, len: usize) -> Result<&[u8], Short> {
    at.checked_add(len)
        .and_then(|end| b.get(at..end))
        .ok_or_else(|| Short {
            at,
            wanted: len,
            left: b.len().saturating_sub(at),
        })
}

/// The field of type `T` at byte `at` of `b`.
#[inline(always)]
pub fn read_at<T: Primitive>(b: &[u8], at: usize, endian: Endian) -> Result<T, Short> {
    slice_at(b, at, T::SIZE).map(|s| T::decode(s, endian))
}

/// [`read_at`] as an `Option` (for decoders that give a missing field a
/// value): the record decoders' hot path, so no error is built.
#[inline(always)]
pub fn get_at<T: Primitive>(b: &[u8], at: usize, endian: Endian) -> Option<T> {
    // Two comparisons and no overflow check: `at <= len`, then `SIZE <= len - at`.
    let s = b.get(at..)?.get(..T::SIZE)?;
    Some(T::decode(s, endian))
}

/// A cursor over bytes: every read is bounded by the bytes left and moves past
/// what it read; a read that does not fit moves nothing.
#[derive(Debug, Clone)]
pub struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
    endian: Endian,
}

impl<'a> Reader<'a> {
    /// A reader at the start of `data`.
    pub fn new(data: &'a [u8], endian: Endian) -> Self {
        Reader {
            data,
            pos: 0,
            endian,
        }
    }

    /// Where the next read starts.
    pub fn pos(&self) -> usize {
        self.pos
    }

    /// Move to byte `pos` (beyond the end: every read then comes up short).
    pub fn seek(&mut self, pos: usize) {
        self.pos = pos;
    }

    /// The whole buffer's length.
    pub fn len(&self) -> usize {
        self.data.len()
    }

    /// The bytes from the position to the end.
    pub fn left(&self) -> usize {
        self.data.len().saturating_sub(self.pos)
    }

    /// The next `n` bytes.
    pub fn take(&mut self, n: usize) -> Result<&'a [u8], Short> {
        let s = slice_at(self.data, self.pos, n)?;
        self.pos += n;
        Ok(s)
    }

    /// The next field of type `T`.
    pub fn read<T: Primitive>(&mut self) -> Result<T, Short> {
        let v = read_at(self.data, self.pos, self.endian)?;
        self.pos += T::SIZE;
        Ok(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_read_in_either_order() {
        let b = [1u8, 2, 3, 4, 5, 6, 7, 8];
        assert_eq!(read_at::<u16>(&b, 0, Endian::Little), Ok(0x0201));
        assert_eq!(read_at::<u16>(&b, 0, Endian::Big), Ok(0x0102));
        assert_eq!(read_at::<u32>(&b, 4, Endian::Little), Ok(0x0807_0605));
        assert_eq!(read_at::<i8>(&[0xff], 0, Endian::Little), Ok(-1));
        let x = 1.5f64.to_le_bytes();
        assert_eq!(read_at::<f64>(&x, 0, Endian::Little), Ok(1.5));
        let y = (-2.25f32).to_be_bytes();
        assert_eq!(read_at::<f32>(&y, 0, Endian::Big), Ok(-2.25));
    }

    #[test]
    fn a_short_read_says_where_and_how_much() {
        let b = [0u8; 6];
        let s = read_at::<u64>(&b, 2, Endian::Little).unwrap_err();
        assert_eq!(
            s,
            Short {
                at: 2,
                wanted: 8,
                left: 4
            }
        );
        assert_eq!(slice_at(&b, 7, 1).unwrap_err().left, 0);
        assert!(slice_at(&b, usize::MAX, 2).is_err(), "no overflow");
        assert_eq!(get_at::<u32>(&b, 3, Endian::Little), None);
    }

    #[test]
    fn the_cursor_moves_only_on_success() {
        let mut r = Reader::new(&[1, 0, 2, 0, 0, 0, 9], Endian::Little);
        assert_eq!(r.read::<u16>(), Ok(1));
        assert_eq!(r.read::<u32>(), Ok(2));
        assert_eq!(r.pos(), 6);
        assert!(r.read::<u16>().is_err());
        assert_eq!((r.pos(), r.left()), (6, 1));
        assert_eq!(r.take(1), Ok(&[9u8][..]));
        r.seek(100);
        assert_eq!(r.left(), 0);
        assert!(r.take(1).is_err());
    }
}
