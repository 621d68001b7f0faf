//! The frame tree (`audit FILE... --frames`): every frame and every edge the
//! files yield, each edge with its transform (pose of child in parent,
//! `p_parent = R p_child + d`), joint type and `file:line`, and the
//! `--from` -> `--to` chain marked when one is given. JSON in
//! `docs/schemas/frames.schema.json` (with `warnings`, like every report);
//! its document is one [`Graph`] block, from which the text tree and the
//! pictures (DOT, Mermaid, SVG) are drawn. Each edge's label: its translation
//! (m, 0.1 mm), its rotation as URDF roll-pitch-yaw (deg, 0.001 deg), its
//! joint type and `file:line`.
//!
//! Frames are listed depth first from the roots (sorted), children in the
//! order their edges were read, so a parent always comes before its children.

use crate::document::numbers::{degrees_trimmed, fixed};
use crate::document::scene::{axis_length, Entity, Paint, SceneTransform, Shape};
use crate::document::SCHEMA_VERSION;
use crate::document::{Block, Document, Graph, GraphLink, GraphNode, Report, Scene};
use crate::frames::{Chain, Edge, FrameGraph};
use crate::tolerances::LENGTH_ZERO_TOL;
use serde::Serialize;
use std::collections::{HashMap, HashSet};

/// `frames[i]`: one frame.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FrameJson {
    /// The frame's name, exactly as in the file.
    pub name: String,
    /// Its parent frame; null for a root.
    pub parent: Option<String>,
    /// Edges from its root (0 for a root).
    pub depth: usize,
    /// The frame is on the `--from` -> `--to` chain.
    pub on_chain: bool,
}

/// `edges[i]`: one edge, parent -> child as stored.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FrameEdgeJson {
    /// Parent frame.
    pub parent: String,
    /// Child frame.
    pub child: String,
    /// `d` (m): the origin of the child in parent coordinates.
    pub translation_m: [f64; 3],
    /// URDF fixed-axis `[roll, pitch, yaw]` (deg), `R = Rz(yaw) Ry(pitch) Rx(roll)`.
    pub rpy_deg: [f64; 3],
    /// Rotation angle of `R` in `[0, 180]` (deg).
    pub angle_deg: f64,
    /// `fixed`, or the joint type (`revolute`, `continuous`, `prismatic`,
    /// `floating`, `planar`); a movable joint is drawn at the position used.
    pub joint_type: String,
    /// The movable joint's name; null for a fixed edge.
    pub joint_name: Option<String>,
    /// The file the edge was read from (empty when none).
    pub file: String,
    /// 1-based line; null when unknown.
    pub line: Option<usize>,
    /// 1-based column; null when unknown.
    pub column: Option<usize>,
    /// Id of the format that read it.
    pub format: String,
    /// The edge is on the `--from` -> `--to` chain.
    pub on_chain: bool,
    /// `R` as a unit quaternion `[x, y, z, w]` (the 3D scene's transform;
    /// the JSON has `rpy_deg`).
    #[serde(skip)]
    pub quaternion_xyzw: [f64; 4],
}

/// `chain`: the frame pair asked for and the frames of its path, in order.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ChainFramesJson {
    /// `--from`.
    pub from: String,
    /// `--to`.
    pub to: String,
    /// The frames walked from `from` to `to`, both included.
    pub path: Vec<String>,
}

/// The frame tree report.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FramesReport {
    /// Version of this JSON layout (1).
    pub schema_version: u32,
    /// Every frame, depth first from the roots.
    pub frames: Vec<FrameJson>,
    /// Every edge, in the order of `frames` (the edge into each non-root).
    pub edges: Vec<FrameEdgeJson>,
    /// The highlighted chain; null without `--from`/`--to`.
    pub chain: Option<ChainFramesJson>,
    /// The text tree (the `text` rendering), kept for it.
    #[serde(skip)]
    pub tree_text: String,
}

fn edge_json(e: &Edge, on_chain: bool) -> FrameEdgeJson {
    let t = &e.transform;
    let d = t.translation();
    let rpy = t.rpy();
    let loc = &e.provenance.location;
    FrameEdgeJson {
        parent: e.parent.clone(),
        child: e.child.clone(),
        translation_m: [d.x, d.y, d.z],
        rpy_deg: rpy.map(f64::to_degrees),
        angle_deg: t.rotation_angle_axis().0.to_degrees(),
        joint_type: e
            .joint
            .as_ref()
            .map_or("fixed".to_string(), |j| j.joint_type.name().to_string()),
        joint_name: e.joint.as_ref().map(|j| j.name.clone()),
        file: loc
            .file
            .as_ref()
            .map(|p| p.display().to_string())
            .unwrap_or_default(),
        line: loc.line,
        column: loc.column,
        format: e.provenance.format.to_string(),
        on_chain,
        quaternion_xyzw: t.quaternion_xyzw(),
    }
}

/// The chain's frames in order from `from` to `to`.
fn chain_path(chain: &Chain) -> Vec<String> {
    let mut path = vec![chain.from.clone()];
    for s in &chain.steps {
        let next = if s.inverted {
            &s.edge.parent
        } else {
            &s.edge.child
        };
        path.push(next.clone());
    }
    path
}

/// The frame tree of `graph`, with `chain` marked when given.
pub fn frames_report(graph: &FrameGraph, chain: Option<&Chain>) -> FramesReport {
    let on: HashSet<(String, String)> = chain
        .map(|c| {
            c.steps
                .iter()
                .map(|s| (s.edge.parent.clone(), s.edge.child.clone()))
                .collect()
        })
        .unwrap_or_default();
    let path = chain.map(chain_path).unwrap_or_default();
    let on_frame: HashSet<&str> = path.iter().map(String::as_str).collect();
    let mut kids: HashMap<&str, Vec<&Edge>> = HashMap::new();
    for e in graph.edges() {
        kids.entry(e.parent.as_str()).or_default().push(e);
    }
    let mut frames = Vec::new();
    let mut edges = Vec::new();
    for root in graph.roots() {
        // Explicit stack, children pushed in reverse to pop in file order.
        let mut stack: Vec<(Option<&Edge>, String, usize)> = vec![(None, root, 0)];
        while let Some((edge, name, depth)) = stack.pop() {
            if let Some(e) = edge {
                edges.push(edge_json(
                    e,
                    on.contains(&(e.parent.clone(), e.child.clone())),
                ));
            }
            for e in kids.get(name.as_str()).into_iter().flatten().rev() {
                stack.push((Some(e), e.child.clone(), depth + 1));
            }
            frames.push(FrameJson {
                on_chain: on_frame.contains(name.as_str()),
                parent: edge.map(|e| e.parent.clone()),
                name,
                depth,
            });
        }
    }
    FramesReport {
        schema_version: SCHEMA_VERSION,
        frames,
        edges,
        chain: chain.map(|c| ChainFramesJson {
            from: c.from.clone(),
            to: c.to.clone(),
            path,
        }),
        tree_text: graph.tree_with(|e| Some(tree_numbers(e))),
    }
}

impl FrameEdgeJson {
    /// `file:line` of the edge, the file as given (`<input>` when none).
    fn place(&self) -> String {
        let mut s = if self.file.is_empty() {
            "<input>".to_string()
        } else {
            self.file.clone()
        };
        if let Some(l) = self.line {
            s.push_str(&format!(":{l}"));
        }
        s
    }

    /// The label lines: translation, rotation, joint and place.
    fn label(&self) -> Vec<String> {
        let joint = match &self.joint_name {
            Some(n) => format!("{} joint {n}", self.joint_type),
            None => self.joint_type.clone(),
        };
        let [xyz, rpy] = numbers(self.translation_m, self.rpy_deg);
        vec![xyz, rpy, format!("{joint}, {}", self.place())]
    }
}

/// An edge's translation (m, to 0.1 mm) and roll-pitch-yaw (deg, to 0.001
/// deg, trailing zeros cut) as the pictures and the text tree label it:
/// `xyz [0.1000, 0.0000, 0.2000] m`, `rpy [0, 0, 90] deg`.
fn numbers(translation_m: [f64; 3], rpy_deg: [f64; 3]) -> [String; 2] {
    let d = translation_m.map(|x| fixed(x, 4));
    let r = rpy_deg.map(degrees_trimmed);
    [
        format!("xyz [{}, {}, {}] m", d[0], d[1], d[2]),
        format!("rpy [{}, {}, {}] deg", r[0], r[1], r[2]),
    ]
}

/// The numbers after an edge's line in the text tree.
fn tree_numbers(e: &Edge) -> String {
    let d = e.transform.translation();
    let [xyz, rpy] = numbers([d.x, d.y, d.z], e.transform.rpy().map(f64::to_degrees));
    format!("{xyz}  {rpy}")
}

impl FramesReport {
    /// The tree as a graph: the frames as nodes, the edges as labelled links.
    pub fn graph(&self) -> Graph {
        let index: HashMap<&str, usize> = self
            .frames
            .iter()
            .enumerate()
            .map(|(i, f)| (f.name.as_str(), i))
            .collect();
        let at = |name: &str| index.get(name).copied();
        Graph {
            nodes: self
                .frames
                .iter()
                .map(|f| GraphNode {
                    name: f.name.clone(),
                    parent: f.parent.as_deref().and_then(at),
                    depth: f.depth,
                    on_chain: f.on_chain,
                })
                .collect(),
            links: self
                .edges
                .iter()
                .filter_map(|e| {
                    Some(GraphLink {
                        from: at(&e.parent)?,
                        to: at(&e.child)?,
                        label: e.label(),
                        on_chain: e.on_chain,
                    })
                })
                .collect(),
            chain: self.chain.as_ref().map(|c| c.path.clone()),
            text: self.tree_text.clone(),
        }
    }
}

impl FramesReport {
    /// The tree in 3D: every edge as a transform (pose of the child in the
    /// parent), and with a chain, each of its edges as a line from the
    /// parent's origin to the child's and the axes of its two ends; the
    /// queried chain in the metadata.
    pub fn scene(&self) -> Scene {
        let mut s = Scene::default();
        s.metadata
            .push(("frames".into(), self.frames.len().to_string()));
        s.transforms = self
            .edges
            .iter()
            .map(|e| SceneTransform {
                parent: e.parent.clone(),
                child: e.child.clone(),
                translation_m: e.translation_m,
                rotation_xyzw: e.quaternion_xyzw,
            })
            .collect();
        let Some(c) = &self.chain else {
            return s;
        };
        s.metadata.extend([
            ("from".to_string(), c.from.clone()),
            ("to".to_string(), c.to.clone()),
            ("chain".to_string(), c.path.join(" -> ")),
        ]);
        let mut longest: f64 = 0.0;
        for e in self.edges.iter().filter(|e| e.on_chain) {
            let d = e.translation_m;
            let len = d.iter().map(|x| x * x).sum::<f64>().sqrt();
            longest = longest.max(len);
            if len > LENGTH_ZERO_TOL {
                let mut line = Entity::new(format!("chain/{}/{}", e.parent, e.child), &e.parent);
                line.shapes.push(Shape::Line {
                    points: vec![[0.0; 3], d],
                    paint: Paint::Chain,
                });
                line.fact("on_chain", true);
                s.entities.push(line);
            }
        }
        let axis = axis_length(longest);
        s.entities.push(Entity::axes(&c.from, axis));
        if c.to != c.from {
            s.entities.push(Entity::axes(&c.to, axis));
        }
        s
    }
}

impl Report for FramesReport {
    fn document(&self) -> Document {
        let mut doc = Document::new();
        doc.push(Block::Graph(self.graph()));
        doc.push(Block::Scene(self.scene()));
        doc
    }
}
