//! The frames a run is reported in: the scan frame, body frames named in
//! the run's transforms (a bag's `/tf_static` and `/robot_description`, the
//! extrinsics files given), and the fixed frames of rig files. Each scan
//! gets the pose of every frame in its own frame (see [`super`]'s
//! conventions), resolved once per scan frame name.

use super::scan::FramePoses;
use crate::diagnostic::{Code, Warning};
use crate::frames::FrameGraph;
use crate::geometry::Transform;
use std::collections::HashMap;
use std::sync::Arc;

/// Where a frame comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FrameGroup {
    /// The scan's own frame.
    Scan,
    /// A frame of the run's transforms (`--frame`).
    Named,
    /// A rig file's body frame, the scan taken as its LiDAR's (`--rig-frames`).
    Rig,
    /// A rig's lever arm alone (its translation, no rotation).
    Lever,
}

impl FrameGroup {
    /// The name in reports.
    pub fn name(self) -> &'static str {
        match self {
            FrameGroup::Scan => "scan",
            FrameGroup::Named => "named",
            FrameGroup::Rig => "rig",
            FrameGroup::Lever => "lever",
        }
    }
}

/// One frame of the run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunFrame {
    /// Its name (`scan` for the scan frame; a rig's id; `lever:` and the id).
    pub name: String,
    /// Where it comes from.
    pub group: FrameGroup,
    /// Its pose in the scan frame when it does not depend on the scan.
    pub fixed: Option<Transform>,
    /// What defined it (a file, the bag's transforms).
    pub source: String,
}

/// The run's frames, and the poses per scan frame name.
pub struct Frames {
    /// The frames (the scan frame first).
    pub list: Vec<RunFrame>,
    graph: Option<FrameGraph>,
    cache: HashMap<Option<String>, FramePoses>,
    /// Named warnings of the resolution (a scan frame the transforms never
    /// name), once per scan frame name.
    pub warnings: Vec<Warning>,
}

impl Frames {
    /// The frames `list` (the scan frame first), named frames resolved in `graph`.
    pub fn new(list: Vec<RunFrame>, graph: Option<FrameGraph>) -> Self {
        Frames {
            list,
            graph,
            cache: HashMap::new(),
            warnings: Vec::new(),
        }
    }

    /// The run's transforms, when it has any.
    pub fn graph(&self) -> Option<&FrameGraph> {
        self.graph.as_ref()
    }

    /// The pose of frame `to` in frame `from` along the run's transforms.
    pub fn pose(&self, from: &str, to: &str) -> Option<Transform> {
        if from == to {
            return Some(Transform::identity());
        }
        self.graph
            .as_ref()?
            .transform(from, to)
            .ok()
            .map(|c| c.transform)
    }

    /// Every frame's pose in the scan frame `frame_id`.
    pub fn poses_for(&mut self, frame_id: Option<&str>) -> FramePoses {
        let key = frame_id.map(str::to_string);
        if let Some(p) = self.cache.get(&key) {
            return p.clone();
        }
        let known = match (frame_id, &self.graph) {
            (Some(f), Some(g)) => g.contains(f),
            _ => false,
        };
        let named: Vec<&str> = self
            .list
            .iter()
            .filter(|f| f.group == FrameGroup::Named)
            .map(|f| f.name.as_str())
            .collect();
        if !known && !named.is_empty() {
            let what = frame_id.map_or(
                "files that name no frame (give --lidar-frame)".to_string(),
                |f| format!("`{}`", crate::sanitize::quote(f)),
            );
            self.warnings.push(Warning::new(
                Code::FrameMissing,
                format!(
                    "scan frame {what}: the run's transforms do not name it, so its scans are reported in their own frame only (not in {})",
                    named.join(", ")
                ),
            ));
        }
        let poses: Vec<Option<Transform>> = self
            .list
            .iter()
            .map(|f| match f.group {
                FrameGroup::Scan => Some(Transform::identity()),
                FrameGroup::Named => frame_id
                    .filter(|_| known)
                    .and_then(|s| self.pose(s, &f.name)),
                FrameGroup::Rig | FrameGroup::Lever => f.fixed,
            })
            .collect();
        let p = Arc::new(poses);
        self.cache.insert(key, p.clone());
        p
    }
}
