//! `audit tunnel`: the paper's noise-free circular-tunnel example.
//!
//! A tunnel of radius 2.85 m about the z axis with exact radial normals. With
//! the body origin on the axis the degenerate subspace (point-displacement
//! metric, `lambda < tau`) is rotation about z plus translation along z; its
//! rotational twist is `[0 0 1 0 0 0]`. Re-expressed in a frame one metre off
//! the axis (`--shift 1,0,0`) the subspace is still two-dimensional and the
//! eigenvalues are identical, but the rotational twist reads `[0 0 1 0 1 0]`
//! and the per-axis footprint gains trans-y: the footprint is frame-dependent.

use super::degeneracy::{fmt_bools, fmt_vec, parse_triple, OutputFormat};
use crate::degeneracy::scene::{tunnel_exact, TUNNEL_RADIUS};
use crate::degeneracy::{
    analyse, canonical_basis, check_transport, reexpress, rel_diff, Analysis, Assembly, MetricRule,
};
use crate::diagnostic::{Error, Result};
use crate::geometry::se3::Transform;
use crate::tolerances::DEFAULT_TAU;
use comfy_table::Table;
use nalgebra::{DMatrix, Vector6};
use serde_json::json;

#[derive(clap::Args, Debug, Clone)]
#[command(
    about = "Reproduce the paper's circular-tunnel example (footprint changes, eigenvalues do not)",
    long_about = "Builds a noise-free circular tunnel (radius 2.85 m about z, exact radial \
normals), solves H v = lambda M v with the point-displacement metric with the body origin \
on the axis and again in a frame shifted off the axis, and prints the eigenvalues, the \
nullity, the per-axis footprint of the degenerate subspace (frame-dependent) and the \
rotational degenerate twist as a coordinate tuple.\n\n\
Expected: on the axis the rotational twist is [0 0 1 0 0 0] and the footprint rot-z + \
trans-z; one metre off the axis the twist is [0 0 1 0 1 0] and the footprint rot-z + \
trans-y + trans-z; nullity 2 in both; identical eigenvalues.\n\n\
Examples:\n  audit tunnel\n  audit tunnel --shift 0,2,0 --format json\n  \
audit tunnel --radius 1.5 --length 30"
)]
pub struct TunnelArgs {
    /// Tunnel radius (m).
    #[arg(long, default_value_t = TUNNEL_RADIUS)]
    pub radius: f64,
    /// Tunnel length along z (m), centred on the origin.
    #[arg(long, default_value_t = 20.0)]
    pub length: f64,
    /// Distance between rings of points along the axis (m).
    #[arg(long, default_value_t = 0.1)]
    pub ring_spacing: f64,
    /// Points per ring (equally spaced in angle).
    #[arg(long, default_value_t = 360)]
    pub points_per_ring: usize,
    /// Origin of the second frame in the first, `x,y,z` (m); no rotation.
    #[arg(long, default_value = "1,0,0", allow_hyphen_values = true)]
    pub shift: String,
    /// Degeneracy threshold on the point-displacement eigenvalues.
    #[arg(long, default_value_t = DEFAULT_TAU)]
    pub tau: f64,
    /// Output format.
    #[arg(long, value_enum, default_value_t = OutputFormat::Table)]
    pub format: OutputFormat,
}

/// One frame's view of the tunnel.
#[derive(Debug, Clone, PartialEq)]
pub struct TunnelFrame {
    pub shift: [f64; 3],
    pub eigenvalues: [f64; 6],
    pub nullity: usize,
    pub footprint: [bool; 6],
    /// The rotational degenerate twists (canonical basis, `|omega| = 1`).
    pub rotational_twists: Vec<Vector6<f64>>,
    /// Whether the degenerate subspace contains a twist with zero translation.
    pub contains_pure_rotation: bool,
}

/// The whole example.
#[derive(Debug, Clone, PartialEq)]
pub struct TunnelResult {
    pub points: usize,
    pub on_axis: TunnelFrame,
    pub shifted: TunnelFrame,
    /// `max_k |lambda_k - lambda'_k|`.
    pub eigenvalue_max_abs_diff: f64,
    /// Angle (deg) between the two rotational-twist coordinate tuples.
    pub tuple_angle_deg: Option<f64>,
    /// Largest principal angle between the on-axis subspace and the shifted one
    /// transported back (`v = A v'`), in degrees.
    pub transported_subspace_angle_deg: Option<f64>,
    /// Congruence `A^T H A`, `A^T M A` against reassembly from shifted points.
    pub congruence_rel_diff_h: f64,
    pub congruence_rel_diff_m: f64,
}

fn frame_view(an: &Analysis, shift: [f64; 3]) -> TunnelFrame {
    let basis = canonical_basis(&an.degenerate_vectors());
    let rotational_twists: Vec<Vector6<f64>> = basis
        .iter()
        .filter(|v| v.fixed_rows::<3>(0).norm() > 0.0)
        .copied()
        .collect();
    TunnelFrame {
        shift,
        eigenvalues: an.eig.values,
        nullity: an.degenerate_count,
        footprint: an.footprint(),
        rotational_twists,
        contains_pure_rotation: contains_pure_rotation(&an.degenerate_vectors()),
    }
}

/// Whether some non-zero twist in the span has zero translational part: the
/// translational block of an orthonormal basis is rank-deficient.
pub fn contains_pure_rotation(vs: &[Vector6<f64>]) -> bool {
    if vs.is_empty() {
        return false;
    }
    let m = DMatrix::from_fn(6, vs.len(), |i, j| vs[j][i]);
    let q = m.qr().q();
    let t = q.rows(3, 3).into_owned();
    let sv = t.svd(false, false).singular_values;
    // A 3 x k block with k > 3 always has a null vector.
    vs.len() > 3 || sv.iter().any(|&s| s <= 1e-6)
}

/// Compute the example (the testable core of `run`).
pub fn tunnel_example(args: &TunnelArgs) -> Result<TunnelResult> {
    for (name, v) in [
        ("radius", args.radius),
        ("length", args.length),
        ("ring spacing", args.ring_spacing),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::usage(format!(
                "--{name}: expected a positive number of metres, found {v}"
            )));
        }
    }
    if args.points_per_ring < 3 || args.points_per_ring > 100_000 {
        return Err(Error::usage(format!(
            "--points-per-ring: expected 3 to 100000, found {}",
            args.points_per_ring
        )));
    }
    let rings = args.length / args.ring_spacing;
    if rings * args.points_per_ring as f64 > 2e7 {
        return Err(Error::limit(
            "tunnel would have more than 2e7 points: increase --ring-spacing",
        ));
    }
    let shift = parse_triple(&args.shift, "--shift")?;
    let cloud = tunnel_exact(
        args.radius,
        args.length,
        args.ring_spacing,
        args.points_per_ring,
    );
    let asm = Assembly::from_points(&cloud.points, &cloud.normals, None)?;
    let t = Transform::from_translation(shift)?;
    let (p2, n2) = reexpress(&cloud.points, &cloud.normals, &t);
    let asm2 = Assembly::from_points(&p2, &n2, None)?;
    let a = t.adjoint();
    let cong = asm.congruence(&a);
    let an1 = analyse(&asm, &MetricRule::PointDisplacement, args.tau)?;
    let an2 = analyse(&asm2, &MetricRule::PointDisplacement, args.tau)?;
    let f1 = frame_view(&an1, [0.0; 3]);
    let f2 = frame_view(&an2, shift);
    let eigenvalue_max_abs_diff = (0..6)
        .map(|k| (f1.eigenvalues[k] - f2.eigenvalues[k]).abs())
        .fold(0.0, f64::max);
    let tuple_angle_deg = match (f1.rotational_twists.first(), f2.rotational_twists.first()) {
        (Some(x), Some(y)) => {
            let c = (x.dot(y) / (x.norm() * y.norm())).clamp(-1.0, 1.0);
            Some(c.acos().to_degrees())
        }
        _ => None,
    };
    let tc = check_transport(&an1, &an2, &a);
    Ok(TunnelResult {
        points: cloud.len(),
        on_axis: f1,
        shifted: f2,
        eigenvalue_max_abs_diff,
        tuple_angle_deg,
        transported_subspace_angle_deg: tc.subspace_angle.map(f64::to_degrees),
        congruence_rel_diff_h: rel_diff(&cong.h, &asm2.h),
        congruence_rel_diff_m: rel_diff(&cong.m, &asm2.m),
    })
}

/// Round tiny rounding noise away for display (`|x| < 1e-12` prints as 0).
fn clean(v: &Vector6<f64>) -> Vec<f64> {
    v.iter()
        .map(|&x| if x.abs() < 1e-12 { 0.0 } else { x })
        .collect()
}

fn frame_json(f: &TunnelFrame) -> serde_json::Value {
    json!({
        "origin_m": f.shift,
        "eigenvalues": f.eigenvalues,
        "nullity": f.nullity,
        "footprint": f.footprint,
        "footprint_frame_dependent": true,
        "rotational_twists": f.rotational_twists.iter().map(clean).collect::<Vec<_>>(),
        "contains_pure_rotation": f.contains_pure_rotation,
    })
}

pub fn run(args: &TunnelArgs, out: &mut dyn std::io::Write) -> Result<i32, Error> {
    let r = tunnel_example(args)?;
    let io = |e: std::io::Error| {
        Error::new(
            crate::diagnostic::ErrorKind::Io,
            format!("cannot write output: {e}"),
        )
    };
    match args.format {
        OutputFormat::Json => {
            let v = json!({
                "radius_m": args.radius,
                "points": r.points,
                "tau": args.tau,
                "metric": "point_displacement",
                "on_axis": frame_json(&r.on_axis),
                "shifted": frame_json(&r.shifted),
                "eigenvalue_max_abs_diff": r.eigenvalue_max_abs_diff,
                "rotational_tuple_angle_deg": r.tuple_angle_deg,
                "transported_subspace_angle_deg": r.transported_subspace_angle_deg,
                "congruence_rel_diff": {"h": r.congruence_rel_diff_h, "m": r.congruence_rel_diff_m},
            });
            writeln!(
                out,
                "{}",
                serde_json::to_string_pretty(&v).unwrap_or_default()
            )
            .map_err(io)?;
        }
        OutputFormat::Table => {
            writeln!(
                out,
                "Circular tunnel, radius {} m about z, {} points, exact radial normals, no noise.\nPoint-displacement metric, tau = {}.",
                args.radius, r.points, args.tau
            )
            .map_err(io)?;
            let mut t = Table::new();
            t.load_preset(comfy_table::presets::UTF8_FULL_CONDENSED);
            t.set_header(vec!["quantity", "origin on the axis", "origin at shift"]);
            let f1 = &r.on_axis;
            let f2 = &r.shifted;
            t.add_row(vec![
                "origin (m)".to_string(),
                fmt_vec(&f1.shift, 3),
                fmt_vec(&f2.shift, 3),
            ]);
            t.add_row(vec![
                "eigenvalues".to_string(),
                fmt_vec(&f1.eigenvalues, 4),
                fmt_vec(&f2.eigenvalues, 4),
            ]);
            t.add_row(vec![
                "nullity (lambda < tau)".to_string(),
                f1.nullity.to_string(),
                f2.nullity.to_string(),
            ]);
            let tw = |f: &TunnelFrame| {
                f.rotational_twists
                    .iter()
                    .map(|v| fmt_vec(&clean(v), 3))
                    .collect::<Vec<_>>()
                    .join(" ")
            };
            t.add_row(vec![
                "rotational degenerate twist [w; t]".to_string(),
                tw(f1),
                tw(f2),
            ]);
            t.add_row(vec![
                "subspace contains a pure rotation".to_string(),
                f1.contains_pure_rotation.to_string(),
                f2.contains_pure_rotation.to_string(),
            ]);
            t.add_row(vec![
                "footprint (frame-dependent)".to_string(),
                fmt_bools(&f1.footprint),
                fmt_bools(&f2.footprint),
            ]);
            writeln!(out, "{t}").map_err(io)?;
            writeln!(
                out,
                "max |lambda - lambda'|: {:.3e}",
                r.eigenvalue_max_abs_diff
            )
            .map_err(io)?;
            if let Some(a) = r.tuple_angle_deg {
                writeln!(
                    out,
                    "angle between the two twist tuples: {a:.2} deg (a coordinate diagnostic)"
                )
                .map_err(io)?;
            }
            if let Some(a) = r.transported_subspace_angle_deg {
                writeln!(out, "subspace angle after transport v = A v': {a:.3e} deg")
                    .map_err(io)?;
            }
            writeln!(
                out,
                "congruence A^T H A / A^T M A vs reassembly: {:.2e} / {:.2e} (relative)",
                r.congruence_rel_diff_h, r.congruence_rel_diff_m
            )
            .map_err(io)?;
        }
    }
    Ok(0)
}
