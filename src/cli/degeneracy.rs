//! `audit degeneracy POINTS`: every detector family on the user's own points
//! with normals, optionally re-expressed in another body frame; JSON as in
//! DESIGN.md ("Degeneracy on the user's own points").
//!
//! Also holds the small helpers the detector commands share (output format,
//! `x,y,z` parsing, number formatting).

use crate::degeneracy::points::{accumulate_file, PointData};
use crate::degeneracy::threshold::default_threshold;
use crate::degeneracy::{analyse, reexpress, Analysis, Assembly, MetricRule, AXIS_NAMES};
use crate::diagnostic::{Error, ErrorKind, Result, Warning};
use crate::geometry::se3::Transform;
use crate::tolerances::DEFAULT_TAU;
use comfy_table::Table;
use serde_json::{json, Value};
use std::path::PathBuf;

/// `--format table|json`.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputFormat {
    Table,
    Json,
}

/// Parse `x,y,z` (three finite numbers).
pub fn parse_triple(s: &str, what: &str) -> Result<[f64; 3]> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(Error::usage(format!(
            "{what}: expected three comma-separated numbers x,y,z, found {s:?}"
        )));
    }
    let mut v = [0.0; 3];
    for (k, p) in parts.iter().enumerate() {
        v[k] = p
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| {
                Error::usage(format!("{what}: expected a finite number, found {p:?}"))
            })?;
    }
    Ok(v)
}

/// Parse a comma-separated list of positive lengths.
pub fn parse_ells(s: &str) -> Result<Vec<f64>> {
    s.split(',')
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .map(|p| {
            p.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite() && *x > 0.0)
                .ok_or_else(|| {
                    Error::usage(format!(
                        "--ell: expected positive lengths in metres, found {p:?}"
                    ))
                })
        })
        .collect()
}

/// One number for a table: fixed for ordinary magnitudes, scientific otherwise.
pub fn fmt_num(x: f64, prec: usize) -> String {
    let a = x.abs();
    if x == 0.0 || (0.1..1e4).contains(&a) {
        format!("{x:.prec$}")
    } else {
        format!("{x:.prec$e}")
    }
}

/// `[a b c]`.
pub fn fmt_vec(v: &[f64], prec: usize) -> String {
    let s: Vec<String> = v.iter().map(|&x| fmt_num(x, prec)).collect();
    format!("[{}]", s.join(" "))
}

/// Flagged axis names, or `none`.
pub fn fmt_bools(f: &[bool; 6]) -> String {
    let s: Vec<&str> = (0..6).filter(|&k| f[k]).map(|k| AXIS_NAMES[k]).collect();
    if s.is_empty() {
        "none".into()
    } else {
        s.join(" + ")
    }
}

pub(crate) fn io_err(e: std::io::Error) -> Error {
    Error::new(ErrorKind::Io, format!("cannot write output: {e}"))
}

#[derive(clap::Args, Debug, Clone)]
#[command(
    about = "Degeneracy of your own points with normals, for every detector family",
    long_about = "Reads points with unit normals (CSV x,y,z,nx,ny,nz[,w] with or without a header; \
PLY ascii/binary and PCD ascii/binary with normal fields) expressed in the body frame, optionally \
re-expresses them in another frame, and prints for every detector family the generalized \
eigenvalues of H v = lambda M v (ascending), the threshold and the number of eigenvalues below \
it; then the degenerate subspace under the point-displacement metric as screws (axis, pitch, \
axis point; or a translation direction) and its per-axis footprint, which depends on the frame.\n\n\
--shift x,y,z and --rotate-rpy r,p,y give the new frame's pose T = (R, d) in the input frame \
(R = Rz(y) Ry(p) Rx(r)), so p_new = R^T (p - d) and n_new = R^T n. The point-displacement \
eigenvalues do not change under either; the other families' may.\n\n\
--tau is the point-displacement threshold (dimensionless, default 1e-2). The baselines' \
eigenvalues are dimensioned and scale with the number of points, so each baseline uses the \
threshold `audit calibrate-threshold` finds for it on the synthetic corridors (paper's rule: \
the midpoint of its interval in the 0.10 m voxel, 0.01 m noise configuration); the JSON \
gives each family's threshold.\n\n\
Examples:\n  audit degeneracy scan.pcd\n  audit degeneracy scan.ply --shift 1,0,0 --format json\n  \
audit degeneracy points.csv --rotate-rpy 0,0,1.5708 --tau 0.005 --ell 0.5,2"
)]
pub struct DegeneracyArgs {
    /// Point file with normals (CSV, PLY or PCD; detected from the content).
    pub points: PathBuf,
    /// Point-displacement threshold: an eigenvalue below it is degenerate (baselines use their calibrated thresholds).
    #[arg(long, default_value_t = DEFAULT_TAU)]
    pub tau: f64,
    /// Origin of the new frame in the input frame, `x,y,z` (m).
    #[arg(long, allow_hyphen_values = true)]
    pub shift: Option<String>,
    /// Orientation of the new frame in the input frame, `roll,pitch,yaw` (rad).
    #[arg(long, allow_hyphen_values = true)]
    pub rotate_rpy: Option<String>,
    /// Characteristic lengths (m) for the characteristic-length family, comma-separated.
    #[arg(long, default_value = "0.25,1,2.85,10")]
    pub ell: String,
    /// Output format.
    #[arg(long, value_enum, default_value_t = OutputFormat::Table)]
    pub format: OutputFormat,
}

/// The frame the user asked for (identity without options).
pub fn frame_from_args(shift: Option<&str>, rpy: Option<&str>) -> Result<Transform> {
    let d = match shift {
        Some(s) => parse_triple(s, "--shift")?,
        None => [0.0; 3],
    };
    let r = match rpy {
        Some(s) => parse_triple(s, "--rotate-rpy")?,
        None => [0.0; 3],
    };
    Transform::from_rpy(r, d)
}

/// The report as JSON (DESIGN.md schema, plus `ell_m` on each family entry and
/// `warnings`).
pub fn degeneracy_json(
    data: &PointData,
    frame: &Transform,
    tau: f64,
    ells: &[f64],
) -> Result<Value> {
    let (p, n) = reexpress(&data.points, &data.normals, frame);
    let asm = Assembly::from_points(&p, &n, data.weights.as_deref())?;
    degeneracy_json_for(&asm, &data.warnings, frame, tau, ells)
}

/// The report for an assembly already in the requested frame.
pub fn degeneracy_json_for(
    asm: &Assembly,
    warnings: &[Warning],
    frame: &Transform,
    tau: f64,
    ells: &[f64],
) -> Result<Value> {
    if !(tau.is_finite() && tau > 0.0) {
        return Err(Error::usage(format!(
            "--tau: expected a positive number, found {tau}"
        )));
    }
    let asm = *asm;
    // Point displacement first: its error (collinear points) is the one to report.
    let pd = analyse(&asm, &MetricRule::PointDisplacement, tau)?;
    let mut families = Vec::new();
    for rule in MetricRule::default_set(ells, None) {
        let an: Analysis = if rule == MetricRule::PointDisplacement {
            pd.clone()
        } else {
            match analyse(&asm, &rule, default_threshold(&rule, tau)) {
                Ok(a) => a,
                Err(e) => {
                    families.push(json!({
                        "family": rule.family().name(),
                        "ell_m": rule.ell(&asm).filter(|x| x.is_finite()),
                        "eigenvalues": Value::Null,
                        "threshold": default_threshold(&rule, tau),
                        "degenerate_count": Value::Null,
                        "error": e.message,
                    }));
                    continue;
                }
            }
        };
        families.push(json!({
            "family": rule.family().name(),
            "ell_m": rule.ell(&asm),
            "eigenvalues": an.eig.values,
            "threshold": an.tau,
            "degenerate_count": an.degenerate_count,
        }));
    }
    let subspace: Vec<Value> = pd
        .subspace_screws(&asm.h)
        .into_iter()
        .map(|(q, s)| {
            let v3 = |v: Option<nalgebra::Vector3<f64>>| v.map(|v| [v.x, v.y, v.z]);
            json!({
                "eigenvalue": q,
                "twist": s.twist.as_slice(),
                "screw": {
                    "kind": s.kind,
                    "axis": v3(s.axis),
                    "pitch_m_per_rad": s.pitch,
                    "axis_point_m": v3(s.axis_point),
                    "direction": v3(s.direction),
                }
            })
        })
        .collect();
    let d = frame.translation();
    Ok(json!({
        "schema_version": 1,
        "points": asm.count,
        "frame": {"translation_m": [d.x, d.y, d.z], "rpy_rad": frame.rpy()},
        "families": families,
        "degenerate_subspace": subspace,
        "footprint": pd.footprint(),
        "warnings": warnings.iter().map(|w| w.to_string()).collect::<Vec<_>>(),
    }))
}

/// Render the JSON report as tables.
fn write_table(v: &Value, out: &mut dyn std::io::Write) -> Result<()> {
    let f = |x: &Value| {
        x.as_f64()
            .map(|x| fmt_num(x, 4))
            .unwrap_or_else(|| "-".into())
    };
    writeln!(
        out,
        "{} points; frame: translation {} m, rpy {} rad",
        v["points"], v["frame"]["translation_m"], v["frame"]["rpy_rad"]
    )
    .map_err(io_err)?;
    let mut t = Table::new();
    t.load_preset(comfy_table::presets::UTF8_FULL_CONDENSED);
    t.set_header(vec![
        "family",
        "l (m)",
        "eigenvalues (ascending)",
        "threshold",
        "degenerate",
    ]);
    for fam in v["families"].as_array().into_iter().flatten() {
        let eig = match fam["eigenvalues"].as_array() {
            Some(a) => format!("[{}]", a.iter().map(f).collect::<Vec<_>>().join(" ")),
            None => format!("error: {}", fam["error"].as_str().unwrap_or("")),
        };
        t.add_row(vec![
            fam["family"].as_str().unwrap_or("").to_string(),
            f(&fam["ell_m"]),
            eig,
            f(&fam["threshold"]),
            fam["degenerate_count"].to_string(),
        ]);
    }
    writeln!(out, "{t}").map_err(io_err)?;
    let sub = v["degenerate_subspace"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    if sub.is_empty() {
        writeln!(out, "Degenerate subspace (point displacement): none").map_err(io_err)?;
    } else {
        writeln!(
            out,
            "Degenerate subspace (point displacement), one screw per basis twist:"
        )
        .map_err(io_err)?;
        let mut t = Table::new();
        t.load_preset(comfy_table::presets::UTF8_FULL_CONDENSED);
        t.set_header(vec![
            "Rayleigh quotient",
            "twist [w; t]",
            "kind",
            "axis / direction",
            "pitch (m/rad)",
            "axis point (m)",
        ]);
        let arr = |x: &Value| match x.as_array() {
            Some(a) => format!(
                "[{}]",
                a.iter()
                    .map(|y| fmt_num(y.as_f64().unwrap_or(f64::NAN), 3))
                    .collect::<Vec<_>>()
                    .join(" ")
            ),
            None => "-".into(),
        };
        for s in &sub {
            let sc = &s["screw"];
            let dir = if sc["axis"].is_null() {
                arr(&sc["direction"])
            } else {
                arr(&sc["axis"])
            };
            t.add_row(vec![
                f(&s["eigenvalue"]),
                arr(&s["twist"]),
                sc["kind"].as_str().unwrap_or("").to_string(),
                dir,
                f(&sc["pitch_m_per_rad"]),
                arr(&sc["axis_point_m"]),
            ]);
        }
        writeln!(out, "{t}").map_err(io_err)?;
    }
    let mut fp = [false; 6];
    for (k, b) in v["footprint"]
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
        .take(6)
    {
        fp[k] = b.as_bool().unwrap_or(false);
    }
    writeln!(
        out,
        "Per-axis footprint (depends on the frame): {}",
        fmt_bools(&fp)
    )
    .map_err(io_err)?;
    for w in v["warnings"].as_array().into_iter().flatten() {
        writeln!(out, "{}", w.as_str().unwrap_or("")).map_err(io_err)?;
    }
    Ok(())
}

pub fn run(args: &DegeneracyArgs, out: &mut dyn std::io::Write) -> Result<i32, Error> {
    let frame = frame_from_args(args.shift.as_deref(), args.rotate_rpy.as_deref())?;
    let ells = parse_ells(&args.ell)?;
    // Streamed: H and M without holding the points; the frame by congruence.
    let acc = accumulate_file(&args.points, Some(&frame))?;
    let v = degeneracy_json_for(&acc.assembly, &acc.warnings, &frame, args.tau, &ells)
        .map_err(|e| e.in_file(&args.points))?;
    match args.format {
        OutputFormat::Json => {
            writeln!(
                out,
                "{}",
                serde_json::to_string_pretty(&v).unwrap_or_default()
            )
            .map_err(io_err)?;
        }
        OutputFormat::Table => write_table(&v, out)?,
    }
    Ok(0)
}
