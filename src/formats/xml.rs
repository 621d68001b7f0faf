//! XML shared by the URDF and launch readers: one set of parser options (no
//! DTD: entities can expand without bound) and errors placed at their line.

use crate::diagnostic::{Error, Result};
use crate::formats::source::LineIndex;

/// The roxmltree options every XML reader uses: DTDs refused.
pub fn parse_options<'input>() -> roxmltree::ParsingOptions<'input> {
    roxmltree::ParsingOptions {
        allow_dtd: false,
        ..Default::default()
    }
}

/// Parse XML text with [`parse_options`], the error at its line.
pub fn parse(text: &str) -> Result<roxmltree::Document<'_>> {
    roxmltree::Document::parse_with_options(text, parse_options()).map_err(|e| error(&e, text))
}

/// An XML error at its position; at the end of the text when the input stops early.
pub fn error(e: &roxmltree::Error, text: &str) -> Error {
    let p = e.pos();
    let (row, col) = (p.row as usize, p.col as usize);
    if matches!(e, roxmltree::Error::UnexpectedEndOfStream) {
        let lines = text.lines().count().max(1);
        let last = text
            .lines()
            .last()
            .map(|l| l.chars().count() + 1)
            .unwrap_or(1);
        return Error::parse("not well-formed XML: the file ends inside an element (truncated?)")
            .at_line(lines, Some(last));
    }
    if matches!(e, roxmltree::Error::DtdDetected) {
        // Refused on purpose: DTD entities can expand exponentially ("billion
        // laughs") and no URDF or launch file needs them.
        let line = text
            .lines()
            .position(|l| l.contains("<!DOCTYPE"))
            .map(|i| i + 1)
            .unwrap_or(row);
        return Error::limit(
            "XML with a <!DOCTYPE> (DTD / entity declarations): not read, entities can expand without bound; expected a plain URDF or launch file: remove the DOCTYPE block and write the values out",
        )
        .at_line(line, None);
    }
    Error::parse(format!("not well-formed XML: {e}")).at_line(row, Some(col))
}

/// 1-based (line, column) of an element's start.
pub fn pos_of(idx: &LineIndex, node: roxmltree::Node) -> (usize, usize) {
    idx.pos(node.range().start)
}

/// XML text that no format reads, refused naming its root element (or, when
/// it is not well-formed, where).
pub(crate) fn unknown_root(text: &str) -> Error {
    match roxmltree::Document::parse_with_options(text, parse_options()) {
        Ok(doc) => {
            let root = doc.root_element();
            let (l, c) = LineIndex::new(text).pos(root.range().start);
            Error::parse(format!(
                "root element is <{}>: expected a URDF <robot> or a ROS <launch> file; pass --input-format NAME to force a format",
                root.tag_name().name()
            ))
            .at_line(l, Some(c))
        }
        Err(e) => error(&e, text),
    }
}

/// Whether the input may be read as XML: it looks like XML, or its extension
/// says so (`.urdf`, `.xml`, `.launch`, `.launch.xml`).
pub(crate) fn candidate(input: &crate::formats::spec::Input) -> bool {
    input.looks_xml() || matches!(input.ext(), "urdf" | "xml" | "launch" | "launch.xml")
}
