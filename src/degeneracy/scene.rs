//! Synthetic scenes, seeded and deterministic: circular tunnel, straight
//! rectangular corridor, right-angle corner; range noise, voxel downsampling with
//! a randomised grid origin, PCA normals within a fixed radius.
//!
//! # Geometry (all axes and sizes in metres, sensor at the origin)
//!
//! - Circular tunnel: radius [`TUNNEL_RADIUS`] = 2.85 m about the z axis,
//!   `z` in `[-L/2, L/2]` with `L` = [`SCENE_LENGTH`] = 12 m; normals point at
//!   the axis. Analytic degenerate set: translation along z, rotation about z (2).
//! - Rectangular corridor: axis z, cross-section `x` in `[-1.5, 1.5]`,
//!   `y` in `[-1.0, 1.5]` (a 3.0 m x 2.5 m rectangle, deliberately not centred
//!   and not square), same length; four walls. Analytic: translation along z (1).
//! - Right-angle corner: an L-shaped corridor of the same cross-section: one leg
//!   along z (`z` from `-L/2` to the corner), one along x (`x` from the corner to
//!   `L/2`), joined at the origin; floor, ceiling (L-shaped) and four walls, the
//!   far ends open. Analytic: nothing degenerate (0).
//!
//! Surfaces are sampled on a regular grid of a given spacing with a seeded
//! random phase per surface. Normals of sampled scenes are exact; the
//! preprocessing pipeline ([`synthesize`]) replaces them by PCA normals
//! estimated from the (noisy, downsampled) points.
//!
//! The PRNG is PCG64 (`rand_pcg::Pcg64`, the PCG XSL-RR 128/64 generator, a
//! documented algorithm with a fixed output for a given seed on every platform);
//! uniform doubles take the top 53 bits; normal deviates use Box-Muller.

use super::cells::{floor_i64, order_by_key};
use crate::diagnostic::{Error, Result};
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use nalgebra::{Matrix3, Matrix6, SymmetricEigen, UnitQuaternion, Vector3};
use rand_core::{RngCore, SeedableRng};
use std::f64::consts::PI;

/// Radius of the circular tunnel (m), the paper's example.
pub const TUNNEL_RADIUS: f64 = 2.85;
/// Length of the straight scenes and twice the leg length of the corner (m).
pub const SCENE_LENGTH: f64 = 12.0;
/// Half width of the rectangular cross-section (m), `x` in `[-1.5, 1.5]`.
pub const CORRIDOR_HALF_WIDTH: f64 = 1.5;
/// Floor and ceiling of the rectangular cross-section (m), `y` in `[-1.0, 1.5]`.
pub const CORRIDOR_Y: (f64, f64) = (-1.0, 1.5);
/// Normal-estimation radius (m), the paper's.
pub const NORMAL_RADIUS: f64 = 0.30;
/// Minimum neighbourhood (points within the radius, the point itself included)
/// for a normal; points with fewer are dropped.
pub const MIN_NEIGHBOURS: usize = 8;
/// Largest number of points a synthetic scene may be sampled with (a guard
/// against a tiny spacing).
pub const MAX_SCENE_POINTS: usize = 20_000_000;

/// Seeded PRNG (PCG64) with the few distributions the scenes need.
#[derive(Debug, Clone)]
pub struct SceneRng(rand_pcg::Pcg64);

impl SceneRng {
    /// A generator seeded with `seed` (`Pcg64::seed_from_u64`): the same seed
    /// gives the same stream on every platform.
    pub fn new(seed: u64) -> Self {
        SceneRng(rand_pcg::Pcg64::seed_from_u64(seed))
    }
    /// Uniform in `[0, 1)`.
    pub fn uniform(&mut self) -> f64 {
        (self.0.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Standard normal (Box-Muller; one deviate per call).
    pub fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform(); // (0, 1]
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
    }
    /// Uniform direction on the sphere.
    pub fn unit_vector(&mut self) -> Vector3<f64> {
        loop {
            let v = Vector3::new(self.normal(), self.normal(), self.normal());
            let n = v.norm();
            if n > 1e-9 {
                return v / n;
            }
        }
    }
    /// Uniform rotation (normalised Gaussian quaternion).
    pub fn rotation(&mut self) -> Matrix3<f64> {
        loop {
            let q = nalgebra::Quaternion::new(
                self.normal(),
                self.normal(),
                self.normal(),
                self.normal(),
            );
            if q.norm() > 1e-9 {
                return *UnitQuaternion::from_quaternion(q)
                    .to_rotation_matrix()
                    .matrix();
            }
        }
    }
    /// Random orthogonal 6x6 matrix (QR of a Gaussian matrix, signs fixed so the
    /// distribution is Haar).
    pub fn orthogonal6(&mut self) -> Matrix6<f64> {
        let g = Matrix6::from_fn(|_, _| self.normal());
        let qr = g.qr();
        let mut q = qr.q();
        let r = qr.r();
        for k in 0..6 {
            if r[(k, k)] < 0.0 {
                for i in 0..6 {
                    q[(i, k)] = -q[(i, k)];
                }
            }
        }
        q
    }
}

/// Points with unit normals.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Cloud {
    /// Point positions `[x, y, z]` (m) in the sensor frame.
    pub points: Vec<[f64; 3]>,
    /// Unit normal of each point, same index as `points`.
    pub normals: Vec<[f64; 3]>,
}

impl Cloud {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }
    /// No points.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
}

/// The three synthetic scenes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SceneKind {
    /// Circular tunnel about z (two degenerate directions).
    Tunnel,
    /// Rectangular corridor along z (one degenerate direction).
    Corridor,
    /// Right-angle corner (none).
    Corner,
}

impl SceneKind {
    /// Every scene, in the order the threshold sweep visits them.
    pub const ALL: [SceneKind; 3] = [SceneKind::Corridor, SceneKind::Tunnel, SceneKind::Corner];
    /// The name on the command line and in reports (`tunnel`, `corridor`,
    /// `corner`).
    pub fn name(self) -> &'static str {
        match self {
            SceneKind::Tunnel => "tunnel",
            SceneKind::Corridor => "corridor",
            SceneKind::Corner => "corner",
        }
    }
    /// The number of degenerate directions the geometry implies.
    pub fn analytic_count(self) -> usize {
        match self {
            SceneKind::Tunnel => 2,
            SceneKind::Corridor => 1,
            SceneKind::Corner => 0,
        }
    }
    /// The scene called `s` ([`Self::name`]); `None` for any other string.
    pub fn parse(s: &str) -> Option<SceneKind> {
        match s {
            "tunnel" => Some(SceneKind::Tunnel),
            "corridor" => Some(SceneKind::Corridor),
            "corner" => Some(SceneKind::Corner),
            _ => None,
        }
    }
}

/// The noise-free circular tunnel of the paper's example: rings every
/// `ring_spacing` m along z over `length`, `n_theta` equally spaced points per
/// ring, exact radial normals pointing at the axis.
pub fn tunnel_exact(radius: f64, length: f64, ring_spacing: f64, n_theta: usize) -> Cloud {
    let n_rings = (length / ring_spacing).round() as usize + 1;
    let mut c = Cloud::default();
    for r in 0..n_rings {
        let z = -0.5 * length + r as f64 * ring_spacing;
        for k in 0..n_theta {
            let th = 2.0 * PI * k as f64 / n_theta as f64;
            let (s, co) = th.sin_cos();
            c.points.push([radius * co, radius * s, z]);
            c.normals.push([-co, -s, 0.0]);
        }
    }
    c
}

fn check_spacing(spacing: f64) -> Result<()> {
    if !(spacing.is_finite() && spacing > 0.0) {
        return Err(Error::usage(format!(
            "sampling spacing: expected a positive number of metres, found {spacing}"
        )));
    }
    Ok(())
}

/// Sample a rectangle `origin + u e1 + v e2`, `u` in `[0, lu]`, `v` in `[0, lv]`,
/// on a grid of `spacing` with phase `(pu, pv)` in `[0, spacing)`, keeping the
/// samples `keep` accepts.
#[allow(clippy::too_many_arguments)]
fn sample_rect(
    c: &mut Cloud,
    origin: Vector3<f64>,
    e1: Vector3<f64>,
    lu: f64,
    e2: Vector3<f64>,
    lv: f64,
    normal: Vector3<f64>,
    spacing: f64,
    phase: (f64, f64),
    keep: &dyn Fn(&Vector3<f64>) -> bool,
) {
    let nu = ((lu - phase.0) / spacing).floor().max(-1.0) as i64 + 1;
    let nv = ((lv - phase.1) / spacing).floor().max(-1.0) as i64 + 1;
    for i in 0..nu {
        let u = phase.0 + i as f64 * spacing;
        for j in 0..nv {
            let v = phase.1 + j as f64 * spacing;
            let p = origin + e1 * u + e2 * v;
            if keep(&p) {
                c.points.push([p.x, p.y, p.z]);
                c.normals.push([normal.x, normal.y, normal.z]);
            }
        }
    }
}

/// Expected number of samples (guard against huge allocations).
fn expected_samples(kind: SceneKind, spacing: f64) -> f64 {
    let area = match kind {
        SceneKind::Tunnel => 2.0 * PI * TUNNEL_RADIUS * SCENE_LENGTH,
        SceneKind::Corridor => {
            2.0 * (2.0 * CORRIDOR_HALF_WIDTH + (CORRIDOR_Y.1 - CORRIDOR_Y.0)) * SCENE_LENGTH
        }
        SceneKind::Corner => {
            4.0 * CORRIDOR_HALF_WIDTH * SCENE_LENGTH
                + 2.0 * (CORRIDOR_Y.1 - CORRIDOR_Y.0) * SCENE_LENGTH
        }
    };
    area / (spacing * spacing)
}

/// Sample a scene's surfaces at `spacing` with exact normals (pointing into the
/// free space, toward the sensor at the origin). The grid phase of each surface
/// is drawn from `rng`.
pub fn sample_scene(kind: SceneKind, spacing: f64, rng: &mut SceneRng) -> Result<Cloud> {
    check_spacing(spacing)?;
    let n = expected_samples(kind, spacing);
    if n > MAX_SCENE_POINTS as f64 {
        return Err(Error::limit(format!(
            "sampling spacing {spacing} m would give about {n:.0} points, more than the limit of {MAX_SCENE_POINTS}"
        )));
    }
    let mut c = Cloud::default();
    match kind {
        SceneKind::Tunnel => sample_tunnel(&mut c, spacing, rng),
        SceneKind::Corridor => sample_corridor(&mut c, spacing, rng),
        SceneKind::Corner => sample_corner(&mut c, spacing, rng),
    }
    Ok(c)
}

/// Rings of the circular tunnel about z, normals toward the axis.
fn sample_tunnel(c: &mut Cloud, spacing: f64, rng: &mut SceneRng) {
    let half = 0.5 * SCENE_LENGTH;
    let n_theta = ((2.0 * PI * TUNNEL_RADIUS) / spacing).round().max(3.0) as usize;
    let th0 = rng.uniform() * 2.0 * PI / n_theta as f64;
    let z0 = rng.uniform() * spacing;
    let n_rings = ((SCENE_LENGTH - z0) / spacing).floor() as usize + 1;
    for r in 0..n_rings {
        let zz = -half + z0 + r as f64 * spacing;
        for k in 0..n_theta {
            let th = th0 + 2.0 * PI * k as f64 / n_theta as f64;
            let (s, co) = th.sin_cos();
            c.points.push([TUNNEL_RADIUS * co, TUNNEL_RADIUS * s, zz]);
            c.normals.push([-co, -s, 0.0]);
        }
    }
}

/// The rectangular corridor along z: two walls, floor and ceiling.
fn sample_corridor(c: &mut Cloud, spacing: f64, rng: &mut SceneRng) {
    let half = 0.5 * SCENE_LENGTH;
    let a = CORRIDOR_HALF_WIDTH;
    let (y0, y1) = CORRIDOR_Y;
    let h = y1 - y0;
    let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
    let all = |_: &Vector3<f64>| true;
    let mut ph = || (rng.uniform() * spacing, rng.uniform() * spacing);
    let o = Vector3::new(0.0, 0.0, -half);
    // Walls x = -a and x = +a (u along y, v along z).
    sample_rect(
        c,
        o + Vector3::new(-a, y0, 0.0),
        y,
        h,
        z,
        SCENE_LENGTH,
        x,
        spacing,
        ph(),
        &all,
    );
    sample_rect(
        c,
        o + Vector3::new(a, y0, 0.0),
        y,
        h,
        z,
        SCENE_LENGTH,
        -x,
        spacing,
        ph(),
        &all,
    );
    // Floor y = y0 and ceiling y = y1 (u along x, v along z).
    sample_rect(
        c,
        o + Vector3::new(-a, y0, 0.0),
        x,
        2.0 * a,
        z,
        SCENE_LENGTH,
        y,
        spacing,
        ph(),
        &all,
    );
    sample_rect(
        c,
        o + Vector3::new(-a, y1, 0.0),
        x,
        2.0 * a,
        z,
        SCENE_LENGTH,
        -y,
        spacing,
        ph(),
        &all,
    );
}

/// The right-angle L corner: floor and ceiling kept inside the L, four walls.
fn sample_corner(c: &mut Cloud, spacing: f64, rng: &mut SceneRng) {
    let half = 0.5 * SCENE_LENGTH;
    let a = CORRIDOR_HALF_WIDTH;
    let (y0, y1) = CORRIDOR_Y;
    let h = y1 - y0;
    let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
    let all = |_: &Vector3<f64>| true;
    let mut ph = || (rng.uniform() * spacing, rng.uniform() * spacing);
    // Leg 1: |x| <= a, z in [-half, a]; leg 2: x in [-a, half], |z| <= a.
    let in_l = |p: &Vector3<f64>| {
        (p.x.abs() <= a && p.z >= -half && p.z <= a) || (p.x >= -a && p.x <= half && p.z.abs() <= a)
    };
    let lx = half + a;
    let lz = half + a;
    // Floor and ceiling over the bounding box, kept inside the L.
    sample_rect(
        c,
        Vector3::new(-a, y0, -half),
        x,
        lx,
        z,
        lz,
        y,
        spacing,
        ph(),
        &in_l,
    );
    sample_rect(
        c,
        Vector3::new(-a, y1, -half),
        x,
        lx,
        z,
        lz,
        -y,
        spacing,
        ph(),
        &in_l,
    );
    // Outer wall x = -a, z in [-half, a].
    sample_rect(
        c,
        Vector3::new(-a, y0, -half),
        y,
        h,
        z,
        lz,
        x,
        spacing,
        ph(),
        &all,
    );
    // Outer wall z = +a, x in [-a, half].
    sample_rect(
        c,
        Vector3::new(-a, y0, a),
        y,
        h,
        x,
        lx,
        -z,
        spacing,
        ph(),
        &all,
    );
    // Inner wall x = +a, z in [-half, -a].
    sample_rect(
        c,
        Vector3::new(a, y0, -half),
        y,
        h,
        z,
        half - a,
        -x,
        spacing,
        ph(),
        &all,
    );
    // Inner wall z = -a, x in [a, half].
    sample_rect(
        c,
        Vector3::new(a, y0, -a),
        y,
        h,
        x,
        half - a,
        z,
        spacing,
        ph(),
        &all,
    );
}

/// Range noise: each point moves along its ray from the sensor at the origin by
/// a zero-mean Gaussian of standard deviation `sigma` (m).
pub fn add_range_noise(points: &mut [[f64; 3]], sigma: f64, rng: &mut SceneRng) {
    if sigma <= 0.0 {
        return;
    }
    for p in points.iter_mut() {
        let v = Vector3::from(*p);
        let r = v.norm();
        if r > 0.0 {
            let q = v * (1.0 + sigma * rng.normal() / r);
            *p = [q.x, q.y, q.z];
        }
    }
}

/// Voxel downsampling: one point (the centroid) per occupied voxel of edge
/// `voxel`, the grid shifted by `origin`. Output sorted by voxel index, so it is
/// deterministic.
pub fn voxel_downsample(points: &[[f64; 3]], voxel: f64, origin: [f64; 3]) -> Vec<[f64; 3]> {
    voxel_downsample_weighted(points, None, voxel, origin).0
}

/// [`voxel_downsample`] with per-point weights: each voxel's point is still
/// the plain mean of its points (the grid evens out density; the weights say
/// how much each point counts, not where the surface is) and its weight the
/// mean of their weights, so that a column of ones gives the unweighted
/// result. Weights are returned when given (same order as the points).
pub fn voxel_downsample_weighted(
    points: &[[f64; 3]],
    weights: Option<&[f64]>,
    voxel: f64,
    origin: [f64; 3],
) -> (Vec<[f64; 3]>, Option<Vec<f64>>) {
    // Sort (voxel key, point index) and average runs of equal keys: faster than
    // a hash map at these sizes and deterministic by construction (cells.rs).
    let keys: Vec<[i64; 3]> = points
        .iter()
        .map(|p| std::array::from_fn(|a| floor_i64((p[a] - origin[a]) / voxel)))
        .collect();
    let runs = order_by_key(&keys);
    drop(keys);
    let mut out = Vec::with_capacity(runs.starts.len() - 1);
    let mut wout = Vec::with_capacity(if weights.is_some() { out.capacity() } else { 0 });
    for run in runs.runs() {
        let mut s = [0.0f64; 3];
        let mut sw = 0.0;
        for &i in run {
            let p = points[i];
            s[0] += p[0];
            s[1] += p[1];
            s[2] += p[2];
            if let Some(w) = weights {
                sw += w.get(i).copied().unwrap_or(1.0);
            }
        }
        let nf = run.len() as f64;
        out.push([s[0] / nf, s[1] / nf, s[2] / nf]);
        if weights.is_some() {
            wout.push(sw / nf);
        }
    }
    (out, weights.map(|_| wout))
}

/// Normals by PCA within `radius` (a k-d tree radius search): the eigenvector of
/// the smallest eigenvalue of the neighbourhood covariance, oriented toward
/// `sensor`. Points with fewer than `min_neighbours` points within the radius
/// (the point itself counted) get no normal and are dropped.
pub fn estimate_normals(
    points: &[[f64; 3]],
    radius: f64,
    min_neighbours: usize,
    sensor: [f64; 3],
) -> Cloud {
    let mut out = Cloud::default();
    if points.is_empty() {
        return out;
    }
    let Ok(tree) = ImmutableKdTree::<f64, 3>::new_from_slice(points) else {
        return out;
    };
    let r2 = radius * radius;
    let sensor = Vector3::from(sensor);
    for p in points {
        // One pass over the neighbourhood, no allocation: count, sum and sum of
        // outer products of the offsets from the query point (small numbers, so
        // the one-pass covariance keeps its precision).
        let mut count = 0usize;
        let mut sum = [0.0f64; 3];
        let mut sxx = [0.0f64; 6];
        tree.query(p)
            .within::<SquaredEuclidean<f64>>(r2)
            .unsorted()
            .with_points()
            .visit(|q| {
                let d = [q.point[0] - p[0], q.point[1] - p[1], q.point[2] - p[2]];
                count += 1;
                sum[0] += d[0];
                sum[1] += d[1];
                sum[2] += d[2];
                for (s, t) in sxx.iter_mut().zip(crate::degeneracy::sym3::outer(d)) {
                    *s += t;
                }
            });
        if count < min_neighbours {
            continue;
        }
        let nf = count as f64;
        let m = Vector3::new(sum[0] / nf, sum[1] / nf, sum[2] / nf);
        let s = Matrix3::new(
            sxx[0], sxx[1], sxx[2], sxx[1], sxx[3], sxx[4], sxx[2], sxx[4], sxx[5],
        );
        let cov = s / nf - m * m.transpose();
        if !cov.iter().all(|x| x.is_finite()) {
            continue;
        }
        let eig = SymmetricEigen::new(cov);
        let mut imin = 0;
        for k in 1..3 {
            if eig.eigenvalues[k] < eig.eigenvalues[imin] {
                imin = k;
            }
        }
        let mut n: Vector3<f64> = eig.eigenvectors.column(imin).into_owned();
        let nn = n.norm();
        if !nn.is_finite() || nn <= 0.0 {
            continue;
        }
        n /= nn;
        if n.dot(&(sensor - Vector3::from(*p))) < 0.0 {
            n = -n;
        }
        out.points.push(*p);
        out.normals.push([n.x, n.y, n.z]);
    }
    out
}

/// One preprocessing configuration of the synthetic pipeline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Preprocess {
    /// Surface sampling spacing (m).
    pub spacing: f64,
    /// Range-noise standard deviation (m).
    pub noise: f64,
    /// Voxel edge (m); `None` skips downsampling.
    pub voxel: Option<f64>,
    /// Normal-estimation radius (m); `None` keeps the exact normals.
    pub normal_radius: Option<f64>,
    /// Points with fewer neighbours (itself included) within `normal_radius`
    /// are dropped; unused without `normal_radius`.
    pub min_neighbours: usize,
    /// Seed of the one [`SceneRng`] that draws the sampling phases, the range
    /// noise and the voxel-grid origin.
    pub seed: u64,
}

impl Preprocess {
    /// The paper's pipeline at one voxel size and noise level: sampling at half
    /// the voxel, range noise, voxel grid with a random origin, PCA normals
    /// within 0.30 m from the noisy points with at least 8 neighbours.
    pub fn pipeline(voxel: f64, noise: f64, seed: u64) -> Preprocess {
        Preprocess {
            spacing: 0.5 * voxel,
            noise,
            voxel: Some(voxel),
            normal_radius: Some(NORMAL_RADIUS),
            min_neighbours: MIN_NEIGHBOURS,
            seed,
        }
    }
    /// Exact samples with exact normals, optional noise (normals stay exact).
    pub fn exact(spacing: f64, noise: f64, seed: u64) -> Preprocess {
        Preprocess {
            spacing,
            noise,
            voxel: None,
            normal_radius: None,
            min_neighbours: MIN_NEIGHBOURS,
            seed,
        }
    }
}

/// Build a scene through the preprocessing pipeline: sample, add range noise,
/// downsample on a voxel grid whose origin is uniform in `[0, voxel)^3`,
/// estimate normals. Deterministic for a given configuration and seed.
pub fn synthesize(kind: SceneKind, pre: &Preprocess) -> Result<Cloud> {
    if !(pre.noise.is_finite() && pre.noise >= 0.0) {
        return Err(Error::usage(format!(
            "range noise: expected a non-negative number of metres, found {}",
            pre.noise
        )));
    }
    let mut rng = SceneRng::new(pre.seed);
    let mut cloud = sample_scene(kind, pre.spacing, &mut rng)?;
    add_range_noise(&mut cloud.points, pre.noise, &mut rng);
    let mut pts = cloud.points;
    if let Some(v) = pre.voxel {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::usage(format!(
                "voxel size: expected a positive number of metres, found {v}"
            )));
        }
        let origin = [rng.uniform() * v, rng.uniform() * v, rng.uniform() * v];
        pts = voxel_downsample(&pts, v, origin);
        cloud.normals.clear();
    }
    match pre.normal_radius {
        Some(r) => Ok(estimate_normals(&pts, r, pre.min_neighbours, [0.0; 3])),
        None => {
            if pre.voxel.is_some() {
                return Err(Error::usage(
                    "voxel downsampling needs normal estimation (exact normals do not survive averaging)",
                ));
            }
            Ok(Cloud {
                points: pts,
                normals: cloud.normals,
            })
        }
    }
}

/// The benchmark cloud (criterion benches and `examples/bench_data.rs`, whose
/// file the numpy comparison reads, must agree): `n` points uniform in
/// `[-10, 10]^3` and unit normals uniform on the sphere, from `SceneRng(seed)`.
pub fn random_cloud(seed: u64, n: usize) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let mut rng = SceneRng::new(seed);
    let mut p = Vec::with_capacity(n);
    let mut nn = Vec::with_capacity(n);
    for _ in 0..n {
        p.push([
            20.0 * rng.uniform() - 10.0,
            20.0 * rng.uniform() - 10.0,
            20.0 * rng.uniform() - 10.0,
        ]);
        let u = rng.unit_vector();
        nn.push([u.x, u.y, u.z]);
    }
    (p, nn)
}
