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

/// Line starts of a text, for O(log n) offset -> line lookups
/// (roxmltree's `text_pos_at` scans from the start each time).
pub struct LineIndex<'a> {
    text: &'a str,
    starts: Vec<usize>,
}

impl<'a> LineIndex<'a> {
    /// Index the line starts of `text`.
    pub fn new(text: &'a str) -> Self {
        let mut starts = vec![0];
        starts.extend(
            text.bytes()
                .enumerate()
                .filter(|(_, b)| *b == b'\n')
                .map(|(i, _)| i + 1),
        );
        LineIndex { text, starts }
    }

    /// 1-based (line, column in characters) of a byte offset.
    pub fn pos(&self, offset: usize) -> (usize, usize) {
        let offset = clamp_to_char(self.text, offset);
        let line = self.starts.partition_point(|&s| s <= offset);
        let start = self.starts[line.saturating_sub(1)];
        (line.max(1), column(self.text, start, offset))
    }
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
}
