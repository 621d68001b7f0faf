//! Each frame's child edges, in the order they were linked, as lists
//! threaded through the edges (a first and a last edge per frame, a next
//! edge per edge) rather than a vector per frame: a frame with one child
//! cost a 24-byte vector and a 48-byte allocation (issue 29: memory per
//! link), now three indices.

const NONE: usize = usize::MAX;

/// The child edges of every frame; see the module documentation.
#[derive(Debug, Clone, Default)]
pub(crate) struct Children {
    /// Per frame: its first and its last child edge.
    first: Vec<usize>,
    last: Vec<usize>,
    /// Per edge: the next child edge of the same parent.
    next: Vec<usize>,
}

impl Children {
    /// A new frame, without children.
    pub(crate) fn push_frame(&mut self) {
        self.first.push(NONE);
        self.last.push(NONE);
    }

    /// Room for edges `0..n` (edges not linked have no next edge).
    pub(crate) fn cover_edges(&mut self, n: usize) {
        if self.next.len() < n {
            self.next.resize(n, NONE);
        }
    }

    /// Edge `ei` linked as the last child of frame `p`.
    pub(crate) fn link(&mut self, p: usize, ei: usize) {
        self.cover_edges(ei + 1);
        match self.last[p] {
            NONE => self.first[p] = ei,
            l => self.next[l] = ei,
        }
        self.last[p] = ei;
    }

    /// Frame `i`'s first child edge.
    pub(crate) fn first(&self, i: usize) -> Option<usize> {
        Some(self.first[i]).filter(|&e| e != NONE)
    }

    /// Whether frame `i` has no child edge.
    pub(crate) fn is_empty(&self, i: usize) -> bool {
        self.first[i] == NONE
    }

    /// Frame `i`'s child edges, in the order linked.
    pub(crate) fn of(&self, i: usize) -> impl Iterator<Item = usize> + '_ {
        std::iter::successors(self.first(i), |&e| {
            Some(self.next[e]).filter(|&n| n != NONE)
        })
    }

    /// The edges renumbered after some were removed: `shift(e)` is edge
    /// `e`'s new index and `kept(e)` whether it stays (edges not kept are
    /// in no list).
    pub(crate) fn renumber(
        &mut self,
        shift: impl Fn(usize) -> usize,
        kept: impl Fn(usize) -> bool,
    ) {
        let map = |e: &mut usize| {
            if *e != NONE {
                *e = shift(*e);
            }
        };
        self.first.iter_mut().for_each(map);
        self.last.iter_mut().for_each(map);
        self.next.iter_mut().for_each(map);
        let mut e = 0;
        self.next.retain(|_| {
            e += 1;
            kept(e - 1)
        });
    }

    /// Back to frames `0..frames` and edges `0..edges`: the later edges
    /// (always at the end of a list) are unlinked.
    pub(crate) fn truncate(&mut self, frames: usize, edges: usize) {
        self.first.truncate(frames);
        self.last.truncate(frames);
        for i in 0..frames {
            if self.first[i] >= edges {
                // NONE too: a frame without children stays so.
                (self.first[i], self.last[i]) = (NONE, NONE);
                continue;
            }
            if self.last[i] < edges {
                continue;
            }
            let mut e = self.first[i];
            while self.next[e] < edges {
                e = self.next[e];
            }
            self.next[e] = NONE;
            self.last[i] = e;
        }
        self.next.truncate(edges);
    }
}

#[cfg(test)]
mod tests {
    use super::Children;

    fn lists(c: &Children, frames: usize) -> Vec<Vec<usize>> {
        (0..frames).map(|i| c.of(i).collect()).collect()
    }

    /// The lists of vectors the frames had: linked in order, renumbered,
    /// cut back.
    #[test]
    fn lists_in_link_order() {
        let mut c = Children::default();
        (0..3).for_each(|_| c.push_frame());
        for (p, e) in [(0, 0), (1, 1), (0, 2), (0, 4), (2, 5), (1, 6)] {
            c.link(p, e);
        }
        assert_eq!(lists(&c, 3), [vec![0, 2, 4], vec![1, 6], vec![5]]);
        assert_eq!((c.first(1), c.is_empty(2)), (Some(1), false));
        // Edge 3 was never linked: removed, the later ones move down.
        let mut r = c.clone();
        r.renumber(|e| if e > 3 { e - 1 } else { e }, |e| e != 3);
        assert_eq!(lists(&r, 3), [vec![0, 2, 3], vec![1, 5], vec![4]]);
        // Back to 2 frames and 3 edges.
        c.truncate(2, 3);
        assert_eq!(lists(&c, 2), [vec![0, 2], vec![1]]);
        c.link(1, 3);
        assert_eq!(lists(&c, 2), [vec![0, 2], vec![1, 3]]);
        c.truncate(2, 1);
        assert_eq!(lists(&c, 2), [vec![0], vec![]]);
        assert!(c.is_empty(1) && c.first(1).is_none());
    }
}
