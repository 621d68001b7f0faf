//! The peer of the URDF reader's speed (issue 29, bench/urdf_speed.sh): every
//! quick-xml event of a file, with every attribute of every start tag split
//! and its value unescaped, and nothing else (no names kept, no numbers read).
//! The reader cannot be faster than this loop over the same parser.
//!
//! `cargo run --release --example xml_events_peer -- FILE.urdf`
//! prints the number of elements and attributes and the attribute bytes.

use quick_xml::events::Event;
use quick_xml::reader::Reader;

fn main() {
    let path = std::env::args()
        .nth(1)
        .expect("usage: xml_events_peer FILE");
    let text = std::fs::read_to_string(&path).expect("a UTF-8 file");
    let mut r = Reader::from_str(&text);
    r.config_mut().check_end_names = true;
    let (mut elements, mut attributes, mut bytes) = (0usize, 0usize, 0usize);
    loop {
        match r.read_event().expect("well-formed XML") {
            Event::Start(e) | Event::Empty(e) => {
                elements += 1;
                for a in e.attributes() {
                    let a = a.expect("a well-formed attribute");
                    let v = a.unescape_value().expect("known entities");
                    attributes += 1;
                    bytes += a.key.as_ref().len() + v.len();
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    println!("{elements} elements, {attributes} attributes, {bytes} attribute bytes");
}
