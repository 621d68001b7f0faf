//! No input makes a loader panic: every fixture and bad input, whole and
//! truncated at several points, read as every format.

use extrinsic_audit::internals::formats::{all_formats, load_str};
use extrinsic_audit::internals::frames::FrameGraph;
use extrinsic_audit::LoadOptions;

#[test]
fn no_panics_on_any_format() {
    let mut files = Vec::new();
    for dir in [
        "tests/fixtures/formats",
        "tests/fixtures/urdf",
        "tests/bad_inputs",
    ] {
        for e in std::fs::read_dir(dir).expect("dir") {
            let p = e.expect("entry").path();
            let name = p.to_string_lossy().to_string();
            // Resource-limit cases are in the catalogue; here they only cost time.
            if name.contains("alias-bomb") || name.contains("deep-nesting") {
                continue;
            }
            if let Ok(text) = std::fs::read_to_string(&p) {
                files.push((p, text));
            }
        }
    }
    let mut runs = 0;
    for (p, text) in &files {
        let mut cuts = vec![text.len()];
        if text.len() < 20_000 {
            cuts.extend((1..5).map(|k| text.len() * k / 5));
        }
        for cut in cuts {
            let mut cut = cut;
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            let t = &text[..cut];
            for (f, _) in all_formats() {
                let mut opts = LoadOptions::default();
                opts.format = Some(f);
                if let Ok(l) = load_str(t, p, &opts) {
                    let mut g = FrameGraph::new();
                    if g.add(l).is_ok() {
                        let frames = g.frames();
                        if let (Some(a), Some(b)) = (frames.first(), frames.last()) {
                            let _ = g.transform(a, b);
                        }
                        let _ = g.tree();
                    }
                }
                runs += 1;
            }
        }
    }
    assert!(runs > 1000);
}
