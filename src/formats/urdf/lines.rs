//! Line and column of byte offsets for the URDF reader: a cursor moved from
//! the offset asked for last (issue 29). The reader asks in file order, a few
//! offsets per joint, so counting the line breaks between two offsets costs
//! the file's length once over the whole pass, where a
//! [`LineIndex`](crate::formats::source::LineIndex) keeps every line start
//! (8 bytes a line, 2 MB for a 100,000-link chain) and searches them for each
//! offset. A jump back (an error naming an earlier line, the links listed at
//! the end) counts back, or from the start when that is nearer. The answers
//! are `LineIndex::pos`'s (tested): 1-based line and column, columns in
//! characters, an offset inside a character or past the end taken at the
//! character boundary below it.

use std::cell::Cell;

/// Offsets to (line, column) of one text; see the module documentation.
pub(super) struct Lines<'a> {
    text: &'a str,
    /// Characters are bytes.
    ascii: bool,
    at: Cell<Cursor>,
}

/// Where the last answer was.
#[derive(Clone, Copy)]
struct Cursor {
    offset: usize,
    /// 1-based line of `offset`.
    line: usize,
    /// Byte offset of that line's start.
    line_start: usize,
    /// Characters from `line_start` to `offset`.
    chars: usize,
}

const START: Cursor = Cursor {
    offset: 0,
    line: 1,
    line_start: 0,
    chars: 0,
};

impl<'a> Lines<'a> {
    pub(super) fn new(text: &'a str) -> Self {
        Lines {
            text,
            ascii: text.is_ascii(),
            at: Cell::new(START),
        }
    }

    /// Characters in `text[from..to]` (both at character boundaries).
    fn chars(&self, from: usize, to: usize) -> usize {
        if self.ascii {
            to - from
        } else {
            self.text.get(from..to).map_or(0, |s| s.chars().count())
        }
    }

    /// 1-based (line, column in characters) of a byte offset.
    pub(super) fn pos(&self, offset: usize) -> (usize, usize) {
        let o = clamp_to_char(self.text, offset);
        let mut c = self.at.get();
        if o < c.offset && o < c.offset - o {
            c = START;
        }
        let b = self.text.as_bytes();
        // The gaps are short (within a line, or across one line break):
        // the line breaks are found one at a time (memchr's count costs more
        // than the gap to set up).
        if o >= c.offset {
            let (mut n, mut last) = (0, None);
            for i in memchr::memchr_iter(b'\n', &b[c.offset..o]) {
                (n, last) = (n + 1, Some(i));
            }
            match last {
                None => c.chars += self.chars(c.offset, o),
                Some(i) => {
                    c.line += n;
                    c.line_start = c.offset + i + 1;
                    c.chars = self.chars(c.line_start, o);
                }
            }
        } else {
            match memchr::memchr_iter(b'\n', &b[o..c.offset]).count() {
                0 => c.chars -= self.chars(o, c.offset),
                n => {
                    c.line -= n;
                    c.line_start = memchr::memrchr(b'\n', &b[..o]).map_or(0, |i| i + 1);
                    c.chars = self.chars(c.line_start, o);
                }
            }
        }
        c.offset = o;
        self.at.set(c);
        (c.line, c.chars + 1)
    }

    /// 1-based (line, column) where `part`, a slice of the text, starts;
    /// `None` when it is not a slice of it.
    pub(super) fn pos_of(&self, part: &str) -> Option<(usize, usize)> {
        let start = (part.as_ptr() as usize).checked_sub(self.text.as_ptr() as usize)?;
        (start + part.len() <= self.text.len()).then(|| self.pos(start))
    }
}

/// The largest char boundary at or below `offset`.
fn clamp_to_char(text: &str, offset: usize) -> usize {
    let mut o = offset.min(text.len());
    while !text.is_char_boundary(o) {
        o -= 1;
    }
    o
}

#[cfg(test)]
mod tests {
    use super::Lines;
    use crate::formats::source::LineIndex;

    /// Any sequence of offsets, forwards, backwards, inside characters and
    /// past the end, gets `LineIndex`'s answers.
    #[test]
    fn the_cursor_and_the_index_agree() {
        let texts = [
            "ab\ncdé\n\nxyz".to_string(),
            String::new(),
            "\n\n\n".to_string(),
            "one line ".repeat(50),
            "é\nàbç\n\n€ x\n".repeat(40),
            "<robot>\n<link name=\"a\"/>\r\n<joint>é</joint>\n".repeat(30),
        ];
        for t in &texts {
            let idx = LineIndex::new(t);
            let lines = Lines::new(t);
            let n = t.len() + 3;
            // Forwards, then a pseudo-random walk (a fixed LCG: reproducible).
            let mut offsets: Vec<usize> = (0..=n).collect();
            let mut x: usize = 12345;
            for _ in 0..2000 {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                offsets.push((x >> 33) % (n + 1));
            }
            offsets.extend((0..=n).rev());
            for off in offsets {
                assert_eq!(lines.pos(off), idx.pos(off), "offset {off} of {t:?}");
            }
            if !t.is_empty() {
                let k = t
                    .char_indices()
                    .nth(t.chars().count() / 2)
                    .map_or(0, |(i, _)| i);
                let part = &t[k..];
                assert_eq!(lines.pos_of(part), Some(idx.pos(k)));
            }
            assert_eq!(lines.pos_of("elsewhere"), None);
        }
    }
}
