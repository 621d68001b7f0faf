//! Property tests of the SE(3) core over thousands of random transforms.

// Index loops over fixed-size vectors read more clearly than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use extrinsic_audit::analyze;
use extrinsic_audit::internals::analysis::metric::adapted_metric;
use extrinsic_audit::internals::geometry::certificate::{
    adjoint_singular_values, ata_minus_i_rel, band,
};
use extrinsic_audit::internals::tolerances::DEFAULT_PITCH_TOL;
use extrinsic_audit::{QuatOrder, ScrewKind, Transform};
use nalgebra::{Matrix3, Matrix6, SymmetricEigen, Vector3, Vector6};
use proptest::prelude::*;

const CASES: u32 = 4000;

fn unit_quat() -> impl Strategy<Value = [f64; 4]> {
    prop::array::uniform4(-1.0f64..1.0).prop_filter("non-degenerate", |q| {
        q.iter().map(|x| x * x).sum::<f64>() > 1e-3
    })
}

fn translation(max: f64) -> impl Strategy<Value = [f64; 3]> {
    prop::array::uniform3(-max..max)
}

/// Random rigid transform: uniform-ish rotation, lever arm up to ~8.7 m.
fn transform() -> impl Strategy<Value = Transform> {
    (unit_quat(), translation(5.0)).prop_map(|(q, d)| {
        let mut w = Vec::new();
        Transform::from_quaternion(q, QuatOrder::Xyzw, d, &mut w).expect("valid")
    })
}

fn unit_axis() -> impl Strategy<Value = Vector3<f64>> {
    prop::array::uniform3(-1.0f64..1.0)
        .prop_filter("non-zero", |a| a.iter().map(|x| x * x).sum::<f64>() > 1e-2)
        .prop_map(|a| Vector3::from(a).normalize())
}

fn rot(e: &Vector3<f64>, phi: f64) -> Matrix3<f64> {
    let t = Transform::from_axis_angle([e.x, e.y, e.z], phi, [0.0; 3]).expect("rotation");
    *t.rotation()
}

fn from_rd(r: &Matrix3<f64>, d: &Vector3<f64>) -> Transform {
    let mut w = Vec::new();
    let rows = [
        [r[(0, 0)], r[(0, 1)], r[(0, 2)]],
        [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
        [r[(2, 0)], r[(2, 1)], r[(2, 2)]],
    ];
    Transform::from_matrix3(rows, [d.x, d.y, d.z], &mut w).expect("rotation")
}

fn rel_close(got: f64, want: f64, tol: f64) -> bool {
    (got - want).abs() <= tol * want.abs()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]

    /// Closed-form singular values equal nalgebra's SVD of Ad(T) to 1e-12 relative.
    #[test]
    fn closed_form_singular_values_match_svd(t in transform()) {
        let mut sv: Vec<f64> = t.adjoint().singular_values().iter().copied().collect();
        sv.sort_by(|a, b| b.total_cmp(a));
        let cf = adjoint_singular_values(t.lever_arm());
        for k in 0..6 {
            prop_assert!(rel_close(cf[k], sv[k], 1e-12), "k={k} closed {} svd {}", cf[k], sv[k]);
        }
        // And ||A^T A - I||_F / ||I||_F.
        let a = t.adjoint();
        let direct = (a.transpose() * a - Matrix6::identity()).norm() / 6f64.sqrt();
        let cf = ata_minus_i_rel(t.lever_arm());
        prop_assert!((direct - cf).abs() <= 1e-12 * cf.max(1.0), "{direct} vs {cf}");
    }

    /// Ad(T1 T2) = Ad(T1) Ad(T2).
    #[test]
    fn adjoint_is_a_homomorphism(t1 in transform(), t2 in transform()) {
        let lhs = t1.compose(&t2).adjoint();
        let rhs = t1.adjoint() * t2.adjoint();
        let scale = 1.0 + t1.adjoint().norm() * t2.adjoint().norm();
        prop_assert!((lhs - rhs).norm() <= 1e-12 * scale, "diff {}", (lhs - rhs).norm());
    }

    /// Ad(T^-1) = Ad(T)^-1, and adjoint_inverse() is that matrix.
    #[test]
    fn adjoint_of_inverse_is_inverse(t in transform()) {
        let a = t.adjoint();
        let ai = t.inverse().adjoint();
        prop_assert_eq!(ai, t.adjoint_inverse());
        let scale = 1.0 + a.norm() * ai.norm();
        prop_assert!((a * ai - Matrix6::identity()).norm() <= 1e-12 * scale);
        prop_assert!((ai * a - Matrix6::identity()).norm() <= 1e-12 * scale);
        let inv = a.try_inverse().expect("invertible");
        prop_assert!((inv - ai).norm() <= 1e-12 * scale);
    }

    /// h(T) = h(T^-1), and the screw reconstructs T: R = rot(e, phi),
    /// d = (I - R) c + h e with c . e = 0.
    #[test]
    fn screw_is_consistent(t in transform()) {
        let s = t.screw(DEFAULT_PITCH_TOL);
        let si = t.inverse().screw(DEFAULT_PITCH_TOL);
        let d = t.translation();
        let scale = 1.0 + d.norm();
        let (h, hi) = (s.translation_along_axis.unwrap(), si.translation_along_axis.unwrap());
        prop_assert!((h - hi).abs() <= 1e-12 * scale, "h {h} vs {hi}");
        prop_assert!((s.angle - si.angle).abs() <= 1e-12);
        let e = s.axis.unwrap();
        let c = s.axis_point.unwrap();
        prop_assert!((e.norm() - 1.0).abs() <= 1e-12);
        prop_assert!(c.dot(&e).abs() <= 1e-12 * (1.0 + c.norm()));
        let r = rot(&e, s.angle);
        prop_assert!((r - t.rotation()).norm() <= 1e-12, "R diff {}", (r - t.rotation()).norm());
        let d_re = (Matrix3::identity() - r) * c + e * h;
        prop_assert!((d_re - d).norm() <= 1e-12 * scale, "d diff {}", (d_re - d).norm());
        prop_assert!(rel_close(s.pitch.unwrap() * s.angle, h, 1e-12) || h.abs() < 1e-300);
    }

    /// A zero-pitch rig (rotation about a line through c): adapted metric exists and is
    /// invariant to 1e-12 relative.
    #[test]
    fn zero_pitch_rigs_get_an_invariant_metric(
        e in unit_axis(), phi in 1e-3f64..std::f64::consts::PI, c in translation(3.0)
    ) {
        let r = rot(&e, phi);
        let c = Vector3::from(c);
        let d = (Matrix3::identity() - r) * c;
        let t = from_rd(&r, &d);
        let am = adapted_metric(&t, DEFAULT_PITCH_TOL);
        prop_assert!(am.exists, "h = {:?}", am.translation_along_axis);
        let res = am.invariance_residual.unwrap();
        prop_assert!(res <= 1e-12, "residual {res}");
        let m0 = am.matrix.unwrap();
        let a = t.adjoint();
        let direct = (a.transpose() * m0 * a - m0).norm() / m0.norm();
        prop_assert!(direct <= 1e-12);
        // M0 is positive definite.
        prop_assert!(m0.cholesky().is_some());
    }

    /// Exact half-turns with an arbitrary translation: h >= 0, h(T) = h(T^-1),
    /// and the screw reconstructs T.
    #[test]
    fn half_turns_are_canonical(e in unit_axis(), d in translation(2.0)) {
        let r = 2.0 * e * e.transpose() - Matrix3::identity();
        let t = from_rd(&r, &Vector3::from(d));
        let s = t.screw(DEFAULT_PITCH_TOL);
        let si = t.inverse().screw(DEFAULT_PITCH_TOL);
        let h = s.translation_along_axis.unwrap();
        prop_assert!(h >= 0.0);
        prop_assert!((h - si.translation_along_axis.unwrap()).abs() <= 1e-12 * (1.0 + h));
        let ea = s.axis.unwrap();
        let rr = rot(&ea, s.angle);
        prop_assert!((rr - t.rotation()).norm() <= 1e-12);
        let d_re = (Matrix3::identity() - rr) * s.axis_point.unwrap() + ea * h;
        prop_assert!((d_re - t.translation()).norm() <= 1e-12 * (1.0 + h));
    }

    /// Nonzero pitch: no adapted metric, reason says so.
    #[test]
    fn nonzero_pitch_rigs_get_no_metric(
        e in unit_axis(), phi in 1e-3f64..std::f64::consts::PI, c in translation(3.0),
        h in prop_oneof![1e-6f64..1.0, -1.0f64..-1e-6]
    ) {
        let r = rot(&e, phi);
        let d = (Matrix3::identity() - r) * Vector3::from(c) + e * h;
        let t = from_rd(&r, &d);
        let a = analyze(&t, &[1.0], DEFAULT_PITCH_TOL).unwrap();
        prop_assert_eq!(a.screw.kind, ScrewKind::General);
        prop_assert!(!a.adapted_metric.exists);
        prop_assert!(a.adapted_metric.matrix.is_none());
        prop_assert!((a.adapted_metric.translation_along_axis.unwrap().abs() - h.abs()).abs() <= 1e-12);
    }

    /// Ostrowski: generalized eigenvalues of (H, diag(l^2 I, I)) and
    /// (A^T H A, diag(l^2 I, I)) differ by a factor inside the band at delta_eff.
    #[test]
    fn eigenvalue_drift_stays_in_band(
        t in transform(), ell in 0.1f64..5.0,
        g in prop::array::uniform6(prop::array::uniform6(-1.0f64..1.0))
    ) {
        let gm = Matrix6::from_fn(|i, j| g[i][j]);
        let h = gm.transpose() * gm + Matrix6::identity() * 1e-3;
        let s = Vector6::new(1.0 / ell, 1.0 / ell, 1.0 / ell, 1.0, 1.0, 1.0);
        let ms = Matrix6::from_diagonal(&s); // M^-1/2
        let a = t.adjoint();
        let ev = |hh: &Matrix6<f64>| {
            let mut v: Vec<f64> = SymmetricEigen::new(ms * hh * ms).eigenvalues.iter().copied().collect();
            v.sort_by(|x, y| x.total_cmp(y));
            v
        };
        let l0 = ev(&h);
        let l1 = ev(&(a.transpose() * h * a));
        let [lo, hi] = band(t.lever_arm() / ell);
        for k in 0..6 {
            let theta = l1[k] / l0[k];
            prop_assert!(theta >= lo * (1.0 - 1e-9) && theta <= hi * (1.0 + 1e-9),
                "k={k} theta {theta} band [{lo}, {hi}]");
        }
    }
}
