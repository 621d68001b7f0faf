//! Positions in source text: the one way the readers turn a byte offset into a
//! 1-based line and column (columns count characters, as rustc does).

/// 1-based (line, column) of a byte offset in `text`, for a single lookup
/// (use [`LineIndex`] for many).
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = clamp_to_char(text, offset);
    let line_start = text[..offset].rfind('\n').map(|p| p + 1).unwrap_or(0);
    let line = text.as_bytes()[..offset]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1;
    (line, column(text, line_start, offset))
}

/// The largest char boundary at or below `offset`.
fn clamp_to_char(text: &str, offset: usize) -> usize {
    let mut o = offset.min(text.len());
    while !text.is_char_boundary(o) {
        o -= 1;
    }
    o
}

fn column(text: &str, line_start: usize, offset: usize) -> usize {
    text.get(line_start..offset)
        .map(|s| s.chars().count() + 1)
        .unwrap_or(1)
}

/// Bytes between two character-count marks of a [`LineIndex`]: a column
/// costs at most this many bytes of counting, whatever the line's length.
const CHAR_MARK_STRIDE: usize = 4096;

/// Line starts of a text, for O(log n) offset -> (line, column) lookups,
/// whatever the line lengths (a URDF dumped on one line has one line of
/// megabytes): columns come from character counts kept every
/// 4096 bytes, or from byte offsets when the text is ASCII.
/// (roxmltree's `text_pos_at` scans from the start each time.)
pub struct LineIndex<'a> {
    text: &'a str,
    starts: Vec<usize>,
    /// (byte offset at a char boundary, characters before it), increasing;
    /// empty when the text is ASCII (a column is then a byte difference).
    marks: Vec<(usize, usize)>,
}

impl<'a> LineIndex<'a> {
    /// Index the line starts of `text`.
    pub fn new(text: &'a str) -> Self {
        let mut starts = vec![0];
        // memchr: a vectorised search (a byte-at-a-time filter was a twentieth
        // of loading a 100,000-link URDF, issue 29).
        starts.extend(memchr::memchr_iter(b'\n', text.as_bytes()).map(|i| i + 1));
        LineIndex {
            text,
            starts,
            marks: if text.is_ascii() {
                Vec::new()
            } else {
                char_marks(text)
            },
        }
    }

    /// 1-based (line, column in characters) of a byte offset.
    pub fn pos(&self, offset: usize) -> (usize, usize) {
        let offset = clamp_to_char(self.text, offset);
        let line = self.starts.partition_point(|&s| s <= offset);
        let start = self.starts[line.saturating_sub(1)];
        let col = self.chars_before(offset) - self.chars_before(start) + 1;
        (line.max(1), col)
    }

    /// Characters before a byte offset (at a char boundary).
    fn chars_before(&self, offset: usize) -> usize {
        if self.marks.is_empty() {
            return offset;
        }
        let k = self.marks.partition_point(|&(b, _)| b <= offset);
        let (b, n) = self.marks[k.saturating_sub(1)];
        n + self.text.get(b..offset).map_or(0, |s| s.chars().count())
    }
}

/// Character-count marks every [`CHAR_MARK_STRIDE`] bytes (the first at 0).
fn char_marks(text: &str) -> Vec<(usize, usize)> {
    let mut marks = vec![(0, 0)];
    let (mut b, mut n) = (0, 0);
    while b + CHAR_MARK_STRIDE < text.len() {
        let next = clamp_to_char(text, b + CHAR_MARK_STRIDE);
        n += text[b..next].chars().count();
        b = next;
        marks.push((b, n));
    }
    marks
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_lookup_and_the_index_agree() {
        let t = "ab\ncdé\n\nxyz";
        let idx = LineIndex::new(t);
        for off in 0..=t.len() + 3 {
            assert_eq!(line_col(t, off), idx.pos(off), "offset {off}");
        }
        assert_eq!(line_col(t, 0), (1, 1));
        assert_eq!(line_col(t, 4), (2, 2));
        assert_eq!(line_col(t, 8), (3, 1));
        assert_eq!(line_col(t, 9), (4, 1));
    }

    #[test]
    fn columns_on_a_long_multibyte_line_agree_with_counting() {
        let t = format!("x\n{}\n{}", "aé€".repeat(5000), "b".repeat(9000));
        let idx = LineIndex::new(&t);
        for off in (0..t.len() + 2).step_by(97).chain([t.len(), 2, 3, 4, 5]) {
            assert_eq!(line_col(&t, off), idx.pos(off), "offset {off}");
        }
        let ascii = "ab\n".repeat(3000);
        let idx = LineIndex::new(&ascii);
        for off in (0..ascii.len()).step_by(7) {
            assert_eq!(line_col(&ascii, off), idx.pos(off), "offset {off}");
        }
    }
}
