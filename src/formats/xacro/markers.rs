//! What marks text as xacro, and the advice for a `.urdf` that holds it: a
//! leaf, so that the URDF reader can refuse un-expanded xacro without
//! importing the expander (which reads its output as URDF).

use std::path::Path;

/// Whether URDF text still holds xacro: the namespace, elements or
/// substitutions.
pub fn has_markers(text: &str) -> bool {
    text.contains("xmlns:xacro")
        || text.contains("<xacro:")
        || text.contains("${")
        || text.contains("$(")
}

/// What to do with a `.urdf` that holds xacro, for messages.
pub fn advice(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_else(|| "robot.urdf".to_string());
    format!("read it as xacro: `audit --input-format xacro {name}` (or name it .xacro)")
}
