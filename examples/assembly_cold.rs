//! Assembly of H and M per 1e6 points in cache-cold memory against the
//! memory-bandwidth floor measured the same way, in one process:
//! `cargo run --release --example assembly_cold -- [THREADS] [REPS] [scalar]`.
//!
//! 16 copies of the benchmark cloud (1e6 points, 768 MB, more than the
//! last-level cache) are cycled through, so every iteration reads its 48 MB
//! from memory. The floor sums the same doubles (8 vectorised lanes, one
//! thread). Prints min / median / max in ms and the median ratio.

use extrinsic_audit::internals::degeneracy::scene::random_cloud;
use extrinsic_audit::internals::degeneracy::{Accumulator, Kernel};
use std::hint::black_box;
use std::time::Instant;

fn floor(p: &[[f64; 3]], n: &[[f64; 3]]) -> f64 {
    let mut acc = [0.0f64; 8];
    for s in [p.as_flattened(), n.as_flattened()] {
        for x in s.chunks_exact(8) {
            for l in 0..8 {
                acc[l] += x[l];
            }
        }
    }
    acc.iter().sum()
}

fn stats(mut v: Vec<f64>) -> [f64; 3] {
    v.sort_by(f64::total_cmp);
    [v[0], v[v.len() / 2], v[v.len() - 1]].map(|x| x * 1e3)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let threads: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(1);
    let reps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(64);
    let kernel = if args.get(3).map(String::as_str) == Some("scalar") {
        Kernel::Scalar
    } else {
        Kernel::detect()
    };
    let (p, n) = random_cloud(2024, 1_000_000);
    let copies: Vec<_> = (0..16).map(|_| (p.clone(), n.clone())).collect();
    let (mut ta, mut tf) = (Vec::new(), Vec::new());
    for r in 0..reps {
        let (p, n) = &copies[r % 16];
        let t = Instant::now();
        let mut a = Accumulator::with_kernel(kernel).threads(threads);
        a.add(black_box(p), black_box(n), None).unwrap_or_default();
        black_box(a.finish());
        ta.push(t.elapsed().as_secs_f64());
        let (p, n) = &copies[(r + 8) % 16];
        let t = Instant::now();
        black_box(floor(black_box(p), black_box(n)));
        tf.push(t.elapsed().as_secs_f64());
    }
    let (a, f) = (stats(ta), stats(tf));
    println!(
        "kernel {kernel:?}, threads {threads}, {reps} reps\nassembly per 1e6 points, cold: min {:.2} median {:.2} max {:.2} ms\nbandwidth floor (48 MB, 1 thread): min {:.2} median {:.2} max {:.2} ms\nmedian ratio {:.2}",
        a[0], a[1], a[2], f[0], f[1], f[2], a[1] / f[1]
    );
}
