//! Writes the detector benchmark data for `bench/compare_numpy.py` and times the
//! same operations in Rust (single thread):
//! `cargo run --release --example bench_data -- OUT_DIR [N]`.
//!
//! OUT_DIR/points.f64: N x 6 little-endian doubles `x y z nx ny nz` (seed 2024,
//! points uniform in [-10, 10]^3, unit normals uniform on the sphere: the data
//! of `benches/detector.rs`); OUT_DIR/rust.json: H, M, the generalized
//! eigenvalues and the times (min, median, max).

use extrinsic_audit::internals::degeneracy::scene::random_cloud;
use extrinsic_audit::internals::degeneracy::{generalized_eigen_raw, Assembly};
use std::io::Write;
use std::time::Instant;

/// Min, median, max of the timings.
fn spread(mut v: Vec<f64>) -> [f64; 3] {
    v.sort_by(f64::total_cmp);
    [v[0], v[v.len() / 2], v[v.len() - 1]]
}

fn main() {
    let dir = std::path::PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "bench/data".into()),
    );
    let n: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("cannot create {}: {e}", dir.display());
        std::process::exit(2);
    }
    let (p, nn) = random_cloud(2024, n);
    let mut bytes = Vec::with_capacity(n * 48);
    for i in 0..n {
        for v in p[i].iter().chain(nn[i].iter()) {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    std::fs::write(dir.join("points.f64"), &bytes).expect("write points");
    let mut ta = Vec::new();
    let mut asm = Assembly::from_points(&p, &nn, None).expect("assemble");
    for _ in 0..30 {
        let t = Instant::now();
        asm = Assembly::from_points(std::hint::black_box(&p), std::hint::black_box(&nn), None)
            .expect("assemble");
        ta.push(t.elapsed().as_secs_f64());
    }
    let mut te = Vec::new();
    let mut eig = generalized_eigen_raw(&asm.h, &asm.m).expect("eigen");
    for _ in 0..50 {
        let t = Instant::now();
        for _ in 0..1000 {
            eig = generalized_eigen_raw(std::hint::black_box(&asm.h), std::hint::black_box(&asm.m))
                .expect("eigen");
        }
        te.push(t.elapsed().as_secs_f64() / 1000.0);
    }
    let rows = |m: &nalgebra::Matrix6<f64>| -> Vec<Vec<f64>> {
        (0..6)
            .map(|i| (0..6).map(|j| m[(i, j)]).collect())
            .collect()
    };
    let json = serde_json::json!({
        "n": n,
        "h": rows(&asm.h),
        "m": rows(&asm.m),
        "eigenvalues": eig.values,
        "assemble_s": spread(ta),
        "gen_eigen_s": spread(te),
    });
    let mut f = std::fs::File::create(dir.join("rust.json")).expect("create rust.json");
    writeln!(
        f,
        "{}",
        serde_json::to_string_pretty(&json).unwrap_or_default()
    )
    .expect("write rust.json");
    println!(
        "{}",
        serde_json::to_string(&json["assemble_s"]).unwrap_or_default()
    );
}
