//! Explicit edge cases of the SE(3) core, the certificate and the metric verdicts,
//! plus the paper's figures.

// Index loops over fixed-size vectors read more clearly than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use extrinsic_audit::internals::analysis::metric::{family_verdicts, AdaptedReason, VerdictReason};
use extrinsic_audit::internals::geometry::certificate::{
    band, certificates, certifies_no_crossing, delta_eff, sigma_max, sigma_min,
};
use extrinsic_audit::internals::tolerances::{DEFAULT_PITCH_TOL, MAX_ELLS};
use extrinsic_audit::Code;
use extrinsic_audit::{analyze, Family, RigAnalysis};
use extrinsic_audit::{QuatOrder, ScrewKind, Transform};
use nalgebra::{Matrix3, Matrix6, Vector3};
use std::f64::consts::{FRAC_PI_2, PI};

fn an(t: &Transform) -> RigAnalysis {
    analyze(t, &[1.0], DEFAULT_PITCH_TOL).expect("analyze")
}

fn verdict(a: &RigAnalysis, f: Family) -> (bool, bool, VerdictReason) {
    let v = a
        .detectors
        .iter()
        .find(|v| v.family == f)
        .expect("family present");
    (v.equivariant_rule, v.invariant_on_rig, v.reason)
}

fn rx(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}
fn ry(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}
fn rz(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

// ---------------------------------------------------------------- constructors

#[test]
fn rpy_is_fixed_axis_and_ypr_is_the_ros1_argument_order() {
    let (r, p, y) = (0.3, -0.7, 2.1);
    let t = Transform::from_rpy([r, p, y], [1.0, 2.0, 3.0]).unwrap();
    let want = rz(y) * ry(p) * rx(r);
    assert!((t.rotation() - want).norm() < 1e-15);
    let u = Transform::from_ypr([y, p, r], [1.0, 2.0, 3.0]).unwrap();
    assert_eq!(t, u);
    let back = t.rpy();
    assert!((back[0] - r).abs() < 1e-14 && (back[1] - p).abs() < 1e-14);
    assert!((back[2] - y).abs() < 1e-14);
    // Gimbal lock: yaw carries the rest, the matrix is reproduced.
    let g = Transform::from_rpy([0.4, FRAC_PI_2, 0.9], [0.0; 3]).unwrap();
    let gb = g.rpy();
    let g2 = Transform::from_rpy(gb, [0.0; 3]).unwrap();
    assert!((g.rotation() - g2.rotation()).norm() < 1e-12);
}

#[test]
fn quaternion_orders_agree_and_round_trip() {
    let mut w = Vec::new();
    let q = [0.1, -0.5, 0.3, -0.8]; // w < 0
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    let q = q.map(|x| x / n);
    let a = Transform::from_quaternion(q, QuatOrder::Xyzw, [0.0; 3], &mut w).unwrap();
    let b = Transform::from_quaternion([q[3], q[0], q[1], q[2]], QuatOrder::Wxyz, [0.0; 3], &mut w)
        .unwrap();
    assert!(w.is_empty());
    assert_eq!(a, b);
    let back = a.quaternion_xyzw();
    assert!(back[3] >= 0.0);
    for k in 0..4 {
        assert!((back[k] + q[k]).abs() < 1e-15, "sign flipped to w >= 0");
    }
    // Rz(90 deg) from [0, 0, sin45, cos45].
    let s = FRAC_PI_2.sin() / 2f64.sqrt();
    let z =
        Transform::from_quaternion([0.0, 0.0, s, s], QuatOrder::Xyzw, [0.0; 3], &mut w).unwrap();
    assert!((z.rotation() - rz(FRAC_PI_2)).norm() < 1e-15);
}

#[test]
fn quaternion_norm_zero_is_an_error() {
    let mut w = Vec::new();
    let e = Transform::from_quaternion([0.0; 4], QuatOrder::Xyzw, [0.0; 3], &mut w).unwrap_err();
    assert_eq!(e.code, Code::Invalid);
    assert!(e.message.contains("norm"), "{}", e.message);
    let e = Transform::from_quaternion([1e-300, 0.0, 0.0, 0.0], QuatOrder::Wxyz, [0.0; 3], &mut w)
        .unwrap_err();
    assert!(e.message.contains("norm"), "{}", e.message);
    assert!(w.is_empty());
}

#[test]
fn quaternion_norm_1_001_warns_and_normalises() {
    let mut w = Vec::new();
    let t = Transform::from_quaternion([0.0, 0.0, 0.0, 1.001], QuatOrder::Xyzw, [0.0; 3], &mut w)
        .unwrap();
    assert_eq!(w.len(), 1);
    assert_eq!(w[0].code, Code::NonUnitQuaternion);
    assert_eq!(w[0].code.name(), "non-unit-quaternion");
    assert!(w[0].message.contains("1.001"), "{}", w[0].message);
    assert!((t.rotation() - Matrix3::identity()).norm() < 1e-15);
    // Seven printed digits stay quiet.
    let mut w = Vec::new();
    Transform::from_quaternion(
        [0.0, 0.0, 0.0, 1.0000001],
        QuatOrder::Xyzw,
        [0.0; 3],
        &mut w,
    )
    .unwrap();
    assert!(w.is_empty());
}

#[test]
fn quaternion_norm_1e300_is_normalised_with_a_warning() {
    let mut w = Vec::new();
    let t = Transform::from_quaternion([0.0, 0.0, 1e300, 1e300], QuatOrder::Xyzw, [0.0; 3], &mut w)
        .unwrap();
    assert_eq!(w.len(), 1);
    assert_eq!(w[0].code, Code::NonUnitQuaternion);
    assert!((t.rotation() - rz(FRAC_PI_2)).norm() < 1e-15);
    // Beyond f64 range the norm is infinite: an error, not a panic.
    let e = Transform::from_quaternion([1e308; 4], QuatOrder::Xyzw, [0.0; 3], &mut w).unwrap_err();
    assert_eq!(e.code, Code::Invalid);
}

#[test]
fn det_minus_one_is_an_error_that_says_det() {
    let mut w = Vec::new();
    let e = Transform::from_matrix3(
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]],
        [0.0; 3],
        &mut w,
    )
    .unwrap_err();
    assert_eq!(e.code, Code::Invalid);
    assert!(e.message.contains("det"), "{}", e.message);
    assert!(e.message.contains("-1"), "{}", e.message);
}

#[test]
fn non_orthonormal_matrices_warn_or_fail_saying_how_far_off() {
    let mut w = Vec::new();
    // Four-digit rounding of Rz(0.3): projected with a warning.
    let r = rz(0.3);
    let rounded = [
        [
            (r[(0, 0)] * 1e4).round() / 1e4,
            (r[(0, 1)] * 1e4).round() / 1e4,
            0.0,
        ],
        [
            (r[(1, 0)] * 1e4).round() / 1e4,
            (r[(1, 1)] * 1e4).round() / 1e4,
            0.0,
        ],
        [0.0, 0.0, 1.0],
    ];
    let t = Transform::from_matrix3(rounded, [0.0; 3], &mut w).unwrap();
    assert_eq!(w.len(), 1);
    assert_eq!(w[0].code, Code::NonOrthonormalRotation);
    let rt = t.rotation();
    assert!((rt.transpose() * rt - Matrix3::identity()).norm() < 1e-14);
    assert!((rt.determinant() - 1.0).abs() < 1e-14);
    assert!((rt - r).norm() < 1e-4);
    // Far off: an error with the size of the defect.
    let e = Transform::from_matrix3(
        [[1.1, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        [0.0; 3],
        &mut w,
    )
    .unwrap_err();
    assert!(
        e.message.contains("||R^T R - I||_F = 2.100e-1"),
        "{}",
        e.message
    );
}

#[test]
fn bad_bottom_row_is_an_error() {
    let mut w = Vec::new();
    let mut m = [[0.0; 4]; 4];
    for (i, row) in m.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    m[3] = [0.0, 0.0, 0.1, 1.0];
    let e = Transform::from_matrix4(m, &mut w).unwrap_err();
    assert!(e.message.contains("bottom row"), "{}", e.message);
    m[3] = [0.0, 0.0, 0.0, 2.0];
    assert!(Transform::from_matrix4(m, &mut w).is_err());
    m[3] = [0.0, 0.0, 0.0, 1.0];
    m[0][3] = 0.5;
    let t = Transform::from_matrix4(m, &mut w).unwrap();
    assert_eq!(t.translation(), &Vector3::new(0.5, 0.0, 0.0));
    assert_eq!(t.matrix4()[(0, 3)], 0.5);
}

#[test]
fn non_finite_numbers_are_errors_never_panics() {
    let mut w = Vec::new();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for k in 0..3 {
            let mut d = [0.1, 0.2, 0.3];
            d[k] = bad;
            assert!(Transform::from_translation(d).is_err());
            assert!(Transform::from_rpy([0.0; 3], d).is_err());
            assert!(Transform::from_ypr([0.0; 3], d).is_err());
            assert!(Transform::from_axis_angle([0.0, 0.0, 1.0], 0.5, d).is_err());
            assert!(Transform::from_axis_angle([0.0, 0.0, 1.0], 0.0, d).is_err());
            assert!(Transform::from_rotation_vector([0.0, 0.0, 0.5], d).is_err());
            assert!(Transform::from_rotation_vector([0.0; 3], d).is_err());
            assert!(
                Transform::from_quaternion([0.0, 0.0, 0.0, 1.0], QuatOrder::Xyzw, d, &mut w)
                    .is_err()
            );
            assert!(Transform::from_matrix3(
                [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                d,
                &mut w
            )
            .is_err());
            let mut v = [0.1, 0.2, 0.3];
            v[k] = bad;
            assert!(Transform::from_rpy(v, [0.0; 3]).is_err());
            assert!(Transform::from_axis_angle(v, 0.5, [0.0; 3]).is_err());
            assert!(Transform::from_rotation_vector(v, [0.0; 3]).is_err());
        }
        assert!(Transform::from_axis_angle([0.0, 0.0, 1.0], bad, [0.0; 3]).is_err());
        for k in 0..4 {
            let mut q = [0.0, 0.0, 0.0, 1.0];
            q[k] = bad;
            assert!(Transform::from_quaternion(q, QuatOrder::Xyzw, [0.0; 3], &mut w).is_err());
            assert!(Transform::from_quaternion(q, QuatOrder::Wxyz, [0.0; 3], &mut w).is_err());
        }
        for i in 0..4 {
            for j in 0..4 {
                let mut m = [[0.0; 4]; 4];
                for (k, row) in m.iter_mut().enumerate() {
                    row[k] = 1.0;
                }
                m[i][j] = bad;
                let e = Transform::from_matrix4(m, &mut w).unwrap_err();
                assert!(e.message.contains("finite"), "{}", e.message);
                if i < 3 && j < 3 {
                    let r = [
                        [m[0][0], m[0][1], m[0][2]],
                        [m[1][0], m[1][1], m[1][2]],
                        [m[2][0], m[2][1], m[2][2]],
                    ];
                    assert!(Transform::from_matrix3(r, [0.0; 3], &mut w).is_err());
                }
            }
        }
        // A transform made non-finite after construction: analyze refuses it.
        let t = Transform::from_translation([1.0, 0.0, 0.0])
            .unwrap()
            .scaled_translation(bad);
        assert!(analyze(&t, &[1.0], DEFAULT_PITCH_TOL).is_err());
        let _ = t.screw(DEFAULT_PITCH_TOL); // no panic
    }
    assert!(w.is_empty());
}

#[test]
fn huge_values_have_defined_outcomes() {
    // Translations of 1e12 m.
    let t = Transform::from_rpy([PI, 0.0, 0.0], [1e12, -1e12, 1e12]).unwrap();
    let a = an(&t);
    let delta = 3f64.sqrt() * 1e12;
    assert!((a.lever_arm_m - delta).abs() <= 1e-15 * delta);
    assert!((a.adjoint.singular_values[0] - delta).abs() <= 1e-12 * delta);
    assert!((a.adjoint.singular_values[5] * delta - 1.0).abs() <= 1e-12);
    let b = a.certificate.as_slice()[0].band;
    assert!(b[0] > 0.0 && b[1].is_finite());
    assert!(a.adjoint.ata_minus_i_rel.is_finite());
    assert!(a.screw.translation_along_axis.unwrap().is_finite());
    // Angles of 1e6 rad are reduced mod 2 pi by the trig functions.
    let red = 1e6f64.rem_euclid(2.0 * PI);
    let t = Transform::from_rpy([1e6, 0.0, 0.0], [0.0; 3]).unwrap();
    assert!((t.rotation() - rx(red)).norm() < 1e-9);
    let t = Transform::from_axis_angle([0.0, 2.0, 0.0], 1e6, [0.0; 3]).unwrap();
    assert!((t.rotation() - ry(red)).norm() < 1e-9);
    let r = t.rotation();
    assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-14);
    // An axis whose squared norm would overflow.
    let t = Transform::from_axis_angle([1e300, 1e300, 0.0], PI, [0.0; 3]).unwrap();
    let e = t.rotation_angle_axis().1.unwrap();
    assert!((e - Vector3::new(1.0, 1.0, 0.0) / 2f64.sqrt()).norm() < 1e-15);
    // A rotation vector that large has a finite norm (computed without overflow):
    // a valid, if meaningless, rotation; never a NaN matrix or a panic.
    let t = Transform::from_rotation_vector([1e300, 1e300, 1e300], [0.0; 3]).unwrap();
    let r = t.rotation();
    assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-14);
    assert!((r.determinant() - 1.0).abs() < 1e-14);
    assert!(Transform::from_axis_angle([0.0; 3], 1.0, [0.0; 3]).is_err());
}

// ---------------------------------------------------------------- screw edges

#[test]
fn identity() {
    let t = Transform::identity();
    let a = an(&t);
    assert_eq!(a.screw.kind, ScrewKind::Identity);
    assert_eq!(a.angle_rad, 0.0);
    assert!(a.axis.is_none() && a.screw.translation_along_axis.is_none());
    assert_eq!(a.adjoint.singular_values, [1.0; 6]);
    assert!(a.adjoint.orthogonal);
    assert_eq!(a.adjoint.ata_minus_i_rel, 0.0);
    assert_eq!(a.certificate.as_slice()[0].band, [1.0, 1.0]);
    assert!(a.adapted_metric.exists);
    assert_eq!(a.adapted_metric.reason, AdaptedReason::Identity);
    assert_eq!(a.adapted_metric.matrix, Some(Matrix6::identity()));
    assert_eq!(a.adapted_metric.invariance_residual, Some(0.0));
    assert!(a.detectors.iter().all(|v| v.invariant_on_rig));
    assert_eq!(t.inverse(), t);
    assert_eq!(t.compose(&t), t);
}

#[test]
fn half_turns_about_several_axes() {
    for axis in [
        [1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, -2.0, 3.0],
        [-0.3, -0.4, 0.5],
        [-1.0, -1.0, -1.0],
    ] {
        let e0 = Vector3::from(axis).normalize();
        for d in [[0.0, 0.0, 0.0], [0.3, -0.2, 0.1], [-0.3, 0.2, -0.1]] {
            let t = Transform::from_axis_angle(axis, PI, d).unwrap();
            let s = t.screw(DEFAULT_PITCH_TOL);
            assert!((s.angle - PI).abs() < 1e-15, "{axis:?}: angle {}", s.angle);
            assert!(s.half_turn);
            let e = s.axis.unwrap();
            assert!((e.dot(&e0).abs() - 1.0).abs() < 1e-15, "{axis:?}: axis {e}");
            let h = s.translation_along_axis.unwrap();
            assert!(h >= 0.0, "{axis:?}: h = {h}");
            assert!((h - e0.dot(&Vector3::from(d)).abs()).abs() < 1e-15);
            let si = t.inverse().screw(DEFAULT_PITCH_TOL);
            assert!((si.translation_along_axis.unwrap() - h).abs() < 1e-15);
            if h == 0.0 {
                // Canonical sign: first non-zero component positive.
                let first = e.iter().find(|x| x.abs() > 1e-12).unwrap();
                assert!(*first > 0.0);
            }
            // Axis point: c = d_perp / 2 at a half-turn.
            let dv = Vector3::from(d);
            let c = s.axis_point.unwrap();
            assert!((c - 0.5 * (dv - e * e.dot(&dv))).norm() < 1e-15);
        }
    }
}

#[test]
fn just_short_of_a_half_turn_keeps_the_axis_sign() {
    // phi = pi - 1e-9: the skew part (sin phi = 1e-9) still fixes the sign, so the
    // axis is +e even when h < 0, the inverse's is -e, and h agrees.
    let e0 = Vector3::new(1.0, -2.0, 3.0).normalize();
    let phi = PI - 1e-9;
    let d = [0.1, 0.2, -0.3]; // e0 . d < 0
    let t = Transform::from_axis_angle([e0.x, e0.y, e0.z], phi, d).unwrap();
    let s = t.screw(DEFAULT_PITCH_TOL);
    assert!(!s.half_turn);
    assert!((s.angle - phi).abs() < 1e-15);
    let e = s.axis.unwrap();
    assert!((e - e0).norm() < 1e-12, "axis {e}");
    let h = s.translation_along_axis.unwrap();
    assert!((h - e0.dot(&Vector3::from(d))).abs() < 1e-15 && h < 0.0);
    let si = t.inverse().screw(DEFAULT_PITCH_TOL);
    assert!((si.axis.unwrap() + e0).norm() < 1e-12);
    assert!((si.translation_along_axis.unwrap() - h).abs() < 1e-15);
}

#[test]
fn tiny_angle_is_a_pure_translation() {
    // phi = 1e-12: the axis would lie ||d|| / phi = 1e11 m away: treated as no
    // rotation (ANGLE_ZERO_TOL = 1e-9); the angle itself is still reported.
    let t = Transform::from_axis_angle([0.0, 0.0, 1.0], 1e-12, [0.1, 0.0, 0.0]).unwrap();
    let a = an(&t);
    assert!((a.angle_rad - 1e-12).abs() < 1e-20);
    assert_eq!(a.screw.kind, ScrewKind::PureTranslation);
    assert!(a.axis.is_none());
    assert!(!a.adapted_metric.exists);
    assert_eq!(a.adapted_metric.reason, AdaptedReason::PureTranslation);
    let t = Transform::from_axis_angle([0.0, 0.0, 1.0], 1e-12, [0.0; 3]).unwrap();
    assert_eq!(an(&t).screw.kind, ScrewKind::Identity);
    // Just above the threshold the axis is accurate.
    let t = Transform::from_axis_angle([0.0, 0.6, 0.8], 1e-8, [0.0; 3]).unwrap();
    let s = t.screw(DEFAULT_PITCH_TOL);
    assert!((s.angle - 1e-8).abs() < 1e-22);
    assert!((s.axis.unwrap() - Vector3::new(0.0, 0.6, 0.8)).norm() < 1e-8);
}

#[test]
fn pure_rotation_leaves_every_isotropic_family_invariant() {
    // Paper, Proposition "Orthogonality": d = 0 => Ad(T) orthogonal.
    let t = Transform::from_rpy([0.1, 0.2, 0.3], [0.0; 3]).unwrap();
    let a = an(&t);
    assert_eq!(a.screw.kind, ScrewKind::ZeroPitch);
    assert!(a.adjoint.orthogonal);
    assert_eq!(a.adjoint.singular_values, [1.0; 6]);
    assert_eq!(a.adjoint.ata_minus_i_rel, 0.0);
    assert_eq!(a.screw.axis_point, Some(Vector3::zeros()));
    for f in [
        Family::Unnormalized,
        Family::CharacteristicLength,
        Family::BlockScaling,
    ] {
        let (eq, inv, _) = verdict(&a, f);
        assert!(!eq && inv, "{f:?}");
    }
    // A general rotation mixes axes: Jacobi is not invariant.
    let (_, inv, reason) = verdict(&a, Family::Jacobi);
    assert!(!inv);
    assert_eq!(reason, VerdictReason::JacobiMixesAxes);
    // The adapted metric of a rotation about the origin is I6.
    let m0 = a.adapted_metric.matrix.unwrap();
    assert!((m0 - Matrix6::identity()).norm() == 0.0);
    // Numerically: A^T A = I.
    let ad = t.adjoint();
    assert!((ad.transpose() * ad - Matrix6::identity()).norm() < 1e-15);
    // An exact signed permutation: Jacobi is invariant too.
    let mut w = Vec::new();
    let p = Transform::from_matrix3(
        [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
        [0.0; 3],
        &mut w,
    )
    .unwrap();
    let (_, inv, reason) = verdict(&an(&p), Family::Jacobi);
    assert!(inv);
    assert_eq!(reason, VerdictReason::JacobiSignedPermutation);
}

#[test]
fn pure_translation_admits_no_adapted_metric() {
    let t = Transform::from_translation([0.04165, 0.02326, -0.0284]).unwrap();
    let a = an(&t);
    assert_eq!(a.screw.kind, ScrewKind::PureTranslation);
    assert!(!a.adapted_metric.exists);
    assert!(a.adapted_metric.matrix.is_none());
    assert!(a.adapted_metric.invariance_residual.is_none());
    assert_eq!(a.adapted_metric.reason, AdaptedReason::PureTranslation);
    assert!(a
        .adapted_metric
        .reason
        .text()
        .starts_with("pure translation"));
    assert!(!a.adjoint.orthogonal);
    for v in &a.detectors {
        assert_eq!(
            v.invariant_on_rig,
            v.family == Family::PointDisplacement,
            "{v:?}"
        );
        assert_eq!(v.equivariant_rule, v.family == Family::PointDisplacement);
    }
}

#[test]
fn nonzero_pitch_says_why() {
    // A general screw: 30 degrees about z and 5 cm along it.
    let t = Transform::from_rpy([0.0, 0.0, PI / 6.0], [0.1, 0.0, 0.05]).unwrap();
    let a = an(&t);
    assert_eq!(a.screw.kind, ScrewKind::General);
    assert!((a.screw.translation_along_axis.unwrap() - 0.05).abs() < 1e-15);
    assert!((a.screw.pitch.unwrap() - 0.05 / (PI / 6.0)).abs() < 1e-15);
    assert!(!a.adapted_metric.exists);
    assert_eq!(a.adapted_metric.reason, AdaptedReason::NonzeroPitch);
    assert!(a.adapted_metric.reason.text().contains("defective"));
    assert_eq!(
        a.adapted_metric.translation_along_axis,
        Some(a.screw.translation_along_axis.unwrap())
    );
    let (_, inv, r) = verdict(&a, Family::AdaptedConstant);
    assert!(!inv);
    assert_eq!(r, VerdictReason::AdaptedNonzeroPitch);
}

#[test]
fn pitch_tolerance_is_configurable_and_h_is_reported() {
    // A half-turn about x with 1e-7 m along the axis (a value printed to 7 digits).
    let mut w = Vec::new();
    let t = Transform::from_matrix3(
        [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]],
        [1e-7, 0.0, -0.05],
        &mut w,
    )
    .unwrap();
    let strict = analyze(&t, &[1.0], DEFAULT_PITCH_TOL).unwrap();
    assert_eq!(strict.screw.kind, ScrewKind::General);
    assert!(!strict.adapted_metric.exists);
    assert_eq!(strict.adapted_metric.translation_along_axis, Some(1e-7));
    assert_eq!(strict.adapted_metric.pitch_tol, DEFAULT_PITCH_TOL);
    let loose = analyze(&t, &[1.0], 1e-6).unwrap();
    assert_eq!(loose.screw.kind, ScrewKind::ZeroPitch);
    assert!(loose.adapted_metric.exists);
    assert_eq!(loose.adapted_metric.translation_along_axis, Some(1e-7));
    assert_eq!(loose.pitch_tol, 1e-6);
    // Built on the axis of the nearly-zero-pitch rig, M0 is invariant only up to h.
    assert!(loose.adapted_metric.invariance_residual.unwrap() < 1e-6);
    for bad in [-1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(analyze(&t, &[1.0], bad).unwrap_err().code, Code::Usage);
    }
}

#[test]
fn verdict_table_for_a_general_rig() {
    let t = Transform::from_rpy([0.1, -0.2, 0.3], [0.2, 0.1, -0.05]).unwrap();
    let s = t.screw(DEFAULT_PITCH_TOL);
    let v = family_verdicts(&t, &s);
    assert_eq!(v.map(|x| x.family), Family::ALL);
    for x in v {
        assert_eq!(x.equivariant_rule, x.family == Family::PointDisplacement);
        assert_eq!(x.invariant_on_rig, x.family == Family::PointDisplacement);
        assert!(!x.reason.text().is_empty());
    }
    assert_eq!(v[3].reason, VerdictReason::JacobiLeverArm);
    assert_eq!(
        Family::ALL.map(|f| f.name()),
        [
            "unnormalized",
            "characteristic_length",
            "block_scaling",
            "jacobi",
            "adapted_constant",
            "point_displacement"
        ]
    );
}

// ---------------------------------------------------------------- certificate

#[test]
fn paper_band_at_the_largest_lever_arm() {
    // delta = 0.552 m, l = 1 => [0.58, 1.72] (paper, Section V).
    let t = Transform::from_rpy([0.0, 0.0, 0.0], [0.552, 0.0, 0.0]).unwrap();
    let a = analyze(&t, &[1.0], DEFAULT_PITCH_TOL).unwrap();
    let b = a.certificate.as_slice()[0].band;
    assert_eq!((b[0] * 100.0).round() / 100.0, 0.58);
    assert_eq!((b[1] * 100.0).round() / 100.0, 1.72);
    // Closed form by hand: s_max = 0.276 + sqrt(1 + 0.276^2).
    let smax = 0.276 + (1.0f64 + 0.276 * 0.276).sqrt();
    assert!((b[1] - smax * smax).abs() < 1e-15);
    assert!((b[0] * b[1] - 1.0).abs() < 1e-15);
    assert!((sigma_min(0.552) * sigma_max(0.552) - 1.0).abs() < 1e-15);
}

#[test]
fn certificate_edges_and_errors() {
    let de = 0.552;
    let [lo, hi] = band(de);
    let k = 0.01;
    // Inside (and on the edges): not certified.
    for r in [
        1.0,
        lo,
        hi,
        0.5 * (lo + hi),
        lo * (1.0 + 1e-15),
        hi * (1.0 - 1e-15),
    ] {
        assert!(!certifies_no_crossing(r * k, k, de).unwrap(), "ratio {r}");
    }
    // Outside by a relative 1e-12: certified.
    for r in [lo * (1.0 - 1e-12), hi * (1.0 + 1e-12), 0.0, -1.0, 100.0] {
        assert!(certifies_no_crossing(r * k, k, de).unwrap(), "ratio {r}");
    }
    // No lever arm: the band is the point 1, only lambda = kappa is uncertain.
    assert!(!certifies_no_crossing(k, k, 0.0).unwrap());
    assert!(certifies_no_crossing(k * (1.0 + 1e-12), k, 0.0).unwrap());
    // Errors: kappa <= 0 or non-finite, lambda non-finite, delta_eff invalid.
    for bad_k in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(
            certifies_no_crossing(0.1, bad_k, de).unwrap_err().code,
            Code::Usage
        );
    }
    assert!(certifies_no_crossing(f64::NAN, k, de).is_err());
    assert!(certifies_no_crossing(0.1, k, -1.0).is_err());
    assert!(certifies_no_crossing(0.1, k, f64::NAN).is_err());
    // Entry method agrees.
    let c = certificates(0.552, &[1.0]).unwrap();
    assert!(c.as_slice()[0].certifies_no_crossing(2.0 * k, k).unwrap());
}

#[test]
fn characteristic_lengths() {
    let c = certificates(0.5, &[1.0, 0.25, 2.85]).unwrap();
    assert_eq!(c.len(), 3);
    let de: Vec<f64> = c.iter().map(|e| e.delta_eff).collect();
    assert_eq!(de, vec![0.5, 2.0, 0.5 / 2.85]);
    assert_eq!(c.as_slice()[1].ell_m, 0.25);
    // Larger l shrinks the band, never to a point.
    assert!(c.as_slice()[2].band[1] < c.as_slice()[0].band[1]);
    assert!(c.as_slice()[2].band[1] > 1.0);
    assert!(certificates(0.5, &[]).unwrap().is_empty());
    assert!(certificates(0.5, &[1.0; MAX_ELLS]).is_ok());
    assert_eq!(
        certificates(0.5, &[1.0; MAX_ELLS + 1]).unwrap_err().code,
        Code::Usage
    );
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(certificates(0.5, &[1.0, bad]).is_err());
        assert!(delta_eff(0.5, bad).is_err());
    }
    assert!(delta_eff(f64::NAN, 1.0).is_err());
    let t = Transform::from_translation([0.3, 0.4, 0.0]).unwrap();
    assert!(analyze(&t, &[1.0; MAX_ELLS + 1], DEFAULT_PITCH_TOL).is_err());
}
