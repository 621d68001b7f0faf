//! Run `audit calibrate-threshold` without the CLI front end (until it is wired):
//! `cargo run --release --example calibrate -- [SEEDS] [table|json] [NOISE,..] [VOXEL,..]`.
use extrinsic_audit::cli::calibrate_threshold::{run, CalibrateThresholdArgs};
use extrinsic_audit::cli::degeneracy::OutputFormat;

fn main() {
    let seeds = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(8);
    let json = std::env::args().nth(2).is_some_and(|s| s == "json");
    let args = CalibrateThresholdArgs {
        seeds,
        noise: std::env::args()
            .nth(3)
            .unwrap_or_else(|| "0,0.01,0.05".into()),
        voxel: std::env::args()
            .nth(4)
            .unwrap_or_else(|| "0.05,0.1,0.2".into()),
        ell: "0.25,1,2.85,10".into(),
        threads: 0,
        format: if json {
            OutputFormat::Json
        } else {
            OutputFormat::Table
        },
    };
    let t = std::time::Instant::now();
    let mut out = std::io::stdout();
    match run(&args, &mut out) {
        Ok(_) => eprintln!("elapsed {:.2} s", t.elapsed().as_secs_f64()),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    }
}
