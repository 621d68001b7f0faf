//! What every picture of a graph shares.

use crate::sanitize;

/// Colour of the highlighted chain in every picture.
pub const CHAIN_COLOUR: &str = "#c0392b";

/// Text from a file made visible (control and bidirectional characters as
/// escapes), before a format escapes it its own way.
pub fn shown(s: &str) -> String {
    sanitize::visible(s, false).into_owned()
}
