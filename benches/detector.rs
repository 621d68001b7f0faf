//! Detector benchmarks (figures in BENCHMARKS.md, "## Detector"):
//! - `assemble_1e6`: H and M from 1,000,000 points with normals (target <= 10 ms);
//! - `gen_eigen_6x6`: one generalized eigen-solve H v = lambda M v (target <= 3 us);
//! - `frame_sweep_861x8`: the paper's per-pair sweep, 861 frame changes x 8 metric
//!   configurations on one scene (target <= 1 s).
//!
//! Run: `cargo bench --bench detector`.

use criterion::{criterion_group, criterion_main, Criterion};
use extrinsic_audit::degeneracy::scene::{random_cloud, synthesize, Preprocess, SceneKind};
use extrinsic_audit::degeneracy::threshold::default_threshold;
use extrinsic_audit::degeneracy::{
    frame_sweep, generalized_eigen_raw, paper_frame_changes, Assembly, MetricRule,
};
use std::hint::black_box;

/// The benchmark data set (also written by `examples/bench_data.rs` for the
/// numpy comparison): seed 2024, points uniform in [-10, 10]^3, unit normals
/// uniform on the sphere.
fn data(n: usize) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    random_cloud(2024, n)
}

fn benches(c: &mut Criterion) {
    let (p, n) = data(1_000_000);
    let mut g = c.benchmark_group("detector");
    g.sample_size(30);
    g.bench_function("assemble_1e6", |b| {
        b.iter(|| Assembly::from_points(black_box(&p), black_box(&n), None).unwrap())
    });
    let asm = Assembly::from_points(&p[..10_000], &n[..10_000], None).unwrap();
    g.sample_size(100);
    g.bench_function("gen_eigen_6x6", |b| {
        b.iter(|| generalized_eigen_raw(black_box(&asm.h), black_box(&asm.m)).unwrap())
    });
    let cloud = synthesize(SceneKind::Tunnel, &Preprocess::pipeline(0.1, 0.01, 1)).unwrap();
    let scene = Assembly::from_points(&cloud.points, &cloud.normals, None).unwrap();
    let changes = paper_frame_changes(1);
    let rules = MetricRule::paper_configs();
    let taus: Vec<f64> = rules.iter().map(|r| default_threshold(r, 1e-2)).collect();
    g.sample_size(10);
    g.bench_function("frame_sweep_861x8", |b| {
        b.iter(|| frame_sweep(black_box(&scene), &changes, &rules, &taus).unwrap())
    });
    g.finish();
}

criterion_group!(detector, benches);
criterion_main!(detector);
