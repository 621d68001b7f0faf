//! Where a plot's point labels go so that none covers another (the survey
//! plot's rigs at `|h| = 0` sit on one line and their labels overlapped).
//!
//! Pixels, y down. A label is a box `width x height` whose top-left corner
//! is its point plus an offset. Labels are placed greedily, left to right
//! (then top to bottom) by their points: each takes the first offset, among
//! the mark's own and that offset moved up or down by whole label heights
//! (nearest first, up before down; at each height right of the point, then
//! left of it), whose box stays inside the plot area and meets no box placed
//! before it nor any labelled point's mark. A label that finds no free place
//! in the area's height keeps the mark's own offset. The SVG backend draws text without fonts, so a label's
//! width is estimated ([`LABEL_CHAR_EM`]).

/// Width of one character of a label, in ems of its font size: above the
/// average advance of a sans-serif face (about 0.5 em for DejaVu Sans and
/// Liberation Sans on lower-case names), so that a box is not narrower than
/// the text a viewer draws.
pub const LABEL_CHAR_EM: f64 = 0.6;

/// More labels than this are drawn at the mark's own offset, unplaced: the
/// greedy search is quadratic in the number of labels (times the places a
/// label may take), and a plot of that many labelled points is unreadable
/// whatever their places.
pub const LABEL_PLACE_MAX: usize = 300;

/// A label's height (px) at font `size`: the font size and a pixel apart.
pub fn height(size: u32) -> i32 {
    size as i32 + 1
}

/// A label's estimated width (px) at font `size`.
pub fn width(text: &str, size: u32) -> i32 {
    (text.chars().count() as f64 * f64::from(size) * LABEL_CHAR_EM).ceil() as i32
}

/// The box `[left, top, right, bottom]` of a label at `anchor + offset`.
pub fn bounds(anchor: (i32, i32), offset: (i32, i32), width: i32, height: i32) -> [i32; 4] {
    let (x, y) = (anchor.0 + offset.0, anchor.1 + offset.1);
    [x, y, x + width, y + height]
}

/// Whether two boxes share any area (touching edges do not).
pub fn overlap(a: &[i32; 4], b: &[i32; 4]) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

/// Half the side (px) of the square kept clear around each labelled point,
/// so that no label covers a point's mark (marks are 4-7 px in radius).
pub const LABEL_MARK_CLEAR_PX: i32 = 5;

/// Whether box `b` lies inside `area` (`[left, top, right, bottom]`).
fn inside(b: &[i32; 4], area: &[i32; 4]) -> bool {
    b[0] >= area[0] && b[1] >= area[1] && b[2] <= area[2] && b[3] <= area[3]
}

/// Each label's offset from its point: `labels[i]` is the point (px) and the
/// label's width; `offset` is the mark's own. A moved label stays inside
/// `area` (the plot area) and clear of every labelled point's mark.
pub fn place(
    labels: &[((i32, i32), i32)],
    height: i32,
    offset: (i32, i32),
    area: [i32; 4],
) -> Vec<(i32, i32)> {
    let mut out = vec![offset; labels.len()];
    if labels.len() > LABEL_PLACE_MAX {
        return out;
    }
    let mut order: Vec<usize> = (0..labels.len()).collect();
    order.sort_by_key(|&i| labels[i].0);
    let c = LABEL_MARK_CLEAR_PX;
    // Up and down as far as the area is high.
    let steps = ((area[3] - area[1]) / height.max(1)).max(1);
    let mut placed: Vec<[i32; 4]> = labels
        .iter()
        .map(|&((x, y), _)| [x - c, y - c, x + c, y + c])
        .collect();
    for i in order {
        let (anchor, w) = labels[i];
        let steps = (1..=steps).flat_map(|k| [-k, k]);
        let left = -offset.0 - w;
        let chosen = std::iter::once(0)
            .chain(steps)
            .flat_map(|k| {
                [
                    (offset.0, offset.1 + k * height),
                    (left, offset.1 + k * height),
                ]
            })
            .find(|&o| {
                let b = bounds(anchor, o, w, height);
                inside(&b, &area) && placed.iter().all(|p| !overlap(&b, p))
            })
            .unwrap_or(offset);
        out[i] = chosen;
        placed.push(bounds(anchor, chosen, w, height));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn boxes(labels: &[((i32, i32), i32)], h: i32, o: &[(i32, i32)]) -> Vec<[i32; 4]> {
        labels
            .iter()
            .zip(o)
            .map(|(&(a, w), &o)| bounds(a, o, w, h))
            .collect()
    }

    const AREA: [i32; 4] = [-1000, -1000, 2000, 2000];

    fn disjoint(b: &[[i32; 4]]) -> bool {
        (0..b.len()).all(|i| (i + 1..b.len()).all(|j| !overlap(&b[i], &b[j])))
    }

    #[test]
    fn labels_of_one_point_stack_without_overlap() {
        let labels = vec![((100, 300), 80); 12];
        let o = place(&labels, 10, (6, -4), AREA);
        assert!(disjoint(&boxes(&labels, 10, &o)), "{o:?}");
        // The first keeps the mark's offset; the others move by whole heights.
        assert_eq!(o[0], (6, -4));
        assert!(o
            .iter()
            .all(|&(x, y)| [6, -86].contains(&x) && (y + 4) % 10 == 0));
        // Nearest first, up before down, right before left: the left place
        // at the mark's own height is taken before moving up.
        assert_eq!(&o[1..4], &[(-86, -4), (6, -14), (-86, -14)]);
    }

    #[test]
    fn labels_on_one_line_move_only_where_they_would_meet() {
        // Points 50 px apart on a line with labels 80 px wide: a label at
        // the mark's offset would cover the next point, so each moves (the
        // first to the left of its point, where nothing is); points 200 px
        // apart meet nothing.
        let near: Vec<_> = (0..6).map(|k| ((50 * k, 400), 80)).collect();
        let o = place(&near, 10, (6, -4), AREA);
        assert!(disjoint(&boxes(&near, 10, &o)), "{o:?}");
        assert_eq!(o[0], (-86, -4));
        assert!(o[..5].iter().all(|&o| o != (6, -4)), "{o:?}");
        let far: Vec<_> = (0..6).map(|k| ((200 * k, 400), 80)).collect();
        assert!(place(&far, 10, (6, -4), AREA).iter().all(|&o| o == (6, -4)));
    }

    #[test]
    fn labels_stay_inside_the_area_and_off_the_marks() {
        // Points on the area's bottom edge: no label may go below it, and
        // none may cover a point (a 10 px square around each).
        let area = [0, 0, 400, 300];
        let labels: Vec<_> = (0..8).map(|k| ((20 + 4 * k, 300), 60)).collect();
        let o = place(&labels, 10, (6, -4), area);
        let b = boxes(&labels, 10, &o);
        assert!(disjoint(&b), "{o:?}");
        for (k, bx) in b.iter().enumerate().skip(1) {
            assert!(inside(bx, &area), "{k}: {bx:?}");
            for &((x, y), _) in &labels {
                assert!(!overlap(bx, &[x - 5, y - 5, x + 5, y + 5]), "{k}: {bx:?}");
            }
        }
    }

    #[test]
    fn too_many_labels_keep_the_marks_offset() {
        let labels = vec![((0, 0), 10); LABEL_PLACE_MAX + 1];
        assert!(place(&labels, 10, (6, -4), AREA)
            .iter()
            .all(|&o| o == (6, -4)));
    }

    #[test]
    fn touching_boxes_do_not_overlap() {
        assert!(!overlap(&[0, 0, 10, 10], &[10, 0, 20, 10]));
        assert!(!overlap(&[0, 0, 10, 10], &[0, 10, 10, 20]));
        assert!(overlap(&[0, 0, 10, 10], &[9, 9, 20, 20]));
    }

    #[test]
    fn width_counts_characters_not_bytes() {
        assert_eq!(width("abc", 10), 18);
        assert_eq!(width("ééé", 10), 18);
    }
}
