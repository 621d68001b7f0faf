//! Frame graph with provenance: frames are nodes, edges carry a `Transform`
//! (pose of child in parent) and where it came from.
//!
//! The graph is a forest: every frame has at most one parent. Adding an edge
//! checks, in this order:
//!
//! - a frame that is its own parent: error;
//! - the same edge again (same parent and child, or the reverse pair): if the two
//!   transforms agree within [`DUPLICATE_TRANSLATION_TOL`] (m) and
//!   [`DUPLICATE_ROTATION_TOL`] (rad, angle of `R1^T R2`), a `duplicate-edge`
//!   warning naming both places; otherwise an error naming both places;
//! - a child that already has another parent: error naming both edges;
//! - an edge whose child is an ancestor of its parent: a cycle, error listing it.
//!
//! A source may also give redundant edges ([`EdgeSet::redundant`]: Kalibr's
//! `T_cn_cnm1` beside every camera's `T_cam_imu` closes a loop). They are
//! checked after the source's tree edges: one whose frames the tree already
//! connects is compared with the tree path between them; agreeing within
//! [`REDUNDANT_TRANSLATION_TOL`] (m) and [`REDUNDANT_ROTATION_TOL`] (rad) is a
//! note ([`FrameGraph::notes`]), disagreeing a `redundant-edge-disagrees`
//! warning with both values. Paths always run through the tree; a chain
//! between the two frames of a redundant edge says so in [`Chain::notes`]. A
//! redundant edge whose frames the tree does not connect is added as a tree
//! edge (reversed when its child already has a parent).
//!
//! Frame names are looked up as given, then without a leading `/` (loaders
//! drop it, as tf2 does; `--from /camera` names `camera`).
//!
//! A frame can also be declared without an edge ([`FrameGraph::add_frame`], a
//! URDF link no joint attaches): it is a root of its own, listed by
//! [`FrameGraph::tree`] with a note, and connected to nothing.
//!
//! [`FrameGraph::transform`] walks from both frames up to their common ancestor
//! (O(depth) with parent pointers), composes `T_from_to = T_lca_from^-1 T_lca_to`
//! and returns the edges used in order from `from` to `to`, edges walked upwards
//! marked `inverted`. Movable joints at their default position on the path give a
//! `joint-at-default` warning in [`Chain::warnings`]; floating and planar joints
//! that were not set make the path an error.

use super::children::Children;
use super::keyed::{Keyed, Names};
use super::names::{Likeness, Resemblance};
use crate::analysis::mistakes::{explain, MistakeTol};
use crate::diagnostic::{Code, Error, Location, Result, Warning};
use crate::frames::edge::{Edge, JointType};

use crate::geometry::se3::Transform;
use crate::tolerances::{
    CYCLE_LIST_MAX, DUPLICATE_ROTATION_TOL, DUPLICATE_TRANSLATION_TOL, REDUNDANT_ROTATION_TOL,
    REDUNDANT_TRANSLATION_TOL, TREE_MAX_INDENT,
};
// foldhash: frame names are short and hashed several times per edge; SipHash
// was a tenth of loading a 100,000-link URDF (issue 29). Seeded per process.
use foldhash::HashMap;
use std::hash::BuildHasher;

/// The [`crate::frames::JointState::name`] prefix of a transform that changes
/// between the messages of a tf dump (`formats::yaml_dialects`): a floating
/// joint without a value, so that only a path that uses it is refused; the
/// rest of the name says which messages disagree.
pub const MOVING_TF: &str = "moving tf: ";

/// One step of a composed chain: an edge walked down (parent -> child) or up
/// (`inverted`, child -> parent).
#[derive(Debug, Clone, PartialEq)]
pub struct ChainStep {
    /// The edge as stored (pose of its child in its parent).
    pub edge: Edge,
    /// Walked upwards, child -> parent: its transform enters inverted.
    pub inverted: bool,
}

/// A frame a source declares, with or without edges (a URDF `<link>`).
#[derive(Debug, Clone, PartialEq)]
pub struct FrameDecl {
    /// The frame's name.
    pub name: String,
    /// Where it is declared.
    pub location: Location,
}

/// What one source yields for the graph: edges, declared frames and the
/// warnings raised while reading them.
#[derive(Debug, Clone, Default)]
pub struct EdgeSet {
    /// Edges, in the order they were read.
    pub edges: Vec<Edge>,
    /// Frames declared by the source, edges or not.
    pub frames: Vec<FrameDecl>,
    /// Named warnings about them.
    pub warnings: Vec<Warning>,
    /// Edges that may close a loop with `edges` (checked against the tree,
    /// see the module documentation).
    pub redundant: Vec<Edge>,
}

/// A redundant edge and how it compares with the tree path between its frames.
#[derive(Debug, Clone, PartialEq)]
pub struct RedundantEdge {
    /// The edge as the file gives it.
    pub edge: Edge,
    /// The same pose composed along the tree.
    pub tree: Transform,
    /// The tree path, e.g. `cam0 <- imu -> cam1`.
    pub path: String,
    /// Translation gap (m) between the two.
    pub translation_gap: f64,
    /// Rotation gap (rad) between the two.
    pub rotation_gap: f64,
}

impl RedundantEdge {
    /// Whether the two agree within the redundant-edge tolerances.
    pub fn agrees(&self) -> bool {
        self.translation_gap <= REDUNDANT_TRANSLATION_TOL
            && self.rotation_gap <= REDUNDANT_ROTATION_TOL
    }
    fn summary(&self) -> String {
        let e = &self.edge;
        format!(
            "redundant edge {} -> {} ({} at {}) {} the tree path {} (translation gap {:.3e} m, rotation gap {:.3e} rad; tolerances {:e} m, {:e} rad)",
            e.parent,
            e.child,
            e.provenance.key,
            e.provenance.location,
            if self.agrees() { "agrees with" } else { "disagrees with" },
            self.path,
            self.translation_gap,
            self.rotation_gap,
            REDUNDANT_TRANSLATION_TOL,
            REDUNDANT_ROTATION_TOL
        )
    }
}

/// `T_from_to` and the edges used, in order from `from` to `to`.
#[derive(Debug, Clone)]
pub struct Chain {
    /// The frame the transform is expressed in.
    pub from: String,
    /// The frame whose pose it is.
    pub to: String,
    /// `T_from_to`: the pose of `to` in `from`, `p_from = R p_to + d`.
    pub transform: Transform,
    /// The edges composed, in order from `from` to `to`.
    pub steps: Vec<ChainStep>,
    /// Warnings raised by the path (joints at default position, ...).
    pub warnings: Vec<Warning>,
    /// Which path was used when a redundant edge offers another.
    pub notes: Vec<String>,
}

/// The sizes of a [`FrameGraph`]'s parts at one moment.
struct Mark {
    edges: usize,
    frames: usize,
    warnings: usize,
    redundant: usize,
    notes: usize,
}

/// The frame graph: a forest of frames joined by edges with provenance (see
/// the module documentation for what adding an edge checks).
#[derive(Debug, Clone, Default)]
pub struct FrameGraph {
    edges: Vec<Edge>,
    warnings: Vec<Warning>,
    /// Frame name -> index into `names` / `parent` (by hash: the names are
    /// kept once, in `names`).
    index: Keyed,
    names: Names,
    /// For each frame, the index of the edge that names it as child.
    parent: Vec<Option<usize>>,
    /// For each frame, the edges that name it as parent (in insertion order).
    children: Children,
    /// For each frame, the index of its parent frame.
    parent_frame: Vec<Option<usize>>,
    /// Where a source declared a frame (first declaration), for the frames
    /// that had no edge then: the place is only shown for a frame no edge
    /// attaches, and an edge is never removed (sparse: issue 12).
    declared: HashMap<usize, Location>,
    /// Union-find over frames (one set per tree), for an O(α(n)) cycle check:
    /// walking ancestors on every edge is quadratic on adversarial inputs.
    uf: Vec<usize>,
    /// Redundant edges checked against the tree.
    redundant: Vec<RedundantEdge>,
    /// Notes: redundant edges that agree with the tree.
    notes: Vec<String>,
    /// The resemblance keys of the frames (look-alike names).
    resemblance: Resemblance,
}

fn vec3(v: &nalgebra::Vector3<f64>) -> String {
    format!("[{:.9}, {:.9}, {:.9}]", v.x, v.y, v.z)
}

fn quat(t: &Transform) -> String {
    let q = t.quaternion_xyzw();
    format!("[{:.9}, {:.9}, {:.9}, {:.9}]", q[0], q[1], q[2], q[3])
}

/// The frames a chain passes, `a <- b -> c` (arrows point from parent to child).
/// A chain as `from -> child <- parent ...`, for messages.
pub(crate) fn path_text(chain: &Chain) -> String {
    let mut out = chain.from.clone();
    for s in &chain.steps {
        if s.inverted {
            out.push_str(&format!(" <- {}", s.edge.parent));
        } else {
            out.push_str(&format!(" -> {}", s.edge.child));
        }
    }
    out
}

/// `file:line` of an edge, for messages.
fn place(e: &Edge) -> String {
    format!("{} ({})", e.provenance.location, e.provenance.key)
}

fn rotation_angle_between(a: &Transform, b: &Transform) -> f64 {
    let m = a.rotation().transpose() * b.rotation();
    let c = ((m.trace() - 1.0) / 2.0).clamp(-1.0, 1.0);
    // acos is ill-conditioned near 0: use the skew part there.
    let s = 0.5
        * ((m[(2, 1)] - m[(1, 2)]).powi(2)
            + (m[(0, 2)] - m[(2, 0)]).powi(2)
            + (m[(1, 0)] - m[(0, 1)]).powi(2))
        .sqrt();
    s.atan2(c)
}

/// An edge without two distinct, non-empty frames.
fn shape_error(edge: &Edge) -> Option<Error> {
    if edge.parent.is_empty() || edge.child.is_empty() {
        return Some(
            Error::frame(format!(
                "expected two non-empty frame names, found parent '{}' and child '{}'",
                edge.parent, edge.child
            ))
            .at(&edge.provenance.location),
        );
    }
    if edge.parent == edge.child {
        return Some(
            Error::frame(format!(
                "frame '{}' is its own parent: expected two different frames",
                edge.parent
            ))
            .at(&edge.provenance.location),
        );
    }
    None
}

/// The same pair again: a warning when the values agree, else an error.
fn duplicate(old: &Edge, edge: &Edge, reversed: bool) -> Result<Warning> {
    let given = if reversed {
        edge.transform.inverse()
    } else {
        edge.transform
    };
    if transforms_agree(&old.transform, &given) {
        return Ok(Warning::new(
            Code::DuplicateEdge,
            format!(
                "edge {} -> {} given twice, agreeing within {:e} m and {:e} rad: here and at {}",
                edge.parent,
                edge.child,
                DUPLICATE_TRANSLATION_TOL,
                DUPLICATE_ROTATION_TOL,
                place(old)
            ),
        )
        .at(&edge.provenance.location));
    }
    let dt = (old.transform.translation() - given.translation()).norm();
    let da = rotation_angle_between(&old.transform, &given);
    Err(Error::frame(format!(
        "edge {} -> {} given twice with different values (translation differs by {:.3e} m, rotation by {:.3e} rad): first at {}, again at {}{}",
        old.parent,
        old.child,
        dt,
        da,
        place(old),
        place(edge),
        if reversed { " (as the reverse pair)" } else { "" }
    ))
    .at(&edge.provenance.location))
}

fn two_parents(old: &Edge, edge: &Edge) -> Error {
    Error::frame(format!(
        "frame '{}' has two parents: expected one, found '{}' at {} and '{}' at {}",
        edge.child,
        old.parent,
        place(old),
        edge.parent,
        place(edge)
    ))
    .at(&edge.provenance.location)
}

/// Frames from `c` (the root of `p`'s tree) down to `p`, then `c` again;
/// `parent` gives a frame's parent frame, `n` bounds the walk.
fn cycle_path(p: usize, c: usize, n: usize, parent: impl Fn(usize) -> Option<usize>) -> Vec<usize> {
    let mut path = vec![p];
    let mut cur = p;
    while let Some(up) = parent(cur) {
        path.push(up);
        if up == c || path.len() > n {
            break;
        }
        cur = up;
    }
    path.reverse();
    path.push(c);
    path
}

fn cycle(edge: &Edge, names: &[&str]) -> Error {
    Error::frame(format!(
        "edge {} -> {} closes a cycle: expected a tree, found {}",
        edge.parent,
        edge.child,
        cycle_text(names)
    ))
    .at(&edge.provenance.location)
}

/// `a -> b -> ... -> a`, the middle elided past [`CYCLE_LIST_MAX`] frames.
fn cycle_text(names: &[&str]) -> String {
    if names.len() <= CYCLE_LIST_MAX {
        return names.join(" -> ");
    }
    let h = CYCLE_LIST_MAX / 2;
    format!(
        "{} -> ... ({} more frames) ... -> {}",
        names[..h].join(" -> "),
        names.len() - 2 * h,
        names[names.len() - h..].join(" -> ")
    )
}

fn find(uf: &mut [usize], mut x: usize) -> usize {
    while uf[x] != x {
        uf[x] = uf[uf[x]];
        x = uf[x];
    }
    x
}

/// Whether `edges`, added in order to an empty [`FrameGraph`], would be
/// accepted, with the same error when not; the edges are not copied (a
/// reader's own check: a graph would hold a second copy of every edge).
///
/// Its tables hold `u32`s (issue 29: memory per link; 22 bytes a frame where
/// a map of names and `Option<usize>`s was 89): a frame is found by its name
/// through a table of frame numbers, and a frame's name is read from the
/// edge that first named it. 2^31 edges are far beyond the memory an edge
/// list fits in; past that an index saturates and finds nothing.
pub fn check_tree(edges: &[Edge]) -> Result<()> {
    let n = edges.len() + 1;
    let hasher = foldhash::fast::RandomState::default();
    let mut index: hashbrown::HashTable<u32> = hashbrown::HashTable::with_capacity(n);
    let mut t = TreeCheck {
        edges,
        named_by: Vec::with_capacity(n),
        parent: Vec::with_capacity(n),
        parent_frame: Vec::with_capacity(n),
        uf: Vec::with_capacity(n),
    };
    for (ei, edge) in edges.iter().enumerate() {
        if let Some(e) = shape_error(edge) {
            return Err(e);
        }
        let hp = hasher.hash_one(edge.parent.as_str());
        let hc = hasher.hash_one(edge.child.as_str());
        let find_frame = |t: &TreeCheck, name: &str, h: u64| {
            index
                .find(h, |&f| t.name(f as usize) == name)
                .map(|&f| f as usize)
        };
        let (p, c) = (
            find_frame(&t, &edge.parent, hp),
            find_frame(&t, &edge.child, hc),
        );
        if let (Some(p), Some(c)) = (p, c) {
            let old = some(t.parent[c])
                .filter(|&o| edges[o].parent == edge.parent)
                .map(|o| (o, false))
                .or_else(|| {
                    some(t.parent[p])
                        .filter(|&o| edges[o].parent == edge.child)
                        .map(|o| (o, true))
                });
            if let Some((o, reversed)) = old {
                duplicate(&edges[o], edge, reversed)?;
                continue;
            }
        }
        if let Some(o) = c.and_then(|c| some(t.parent[c])) {
            return Err(two_parents(&edges[o], edge));
        }
        if let (Some(p), Some(c)) = (p, c) {
            if find32(&mut t.uf, p) == find32(&mut t.uf, c) {
                let path = t.cycle_path(p, c);
                let ns: Vec<&str> = path.iter().map(|&i| t.name(i)).collect();
                return Err(cycle(edge, &ns));
            }
        }
        // Parent and child differ (shape_error): adding one cannot make
        // the other found.
        let mut id = |found: Option<usize>, h: u64, named_by: usize| {
            found.unwrap_or_else(|| {
                let f = t.named_by.len();
                index.insert_unique(h, to_u32(f), |&g| hasher.hash_one(t.name(g as usize)));
                t.add(named_by)
            })
        };
        let p = id(p, hp, 2 * ei);
        let c = id(c, hc, 2 * ei + 1);
        let (rp, rc) = (find32(&mut t.uf, p), find32(&mut t.uf, c));
        t.uf[rc] = to_u32(rp);
        t.parent[c] = to_u32(ei);
        t.parent_frame[c] = to_u32(p);
    }
    Ok(())
}

/// No edge or frame (in [`TreeCheck`]'s tables).
const NONE: u32 = u32::MAX;

fn to_u32(i: usize) -> u32 {
    u32::try_from(i).unwrap_or(NONE)
}

fn some(i: u32) -> Option<usize> {
    (i != NONE).then_some(i as usize)
}

/// [`check_tree`]'s frames: per frame, the edge that first named it (its
/// index times 2, plus 1 when as child), its parent edge, its parent frame
/// and its union-find link.
struct TreeCheck<'e> {
    edges: &'e [Edge],
    named_by: Vec<u32>,
    parent: Vec<u32>,
    parent_frame: Vec<u32>,
    uf: Vec<u32>,
}

impl<'e> TreeCheck<'e> {
    fn name(&self, f: usize) -> &'e str {
        let at = self.named_by.get(f).map_or(usize::MAX, |&a| a as usize);
        match self.edges.get(at / 2) {
            Some(e) if at % 2 == 1 => &e.child,
            Some(e) => &e.parent,
            None => "",
        }
    }

    /// A new frame, named by edge `named_by / 2`; its number.
    fn add(&mut self, named_by: usize) -> usize {
        let f = self.named_by.len();
        self.named_by.push(to_u32(named_by));
        self.parent.push(NONE);
        self.parent_frame.push(NONE);
        self.uf.push(to_u32(f));
        f
    }

    /// [`cycle_path`] over these tables.
    fn cycle_path(&self, p: usize, c: usize) -> Vec<usize> {
        cycle_path(p, c, self.named_by.len(), |f| some(self.parent_frame[f]))
    }
}

/// [`find`] over `u32` links.
fn find32(uf: &mut [u32], x: usize) -> usize {
    let mut x = x as u32;
    while uf[x as usize] != x {
        uf[x as usize] = uf[uf[x as usize] as usize];
        x = uf[x as usize];
    }
    x as usize
}

/// Whether two transforms agree within the duplicate-edge tolerances.
pub fn transforms_agree(a: &Transform, b: &Transform) -> bool {
    (a.translation() - b.translation()).norm() <= DUPLICATE_TRANSLATION_TOL
        && rotation_angle_between(a, b) <= DUPLICATE_ROTATION_TOL
}

impl FrameGraph {
    /// An empty graph.
    pub fn new() -> Self {
        Self::default()
    }

    /// Add everything one source yielded (a file's edges and warnings): all
    /// of it or, on an error, none of it.
    pub fn add(&mut self, set: impl Into<EdgeSet>) -> Result<()> {
        // Undone on an error (the graph was cloned for each source, so that
        // loading many files was quadratic: issue 29).
        let mark = self.mark();
        let added = self.add_all(set.into());
        if added.is_err() {
            self.undo(mark);
        }
        added
    }

    fn add_all(&mut self, set: EdgeSet) -> Result<()> {
        let next = self;
        next.warnings.extend(set.warnings);
        if next.edges.is_empty() {
            // The source's vector becomes the graph's: no second copy of the
            // edges, even for a moment (issue 12: memory per link).
            next.adopt(set.edges)?;
        } else {
            // Moved over in order from the back of a reversed copy, which is
            // shrunk as it empties: the two vectors together hold little
            // more than one copy of the edges.
            let mut edges = set.edges;
            edges.reverse();
            while let Some(e) = edges.pop() {
                next.add_edge(e)?;
                if edges.len() <= edges.capacity() / 8 * 7 {
                    edges.shrink_to_fit();
                }
            }
        }
        for f in set.frames {
            next.add_frame(&f.name, f.location)?;
        }
        for e in set.redundant {
            next.add_redundant(e)?;
        }
        Ok(())
    }

    /// How far the graph has grown: what [`FrameGraph::undo`] goes back to.
    fn mark(&self) -> Mark {
        Mark {
            edges: self.edges.len(),
            frames: self.names.len(),
            warnings: self.warnings.len(),
            redundant: self.redundant.len(),
            notes: self.notes.len(),
        }
    }

    /// The graph as it was at `m`: what was added since is taken away, and
    /// the links the new edges made to older frames are cut.
    fn undo(&mut self, m: Mark) {
        self.index.forget_from(m.frames);
        self.resemblance.forget_from(m.frames);
        self.names.truncate(m.frames);
        self.parent.truncate(m.frames);
        self.parent_frame.truncate(m.frames);
        self.children.truncate(m.frames, m.edges);
        for i in 0..m.frames {
            if self.parent[i].is_some_and(|ei| ei >= m.edges) {
                self.parent[i] = None;
                self.parent_frame[i] = None;
            }
        }
        self.declared.retain(|&i, _| i < m.frames);
        // The trees again from the parent links (path halving and unions
        // since the mark have touched older frames too).
        self.uf.truncate(m.frames);
        for (i, u) in self.uf.iter_mut().enumerate() {
            *u = i;
        }
        for i in 0..m.frames {
            if let Some(p) = self.parent_frame[i] {
                let (rp, ri) = (self.find(p), self.find(i));
                self.uf[ri] = rp;
            }
        }
        self.edges.truncate(m.edges);
        self.warnings.truncate(m.warnings);
        self.redundant.truncate(m.redundant);
        self.notes.truncate(m.notes);
    }

    /// Check a redundant edge against the tree, or add it to the tree when
    /// the tree does not connect its frames yet.
    fn add_redundant(&mut self, edge: Edge) -> Result<()> {
        let tree = match (self.id(&edge.parent), self.id(&edge.child)) {
            (Some(_), Some(_)) => self.transform_inner(&edge.parent, &edge.child).ok(),
            _ => None,
        };
        let Some(chain) = tree else {
            let child_has_parent = self.parent_edge(&edge.child).is_some();
            let e = if child_has_parent {
                let mut r = edge.clone();
                std::mem::swap(&mut r.parent, &mut r.child);
                r.transform = edge.transform.inverse();
                r.provenance.key = format!("{} (inverted)", edge.provenance.key);
                r
            } else {
                edge
            };
            return self.add_edge(e);
        };
        let r = RedundantEdge {
            translation_gap: (chain.transform.translation() - edge.transform.translation()).norm(),
            rotation_gap: rotation_angle_between(&chain.transform, &edge.transform),
            tree: chain.transform,
            path: path_text(&chain),
            edge,
        };
        if r.agrees() {
            self.notes.push(r.summary());
        } else {
            // The convention mistake that reconciles the two, under the
            // redundant-edge tolerances (issue 30).
            let tol = MistakeTol {
                translation_mm: REDUNDANT_TRANSLATION_TOL * 1e3,
                rotation_deg: REDUNDANT_ROTATION_TOL.to_degrees(),
            };
            let mistake = explain(&r.tree, &r.edge.transform, &tol)
                .sentence("the tree", "the file")
                .unwrap_or_else(|| "no usual convention mistake reconciles them".into());
            let at = r
                .edge
                .provenance
                .value_location(r.translation_gap > REDUNDANT_TRANSLATION_TOL);
            self.warnings.push(
                Warning::new(
                    Code::RedundantEdgeDisagrees,
                    format!(
                        "{}: the file gives translation {} and rotation (quaternion xyzw) {}, the tree {} and {}; {mistake}",
                        r.summary(),
                        vec3(r.edge.transform.translation()),
                        quat(&r.edge.transform),
                        vec3(r.tree.translation()),
                        quat(&r.tree)
                    ),
                )
                .at(&at),
            );
        }
        self.redundant.push(r);
        Ok(())
    }

    /// The redundant edges checked against the tree, in the order added.
    pub fn redundant(&self) -> &[RedundantEdge] {
        &self.redundant
    }

    /// Notes: redundant edges that agree with the tree path.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// The index of frame `name`, added (first met at `at`) when new; a new
    /// name that resembles a known one, or is padded, is warned about.
    fn frame_id(&mut self, name: &str, at: &Location) -> usize {
        let h = self.index.hash(name);
        let i = self.names.len();
        let names = &self.names;
        if let Some(known) = self.index.first_with(name, h, i, |j| &names[j] == name) {
            return known;
        }
        self.names.push(name);
        self.parent.push(None);
        self.parent_frame.push(None);
        self.children.push_frame();
        self.uf.push(i);
        if let Some(like) = self.resemblance.add(i, name, &self.names) {
            let w = self.likeness_warning(name, like).at(at);
            self.warnings.push(w);
        }
        i
    }

    /// The `confusable-frame-name` or `padded-frame-name` warning of frame
    /// `name` (see `frames::names`).
    fn likeness_warning(&self, name: &str, like: Likeness) -> Warning {
        let shown = |n: &str| format!("\"{}\"", crate::sanitize::quote(n));
        match like {
            Likeness::Resembles { other, how } => Warning::new(
                Code::ConfusableFrameName,
                format!(
                    "frame {} resembles frame {}{}: {how}; they are two frames, so an edge written for one does not attach to the other",
                    shown(name),
                    shown(&self.names[other]),
                    self.first_place(other)
                        .map_or_else(String::new, |l| format!(" (at {l})")),
                ),
            ),
            Likeness::Padded => Warning::new(
                Code::PaddedFrameName,
                format!(
                    "frame {} has white space at its start or end: kept as part of the name (tf2 does), so it matches no frame written without it",
                    shown(name)
                ),
            ),
        }
    }

    /// Where frame `i` was first given: its parent edge, its first child
    /// edge, or its declaration.
    fn first_place(&self, i: usize) -> Option<&Location> {
        self.parent[i]
            .or_else(|| self.children.first(i))
            .and_then(|ei| self.edges.get(ei))
            .map(|e| &e.provenance.location)
            .or_else(|| self.declared.get(&i))
            .filter(|l| !l.is_empty())
    }

    /// Declare a frame, with no edge: known to the graph (listed, a root of its
    /// own until an edge attaches it). Declaring a known frame again keeps the
    /// first declaration.
    pub fn add_frame(&mut self, name: &str, location: Location) -> Result<()> {
        if name.is_empty() {
            return Err(Error::frame("expected a non-empty frame name, found \"\"").at(&location));
        }
        let i = self.frame_id(name, &location);
        if self.parent[i].is_none() && self.children.is_empty(i) {
            self.declared.entry(i).or_insert(location);
        }
        Ok(())
    }

    /// Representative of a frame's tree (path halving, iterative).
    fn find(&mut self, x: usize) -> usize {
        find(&mut self.uf, x)
    }

    /// Add one edge, with the checks listed in the module documentation.
    pub fn add_edge(&mut self, edge: Edge) -> Result<()> {
        if self.check_edge(&edge)? {
            let ei = self.edges.len();
            self.link(&edge, ei);
            self.edges.push(edge);
        }
        Ok(())
    }

    /// Edges as the first of the graph, linked where they lie (duplicates
    /// that agree are warned about and dropped afterwards, as
    /// [`FrameGraph::add_edge`] drops them).
    fn adopt(&mut self, edges: Vec<Edge>) -> Result<()> {
        self.edges = edges;
        let mut dropped = Vec::new();
        for ei in 0..self.edges.len() {
            // Taken out while checked: the checks read the edges before it.
            let empty = Edge::new("", "", Transform::identity(), Location::default(), "", "");
            let edge = std::mem::replace(&mut self.edges[ei], empty);
            let linked = self.check_edge(&edge);
            if matches!(linked, Ok(true)) {
                self.link(&edge, ei);
            }
            self.edges[ei] = edge;
            if !linked? {
                dropped.push(ei);
            }
        }
        if !dropped.is_empty() {
            let shift = |ei: usize| ei - dropped.partition_point(|&d| d < ei);
            for p in self.parent.iter_mut().flatten() {
                *p = shift(*p);
            }
            self.children.cover_edges(self.edges.len());
            self.children
                .renumber(shift, |ei| dropped.binary_search(&ei).is_err());
            let mut i = 0;
            self.edges.retain(|_| {
                i += 1;
                dropped.binary_search(&(i - 1)).is_err()
            });
        }
        Ok(())
    }

    /// Whether `edge` is to be linked (`false`: a duplicate that agrees,
    /// warned about), or the error that refuses it.
    fn check_edge(&mut self, edge: &Edge) -> Result<bool> {
        if let Some(e) = shape_error(edge) {
            return Err(e);
        }
        // Duplicate (same or reversed pair)?
        if let (Some(p), Some(c)) = (self.id(&edge.parent), self.id(&edge.child)) {
            if let Some((ei, reversed)) = self.existing(p, c, edge) {
                let w = duplicate(&self.edges[ei], edge, reversed)?;
                self.warnings.push(w);
                return Ok(false);
            }
        }
        // Two parents and cycles are checked before any frame is added, so a
        // refused edge leaves the graph as it was.
        if let Some(ei) = self.id(&edge.child).and_then(|c| self.parent[c]) {
            return Err(two_parents(&self.edges[ei], edge));
        }
        // Cycle: the child has no parent, so it is the root of its tree, and
        // the edge closes a cycle exactly when the parent is in that tree.
        if let (Some(p), Some(c)) = (self.id(&edge.parent), self.id(&edge.child)) {
            if self.find(p) == self.find(c) {
                let path = cycle_path(p, c, self.names.len(), |f| self.parent_frame[f]);
                let names: Vec<&str> = path.iter().map(|&i| &self.names[i]).collect();
                return Err(cycle(edge, &names));
            }
        }
        Ok(true)
    }

    /// Link edge `ei` (checked) from `parent` to `child`.
    fn link(&mut self, edge: &Edge, ei: usize) {
        let at = &edge.provenance.location;
        let p = self.frame_id(&edge.parent, at);
        let c = self.frame_id(&edge.child, at);
        let (rp, rc) = (self.find(p), self.find(c));
        self.uf[rc] = rp;
        self.parent[c] = Some(ei);
        self.parent_frame[c] = Some(p);
        self.children.link(p, ei);
    }

    /// The stored edge joining frames `p` and `c` as `edge` does (reversed or not).
    fn existing(&self, p: usize, c: usize, edge: &Edge) -> Option<(usize, bool)> {
        self.parent[c]
            .filter(|&ei| self.edges[ei].parent == edge.parent)
            .map(|ei| (ei, false))
            .or_else(|| {
                self.parent[p]
                    .filter(|&ei| self.edges[ei].parent == edge.child)
                    .map(|ei| (ei, true))
            })
    }

    /// Every edge, in the order added.
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// The warnings of every source added (and of agreeing duplicate edges).
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// All frame names, sorted.
    pub fn frames(&self) -> Vec<String> {
        let mut v: Vec<String> = self.names.iter().map(String::from).collect();
        v.sort();
        v
    }

    /// The index of frame `name`, if known.
    fn id(&self, name: &str) -> Option<usize> {
        let h = self.index.hash(name);
        self.index.get(name, h, |j| &self.names[j] == name)
    }

    /// Whether the graph knows this frame.
    pub fn contains(&self, frame: &str) -> bool {
        self.id(frame).is_some()
    }

    /// The edge whose child is `frame` (its parent edge), if any.
    pub fn parent_edge(&self, frame: &str) -> Option<&Edge> {
        let i = self.id(frame)?;
        self.parent[i].map(|ei| &self.edges[ei])
    }

    /// Frames without a parent, sorted.
    pub fn roots(&self) -> Vec<String> {
        let mut v: Vec<String> = (0..self.names.len())
            .filter(|&i| self.parent[i].is_none())
            .map(|i| self.names[i].to_string())
            .collect();
        v.sort();
        v
    }

    /// Names of the non-fixed joints the graph's edges carry, sorted.
    pub fn joint_names(&self) -> Vec<String> {
        let mut v: Vec<String> = self
            .edges
            .iter()
            .filter_map(|e| e.joint.as_ref().map(|j| j.name.clone()))
            .collect();
        v.sort();
        v.dedup();
        v
    }

    /// Up to `n` known frame names closest to `name` (edit distance, then
    /// Jaro-Winkler similarity), best first.
    pub fn closest_frames(&self, name: &str, n: usize) -> Vec<String> {
        let lower = name.to_lowercase();
        let mut scored: Vec<(usize, f64, &str)> = self
            .names
            .iter()
            .map(|f| {
                let fl = f.to_lowercase();
                (
                    strsim::levenshtein(&lower, &fl),
                    -strsim::jaro_winkler(&lower, &fl),
                    f,
                )
            })
            .collect();
        scored.sort_by(|a, b| {
            a.0.cmp(&b.0)
                .then(a.1.total_cmp(&b.1))
                .then_with(|| a.2.cmp(b.2))
        });
        scored
            .into_iter()
            .take(n)
            .map(|s| s.2.to_string())
            .collect()
    }

    fn lookup(&self, name: &str) -> Result<usize> {
        if let Some(i) = self.id(name).or_else(|| self.id(name.strip_prefix('/')?)) {
            return Ok(i);
        }
        if self.names.is_empty() {
            return Err(Error::frame(format!(
                "unknown frame '{name}': the loaded files yield no frames"
            )));
        }
        let close = self.closest_frames(name, 3);
        Err(Error::frame(format!(
            "unknown frame '{name}': expected one of the {} loaded frames; closest: {}{}",
            self.names.len(),
            quoted_list(&close),
            self.root_hint()
        )))
    }

    /// Where the trees start, for an unknown frame: `base_link` on a robot
    /// whose root is `pelvis` is most often meant as that root, so the roots
    /// (up to three) are named with the frames one edge below each.
    fn root_hint(&self) -> String {
        let roots: Vec<usize> = (0..self.names.len())
            .filter(|&i| self.parent[i].is_none() && !self.children.is_empty(i))
            .collect();
        let Some(&first) = roots.first() else {
            return String::new();
        };
        let below = |r: usize| -> Vec<String> {
            let mut kids: Vec<String> = self
                .children
                .of(r)
                .map(|ei| self.edges[ei].child.clone())
                .collect();
            kids.sort();
            kids.dedup();
            kids.truncate(3);
            kids
        };
        if roots.len() == 1 {
            return format!(
                "; the tree's root: '{}' (one edge below it: {})",
                &self.names[first],
                quoted_list(&below(first))
            );
        }
        let names: Vec<String> = roots
            .iter()
            .take(3)
            .map(|&r| self.names[r].to_string())
            .collect();
        format!(
            "; the {} trees' roots: {}",
            roots.len(),
            quoted_list(&names)
        )
    }

    /// The frames from `i` up to its root, with the edge leading to each parent.
    fn ancestors(&self, i: usize) -> Vec<(usize, Option<usize>)> {
        let mut v = vec![];
        let mut cur = i;
        loop {
            let pe = self.parent[cur];
            v.push((cur, pe));
            match (pe, self.parent_frame[cur]) {
                (Some(_), Some(up)) => cur = up,
                _ => break,
            }
            if v.len() > self.names.len() {
                break; // cannot happen: cycles are refused on insertion
            }
        }
        v
    }

    /// The files the edges came from, in first-seen order.
    pub fn files(&self) -> Vec<std::path::PathBuf> {
        let mut v: Vec<std::path::PathBuf> = Vec::new();
        for e in &self.edges {
            if let Some(f) = &e.provenance.location.file {
                if !v.iter().any(|p| **p == **f) {
                    v.push(f.to_path_buf());
                }
            }
        }
        v
    }

    /// Compose `T_from_to` along the path through the common ancestor.
    ///
    /// Errors that concern no single edge (unknown frame, not connected) name the
    /// file when the graph holds one file, else list the files.
    pub fn transform(&self, from: &str, to: &str) -> Result<Chain> {
        self.transform_inner(from, to).map_err(|e| {
            if e.location.file.is_some() {
                return e;
            }
            let files = self.files();
            match files.len() {
                0 => e,
                1 => e.in_file(&files[0]),
                _ => Error {
                    message: format!(
                        "{} (files: {})",
                        e.message,
                        files
                            .iter()
                            .map(|f| f.display().to_string())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                    ..e
                },
            }
        })
    }

    fn transform_inner(&self, from: &str, to: &str) -> Result<Chain> {
        let fi = self.lookup(from)?;
        let ti = self.lookup(to)?;
        let (from, to) = (&self.names[fi], &self.names[ti]);
        let up_from = self.ancestors(fi);
        let up_to = self.ancestors(ti);
        let root_f = up_from.last().map(|x| x.0).unwrap_or(fi);
        let root_t = up_to.last().map(|x| x.0).unwrap_or(ti);
        if root_f != root_t {
            return Err(Error::frame(format!(
                "frames '{from}' and '{to}' are not connected: '{from}' is in the tree rooted at '{}', '{to}' in the tree rooted at '{}'",
                &self.names[root_f], &self.names[root_t]
            )));
        }
        // Lowest common ancestor: strip the common suffix of both root paths.
        let (mut a, mut b) = (up_from.len(), up_to.len());
        while a > 0 && b > 0 && up_from[a - 1].0 == up_to[b - 1].0 {
            a -= 1;
            b -= 1;
        }
        // up_from[..a] are the frames strictly below the LCA on the `from` side.
        let mut steps = Vec::with_capacity(a + b);
        let mut t_lca_from = Transform::identity();
        for &(_, pe) in up_from[..a].iter() {
            if let Some(ei) = pe {
                steps.push(ChainStep {
                    edge: self.edges[ei].clone(),
                    inverted: true,
                });
            }
        }
        for &(_, pe) in up_from[..a].iter().rev() {
            if let Some(ei) = pe {
                t_lca_from = t_lca_from.compose(&self.edges[ei].transform);
            }
        }
        let mut t_lca_to = Transform::identity();
        for &(_, pe) in up_to[..b].iter().rev() {
            if let Some(ei) = pe {
                t_lca_to = t_lca_to.compose(&self.edges[ei].transform);
                steps.push(ChainStep {
                    edge: self.edges[ei].clone(),
                    inverted: false,
                });
            }
        }
        let transform = t_lca_from.inverse().compose(&t_lca_to);
        let mut warnings = Vec::new();
        let mut defaulted = Vec::new();
        for s in &steps {
            if let Some(j) = &s.edge.joint {
                if j.value.is_none()
                    && j.joint_type == JointType::Floating
                    && j.name.starts_with(MOVING_TF)
                {
                    // A tf transform that changes between messages (formats::yaml_dialects).
                    return Err(Error::frame(format!(
                        "the transform {} -> {} lies on the path {from} -> {to} and {}: no single pose; refusing (record it with a static publisher, or give it in another file)",
                        s.edge.parent, s.edge.child, &j.name[MOVING_TF.len()..]
                    ))
                    .at(&s.edge.provenance.location));
                }
                if j.value.is_none() {
                    return Err(Error::frame(format!(
                        "joint '{}' ({}) lies on the path {from} -> {to}: its pose is not defined by the file; refusing (set it to its origin with --joint {}=0, or give this transform in another file)",
                        j.name, j.joint_type, j.name
                    ))
                    .at(&s.edge.provenance.location));
                }
                if j.defaulted {
                    defaulted.push((j.name.clone(), j.joint_type, s));
                }
            }
        }
        for (name, jt, s) in defaulted {
            warnings.push(
                Warning::new(
                    Code::JointAtDefault,
                    format!(
                        "{jt} joint '{name}' on the path {from} -> {to} taken at position 0; set it with --joint {name}=VALUE"
                    ),
                )
                .at(&s.edge.provenance.location),
            );
        }
        let mut chain = Chain {
            from: from.to_string(),
            to: to.to_string(),
            transform,
            steps,
            warnings,
            notes: Vec::new(),
        };
        chain.notes = self.path_notes(&chain);
        Ok(chain)
    }

    /// Notes on a chain whose two frames a redundant edge also joins: which
    /// path was used, and how to read the other.
    fn path_notes(&self, chain: &Chain) -> Vec<String> {
        self.redundant
            .iter()
            .filter(|r| {
                let (p, c) = (&r.edge.parent, &r.edge.child);
                (*p == chain.from && *c == chain.to) || (*p == chain.to && *c == chain.from)
            })
            .map(|r| {
                format!(
                    "path used: {} (the tree); {}; to use that edge alone, read it with --key {}",
                    path_text(chain),
                    r.summary(),
                    r.edge.provenance.key
                )
            })
            .collect()
    }

    /// The frame tree as text, one frame a line, children indented under their
    /// parent (like `check_urdf`), each with the place its edge came from; a
    /// frame declared without any edge is a root with a note saying so.
    /// Levels deeper than `TREE_MAX_INDENT` are written `[depth N]` instead of
    /// being indented further, so the text stays linear in the number of frames.
    pub fn tree(&self) -> String {
        self.tree_with(|_| None)
    }

    /// [`FrameGraph::tree`], each edge's line followed by `numbers(edge)`
    /// where it gives some (the frame-tree report's translation and
    /// rotation), two spaces after the place's bracket.
    pub fn tree_with(&self, numbers: impl Fn(&Edge) -> Option<String>) -> String {
        let mut out = String::new();
        for root in self.roots() {
            out.push_str(&root);
            let ri = self.id(&root).expect("a root is a frame");
            if self.children.is_empty(ri) {
                // Declared without an edge: say so rather than list it bare.
                match self.declared.get(&ri) {
                    Some(loc) => out.push_str(&format!("  [{loc}, no edge attaches it]")),
                    None => out.push_str("  [no edge attaches it]"),
                }
            }
            out.push('\n');
            // Explicit stack (deep chains must not exhaust the call stack):
            // (edge, depth, last child of its parent).
            let mut stack: Vec<(usize, usize, bool)> = Vec::new();
            let mut kids: Vec<usize> = self.children.of(ri).collect();
            for (k, &ei) in kids.iter().enumerate().rev() {
                stack.push((ei, 0, k + 1 == kids.len()));
            }
            // trail[d]: whether the ancestor at depth d was a last child.
            let mut trail: Vec<bool> = Vec::new();
            while let Some((ei, depth, last)) = stack.pop() {
                trail.truncate(depth);
                trail.push(last);
                let e = &self.edges[ei];
                if depth >= TREE_MAX_INDENT {
                    for &l in &trail[..TREE_MAX_INDENT] {
                        out.push_str(if l { "    " } else { "│   " });
                    }
                    out.push_str(&format!("[depth {}] ", depth + 1));
                } else {
                    for &l in &trail[..depth] {
                        out.push_str(if l { "    " } else { "│   " });
                    }
                    out.push_str(if last { "└── " } else { "├── " });
                }
                out.push_str(&e.child);
                out.push_str("  [");
                out.push_str(&e.provenance.location.to_string());
                if let Some(j) = &e.joint {
                    out.push_str(&format!(", {} joint '{}'", j.joint_type, j.name));
                }
                out.push(']');
                if let Some(n) = numbers(e) {
                    out.push_str("  ");
                    out.push_str(&n);
                }
                out.push('\n');
                let ci = self.id(&e.child).expect("a child is a frame");
                kids.clear();
                kids.extend(self.children.of(ci));
                for (k, &cei) in kids.iter().enumerate().rev() {
                    stack.push((cei, depth + 1, k + 1 == kids.len()));
                }
            }
        }
        for r in &self.redundant {
            out.push_str(&format!(
                "redundant {} -> {}  [{}, {}; {} the tree path {}]\n",
                r.edge.parent,
                r.edge.child,
                r.edge.provenance.location,
                r.edge.provenance.key,
                if r.agrees() {
                    "agrees with"
                } else {
                    "DISAGREES with"
                },
                r.path
            ));
        }
        out
    }
}

/// `'a', 'b', 'c'`.
fn quoted_list(names: &[String]) -> String {
    names
        .iter()
        .map(|s| format!("'{s}'"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::{EdgeSet, FrameDecl, FrameGraph};
    use crate::diagnostic::{Code, Location};
    use crate::frames::Edge;
    use crate::geometry::se3::Transform;

    fn edge(p: &str, c: &str, x: f64, line: usize) -> Edge {
        let t = Transform::from_translation([x, 0.0, 0.0]).expect("finite");
        Edge::new(p, c, t, Location::at("t.txt", line, None), "rig", "k")
    }

    /// `check_tree` accepts what an empty graph accepts, with the same
    /// error: random edge lists over a few frames (duplicates agreeing and
    /// not, reversed pairs, two parents, cycles, self-loops, empty names).
    #[test]
    fn check_tree_is_the_graph_s_check() {
        let mut x: u64 = 7;
        let mut next = |n: u64| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (x >> 33) % n
        };
        let (mut accepted, mut refused) = (0, 0);
        for _ in 0..3000 {
            let frames = 2 + next(8);
            let edges: Vec<Edge> = (0..1 + next(9))
                .map(|k| {
                    let name = |i: u64| {
                        if i == 9 {
                            String::new()
                        } else {
                            format!("f{i}")
                        }
                    };
                    let (p, c) = (name(next(frames + 1)), name(next(frames)));
                    edge(&p, &c, next(2) as f64, k as usize + 1)
                })
                .collect();
            let ours = super::check_tree(&edges).map_err(|e| e.to_string());
            let graph = FrameGraph::new()
                .add(set(edges.clone(), &[], Vec::new()))
                .map_err(|e| e.to_string());
            assert_eq!(ours, graph, "{edges:?}");
            match ours {
                Ok(()) => accepted += 1,
                Err(_) => refused += 1,
            }
        }
        assert!(accepted > 300 && refused > 300, "{accepted} {refused}");
    }

    fn set(edges: Vec<Edge>, frames: &[&str], redundant: Vec<Edge>) -> EdgeSet {
        EdgeSet {
            edges,
            frames: frames
                .iter()
                .map(|f| FrameDecl {
                    name: f.to_string(),
                    location: Location::at("t.txt", 9, None),
                })
                .collect(),
            warnings: Vec::new(),
            redundant,
        }
    }

    /// What the graph shows of itself.
    fn seen(g: &FrameGraph) -> (Vec<Edge>, Vec<String>, Vec<String>, String, Vec<String>) {
        let warnings = g.warnings().iter().map(|w| w.to_string()).collect();
        (
            g.edges().to_vec(),
            g.frames(),
            g.roots(),
            g.tree(),
            warnings,
        )
    }

    /// A source refused half-way leaves nothing behind: not its edges, its
    /// frames, its warnings, the links its edges made to the older frames,
    /// nor its names among those later names are compared with.
    #[test]
    fn a_refused_source_leaves_the_graph_as_it_was() {
        let first = || {
            set(
                vec![edge("a", "b", 1.0, 1), edge("b", "c", 1.0, 2)],
                &["lone"],
                vec![],
            )
        };
        let mut g = FrameGraph::new();
        g.add(first()).unwrap();
        let before = seen(&g);
        // New frames below old ones, a look-alike (a warning), a duplicate
        // (a warning), then a second parent for `b`: refused.
        let bad = set(
            vec![
                edge("c", "d", 1.0, 3),
                edge("a", "Lone", 1.0, 4),
                edge("a", "b", 1.0, 5),
                edge("z", "e", 1.0, 6),
                edge("e", "b", 1.0, 7),
            ],
            &["f"],
            vec![],
        );
        assert!(g.add(bad).is_err());
        assert_eq!(seen(&g), before);
        // A cycle through old frames, refused after the tree edges were
        // linked (the union-find must forget them too).
        let cyc = set(
            vec![edge("c", "x", 1.0, 8), edge("x", "a", 1.0, 9)],
            &[],
            vec![],
        );
        assert!(g.add(cyc).is_err());
        assert_eq!(seen(&g), before);
        // A refused declaration (an empty name): the edges before it go too.
        let red = set(vec![edge("c", "y", 1.0, 10)], &[""], vec![]);
        assert!(g.add(red).is_err());
        assert_eq!(seen(&g), before);
        // The same sources on a graph that never saw the refused ones.
        let next = || {
            set(
                vec![edge("c", "d", 2.0, 11), edge("d", "x", 1.0, 12)],
                &["lone2"],
                vec![],
            )
        };
        let mut fresh = FrameGraph::new();
        fresh.add(first()).unwrap();
        fresh.add(next()).unwrap();
        g.add(next()).unwrap();
        assert_eq!(seen(&g), seen(&fresh));
        assert!(g
            .warnings()
            .iter()
            .all(|w| w.code != Code::ConfusableFrameName));
        let t = g.transform("a", "x").unwrap();
        assert_eq!(t.transform.translation().x, 1.0 + 1.0 + 2.0 + 1.0);
        // `x` was in the refused cycle: now it is below `d`, not above `a`.
        assert_eq!(g.parent_edge("x").unwrap().parent, "d");
        assert!(g.parent_edge("a").is_none());
    }

    /// A first source whose agreeing duplicates are dropped: the child lists
    /// renumbered (the tree and the chains use them).
    #[test]
    fn dropped_duplicates_renumber_the_children() {
        let mut g = FrameGraph::new();
        let edges = vec![
            edge("a", "b", 1.0, 1),
            edge("a", "b", 1.0, 2),
            edge("b", "c", 2.0, 3),
            edge("c", "b", -2.0, 4),
            edge("a", "d", 3.0, 5),
        ];
        g.add(set(edges, &[], vec![])).unwrap();
        let lines: Vec<_> = g
            .edges()
            .iter()
            .map(|e| e.provenance.location.line)
            .collect();
        assert_eq!(lines, [Some(1), Some(3), Some(5)]);
        assert_eq!(g.warnings().len(), 2);
        assert_eq!(
            g.tree(),
            "a\n├── b  [t.txt:1]\n│   └── c  [t.txt:3]\n└── d  [t.txt:5]\n"
        );
        g.add(set(vec![edge("a", "e", 1.0, 6)], &[], vec![]))
            .unwrap();
        assert!(
            g.tree().ends_with("├── d  [t.txt:5]\n└── e  [t.txt:6]\n"),
            "{}",
            g.tree()
        );
    }
}
