//! Criterion benchmark of the core analysis of one transform (issue 2: at most
//! 2 microseconds, no heap). Run: `cargo bench --bench core`.

use criterion::{criterion_group, criterion_main, Criterion};
use extrinsic_audit::analyze;
use extrinsic_audit::internals::tolerances::DEFAULT_PITCH_TOL;
use extrinsic_audit::Transform;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut w = Vec::new();
    let general = Transform::from_rpy([0.01, -0.02, 1.3], [0.12, -0.05, 0.3]).unwrap();
    let zero_pitch = Transform::from_matrix3(
        [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]],
        [0.0, 0.0, -0.05],
        &mut w,
    )
    .unwrap();
    let ells = [1.0, 0.25, 2.85];
    let mut g = c.benchmark_group("core");
    g.bench_function("analyze_general_screw_3_ells", |b| {
        b.iter(|| analyze(black_box(&general), black_box(&ells), DEFAULT_PITCH_TOL).unwrap())
    });
    // Zero pitch is the most expensive path: M0 is built and its residual checked.
    g.bench_function("analyze_zero_pitch_3_ells", |b| {
        b.iter(|| analyze(black_box(&zero_pitch), black_box(&ells), DEFAULT_PITCH_TOL).unwrap())
    });
    g.bench_function("analyze_zero_pitch_8_ells", |b| {
        let ells8 = [0.1, 0.25, 0.5, 1.0, 2.0, 2.85, 5.0, 10.0];
        b.iter(|| analyze(black_box(&zero_pitch), black_box(&ells8), DEFAULT_PITCH_TOL).unwrap())
    });
    g.bench_function("screw_only", |b| {
        b.iter(|| black_box(&general).screw(DEFAULT_PITCH_TOL))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
