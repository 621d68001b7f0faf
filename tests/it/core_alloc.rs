//! "Analysing one transform allocates nothing on the heap": a counting global
//! allocator (per thread, so the test harness's own threads do not interfere)
//! around `analyze` and the other core calls a report needs.

use extrinsic_audit::analysis::metric::{adapted_metric, analyze, family_verdicts};
use extrinsic_audit::geometry::certificate::{
    adjoint_summary, certificates, certifies_no_crossing,
};
use extrinsic_audit::geometry::se3::{QuatOrder, Transform};
use extrinsic_audit::tolerances::DEFAULT_PITCH_TOL;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::hint::black_box;

struct Counting;

thread_local! {
    static ALLOCS: Cell<usize> = const { Cell::new(0) };
}

fn bump() {
    // `try_with`: the thread-local may already be gone during thread teardown.
    let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        bump();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        bump();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        bump();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations_during(f: impl FnOnce()) -> usize {
    let before = ALLOCS.with(|c| c.get());
    f();
    ALLOCS.with(|c| c.get()) - before
}

#[test]
fn counter_sees_allocations() {
    let n = allocations_during(|| {
        black_box(vec![1u8; 16]);
    });
    assert!(n >= 1, "the counting allocator must see a Vec");
}

#[test]
fn analysing_one_transform_allocates_nothing() {
    let mut warnings = Vec::new(); // empty Vec: no allocation until pushed to
    let rigs = [
        // general screw
        Transform::from_rpy([0.01, -0.02, 1.3], [0.12, -0.05, 0.3]).unwrap(),
        // zero pitch, exact half-turn (LIO-SAM Mid-360)
        Transform::from_matrix3(
            [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]],
            [0.0, 0.0, -0.05],
            &mut warnings,
        )
        .unwrap(),
        // pure translation, identity, pure rotation
        Transform::from_translation([0.04165, 0.02326, -0.0284]).unwrap(),
        Transform::identity(),
        Transform::from_axis_angle([0.0, 0.0, 1.0], 0.4, [0.0; 3]).unwrap(),
    ];
    let ells = [1.0, 0.25, 2.85];
    // Warm up anything lazily initialised.
    for t in &rigs {
        black_box(analyze(t, &ells, DEFAULT_PITCH_TOL).unwrap());
    }
    let n = allocations_during(|| {
        for t in &rigs {
            let a = analyze(black_box(t), black_box(&ells), DEFAULT_PITCH_TOL).unwrap();
            for c in a.certificate.iter() {
                black_box(c.certifies_no_crossing(0.02, 0.01).unwrap());
            }
            black_box(a.adapted_metric.reason.text());
            black_box(a.detectors.map(|v| v.reason.text()));
            black_box(a);
        }
    });
    assert_eq!(n, 0, "analyze allocated {n} times");

    // The building blocks and the constructors on valid input, too.
    let n = allocations_during(|| {
        let t = Transform::from_quaternion(
            black_box([0.5, -0.5, 0.5, 0.5]),
            QuatOrder::Xyzw,
            [0.1, 0.2, 0.3],
            &mut warnings,
        )
        .unwrap();
        let u = Transform::from_matrix4(
            black_box([
                [1.0, 0.0, 0.0, 0.5],
                [0.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ]),
            &mut warnings,
        )
        .unwrap();
        let v = t.compose(&u).inverse();
        let s = v.screw(DEFAULT_PITCH_TOL);
        black_box(family_verdicts(&v, &s));
        black_box(adapted_metric(&v, DEFAULT_PITCH_TOL));
        black_box(adjoint_summary(&v));
        black_box(certificates(v.lever_arm(), &[1.0, 2.0]).unwrap());
        black_box(certifies_no_crossing(0.5, 0.01, 0.3).unwrap());
        black_box((
            v.quaternion_xyzw(),
            v.rpy(),
            v.matrix4(),
            v.adjoint_inverse(),
        ));
    });
    assert!(warnings.is_empty());
    assert_eq!(n, 0, "core building blocks allocated {n} times");
}
