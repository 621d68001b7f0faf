//! Detector benchmarks (figures in BENCHMARKS.md, "## Detector"):
//! - `assemble_1e6`: H and M from 1,000,000 points with normals already in
//!   cache (the 48 MB fit this machine's last-level cache), threads as the
//!   machine has;
//! - `assemble_1e6_cold_1thread` / `_threads`: the same, each iteration on
//!   another of 16 copies of the cloud (768 MB, more than the last-level
//!   cache), so that every point comes from memory; one thread, then one per core;
//! - `read_floor_1e6_cold`: the bandwidth floor for the cold case: summing the
//!   same 48 MB (6e6 doubles) from the same rotating copies, one thread;
//! - `gen_eigen_6x6`: one generalized eigen-solve H v = lambda M v (target <= 3 us);
//! - `frame_sweep_861x8`: the paper's per-pair sweep, 861 frame changes x 8 metric
//!   configurations on one scene (target <= 1 s).
//!
//! Run: `cargo bench --bench detector`.

use criterion::{criterion_group, criterion_main, Criterion};
use extrinsic_audit::internals::degeneracy::scene::{
    random_cloud, synthesize, Preprocess, SceneKind,
};
use extrinsic_audit::internals::degeneracy::threshold::default_threshold;
use extrinsic_audit::internals::degeneracy::{
    frame_sweep, generalized_eigen_raw, paper_frame_changes, Accumulator, Assembly, MetricRule,
};
use std::hint::black_box;

/// The benchmark data set (also written by `examples/bench_data.rs` for the
/// numpy comparison and by `examples/write_cloud.rs` as point files): seed
/// 2024, points uniform in [-10, 10]^3, unit normals uniform on the sphere.
fn data(n: usize) -> Cloud {
    random_cloud(2024, n)
}

/// Points and normals.
type Cloud = (Vec<[f64; 3]>, Vec<[f64; 3]>);

/// Copies of the cloud cycled through so that no iteration finds its data in cache.
const COLD_COPIES: usize = 16;

fn assemble(p: &[[f64; 3]], n: &[[f64; 3]], threads: usize) -> Assembly {
    let mut a = Accumulator::new().threads(threads);
    a.add(p, n, None).unwrap();
    a.finish()
}

/// Sum of every double, 8 independent lanes (vectorised, memory-bound).
fn read_floor(p: &[[f64; 3]], n: &[[f64; 3]]) -> f64 {
    let mut acc = [0.0f64; 8];
    for s in [p.as_flattened(), n.as_flattened()] {
        let c = s.chunks_exact(8);
        let rest: f64 = c.remainder().iter().sum();
        for x in c {
            for l in 0..8 {
                acc[l] += x[l];
            }
        }
        acc[0] += rest;
    }
    acc.iter().sum()
}

fn cold(c: &mut Criterion) {
    let (p, n) = data(1_000_000);
    let copies: Vec<Cloud> = (0..COLD_COPIES).map(|_| (p.clone(), n.clone())).collect();
    let mut g = c.benchmark_group("detector");
    g.sample_size(30);
    g.bench_function("assemble_1e6", |b| {
        b.iter(|| assemble(black_box(&p), black_box(&n), 0))
    });
    let mut k = 0;
    let mut next = || {
        k = (k + 1) % COLD_COPIES;
        &copies[k]
    };
    g.bench_function("assemble_1e6_cold_1thread", |b| {
        b.iter(|| {
            let (p, n) = next();
            assemble(black_box(p), black_box(n), 1)
        })
    });
    g.bench_function("assemble_1e6_cold_threads", |b| {
        b.iter(|| {
            let (p, n) = next();
            assemble(black_box(p), black_box(n), 0)
        })
    });
    g.bench_function("read_floor_1e6_cold", |b| {
        b.iter(|| {
            let (p, n) = next();
            read_floor(black_box(p), black_box(n))
        })
    });
    g.finish();
}

fn solve_and_sweep(c: &mut Criterion) {
    let (p, n) = data(10_000);
    let mut g = c.benchmark_group("detector");
    let asm = Assembly::from_points(&p, &n, None).unwrap();
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

criterion_group!(detector, cold, solve_and_sweep);
criterion_main!(detector);
