//! Pictures of a [`Graph`](crate::document::Graph) (the frame tree,
//! `audit FILE --frames --format dot|mermaid|svg`): every link labelled with
//! its label lines, the highlighted chain drawn in red.
//!
//! Names and labels come from files: hostile input. Each format escapes
//! them its own way (DOT quoted strings, Mermaid entity codes, XML
//! entities), after [`crate::sanitize::visible`] has turned control and
//! bidirectional characters into visible escapes (`shared.rs`).

mod dot;
mod mermaid;
mod shared;
mod svg;

pub use dot::dot;
pub use mermaid::mermaid;
pub use svg::svg;
