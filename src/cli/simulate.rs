//! `audit simulate FILE... --from A --to B`: a synthetic scene seen from both
//! frames of the user's rig, every detector family side by side.
//!
//! The scene is built about the origin of frame `A` (the body), re-expressed in
//! frame `B` with the rig's `T = (R, d)` (pose of `B` in `A`: `p_B = R^T (p_A - d)`,
//! `n_B = R^T n_A`) and reassembled there. For each family: the eigenvalues in
//! both frames, whether the binary decision changes, the degenerate count, the
//! footprint in both frames, the angle between the degenerate subspaces after
//! transport (`v = A v'`) and the difference between the two frames' applied
//! corrections `Delta = (P_A - Ad P_B Ad^-1) xi` for one update `xi`.

use super::degeneracy::{
    fmt_bools, fmt_num, fmt_vec, frame_from_args, io_err, parse_ells, OutputFormat,
};
use crate::analysis::metric::adapted_metric_matrix;
use crate::degeneracy::scene::{synthesize, Preprocess, SceneKind};
use crate::degeneracy::threshold::default_threshold;
use crate::degeneracy::{
    analyse, check_transport, correction_difference, reexpress, Assembly, MetricRule,
};
use crate::diagnostic::{Error, Result};
use crate::formats::{load_file, LoadOptions};
use crate::frames::FrameGraph;
use crate::geometry::se3::Transform;
use crate::tolerances::{DEFAULT_PITCH_TOL, DEFAULT_TAU};
use comfy_table::Table;
use nalgebra::Vector6;
use serde_json::{json, Value};
use std::path::PathBuf;

#[derive(clap::Args, Debug, Clone)]
#[command(
    about = "Show what your rig's extrinsic does to each detector on a synthetic scene",
    long_about = "Builds a synthetic scene (circular tunnel, rectangular corridor or right-angle \
corner; see `audit calibrate-threshold --help` for the geometry) about the origin of frame --from, \
expresses it in both frames of your rig (the transform from --from to --to composed from FILE...), \
and prints, for every detector family, the generalized eigenvalues in both frames, whether the \
degeneracy decision changes, the degenerate count, the per-axis footprint in both frames, the \
largest principal angle between the degenerate subspaces after transport v = Ad(T) v', and the \
difference between the corrections a remapping estimator applies in the two frames, \
Delta = (P_A - Ad(T) P_B Ad(T)^-1) xi, for the update --update.\n\n\
The scene goes through the paper's pipeline (range noise, voxel grid with a random origin, PCA \
normals within 0.30 m from at least 8 neighbours) unless --exact-normals is given.\n\n\
Without FILE, --shift and --rotate-rpy give the pose of frame B in frame A directly.\n\n\
Examples:\n  audit simulate robot.urdf --from base_link --to velodyne\n  \
audit simulate fastlio.yaml --from imu --to lidar --scene corridor --noise 0.01 --seed 3\n  \
audit simulate --shift 0.3,0,0.2 --rotate-rpy 0,0,1.57 --scene tunnel --format json"
)]
pub struct SimulateArgs {
    /// Calibration files that define the frames (URDF, TF, LIO YAML, ...).
    pub files: Vec<PathBuf>,
    /// Body frame (the scene is built about its origin).
    #[arg(long)]
    pub from: Option<String>,
    /// Sensor frame.
    #[arg(long)]
    pub to: Option<String>,
    /// Without FILE: origin of frame B in frame A, `x,y,z` (m).
    #[arg(long, allow_hyphen_values = true)]
    pub shift: Option<String>,
    /// Without FILE: orientation of frame B in frame A, `roll,pitch,yaw` (rad).
    #[arg(long, allow_hyphen_values = true)]
    pub rotate_rpy: Option<String>,
    /// Scene: tunnel (2 degenerate directions), corridor (1) or corner (0).
    #[arg(long, default_value = "tunnel")]
    pub scene: String,
    /// Range-noise standard deviation (m).
    #[arg(long, default_value_t = 0.0)]
    pub noise: f64,
    /// Seed of the scene (sampling phase, noise, voxel grid origin).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Voxel size (m) of the preprocessing pipeline.
    #[arg(long, default_value_t = 0.1)]
    pub voxel: f64,
    /// Keep the exact surface normals (no voxel grid, no normal estimation).
    #[arg(long)]
    pub exact_normals: bool,
    /// Point-displacement threshold (baselines use their calibrated thresholds, see `audit degeneracy --help`).
    #[arg(long, default_value_t = DEFAULT_TAU)]
    pub tau: f64,
    /// Characteristic lengths (m), comma-separated.
    #[arg(long, default_value = "0.25,1,2.85,10")]
    pub ell: String,
    /// Pose update xi = `wx,wy,wz,tx,ty,tz` in frame A (rad, m) for the correction difference.
    #[arg(
        long,
        default_value = "0.01,-0.02,0.015,0.05,0.03,-0.04",
        allow_hyphen_values = true
    )]
    pub update: String,
    /// Output format.
    #[arg(long, value_enum, default_value_t = OutputFormat::Table)]
    pub format: OutputFormat,
}

/// One family's comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct FamilyComparison {
    pub rule: MetricRule,
    /// Threshold used for this family.
    pub threshold: f64,
    pub ell: [Option<f64>; 2],
    pub eigenvalues: [[f64; 6]; 2],
    pub counts: [usize; 2],
    pub decision_changes: bool,
    pub footprints: [[bool; 6]; 2],
    /// Largest principal angle (deg) after transport; `None` when counts differ
    /// or nothing is degenerate.
    pub subspace_angle_deg: Option<f64>,
    /// `Delta` (frame A): rotational and translational norms.
    pub delta_rot_rad: f64,
    pub delta_trans_m: f64,
    pub max_eigenvalue_rel_change: f64,
}

/// Everything `simulate` prints.
#[derive(Debug, Clone, PartialEq)]
pub struct Simulation {
    pub scene: SceneKind,
    pub points: usize,
    pub transform: Transform,
    pub rows: Vec<FamilyComparison>,
}

fn parse_update(s: &str) -> Result<Vector6<f64>> {
    let v: Vec<f64> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect::<Option<Vec<f64>>>()
        .ok_or_else(|| Error::usage(format!("--update: expected six numbers, found {s:?}")))?;
    if v.len() != 6 {
        return Err(Error::usage(format!(
            "--update: expected six numbers wx,wy,wz,tx,ty,tz, found {}",
            v.len()
        )));
    }
    Ok(Vector6::from_column_slice(&v))
}

/// The testable core: simulate for a given `T` (pose of B in A).
pub fn simulate(args: &SimulateArgs, t: &Transform) -> Result<Simulation> {
    let kind = SceneKind::parse(&args.scene).ok_or_else(|| {
        Error::usage(format!(
            "--scene: expected tunnel, corridor or corner, found {:?}",
            args.scene
        ))
    })?;
    if !(args.tau.is_finite() && args.tau > 0.0) {
        return Err(Error::usage(format!(
            "--tau: expected a positive number, found {}",
            args.tau
        )));
    }
    let ells = parse_ells(&args.ell)?;
    let xi = parse_update(&args.update)?;
    let pre = if args.exact_normals {
        Preprocess::exact(0.05, args.noise, args.seed)
    } else {
        if !(args.voxel.is_finite() && args.voxel >= 0.02) {
            return Err(Error::usage(format!(
                "--voxel: expected at least 0.02 m, found {}",
                args.voxel
            )));
        }
        Preprocess::pipeline(args.voxel, args.noise, args.seed)
    };
    let cloud = synthesize(kind, &pre)?;
    let asm_a = Assembly::from_points(&cloud.points, &cloud.normals, None)?;
    let (pb, nb) = reexpress(&cloud.points, &cloud.normals, t);
    let asm_b = Assembly::from_points(&pb, &nb, None)?;
    let a = t.adjoint();
    let a_inv = t.adjoint_inverse();
    let rules = MetricRule::default_set(&ells, adapted_metric_matrix(t, DEFAULT_PITCH_TOL));
    let mut rows = Vec::new();
    for rule in rules {
        let tau = default_threshold(&rule, args.tau);
        let an_a = analyse(&asm_a, &rule, tau)?;
        let an_b = analyse(&asm_b, &rule, tau)?;
        let tc = check_transport(&an_a, &an_b, &a);
        let delta = correction_difference(&an_a, &an_b, &a, &a_inv, &xi);
        let max_rel = (0..6)
            .map(|k| {
                (an_a.eig.values[k] - an_b.eig.values[k]).abs()
                    / an_a.eig.values[k].abs().max(1e-12)
            })
            .fold(0.0, f64::max);
        rows.push(FamilyComparison {
            threshold: tau,
            ell: [rule.ell(&asm_a), rule.ell(&asm_b)],
            eigenvalues: [an_a.eig.values, an_b.eig.values],
            counts: [an_a.degenerate_count, an_b.degenerate_count],
            decision_changes: an_a.degenerate() != an_b.degenerate(),
            footprints: [an_a.footprint(), an_b.footprint()],
            subspace_angle_deg: tc.subspace_angle.map(f64::to_degrees),
            delta_rot_rad: delta.fixed_rows::<3>(0).norm(),
            delta_trans_m: delta.fixed_rows::<3>(3).norm(),
            max_eigenvalue_rel_change: max_rel,
            rule,
        });
    }
    Ok(Simulation {
        scene: kind,
        points: cloud.len(),
        transform: *t,
        rows,
    })
}

/// Compose `T_from_to` from the files (thin glue over `formats` and `graph`).
fn load_transform(args: &SimulateArgs) -> Result<Transform> {
    if args.files.is_empty() {
        if args.shift.is_none() && args.rotate_rpy.is_none() {
            return Err(Error::usage(
                "expected calibration FILE... with --from/--to, or --shift/--rotate-rpy",
            ));
        }
        return frame_from_args(args.shift.as_deref(), args.rotate_rpy.as_deref());
    }
    if args.shift.is_some() || args.rotate_rpy.is_some() {
        return Err(Error::usage("--shift/--rotate-rpy apply only without FILE"));
    }
    let opts = LoadOptions::default();
    let mut g = FrameGraph::new();
    for f in &args.files {
        g.add(load_file(f, &opts)?)?;
    }
    let (from, to) = match (&args.from, &args.to) {
        (Some(a), Some(b)) => (a.clone(), b.clone()),
        (None, None) if g.edges().len() == 1 => {
            (g.edges()[0].parent.clone(), g.edges()[0].child.clone())
        }
        _ => {
            return Err(Error::usage(format!(
                "expected --from and --to (frames: {})",
                g.frames().join(", ")
            )))
        }
    };
    Ok(g.transform(&from, &to)?.transform)
}

fn to_json(s: &Simulation, args: &SimulateArgs) -> Value {
    let d = s.transform.translation();
    json!({
        "scene": s.scene.name(),
        "points": s.points,
        "noise_m": args.noise,
        "seed": args.seed,
        "tau": args.tau,
        "transform": {"translation_m": [d.x, d.y, d.z], "rpy_rad": s.transform.rpy()},
        "families": s.rows.iter().map(|r| json!({
            "family": r.rule.family().name(),
            "ell_m": r.ell,
            "threshold": r.threshold,
            "eigenvalues": {"from": r.eigenvalues[0], "to": r.eigenvalues[1]},
            "degenerate_count": {"from": r.counts[0], "to": r.counts[1]},
            "decision_changes": r.decision_changes,
            "footprint": {"from": r.footprints[0], "to": r.footprints[1]},
            "footprint_changes": r.footprints[0] != r.footprints[1],
            "subspace_angle_deg": r.subspace_angle_deg,
            "correction_difference": {"rotation_rad": r.delta_rot_rad, "translation_m": r.delta_trans_m},
            "max_eigenvalue_rel_change": r.max_eigenvalue_rel_change,
        })).collect::<Vec<_>>(),
    })
}

pub fn run(args: &SimulateArgs, out: &mut dyn std::io::Write) -> Result<i32, Error> {
    let t = load_transform(args)?;
    let s = simulate(args, &t)?;
    match args.format {
        OutputFormat::Json => {
            writeln!(
                out,
                "{}",
                serde_json::to_string_pretty(&to_json(&s, args)).unwrap_or_default()
            )
            .map_err(io_err)?;
        }
        OutputFormat::Table => {
            let d = t.translation();
            writeln!(
                out,
                "Scene {} ({} points, noise {} m, seed {}), built in frame A; frame B at translation {} m, rpy {} rad (lever arm {:.4} m). point-displacement tau = {}.",
                s.scene.name(),
                s.points,
                args.noise,
                args.seed,
                fmt_vec(&[d.x, d.y, d.z], 4),
                fmt_vec(&t.rpy(), 4),
                t.lever_arm(),
                args.tau
            )
            .map_err(io_err)?;
            let mut tb = Table::new();
            tb.load_preset(comfy_table::presets::UTF8_FULL_CONDENSED);
            tb.set_header(vec![
                "family",
                "threshold",
                "eigenvalues A / B",
                "decision",
                "count A -> B",
                "footprint A / B (frame-dependent)",
                "subspace angle (deg)",
                "|Delta| rot (rad) / trans (m)",
            ]);
            for r in &s.rows {
                tb.add_row(vec![
                    r.rule.label(),
                    fmt_num(r.threshold, 3),
                    format!(
                        "{}\n{}",
                        fmt_vec(&r.eigenvalues[0], 4),
                        fmt_vec(&r.eigenvalues[1], 4)
                    ),
                    if r.decision_changes {
                        "CHANGES".into()
                    } else {
                        "same".into()
                    },
                    format!("{} -> {}", r.counts[0], r.counts[1]),
                    format!(
                        "{}\n{}{}",
                        fmt_bools(&r.footprints[0]),
                        fmt_bools(&r.footprints[1]),
                        if r.footprints[0] != r.footprints[1] {
                            " (changed)"
                        } else {
                            ""
                        }
                    ),
                    r.subspace_angle_deg
                        .map_or("-".into(), |a| format!("{a:.3e}")),
                    format!("{:.3e} / {:.3e}", r.delta_rot_rad, r.delta_trans_m),
                ]);
            }
            writeln!(out, "{tb}").map_err(io_err)?;
        }
    }
    Ok(0)
}
