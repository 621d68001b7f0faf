//! Reads a raw scan (any point format, LAS and LAZ included) the way
//! `audit degeneracy --estimate-normals` does, and prints its point count and
//! coordinate sums: the unit of the LAS/LAZ read benchmark
//! (`bench/las_read.sh`, paired with laspy).
//! `cargo run --release --example read_xyz -- FILE`

use extrinsic_audit::internals::degeneracy::points::read_xyz;

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: read_xyz FILE");
        std::process::exit(2);
    };
    match read_xyz(std::path::Path::new(&path)) {
        Ok(d) => {
            let s: Vec<f64> = (0..3)
                .map(|c| d.points.iter().map(|p| p[c]).sum())
                .collect();
            println!(
                "{} {} {:?} {:?} {:?}",
                d.format.name(),
                d.points.len(),
                s[0],
                s[1],
                s[2]
            );
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    }
}
