//! The run's summary, folded from the outcomes as they come, in run order,
//! without keeping them: scans read and skipped (by reason), per family and
//! frame the degenerate scans and their intervals, per family and body
//! frame the label changes against the scan frame, how far the
//! point-displacement eigenvalues moved between frames, and the timeline's
//! series (binned: at most [`TIMELINE_BINS`] points each, whatever the
//! run's length).
//!
//! An interval is a run of consecutive analysed scans that a family declares
//! degenerate in a frame; skipped scans (and scans without that frame) are
//! gaps that neither extend nor end it.

use super::scan::{FamilyResult, Outcome, Skip};
use crate::tolerances::{MAX_RUN_EXAMPLES, TIMELINE_BINS};
use std::collections::BTreeMap;

/// Scans left out for one reason.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SkipTally {
    /// How many.
    pub count: usize,
    /// The first one's message.
    pub first_message: String,
    /// Their indices (the first [`MAX_RUN_EXAMPLES`]).
    pub indices: Vec<usize>,
}

/// A degenerate interval.
#[derive(Debug, Clone, PartialEq)]
pub struct Interval {
    /// Index of its first scan (a pair's source).
    pub start: usize,
    /// Index of its last scan.
    pub end: usize,
    /// Their times (s), when known.
    pub start_s: Option<f64>,
    /// The last scan's time.
    pub end_s: Option<f64>,
    /// Scans in it.
    pub scans: usize,
    /// Smallest `lambda_min / threshold` in it.
    pub worst_margin: f64,
    /// Where that was.
    pub worst_at: usize,
}

/// One family in one frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Degenerate {
    /// Scans analysed with an answer in this frame.
    pub analysed: usize,
    /// Scans declared degenerate.
    pub scans: usize,
    /// Intervals (the first [`MAX_RUN_EXAMPLES`]).
    pub intervals: Vec<Interval>,
    /// Every interval, counted.
    pub interval_count: usize,
    /// The longest (most scans; ties: the smaller margin), even past the
    /// kept ones.
    pub longest: Option<Interval>,
    open: Option<Interval>,
}

/// Label changes of one family in one body frame against the scan frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Changes {
    /// Scans with an answer in both frames.
    pub compared: usize,
    /// The decision (any degenerate direction) differs.
    pub decision: usize,
    /// The count differs.
    pub count: usize,
    /// The per-axis footprint differs.
    pub footprint: usize,
    /// Indices of the scans whose decision changed (the first
    /// [`MAX_RUN_EXAMPLES`]).
    pub decision_at: Vec<usize>,
    /// Indices whose count changed (the first [`MAX_RUN_EXAMPLES`]).
    pub count_at: Vec<usize>,
}

/// The timeline: for each drawn frame and family, the smallest
/// `lambda_min / threshold` per bin of consecutive scans; and per family
/// whether a body frame changed its decision in the bin.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Timeline {
    /// Scans per bin (doubles as the run grows).
    pub width: usize,
    /// Each bin's first and last x (time in s, or index without times).
    pub x: Vec<(f64, f64)>,
    /// `[frame][family][bin]`: the smallest margin (NaN: no answer).
    pub margin: Vec<Vec<Vec<f64>>>,
    /// `[family][bin]`: some body frame changed the decision.
    pub changed: Vec<Vec<bool>>,
    seen: usize,
}

impl Timeline {
    fn new(frames: usize, families: usize) -> Self {
        Timeline {
            width: 1,
            margin: vec![vec![Vec::new(); families]; frames],
            changed: vec![Vec::new(); families],
            ..Timeline::default()
        }
    }

    /// Add one scan at `x`: its margins per drawn frame and family, and its
    /// decision changes per family.
    fn push(&mut self, x: f64, margins: &[Vec<f64>], changed: &[bool]) {
        if self.seen.is_multiple_of(self.width) {
            if self.x.len() == TIMELINE_BINS {
                self.halve();
            }
            if self.seen.is_multiple_of(self.width) {
                self.x.push((x, x));
                self.margin
                    .iter_mut()
                    .flatten()
                    .for_each(|s| s.push(f64::NAN));
                self.changed.iter_mut().for_each(|s| s.push(false));
            }
        }
        self.seen += 1;
        let b = self.x.len() - 1;
        self.x[b].1 = x;
        for (f, fm) in margins.iter().enumerate() {
            for (k, m) in fm.iter().enumerate() {
                let v = &mut self.margin[f][k][b];
                *v = if v.is_nan() { *m } else { v.min(*m) };
            }
        }
        for (k, c) in changed.iter().enumerate() {
            self.changed[k][b] |= *c;
        }
    }

    /// Merge neighbouring bins: twice the scans per bin.
    fn halve(&mut self) {
        let pair_min = |a: f64, b: f64| {
            if a.is_nan() {
                b
            } else if b.is_nan() {
                a
            } else {
                a.min(b)
            }
        };
        self.x = self
            .x
            .chunks(2)
            .map(|c| (c[0].0, c[c.len() - 1].1))
            .collect();
        for s in self.margin.iter_mut().flatten() {
            *s = s
                .chunks(2)
                .map(|c| c.iter().copied().fold(f64::NAN, pair_min))
                .collect();
        }
        for s in self.changed.iter_mut() {
            *s = s.chunks(2).map(|c| c.iter().any(|&b| b)).collect();
        }
        self.width *= 2;
    }
}

/// What the run's frames are, for the summary: how many, and which are drawn.
#[derive(Debug, Clone)]
pub struct Shape {
    /// Frames (the scan frame first).
    pub frames: usize,
    /// The frames the timeline draws (indices into the frames).
    pub drawn: Vec<usize>,
    /// Families (report order).
    pub families: usize,
    /// Index of point displacement among the families.
    pub point_displacement: Option<usize>,
}

/// The summary so far.
#[derive(Debug, Clone)]
pub struct Summary {
    /// What it is folded over.
    pub shape: Shape,
    /// Outcomes seen.
    pub read: usize,
    /// Outcomes analysed.
    pub analysed: usize,
    /// Skipped, by reason.
    pub skipped: BTreeMap<Skip, SkipTally>,
    /// Outcomes where some requested frame was unknown to the scan's transforms.
    pub frames_missing: usize,
    /// `[frame][family]`.
    pub degenerate: Vec<Vec<Degenerate>>,
    /// `[frame][family]` (frame 0, the scan frame, is all zero).
    pub changes: Vec<Vec<Changes>>,
    /// Largest relative change of the point-displacement eigenvalues between
    /// the scan frame and a body frame (`max |dl| / max |l|`).
    pub point_displacement_change: f64,
    /// The picture's data.
    pub timeline: Timeline,
    /// First and last time (s) of the outcomes seen.
    pub span_s: Option<(f64, f64)>,
}

fn push_limited<T>(v: &mut Vec<T>, x: T) {
    if v.len() < MAX_RUN_EXAMPLES {
        v.push(x);
    }
}

impl Summary {
    /// An empty summary of a run of this shape.
    pub fn new(shape: Shape) -> Self {
        let (f, k) = (shape.frames, shape.families);
        Summary {
            timeline: Timeline::new(shape.drawn.len(), k),
            shape,
            read: 0,
            analysed: 0,
            skipped: BTreeMap::new(),
            frames_missing: 0,
            degenerate: vec![vec![Degenerate::default(); k]; f],
            changes: vec![vec![Changes::default(); k]; f],
            point_displacement_change: 0.0,
            span_s: None,
        }
    }

    /// Fold one outcome in (outcomes come in run order).
    pub fn add(&mut self, o: &Outcome) {
        self.read += 1;
        let at = o.scan.index;
        if let Some(t) = o.scan.time_s {
            let (a, b) = self.span_s.get_or_insert((t, t));
            *a = a.min(t);
            *b = b.max(t);
        }
        if let Some((why, msg)) = &o.skipped {
            let t = self.skipped.entry(*why).or_default();
            if t.count == 0 {
                t.first_message = msg.clone();
            }
            t.count += 1;
            push_limited(&mut t.indices, at);
            return;
        }
        self.analysed += 1;
        if o.frames.iter().any(Option::is_none) {
            self.frames_missing += 1;
        }
        for (f, fr) in o.frames.iter().enumerate() {
            let Some(fr) = fr else { continue };
            for (k, r) in fr.iter().enumerate() {
                self.degenerate[f][k].add(r, at, o.scan.time_s);
            }
        }
        let changed = self.compare(o);
        let margins: Vec<Vec<f64>> = self
            .shape
            .drawn
            .iter()
            .map(|&f| match &o.frames[f] {
                Some(fr) => fr.iter().map(|r| r.margin().unwrap_or(f64::NAN)).collect(),
                None => vec![f64::NAN; self.shape.families],
            })
            .collect();
        let x = o.scan.time_s.unwrap_or(at as f64);
        self.timeline.push(x, &margins, &changed);
    }

    /// Label changes of this outcome against the scan frame; per family,
    /// whether some body frame changed its decision.
    fn compare(&mut self, o: &Outcome) -> Vec<bool> {
        let mut changed = vec![false; self.shape.families];
        let Some(base) = &o.frames[0] else {
            return changed;
        };
        let at = o.scan.index;
        for (f, fr) in o.frames.iter().enumerate().skip(1) {
            let Some(fr) = fr else { continue };
            for (k, (a, b)) in base.iter().zip(fr).enumerate() {
                let (Some(ca), Some(cb)) = (a.count, b.count) else {
                    continue;
                };
                let c = &mut self.changes[f][k];
                c.compared += 1;
                if (ca > 0) != (cb > 0) {
                    c.decision += 1;
                    push_limited(&mut c.decision_at, at);
                    changed[k] = true;
                }
                if ca != cb {
                    c.count += 1;
                    push_limited(&mut c.count_at, at);
                }
                if a.footprint != b.footprint {
                    c.footprint += 1;
                }
            }
            if let Some(k) = self.shape.point_displacement {
                if let (Some(x), Some(y)) = (base[k].eigenvalues, fr[k].eigenvalues) {
                    let top = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    let d = x
                        .iter()
                        .zip(&y)
                        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                    if top > 0.0 {
                        self.point_displacement_change =
                            self.point_displacement_change.max(d / top);
                    }
                }
            }
        }
        changed
    }

    /// Close the open intervals (the run has ended).
    pub fn finish(&mut self) {
        for d in self.degenerate.iter_mut().flatten() {
            d.close();
        }
    }
}

impl Degenerate {
    fn add(&mut self, r: &FamilyResult, at: usize, t: Option<f64>) {
        let (Some(count), Some(margin)) = (r.count, r.margin()) else {
            return;
        };
        self.analysed += 1;
        if count == 0 {
            self.close();
            return;
        }
        self.scans += 1;
        match &mut self.open {
            Some(i) => {
                i.end = at;
                i.end_s = t;
                i.scans += 1;
                if margin < i.worst_margin {
                    i.worst_margin = margin;
                    i.worst_at = at;
                }
            }
            None => {
                self.open = Some(Interval {
                    start: at,
                    end: at,
                    start_s: t,
                    end_s: t,
                    scans: 1,
                    worst_margin: margin,
                    worst_at: at,
                })
            }
        }
    }

    fn close(&mut self) {
        let Some(i) = self.open.take() else { return };
        self.interval_count += 1;
        let longer = match &self.longest {
            None => true,
            Some(l) => i.scans > l.scans || (i.scans == l.scans && i.worst_margin < l.worst_margin),
        };
        if longer {
            self.longest = Some(i.clone());
        }
        push_limited(&mut self.intervals, i);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_timeline_keeps_its_size_and_the_smallest_margins() {
        let mut t = Timeline::new(1, 1);
        let n = TIMELINE_BINS * 4 - 3;
        for k in 0..n {
            let m = if k == 5000 { 0.01 } else { 2.0 };
            t.push(k as f64, &[vec![m]], &[k == 7000]);
        }
        assert!(t.x.len() <= TIMELINE_BINS);
        assert_eq!(t.width, 4);
        let b = 5000 / t.width;
        assert_eq!(t.margin[0][0][b], 0.01);
        assert!(t.changed[0][7000 / t.width]);
        assert_eq!(t.changed[0].iter().filter(|&&c| c).count(), 1);
        assert_eq!(t.x.last().unwrap().1, (n - 1) as f64);
    }
}
