#![no_main]
//! The frame graph fed by a byte-decoded sequence of edges (duplicates, cycles,
//! two parents, self loops, hostile numbers) and queries. Invariants: no panic;
//! an edge refused leaves the graph unchanged; a composed transform is finite
//! and orthonormal when Ok; T(a,b) * T(b,a) ~ identity.
use extrinsic_audit::internals::formats::Parsed;
use extrinsic_audit::internals::frames::FrameGraph;
use extrinsic_audit::internals::tolerances::MAX_TRANSLATION_M;
use extrinsic_audit::Edge;
use extrinsic_audit::Format;
use extrinsic_audit::Location;

use extrinsic_audit::{QuatOrder, Transform};
use fuzz_common::assert_sane;
use libfuzzer_sys::fuzz_target;

const NAMES: &[&str] = &[
    "base_link",
    "imu",
    "lidar",
    "os_sensor",
    "camera",
    "a",
    "b",
    "c",
    "d",
    "e",
    "",
    " ",
    "base_link ",
    "\u{00e9}",
    "x/y",
    "very_long_frame_name_with_many_characters",
];

const SPECIAL: &[f64] = &[
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    1e-7,
    1e-4,
    0.1,
    1e12,
    -1e12,
    1e6,
    1e300,
    -1e300,
    1e-300,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::MIN_POSITIVE,
    f64::EPSILON,
    std::f64::consts::PI,
    std::f64::consts::FRAC_PI_2,
    3.0e8,
];

struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn u8(&mut self) -> Option<u8> {
        let (&b, rest) = self.0.split_first()?;
        self.0 = rest;
        Some(b)
    }
    fn f64(&mut self) -> Option<f64> {
        let tag = self.u8()?;
        if tag & 0x80 != 0 {
            return Some(SPECIAL[(tag as usize & 0x7f) % SPECIAL.len()]);
        }
        if tag & 0x40 != 0 {
            if self.0.len() < 8 {
                return None;
            }
            let (b, rest) = self.0.split_at(8);
            self.0 = rest;
            return Some(f64::from_le_bytes(b.try_into().unwrap()));
        }
        Some((tag as f64 - 32.0) / 8.0)
    }
    fn f3(&mut self) -> Option<[f64; 3]> {
        Some([self.f64()?, self.f64()?, self.f64()?])
    }
}

fn transform(b: &mut Bytes) -> Option<Transform> {
    let kind = b.u8()?;
    let mut w = Vec::new();
    let t = match kind % 5 {
        0 => Transform::from_rpy(b.f3()?, b.f3()?),
        1 => Transform::from_quaternion(
            [b.f64()?, b.f64()?, b.f64()?, b.f64()?],
            QuatOrder::Xyzw,
            b.f3()?,
            &mut w,
        ),
        2 => Transform::from_axis_angle(b.f3()?, b.f64()?, b.f3()?),
        3 => Transform::from_rotation_vector(b.f3()?, b.f3()?),
        _ => {
            let mut m = [[0.0; 3]; 3];
            for row in &mut m {
                *row = b.f3()?;
            }
            Transform::from_matrix3(m, b.f3()?, &mut w)
        }
    };
    match t {
        // The loaders refuse translations beyond MAX_TRANSLATION_M (load_str):
        // the graph is only ever fed edges within it.
        Ok(t) if t.translation().iter().any(|x| x.abs() > MAX_TRANSLATION_M) => {
            Some(Transform::identity())
        }
        Ok(t) => {
            assert_sane(&t, "constructor");
            Some(t)
        }
        Err(_) => Some(Transform::identity()),
    }
}

fn close_to_identity(t: &Transform, scale: f64) -> bool {
    let r = t.rotation();
    let re = (r - nalgebra::Matrix3::identity()).norm();
    let de = t.translation().norm();
    re <= 1e-6 && de <= 1e-6 * scale.max(1.0)
}

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    let mut g = FrameGraph::new();
    let loc = Location::at("fuzz.urdf", 1, None);
    let mut max_t: f64 = 1.0;
    while let Some(op) = b.u8() {
        match op % 4 {
            0 | 1 => {
                let Some(p) = b.u8() else { break };
                let Some(c) = b.u8() else { break };
                let Some(t) = transform(&mut b) else { break };
                max_t += t.translation().norm();
                let e = Edge::new(
                    NAMES[p as usize % NAMES.len()],
                    NAMES[c as usize % NAMES.len()],
                    t,
                    loc.clone(),
                    Format::from_name("urdf").unwrap(),
                    "fuzz",
                );
                let before = g.edges().len();
                if op % 4 == 0 {
                    if g.add_edge(e).is_err() {
                        assert_eq!(g.edges().len(), before, "refused edge changed the graph");
                    }
                } else {
                    let loaded = Parsed {
                        edges: vec![e.clone(), e],
                        ..Default::default()
                    };
                    if g.add(loaded).is_err() {
                        assert_eq!(g.edges().len(), before, "refused file changed the graph");
                    }
                }
            }
            2 => {
                let Some(x) = b.u8() else { break };
                let Some(y) = b.u8() else { break };
                let (x, y) = (
                    NAMES[x as usize % NAMES.len()],
                    NAMES[y as usize % NAMES.len()],
                );
                let ab = g.transform(x, y);
                let ba = g.transform(y, x);
                assert_eq!(
                    ab.is_ok(),
                    ba.is_ok(),
                    "T({x},{y}) and T({y},{x}) disagree on success"
                );
                if let (Ok(ab), Ok(ba)) = (ab, ba) {
                    assert_sane(&ab.transform, "composed");
                    let id = ab.transform.compose(&ba.transform);
                    assert!(
                        close_to_identity(&id, max_t),
                        "T({x},{y}) T({y},{x}) = {id:?}, expected identity"
                    );
                }
            }
            _ => {
                let _ = g.tree();
                let _ = g.roots();
                for f in g.frames() {
                    let _ = g.parent_edge(&f);
                }
            }
        }
    }
});
