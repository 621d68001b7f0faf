//! Where the bytes go when a URDF is loaded (issue 12): a counting global
//! allocator records live and peak heap bytes around each stage.
//! `cargo run --release --example urdf_memory -- FILE.urdf`
//! (make FILE with `bench/gen_urdf_chain.py N FILE [--one-line]`).
//!
//! Prints, per link: the heap the reader needs at its peak and keeps (edges,
//! frames), then the pipeline's frame graph, the sizes of the records, and
//! for comparison the heap of a roxmltree document of the same text (the
//! reader's tree until issue 12). Bytes are those asked of the allocator
//! (its own overhead and the program are in the benchmark's peak RSS).

use extrinsic_audit::internals::formats::load_str;
use extrinsic_audit::internals::frames::{FrameDecl, FrameGraph};
use extrinsic_audit::Edge;
use extrinsic_audit::LoadOptions;
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

struct Counting;
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(l) };
        if !p.is_null() {
            let now = LIVE.fetch_add(l.size(), Relaxed) + l.size();
            PEAK.fetch_max(now, Relaxed);
        }
        p
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        let q = unsafe { System.realloc(p, l, new) };
        if !q.is_null() {
            let now = if new >= l.size() {
                LIVE.fetch_add(new - l.size(), Relaxed) + (new - l.size())
            } else {
                LIVE.fetch_sub(l.size() - new, Relaxed) - (l.size() - new)
            };
            PEAK.fetch_max(now, Relaxed);
        }
        q
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) };
        LIVE.fetch_sub(l.size(), Relaxed);
    }
}

#[global_allocator]
static A: Counting = Counting;

/// Live bytes now, and resets the peak to them.
fn mark() -> usize {
    let now = LIVE.load(Relaxed);
    PEAK.store(now, Relaxed);
    now
}

fn per(bytes: usize, n: usize) -> String {
    format!(
        "{:>9.1} MB {:>7.0} B/link",
        bytes as f64 / 1e6,
        bytes as f64 / n as f64
    )
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .ok_or("usage: urdf_memory FILE.urdf")?;
    let path = Path::new(&path);
    let text = std::fs::read_to_string(path)?;
    let n = text.matches("<link").count().max(1);
    println!("{n} links, file {:.1} MB", text.len() as f64 / 1e6);
    println!(
        "sizes: Edge {} B, FrameDecl {} B",
        std::mem::size_of::<Edge>(),
        std::mem::size_of::<FrameDecl>()
    );
    let base = mark();
    let t0 = std::time::Instant::now();
    let loaded = load_str(&text, path, &LoadOptions::default())?;
    let t_load = t0.elapsed();
    let (peak, kept) = (PEAK.load(Relaxed) - base, LIVE.load(Relaxed) - base);
    println!("reader peak       {}", per(peak, n));
    println!("reader keeps      {}", per(kept, n));
    let base = mark();
    let mut g = FrameGraph::new();
    g.add(loaded)?;
    println!(
        "time: reader {:.0} ms, graph.add {:.0} ms",
        t_load.as_secs_f64() * 1e3,
        (t0.elapsed() - t_load).as_secs_f64() * 1e3
    );
    let (peak, kept) = (PEAK.load(Relaxed) - base, LIVE.load(Relaxed) - base);
    println!(
        "graph.add peak    {}  (beyond what the reader kept)",
        per(peak, n)
    );
    println!(
        "graph keeps       {}  (beyond what the reader kept)",
        per(kept, n)
    );
    drop(g);
    let base = mark();
    let doc = roxmltree::Document::parse(&text)?;
    println!("roxmltree doc     {}", per(LIVE.load(Relaxed) - base, n));
    drop(doc);
    Ok(())
}
