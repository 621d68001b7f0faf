//! Writes the benchmark cloud (`scene::random_cloud`'s data: seed 2024, points
//! uniform in [-10, 10]^3, unit normals uniform on the sphere) as a point file,
//! streamed so that 1e7 points need no memory:
//! `cargo run --release --example write_cloud -- OUT N [ply-le|ply-be|ply-ascii|pcd|pcd-ascii|csv|f64]`.
//!
//! `f64` writes the raw N x 6 little-endian doubles `bench/compare_numpy.py`
//! reads.

use extrinsic_audit::internals::degeneracy::scene::SceneRng;
use std::io::{BufWriter, Write};

fn header(kind: &str, n: usize) -> String {
    let ply = |fmt: &str| {
        format!("ply\nformat {fmt} 1.0\nelement vertex {n}\nproperty double x\nproperty double y\nproperty double z\nproperty double nx\nproperty double ny\nproperty double nz\nend_header\n")
    };
    let pcd = |data: &str| {
        format!("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 8 8 8 8 8 8\nTYPE F F F F F F\nCOUNT 1 1 1 1 1 1\nWIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA {data}\n")
    };
    match kind {
        "ply-le" => ply("binary_little_endian"),
        "ply-be" => ply("binary_big_endian"),
        "ply-ascii" => ply("ascii"),
        "pcd" => pcd("binary"),
        "pcd-ascii" => pcd("ascii"),
        "csv" => "x,y,z,nx,ny,nz\n".into(),
        _ => String::new(),
    }
}

fn main() -> std::io::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let (Some(out), Some(n)) = (
        args.get(1),
        args.get(2).and_then(|s| s.parse::<usize>().ok()),
    ) else {
        eprintln!("usage: write_cloud OUT N [ply-le|ply-be|ply-ascii|pcd|pcd-ascii|csv|f64]");
        std::process::exit(2);
    };
    let kind = args.get(3).map_or("ply-le", String::as_str);
    let mut w = BufWriter::with_capacity(1 << 20, std::fs::File::create(out)?);
    w.write_all(header(kind, n).as_bytes())?;
    let mut rng = SceneRng::new(2024);
    for _ in 0..n {
        // The same draws, in the same order, as `scene::random_cloud`.
        let p = [
            20.0 * rng.uniform() - 10.0,
            20.0 * rng.uniform() - 10.0,
            20.0 * rng.uniform() - 10.0,
        ];
        let u = rng.unit_vector();
        let v = [p[0], p[1], p[2], u.x, u.y, u.z];
        match kind {
            "ply-be" => v.iter().try_for_each(|x| w.write_all(&x.to_be_bytes()))?,
            "ply-ascii" | "pcd-ascii" => writeln!(
                w,
                "{:?} {:?} {:?} {:?} {:?} {:?}",
                v[0], v[1], v[2], v[3], v[4], v[5]
            )?,
            "csv" => writeln!(
                w,
                "{:?},{:?},{:?},{:?},{:?},{:?}",
                v[0], v[1], v[2], v[3], v[4], v[5]
            )?,
            _ => v.iter().try_for_each(|x| w.write_all(&x.to_le_bytes()))?,
        }
    }
    w.flush()
}
