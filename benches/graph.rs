//! Loading a 2,000-link URDF (a chain with a branch every tenth link) and
//! composing one transform across it (leaf to leaf through the root).
//! Run: `cargo bench --bench graph`.

use criterion::{criterion_group, criterion_main, Criterion};
use extrinsic_audit::internals::formats::load_str;
use extrinsic_audit::internals::frames::FrameGraph;
use extrinsic_audit::LoadOptions;
use std::hint::black_box;
use std::path::Path;

fn urdf(n: usize) -> String {
    let mut s =
        String::from("<?xml version=\"1.0\"?>\n<robot name=\"big\">\n  <link name=\"l0\"/>\n");
    for i in 1..n {
        let parent = if i % 10 == 0 { i - 5 } else { i - 1 };
        s.push_str(&format!(
            "  <link name=\"l{i}\"/>\n  <joint name=\"j{i}\" type=\"{}\">\n    <origin xyz=\"0.01 0.002 -0.001\" rpy=\"0.001 -0.002 0.003\"/>\n    <parent link=\"l{parent}\"/>\n    <child link=\"l{i}\"/>\n    <axis xyz=\"0 0 1\"/>\n  </joint>\n",
            if i % 7 == 0 { "revolute" } else { "fixed" }
        ));
    }
    s.push_str("</robot>\n");
    s
}

fn bench(c: &mut Criterion) {
    let text = urdf(2000);
    let path = Path::new("big.urdf");
    let opts = LoadOptions::default();
    c.bench_function("load 2000-link URDF + transform leaf to leaf", |b| {
        b.iter(|| {
            let l = load_str(black_box(&text), path, &opts).expect("load");
            let mut g = FrameGraph::new();
            g.add(l).expect("graph");
            let chain = g.transform("l1999", "l1004").expect("chain");
            black_box(chain.transform)
        })
    });
    let l = load_str(&text, path, &opts).expect("load");
    let mut g = FrameGraph::new();
    g.add(l).expect("graph");
    c.bench_function("transform leaf to leaf in a 2000-link graph", |b| {
        b.iter(|| {
            black_box(
                g.transform(black_box("l1999"), black_box("l1004"))
                    .expect("chain"),
            )
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
