//! Eigenvalues and eigenvectors of a 3x3 symmetric matrix in closed form,
//! for the normals' neighbourhood covariances (normals.rs).
//!
//! D. Eberly, "A Robust Eigensolver for 3x3 Symmetric Matrices" (Geometric
//! Tools, 2014, rev. 2021), the non-iterative solver:
//!
//! 1. The matrix is scaled by its largest absolute entry (no overflow or
//!    underflow in the squares below); a matrix with zero off-diagonal is
//!    its own decomposition.
//! 2. With `q = tr(A) / 3` and `p = sqrt(tr((A - qI)^2) / 6)`, `B = (A - qI) /
//!    p` has eigenvalues `2 cos(phi + 2 pi k / 3)`, `phi = acos(det(B) / 2) /
//!    3` (Smith 1961): the three in ascending order without iteration.
//! 3. The eigenvalue farthest from the other two (the largest when
//!    `det(B) >= 0`, else the smallest) is simple unless all three are equal,
//!    and the trigonometric form is flat there (`phi` near 0 or `pi / 3`), so
//!    it is accurate; `A - lambda I` has rank 2 and the largest of its rows'
//!    three cross products is its eigenvector, whose Rayleigh quotient is
//!    the eigenvalue kept.
//! 4. The other two eigenpairs are those of the 2x2 matrix of `A` on an
//!    orthonormal basis of the plane orthogonal to that vector, diagonalised
//!    by one Jacobi rotation. Near a double eigenvalue `acos` loses up to
//!    half the digits of the other two eigenvalues (Eberly's step 3 takes
//!    them from it); the rotation does not, so the three are orthonormal and
//!    as accurate as an iterative solver's.
//!
//! Accuracy: eigenvalues to a few units of `eps * max|a_ij|` (absolute, as
//! nalgebra's QR iteration and LAPACK's `dsyevd`), an eigenvector to about
//! `eps * max|a_ij| / gap` where `gap` is its eigenvalue's distance to the
//! nearest other one (measured against numpy.linalg.eigh in the tests).
//! A covariance is centred before it gets here (offsets from the query
//! point), so coordinates far from the origin cost nothing. Where the cross
//! products vanish (the rows underflow, a non-finite entry), [`eigen`]
//! returns `None` and the caller keeps nalgebra's iterative solver.

/// Eigen-decomposition of a symmetric 3x3 matrix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Sym3 {
    /// Eigenvalues, ascending.
    pub values: [f64; 3],
    /// `vectors[k]`: a unit eigenvector of `values[k]`; the three are
    /// orthonormal.
    pub vectors: [[f64; 3]; 3],
}

/// Upper triangle of a symmetric matrix, row by row: `[a00, a01, a02, a11,
/// a12, a22]`.
pub(crate) type Upper = [f64; 6];

/// `d d^T` as an [`Upper`]: one offset's term of a neighbourhood's moments.
#[inline(always)]
pub(crate) fn outer(d: [f64; 3]) -> Upper {
    [
        d[0] * d[0],
        d[0] * d[1],
        d[0] * d[2],
        d[1] * d[1],
        d[1] * d[2],
        d[2] * d[2],
    ]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `A v` for the upper triangle `a`.
fn apply(a: &Upper, v: [f64; 3]) -> [f64; 3] {
    [
        a[0] * v[0] + a[1] * v[1] + a[2] * v[2],
        a[1] * v[0] + a[3] * v[1] + a[4] * v[2],
        a[2] * v[0] + a[4] * v[1] + a[5] * v[2],
    ]
}

/// The eigen-decomposition of the symmetric matrix `a` (see the module
/// notes); `None` when an entry is not finite or the closed form cannot
/// give a unit vector.
pub(crate) fn eigen(a: &Upper) -> Option<Sym3> {
    if !a.iter().all(|x| x.is_finite()) {
        return None;
    }
    let amax = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if amax == 0.0 {
        return Some(Sym3 {
            values: [0.0; 3],
            vectors: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        });
    }
    let s = a.map(|x| x / amax);
    let off = s[1] * s[1] + s[2] * s[2] + s[4] * s[4];
    if off == 0.0 {
        return Some(diagonal(a));
    }
    let q = (s[0] + s[3] + s[5]) / 3.0;
    let (b00, b11, b22) = (s[0] - q, s[3] - q, s[5] - q);
    let p = ((b00 * b00 + b11 * b11 + b22 * b22 + 2.0 * off) / 6.0).sqrt();
    let c00 = b11 * b22 - s[4] * s[4];
    let c01 = s[1] * b22 - s[4] * s[2];
    let c02 = s[1] * s[4] - b11 * s[2];
    let half_det = ((b00 * c00 - s[1] * c01 + s[2] * c02) / (p * p * p) / 2.0).clamp(-1.0, 1.0);
    let phi = half_det.acos() / 3.0;
    const TWO_THIRDS_PI: f64 = 2.0 * std::f64::consts::FRAC_PI_3;
    // The simple eigenvalue (the farthest from the other two) is where the
    // trigonometric form is flat (phi near 0 or pi / 3), so accurate; the
    // other two, near a double eigenvalue, are where acos loses digits, so
    // they and their vectors come from the 2x2 problem on the plane
    // orthogonal to the simple one's vector, solved by one Jacobi rotation
    // (accurate to eps of the matrix, whatever their gap).
    let simple = if half_det >= 0.0 {
        q + p * 2.0 * phi.cos()
    } else {
        q + p * 2.0 * (phi + TWO_THIRDS_PI).cos()
    };
    let w = simple_vector(&s, simple)?;
    // Its Rayleigh quotient: the eigenvalue to eps * max|a| (the vector's
    // error enters squared).
    let simple = dot(w, apply(&s, w));
    let [(la, va), (lb, vb)] = plane_pair(&s, w)?;
    let mut pairs = [(simple, w), (la, va), (lb, vb)];
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
    Some(Sym3 {
        values: pairs.map(|(l, _)| l * amax),
        vectors: pairs.map(|(_, v)| v),
    })
}

/// A diagonal matrix: its diagonal sorted, with the axes.
fn diagonal(a: &Upper) -> Sym3 {
    let d = [a[0], a[3], a[5]];
    let mut k = [0usize, 1, 2];
    k.sort_by(|&i, &j| d[i].total_cmp(&d[j]));
    let axis = |i: usize| {
        let mut e = [0.0; 3];
        e[i] = 1.0;
        e
    };
    Sym3 {
        values: k.map(|i| d[i]),
        vectors: k.map(axis),
    }
}

/// The eigenvector of the simple eigenvalue `l` of `s`: the longest cross
/// product of two rows of `s - l I`, normalised.
fn simple_vector(s: &Upper, l: f64) -> Option<[f64; 3]> {
    let r0 = [s[0] - l, s[1], s[2]];
    let r1 = [s[1], s[3] - l, s[4]];
    let r2 = [s[2], s[4], s[5] - l];
    let c = [cross(r0, r1), cross(r0, r2), cross(r1, r2)];
    let d = c.map(|v| dot(v, v));
    let mut k = 0;
    for i in 1..3 {
        if d[i] > d[k] {
            k = i;
        }
    }
    if !(d[k] > 0.0 && d[k].is_finite()) {
        return None;
    }
    Some(scale(c[k], 1.0 / d[k].sqrt()))
}

/// The two eigenpairs of `s` orthogonal to its unit eigenvector `w`: the
/// 2x2 matrix of `s` on an orthonormal basis `u`, `v` of that plane,
/// diagonalised by one Jacobi rotation (Golub and Van Loan, "Matrix
/// Computations", 4th ed., 8.5.2: `t` the smaller root, `|t| <= 1`, so no
/// cancellation). A double eigenvalue gives `u` and `v` themselves.
fn plane_pair(s: &Upper, w: [f64; 3]) -> Option<[(f64, [f64; 3]); 2]> {
    let u = if w[0].abs() > w[1].abs() {
        scale([-w[2], 0.0, w[0]], 1.0 / (w[0] * w[0] + w[2] * w[2]).sqrt())
    } else {
        scale([0.0, w[2], -w[1]], 1.0 / (w[1] * w[1] + w[2] * w[2]).sqrt())
    };
    let v = cross(w, u);
    let (au, av) = (apply(s, u), apply(s, v));
    let (a, b, c) = (dot(u, au), dot(u, av), dot(v, av));
    let out = if b == 0.0 {
        [(a, u), (c, v)]
    } else {
        let tau = (c - a) / (2.0 * b);
        // For |tau| past 1e150 its square would overflow; t is 1 / (2 tau)
        // there to far below eps.
        let t = if tau.abs() > 1e150 {
            0.5 / tau
        } else {
            tau.signum() / (tau.abs() + (1.0 + tau * tau).sqrt())
        };
        let cs = 1.0 / (1.0 + t * t).sqrt();
        let sn = t * cs;
        // [u v] times the rotation's columns (cs, -sn) and (sn, cs).
        [
            (a - t * b, sub(scale(u, cs), scale(v, sn))),
            (
                c + t * b,
                [
                    u[0] * sn + v[0] * cs,
                    u[1] * sn + v[1] * cs,
                    u[2] * sn + v[2] * cs,
                ],
            ),
        ]
    };
    out.iter()
        .all(|(l, x)| l.is_finite() && x.iter().all(|e| e.is_finite()))
        .then_some(out)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `values` and `vectors` decompose `a`: `|A v - l v| <= tol * max|a|`
    /// for each pair, and the vectors are orthonormal.
    fn assert_decomposes(a: &Upper, e: &Sym3, tol: f64) {
        let amax = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for k in 0..3 {
            let v = e.vectors[k];
            let r = sub(apply(a, v), scale(v, e.values[k]));
            assert!(
                dot(r, r).sqrt() <= tol * amax,
                "{a:?}: residual {r:?} of {k}"
            );
            for j in 0..3 {
                let want = if j == k { 1.0 } else { 0.0 };
                assert!(
                    (dot(v, e.vectors[j]) - want).abs() <= 1e-14,
                    "{a:?}: v{k}.v{j}"
                );
            }
        }
        assert!(e.values[0] <= e.values[1] && e.values[1] <= e.values[2]);
    }

    /// `|v . w| = 1` to `tol` (unit vectors, either sign).
    fn assert_parallel(v: [f64; 3], w: [f64; 3], tol: f64) {
        let c = dot(v, w).abs() / dot(w, w).sqrt();
        assert!((1.0 - c).abs() <= tol, "{v:?} vs {w:?}: |cos| = {c}");
    }

    /// `Q diag(l) Q^T`, `Q = [[1, 2, 2], [2, 1, -2], [2, -2, 1]] / 3`
    /// (orthogonal: its columns are the eigenvectors).
    const Q: [[f64; 3]; 3] = [
        [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0],
        [2.0 / 3.0, 1.0 / 3.0, -2.0 / 3.0],
        [2.0 / 3.0, -2.0 / 3.0, 1.0 / 3.0],
    ];

    fn q_column(k: usize) -> [f64; 3] {
        [Q[0][k], Q[1][k], Q[2][k]]
    }

    fn rotated(l: [f64; 3]) -> Upper {
        let m = |i: usize, j: usize| (0..3).map(|k| Q[i][k] * l[k] * Q[j][k]).sum::<f64>();
        [m(0, 0), m(0, 1), m(0, 2), m(1, 1), m(1, 2), m(2, 2)]
    }

    /// Covariance of points (centred on their mean first).
    fn covariance(pts: &[[f64; 3]]) -> Upper {
        let n = pts.len() as f64;
        let mut c = [0.0; 3];
        for p in pts {
            for k in 0..3 {
                c[k] += p[k] / n;
            }
        }
        let mut s = [0.0; 6];
        for p in pts {
            let outer = outer(sub(*p, c));
            for k in 0..6 {
                s[k] += outer[k] / n;
            }
        }
        s
    }

    #[test]
    fn a_diagonal_matrix_is_its_own_decomposition() {
        let e = eigen(&[3.0, 0.0, 0.0, -1.0, 0.0, 2.0]).unwrap();
        assert_eq!(e.values, [-1.0, 2.0, 3.0]);
        assert_eq!(
            e.vectors,
            [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]
        );
        let z = eigen(&[0.0; 6]).unwrap();
        assert_eq!(z.values, [0.0; 3]);
        assert_decomposes(&[0.0; 6], &z, 0.0);
    }

    #[test]
    fn distinct_eigenvalues_of_a_rotated_diagonal() {
        // A plane's covariance: one small eigenvalue, two large; and a
        // general spread, negative values included.
        for l in [[1e-4, 0.02, 0.03], [-2.0, 0.5, 7.0], [1e-12, 1.0, 3.0]] {
            let a = rotated(l);
            let e = eigen(&a).unwrap();
            for k in 0..3 {
                assert!(
                    (e.values[k] - l[k]).abs() <= 1e-15 * l[2].abs().max(2.0),
                    "{l:?}"
                );
                assert_parallel(e.vectors[k], q_column(k), 1e-14);
            }
            assert_decomposes(&a, &e, 1e-14);
        }
    }

    #[test]
    fn repeated_eigenvalues() {
        // Double smallest (a line's covariance: 0, 0, big), double largest
        // (a disc's), triple (a multiple of the identity).
        for (l, simple) in [
            ([1.0, 1.0, 4.0], Some(2)),
            ([0.0, 0.0, 0.09], Some(2)),
            ([0.5, 2.0, 2.0], Some(0)),
            ([2.0, 2.0, 2.0], None),
        ] {
            let a = rotated(l);
            let e = eigen(&a).unwrap();
            for k in 0..3 {
                assert!(
                    (e.values[k] - l[k]).abs() <= 4e-16 * l[2],
                    "{l:?}: {:?}",
                    e.values
                );
            }
            if let Some(k) = simple {
                assert_parallel(e.vectors[k], q_column(k), 1e-14);
            }
            assert_decomposes(&a, &e, 1e-14);
        }
    }

    #[test]
    fn planar_and_collinear_points_far_from_the_origin() {
        // A 7 x 7 patch of the plane with normal (0.64, -0.48, 0.6) about a
        // point 300 km out, and a line along (0, 0.6, 0.8): centred first,
        // the offsets are small and the far origin costs nothing.
        let (a, b) = ([0.6, 0.8, 0.0], [-0.48, 0.36, 0.8]);
        let normal = cross(a, b);
        let far = [3.0e5, -2.0e5, 50.0];
        let mut plane = Vec::new();
        let mut line = Vec::new();
        for i in -3..=3 {
            let s = 0.05 * f64::from(i);
            line.push([far[0], far[1] + 0.6 * s, far[2] + 0.8 * s]);
            for j in -3..=3 {
                let t = 0.05 * f64::from(j);
                plane.push(std::array::from_fn(|k| far[k] + s * a[k] + t * b[k]));
            }
        }
        let c = covariance(&plane);
        let e = eigen(&c).unwrap();
        // Exact: points on a 0.05 m lattice along a and b, 7 per side:
        // variance 0.05^2 * 4 on each (sum of k^2 for k = -3..3 is 28).
        let var = 0.0025 * 4.0;
        assert!(e.values[0].abs() <= 1e-12 * var, "{:?}", e.values);
        // A double eigenvalue (var, var), to the rounding of the input (the
        // offsets from 300 km out carry an ulp of 6e-11 m in 0.15 m: 1e-10
        // of var measured); the decomposition of the matrix as given is to
        // eps (the 2x2 rotation; acos alone lost half the digits here).
        assert!((e.values[1] - var).abs() <= 1e-9 * var && (e.values[2] - var).abs() <= 1e-9 * var);
        assert_decomposes(&c, &e, 1e-15);
        // Rounding of the far coordinates (ulp 6e-11 m) bounds the normal.
        assert_parallel(e.vectors[0], normal, 1e-15);
        let c = covariance(&line);
        let e = eigen(&c).unwrap();
        assert!(e.values[0].abs() <= 1e-15 * var && e.values[1].abs() <= 1e-15 * var);
        assert!((e.values[2] - var).abs() <= 1e-9 * var);
        assert_parallel(e.vectors[2], [0.0, 0.6, 0.8], 1e-15);
        assert_decomposes(&c, &e, 1e-15);
    }

    #[test]
    fn near_isotropic() {
        // The identity nudged by 1e-10: eigenvalues 1 to eps, and a valid
        // orthonormal decomposition (the vectors themselves are ill-posed).
        let a = [1.0, 1e-10, -3e-11, 1.0 + 2e-10, 5e-11, 1.0 - 1e-10];
        let e = eigen(&a).unwrap();
        for l in e.values {
            assert!((l - 1.0).abs() <= 4e-10);
        }
        assert_decomposes(&a, &e, 1e-15);
    }

    #[test]
    fn not_finite_is_refused() {
        assert_eq!(eigen(&[f64::NAN, 0.0, 0.0, 1.0, 0.0, 1.0]), None);
        assert_eq!(eigen(&[1.0, f64::INFINITY, 0.0, 1.0, 0.0, 1.0]), None);
    }

    // Generated by bench/run_sym3_numpy.py (numpy 2.4.6, numpy.linalg.eigh).
    const NUMPY: [(&str, Upper, [f64; 3], [f64; 3]); 7] = [
        (
            "noisy plane",
            [
                0.018792409872155465,
                0.005354503084366074,
                -0.015432062890992226,
                0.015261395723936857,
                0.0061183443528631705,
                0.020944258297332746,
            ],
            [
                8.275935421958282e-05,
                0.019539904787269156,
                0.03537539975193633,
            ],
            [0.6376578502545815, -0.47073077539306174, 0.609758151324402],
        ),
        (
            "thin plane far from the origin (centred first)",
            [
                0.015107353408735053,
                0.007653363225907841,
                -0.00998975395138199,
                0.02412559163729695,
                0.011140502318853418,
                0.01956886063611614,
            ],
            [
                1.1142818481281458e-08,
                0.02557003743633164,
                0.033231757102998014,
            ],
            [0.63995121739453, -0.4800720834120803, 0.5999943617098776],
        ),
        (
            "thin edge",
            [
                7.3207200134637985e-06,
                6.488739330489888e-05,
                8.252253445655663e-05,
                0.00805591552439468,
                0.010673385536324156,
                0.014170096810969885,
            ],
            [
                5.8293773820862686e-06,
                1.1435940927087467e-05,
                0.022216067737068853,
            ],
            [0.9068912148259588, -0.33904129411167394, 0.2501985718555923],
        ),
        (
            "corner",
            [
                0.020792908590625696,
                0.0030955561827391764,
                -0.005548593905270181,
                0.02785089367068135,
                0.004700501145190283,
                0.010616684462038969,
            ],
            [
                0.006715880477598811,
                0.023103029675017157,
                0.029441576570730054,
            ],
            [
                0.40255399011095866,
                -0.25451996619560413,
                0.8793007857687465,
            ],
        ),
        (
            "blob",
            [
                0.01182655279471503,
                -0.00083509711013961,
                0.0007564002331085889,
                0.004677103601589151,
                -0.0006609455183380047,
                0.003994484485639548,
            ],
            [
                0.003585890672710565,
                0.004903619307707051,
                0.01200863090152611,
            ],
            [-0.028498107817118954, 0.50181856473887, 0.864503317480196],
        ),
        (
            "general",
            [4.0, -2.0, 1.0, 3.0, 0.5, -1.0],
            [-1.3931126385232462, 1.7952173261516713, 5.597895312371573],
            [-0.2574168489557233, -0.224169753105409, 0.9399385552611226],
        ),
        (
            "general, tiny",
            [2e-09, 1e-09, 0.0, 2e-09, 1e-09, 2e-09],
            [5.857864376269048e-10, 2e-09, 3.4142135623730956e-09],
            [-0.5, 0.7071067811865475, -0.5000000000000001],
        ),
    ];

    #[test]
    fn numpy_eigh_agrees() {
        for (name, a, values, smallest) in NUMPY {
            let e = eigen(&a).unwrap();
            let amax = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for k in 0..3 {
                assert!(
                    (e.values[k] - values[k]).abs() <= 1e-15 * amax,
                    "{name}: {:?} vs {values:?}",
                    e.values
                );
            }
            // The normal: to eps * max|a| / gap (gap of the smallest).
            let gap = (values[1] - values[0]) / amax;
            assert_parallel(e.vectors[0], smallest, 1e-15 / gap.min(1.0));
            assert_decomposes(&a, &e, 1e-15);
        }
    }
}
