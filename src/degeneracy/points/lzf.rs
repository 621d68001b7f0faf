//! LZF decompression (the format of PCD `DATA binary_compressed`, written by
//! PCL's `lzf_compress`), from the format's description: a control byte
//! `c < 32` is followed by `c + 1` literal bytes; otherwise `len = c >> 5`
//! (7 means "7 plus the next byte") and the back reference copies `len + 2`
//! bytes starting `((c & 31) << 8) + next + 1` bytes before the end of the
//! output (the copy may overlap itself). Every bound is checked: corrupt input
//! is an error, never a panic or an output longer than announced.

use crate::diagnostic::{Error, Result};

/// Decompress `input` into exactly `expected` bytes.
pub(crate) fn decompress(input: &[u8], expected: usize) -> Result<Vec<u8>> {
    let corrupt = |at: usize, what: &str| {
        Error::parse(format!(
            "PCD binary_compressed: corrupt LZF data at compressed byte {at}: {what}"
        ))
    };
    let mut out: Vec<u8> = Vec::with_capacity(expected.min(1 << 26));
    let mut i = 0;
    while i < input.len() {
        let at = i;
        let c = usize::from(input[i]);
        i += 1;
        if c < 32 {
            let n = c + 1;
            let lit = input
                .get(i..i + n)
                .ok_or_else(|| corrupt(at, "literal run past the end"))?;
            if out.len() + n > expected {
                return Err(corrupt(at, "output longer than announced"));
            }
            out.extend_from_slice(lit);
            i += n;
            continue;
        }
        let mut len = c >> 5;
        if len == 7 {
            len += usize::from(
                *input
                    .get(i)
                    .ok_or_else(|| corrupt(at, "truncated length"))?,
            );
            i += 1;
        }
        let lo = usize::from(
            *input
                .get(i)
                .ok_or_else(|| corrupt(at, "truncated offset"))?,
        );
        i += 1;
        let back = ((c & 0x1f) << 8) + lo + 1;
        let n = len + 2;
        if back > out.len() {
            return Err(corrupt(at, "back reference before the start"));
        }
        if out.len() + n > expected {
            return Err(corrupt(at, "output longer than announced"));
        }
        let from = out.len() - back;
        for k in 0..n {
            let b = out[from + k];
            out.push(b);
        }
    }
    if out.len() != expected {
        return Err(Error::parse(format!(
            "PCD binary_compressed: LZF data decompress to {} bytes, the header announces {expected}",
            out.len()
        )));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::decompress;

    #[test]
    fn literals_and_overlapping_back_references() {
        // "abc" literal, then a back reference of length 7 at distance 3
        // (c = (5 << 5) | 0, next = 2): "abcabcabca".
        let data = [2u8, b'a', b'b', b'c', 5 << 5, 2];
        assert_eq!(decompress(&data, 10).unwrap(), b"abcabcabca");
        // Long match: len 7 + 3 = 10, + 2 = 12 bytes of "a".
        let data = [0u8, b'a', 7 << 5, 3, 0];
        assert_eq!(decompress(&data, 13).unwrap(), vec![b'a'; 13]);
    }

    #[test]
    fn corrupt_input_is_an_error() {
        assert!(decompress(&[5, b'a'], 6).is_err()); // literal past the end
        assert!(decompress(&[1 << 5, 9], 3).is_err()); // reference before start
        assert!(decompress(&[0, b'a', 1 << 5, 0], 2).is_err()); // too long
        assert!(decompress(&[0, b'a'], 2).is_err()); // too short
        assert!(decompress(&[0, b'a', 7 << 5], 20).is_err()); // truncated
    }
}
