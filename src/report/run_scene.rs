//! The frames of a run in 3D (`audit run --format mcap`): every edge of the
//! run's transforms (a bag's `/tf_static` and `/robot_description`, the
//! `--extrinsics` files) as the pose of its child in its parent, and every
//! frame whose pose in the scan frame does not depend on the scan (the rig
//! frames and lever arms of `--rig-frames`) as a child of the scan frame.
//! The scan frame's name is the scans' `header.frame_id` (or `scan` for
//! files that name none), known once the first scan is read.

use crate::document::scene::SceneTransform;
use crate::frames::FrameGraph;
use crate::run::frames::{FrameGroup, RunFrame};

/// The run's transforms, waiting for the scan frame's name.
#[derive(Debug, Clone, Default)]
pub struct RunTransforms {
    edges: Vec<SceneTransform>,
    /// Fixed frames: their pose in the scan frame (`parent` left empty).
    fixed: Vec<SceneTransform>,
}

/// The scan frame's name where the scans name none (as `audit degeneracy`).
pub const UNNAMED_SCAN_FRAME: &str = "scan";

impl RunTransforms {
    /// Of the run's `frames` and `graph`.
    pub fn new(frames: &[RunFrame], graph: Option<&FrameGraph>) -> Self {
        let edges: Vec<SceneTransform> = graph
            .map(|g| {
                g.edges()
                    .iter()
                    .map(|e| SceneTransform {
                        parent: e.parent.clone(),
                        child: e.child.clone(),
                        translation_m: (*e.transform.translation()).into(),
                        rotation_xyzw: e.transform.quaternion_xyzw(),
                    })
                    .collect()
            })
            .unwrap_or_default();
        // A frame the graph already places keeps the graph's parent.
        let placed = |name: &str| graph.is_some_and(|g| g.contains(name));
        let fixed = frames
            .iter()
            .filter(|f| f.group != FrameGroup::Scan && !placed(&f.name))
            .filter_map(|f| {
                let t = f.fixed.as_ref()?;
                Some(SceneTransform {
                    parent: String::new(),
                    child: f.name.clone(),
                    translation_m: (*t.translation()).into(),
                    rotation_xyzw: t.quaternion_xyzw(),
                })
            })
            .collect();
        RunTransforms { edges, fixed }
    }

    /// Every transform, the fixed frames under `scan_frame`.
    pub fn resolve(self, scan_frame: Option<&str>) -> Vec<SceneTransform> {
        let parent = scan_frame.unwrap_or(UNNAMED_SCAN_FRAME);
        let mut all = self.edges;
        all.extend(self.fixed.into_iter().map(|mut t| {
            t.parent = parent.to_string();
            t
        }));
        all
    }
}
