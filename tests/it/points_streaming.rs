//! Streaming decode into the accumulator: chunked and whole-file reads give
//! the same bits for every format (read boundaries anywhere inside a record,
//! lying headers), threads do not change the result, the SIMD kernel agrees
//! with the scalar reference, the frame change by congruence agrees with
//! re-expressing the points, and `audit degeneracy` holds no cloud in memory.

use extrinsic_audit::internals::degeneracy::points::*;
use extrinsic_audit::internals::degeneracy::scene::{
    random_cloud, synthesize, Preprocess, SceneKind, SceneRng,
};
use extrinsic_audit::internals::degeneracy::{
    reexpress, rel_diff, Accumulator, Assembly, Kernel, BLOCK,
};
use extrinsic_audit::Transform;
use std::io::Read;
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/detector")
        .join(name)
}

/// A reader that returns at most `step` bytes per call (and sometimes fewer),
/// so that read boundaries fall inside headers, lines and binary records.
struct Trickle<'a> {
    bytes: &'a [u8],
    step: usize,
    calls: usize,
}

impl Read for Trickle<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        self.calls += 1;
        // Alternate full and shorter reads (every read may be short).
        let k = if self.calls.is_multiple_of(3) {
            self.step / 2 + 1
        } else {
            self.step
        };
        let n = k.min(buf.len()).min(self.bytes.len());
        buf[..n].copy_from_slice(&self.bytes[..n]);
        self.bytes = &self.bytes[n..];
        Ok(n)
    }
}

fn trickle(bytes: &[u8], step: usize) -> Trickle<'_> {
    Trickle {
        bytes,
        step,
        calls: 0,
    }
}

/// Bit-for-bit equality of two assemblies.
fn same_bits(a: &Assembly, b: &Assembly, what: &str) {
    assert_eq!(a.count, b.count, "{what}: count");
    let bits = |m: &nalgebra::Matrix6<f64>| m.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.h), bits(&b.h), "{what}: H");
    assert_eq!(bits(&a.m), bits(&b.m), "{what}: M");
    assert_eq!(
        a.weight_sum.to_bits(),
        b.weight_sum.to_bits(),
        "{what}: weight sum"
    );
}

/// A cloud with some non-unit normals (renormalised) and uneven scales.
fn cloud(seed: u64, n: usize) -> (Vec<[f64; 3]>, Vec<[f64; 3]>, Vec<f64>) {
    let mut rng = SceneRng::new(seed);
    let (mut p, mut nn, mut w) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..n {
        p.push([
            rng.normal() * 5.0,
            rng.normal() * 0.01 + 2.0,
            rng.normal() * 300.0,
        ]);
        let u = rng.unit_vector();
        let s = if i % 17 == 0 { 2.5 } else { 1.0 };
        nn.push([u.x * s, u.y * s, u.z * s]);
        w.push(rng.uniform() * 3.0);
    }
    (p, nn, w)
}

/// PLY with a float element before the vertices, float32 properties and a
/// weight, little or big endian.
fn ply_float32_weighted(p: &[[f64; 3]], n: &[[f64; 3]], w: &[f64], little: bool) -> Vec<u8> {
    let fmt = if little {
        "binary_little_endian"
    } else {
        "binary_big_endian"
    };
    let mut out = format!(
        "ply\nformat {fmt} 1.0\nelement camera 2\nproperty float a\nproperty uchar b\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty uchar pad\nproperty float nx\nproperty float ny\nproperty float nz\nproperty double weight\nend_header\n",
        p.len()
    )
    .into_bytes();
    let f = |out: &mut Vec<u8>, x: f32| {
        out.extend_from_slice(&if little {
            x.to_le_bytes()
        } else {
            x.to_be_bytes()
        })
    };
    for _ in 0..2 {
        f(&mut out, 1.5);
        out.push(7);
    }
    for i in 0..p.len() {
        for x in p[i] {
            f(&mut out, x as f32);
        }
        out.push(0xAB);
        for x in n[i] {
            f(&mut out, x as f32);
        }
        let b = if little {
            w[i].to_le_bytes()
        } else {
            w[i].to_be_bytes()
        };
        out.extend_from_slice(&b);
    }
    out
}

/// Every format the readers take, for one cloud (a NaN point in each).
fn every_format(seed: u64, n: usize) -> Vec<(&'static str, Vec<u8>)> {
    let (mut p, nn, w) = cloud(seed, n);
    p[n / 2][1] = f64::NAN;
    vec![
        ("csv", write_csv(&p, &nn, Some(&w))),
        ("ply-ascii", write_ply(&p, &nn, Encoding::Ascii)),
        ("ply-le", write_ply(&p, &nn, Encoding::BinaryLittleEndian)),
        ("ply-be", write_ply(&p, &nn, Encoding::BinaryBigEndian)),
        ("ply-f32-le", ply_float32_weighted(&p, &nn, &w, true)),
        ("ply-f32-be", ply_float32_weighted(&p, &nn, &w, false)),
        ("pcd-ascii", write_pcd(&p, &nn, Encoding::Ascii)),
        (
            "pcd-binary",
            write_pcd(&p, &nn, Encoding::BinaryLittleEndian),
        ),
    ]
}

#[test]
fn chunked_and_whole_decoding_give_identical_h_and_m_for_every_format() {
    for (name, bytes) in every_format(11, 1000) {
        let whole = accumulate_reader(&bytes[..], None).unwrap();
        assert_eq!(
            whole.assembly.count, 999,
            "{name}: the NaN point is skipped"
        );
        assert_eq!(whole.warnings.len(), 2, "{name}: {:?}", whole.warnings);
        // The collecting reader sees the same points in the same blocks.
        let data = parse_points(&bytes).unwrap();
        let collected =
            Assembly::from_points(&data.points, &data.normals, data.weights.as_deref()).unwrap();
        same_bits(&whole.assembly, &collected, name);
        assert_eq!(whole.warnings, data.warnings, "{name}");
        assert_eq!(whole.format, data.format, "{name}");
        for step in [1, 2, 3, 5, 7, 13, 48, 4097] {
            let chunked = accumulate_reader(trickle(&bytes, step), None).unwrap();
            same_bits(
                &whole.assembly,
                &chunked.assembly,
                &format!("{name} step {step}"),
            );
            assert_eq!(whole.warnings, chunked.warnings, "{name} step {step}");
            let d = read_from(trickle(&bytes, step)).unwrap();
            assert_eq!(d.points.len(), data.points.len());
            assert_eq!(
                d.points
                    .iter()
                    .flatten()
                    .map(|x| x.to_bits())
                    .collect::<Vec<_>>(),
                data.points
                    .iter()
                    .flatten()
                    .map(|x| x.to_bits())
                    .collect::<Vec<_>>(),
                "{name} step {step}"
            );
        }
        // From disk, with its own reads.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name);
        std::fs::write(&path, &bytes).unwrap();
        let file = accumulate_file(&path, None).unwrap();
        same_bits(&whole.assembly, &file.assembly, &format!("{name} file"));
    }
}

#[test]
fn the_real_fixtures_stream_like_they_read() {
    for name in [
        "tunnel_small.csv",
        "tunnel_small_noheader.csv",
        "tunnel_small_ascii.ply",
        "tunnel_small_le.ply",
        "tunnel_small_be.ply",
        "tunnel_small_float.ply",
        "tunnel_small_ascii.pcd",
        "tunnel_small_bin.pcd",
        "nonunit.csv",
    ] {
        let d = read_points(&fixture(name)).unwrap();
        let a = Assembly::from_points(&d.points, &d.normals, d.weights.as_deref()).unwrap();
        let s = accumulate_file(&fixture(name), None).unwrap();
        same_bits(&a, &s.assembly, name);
        assert_eq!(s.warnings, d.warnings, "{name}");
        let bytes = std::fs::read(fixture(name)).unwrap();
        for step in [1, 7, 64] {
            let c = accumulate_reader(trickle(&bytes, step), None).unwrap();
            same_bits(&a, &c.assembly, name);
        }
    }
}

#[test]
fn blocks_and_threads_do_not_change_a_bit() {
    // Four whole blocks and a partial one: enough for the threaded paths.
    let n = 4 * BLOCK + 77;
    let (p, nn) = random_cloud(7, n);
    let serial = {
        let mut a = Accumulator::new().threads(1);
        a.add(&p, &nn, None).unwrap();
        a.finish()
    };
    for threads in [0, 2, 3, 5] {
        let mut a = Accumulator::new().threads(threads);
        a.add(&p, &nn, None).unwrap();
        same_bits(&serial, &a.finish(), &format!("{threads} threads"));
    }
    // Batches of any size meet the same block boundaries.
    let mut a = Accumulator::new();
    for (ps, ns) in p.chunks(10_007).zip(nn.chunks(10_007)) {
        a.add(ps, ns, None).unwrap();
    }
    same_bits(&serial, &a.finish(), "batches of 10007");
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in [
        ("le.ply", write_ply(&p, &nn, Encoding::BinaryLittleEndian)),
        ("be.ply", write_ply(&p, &nn, Encoding::BinaryBigEndian)),
        ("bin.pcd", write_pcd(&p, &nn, Encoding::BinaryLittleEndian)),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, &bytes).unwrap();
        // The file path splits by block over the cores; the reader path is serial.
        let file = accumulate_file(&path, None).unwrap();
        same_bits(&serial, &file.assembly, name);
        let reader = accumulate_reader(trickle(&bytes, 65_521), None).unwrap();
        same_bits(&serial, &reader.assembly, name);
    }
}

#[test]
fn a_header_that_lies_about_the_count_is_one_error_however_the_file_is_read() {
    let (p, nn, _) = cloud(3, 300);
    let dir = tempfile::tempdir().unwrap();
    let lie = |bytes: Vec<u8>, from: &str, to: &str| {
        let s = bytes.clone();
        let k = s
            .windows(from.len())
            .position(|w| w == from.as_bytes())
            .unwrap();
        let mut out = s[..k].to_vec();
        out.extend_from_slice(to.as_bytes());
        out.extend_from_slice(&s[k + from.len()..]);
        out
    };
    let cases = [
        (
            "more.ply",
            lie(
                write_ply(&p, &nn, Encoding::BinaryLittleEndian),
                "vertex 300",
                "vertex 301",
            ),
            "holds 300",
        ),
        (
            "more_be.ply",
            lie(
                write_ply(&p, &nn, Encoding::BinaryBigEndian),
                "vertex 300",
                "vertex 1000000",
            ),
            "holds 300",
        ),
        (
            "more_ascii.ply",
            lie(
                write_ply(&p, &nn, Encoding::Ascii),
                "vertex 300",
                "vertex 302",
            ),
            "holds 300",
        ),
        (
            "more.pcd",
            lie(
                write_pcd(&p, &nn, Encoding::BinaryLittleEndian),
                "POINTS 300",
                "POINTS 999",
            ),
            "holds 300",
        ),
        (
            "more_ascii.pcd",
            lie(
                write_pcd(&p, &nn, Encoding::Ascii),
                "POINTS 300",
                "POINTS 301",
            ),
            "holds 300",
        ),
    ];
    for (name, bytes, holds) in cases {
        let whole = accumulate_reader(&bytes[..], None).unwrap_err();
        assert!(
            whole.message.contains("claims") && whole.message.contains(holds),
            "{name}: {whole}"
        );
        for step in [1, 5, 48] {
            let e = accumulate_reader(trickle(&bytes, step), None).unwrap_err();
            assert_eq!(e.message, whole.message, "{name} step {step}");
        }
        assert_eq!(
            parse_points(&bytes).unwrap_err().message,
            whole.message,
            "{name}"
        );
        let path = dir.path().join(name);
        std::fs::write(&path, &bytes).unwrap();
        let e = accumulate_file(&path, None).unwrap_err();
        assert_eq!(e.message, whole.message, "{name}");
        assert!(e.to_string().contains(name), "{e}");
    }
    // A header claiming fewer points than the file holds is the same error
    // however the file is read (it used the first ones silently; issue 12).
    let fewer = lie(
        write_ply(&p, &nn, Encoding::BinaryLittleEndian),
        "vertex 300",
        "vertex 120",
    );
    let whole = parse_points(&fewer).unwrap_err();
    assert!(
        whole
            .message
            .contains("claims 120 vertices of 48 bytes, the file holds 8640 more bytes"),
        "{whole}"
    );
    for step in [3, 4096] {
        let e = accumulate_reader(trickle(&fewer, step), None).unwrap_err();
        assert_eq!(e.message, whole.message, "step {step}");
    }
    let path = dir.path().join("fewer.ply");
    std::fs::write(&path, &fewer).unwrap();
    let e = accumulate_file(&path, None).unwrap_err();
    assert_eq!(e.message, whole.message);
    assert!(e.to_string().contains("fewer.ply"), "{e}");
}

/// `max |a - b| / max |b|` over H and M.
fn kernel_gap(p: &[[f64; 3]], n: &[[f64; 3]], w: Option<&[f64]>) -> f64 {
    let reference = {
        let mut a = Accumulator::with_kernel(Kernel::Scalar);
        a.add(p, n, w).unwrap();
        a.finish()
    };
    let mut worst = 0.0f64;
    for k in Kernel::available() {
        let mut a = Accumulator::with_kernel(k);
        a.add(p, n, w).unwrap();
        let b = a.finish();
        assert_eq!(b.count, reference.count);
        worst = worst
            .max(rel_diff(&b.h, &reference.h))
            .max(rel_diff(&b.m, &reference.m));
    }
    worst
}

#[test]
fn simd_kernel_agrees_with_the_scalar_reference_to_1e12() {
    if Kernel::detect() == Kernel::Scalar {
        eprintln!("no AVX2+FMA on this CPU: only the scalar kernel runs");
    }
    for (seed, n) in [
        (1, 1),
        (2, 3),
        (3, 4),
        (4, 5),
        (5, 255),
        (6, 256),
        (7, 257),
        (8, 1000),
        (9, 100_003),
    ] {
        let (p, nn, w) = cloud(seed, n);
        assert!(kernel_gap(&p, &nn, None) < 1e-12, "seed {seed} n {n}");
        assert!(
            kernel_gap(&p, &nn, Some(&w)) < 1e-12,
            "seed {seed} n {n} weighted"
        );
        let (p, nn) = random_cloud(seed, n);
        assert!(kernel_gap(&p, &nn, None) < 1e-12, "random cloud {seed} {n}");
    }
    // Scenes: the synthetic tunnel and corridor with noise, and the fixtures.
    for kind in [SceneKind::Tunnel, SceneKind::Corridor] {
        let c = synthesize(kind, &Preprocess::pipeline(0.1, 0.01, 3)).unwrap();
        assert!(kernel_gap(&c.points, &c.normals, None) < 1e-12, "{kind:?}");
    }
    for name in [
        "tunnel_small_le.ply",
        "tunnel_small_bin.pcd",
        "tunnel_small_noheader.csv",
    ] {
        let d = read_points(&fixture(name)).unwrap();
        assert!(
            kernel_gap(&d.points, &d.normals, d.weights.as_deref()) < 1e-12,
            "{name}"
        );
    }
}

#[test]
fn the_frame_change_by_congruence_matches_re_expressed_points() {
    let (p, nn, _) = cloud(21, 5000);
    let bytes = write_ply(&p, &nn, Encoding::BinaryLittleEndian);
    let d = parse_points(&bytes).unwrap();
    for (rpy, t) in [
        ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
        ([0.3, -1.2, 2.9], [-4.0, 12.5, 0.25]),
    ] {
        let frame = Transform::from_rpy(rpy, t).unwrap();
        let streamed = accumulate_reader(&bytes[..], Some(&frame))
            .unwrap()
            .assembly;
        let (q, m) = reexpress(&d.points, &d.normals, &frame);
        let direct = Assembly::from_points(&q, &m, None).unwrap();
        assert!(rel_diff(&streamed.h, &direct.h) < 1e-12, "{rpy:?} {t:?}");
        assert!(rel_diff(&streamed.m, &direct.m) < 1e-12, "{rpy:?} {t:?}");
    }
}

/// Peak resident memory (KiB) of `audit degeneracy FILE`, from the kernel's
/// rusage of the process as GNU time reads it (wait4). Not wait4 from here: a
/// child spawned by this (large, multi-threaded) test process starts with
/// this process's high-water mark in its `ru_maxrss`; GNU time is small.
/// `None` without /usr/bin/time.
fn peak_rss_kib(file: &Path) -> Option<u64> {
    let time = Path::new("/usr/bin/time");
    if !time.exists() {
        eprintln!("no /usr/bin/time: peak memory not measured");
        return None;
    }
    let out = std::process::Command::new(time)
        .args(["-f", "peak-rss-kib %M"])
        .arg(assert_cmd::cargo::cargo_bin("audit"))
        .arg("degeneracy")
        .arg(file)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    let line = err.lines().find_map(|l| l.strip_prefix("peak-rss-kib "));
    Some(
        line.and_then(|k| k.trim().parse().ok())
            .expect("GNU time output"),
    )
}

/// Writes the benchmark cloud as binary PLY without holding it.
fn write_big_ply(path: &Path, n: usize) {
    use std::io::Write;
    let mut w = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let header = write_ply(&[], &[], Encoding::BinaryLittleEndian);
    let header = String::from_utf8(header)
        .unwrap()
        .replace("vertex 0", &format!("vertex {n}"));
    w.write_all(header.as_bytes()).unwrap();
    let mut rng = SceneRng::new(2024);
    for _ in 0..n {
        // The draws of `scene::random_cloud`, in its order.
        let q = [rng.uniform(), rng.uniform(), rng.uniform()].map(|x| 20.0 * x - 10.0);
        let u = rng.unit_vector();
        for x in [q[0], q[1], q[2], u.x, u.y, u.z] {
            w.write_all(&x.to_le_bytes()).unwrap();
        }
    }
    w.flush().unwrap();
}

#[test]
fn degeneracy_peak_memory_is_small_on_1e5_points() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.ply");
    write_big_ply(&path, 100_000);
    if let Some(kib) = peak_rss_kib(&path) {
        assert!(kib < 64 * 1024, "peak RSS {kib} KiB");
    }
}

/// `cargo test --release --test it -- --ignored points_streaming::degeneracy_peak_memory`
/// (writes a 480 MB file to the temporary directory).
#[test]
#[ignore = "writes a 480 MB file; run on demand"]
fn degeneracy_peak_memory_stays_under_64_mib_on_1e7_points() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.ply");
    write_big_ply(&path, 10_000_000);
    if let Some(kib) = peak_rss_kib(&path) {
        eprintln!("peak RSS of audit degeneracy on 1e7 points: {kib} KiB");
        assert!(kib < 64 * 1024, "peak RSS {kib} KiB");
    }
}

#[cfg(unix)]
#[test]
fn degeneracy_reads_a_binary_file_from_a_pipe() {
    // Standard input (`-`; a FIFO path is refused, issue 12): no length to
    // split by, read serially.
    let (p, nn) = random_cloud(5, 3000);
    let bytes = write_ply(&p, &nn, Encoding::BinaryLittleEndian);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.ply");
    std::fs::write(&path, &bytes).unwrap();
    let from_file = crate::common::audit()
        .args(["degeneracy", path.to_str().unwrap(), "--format", "json"])
        .output()
        .unwrap();
    let from_pipe = crate::common::audit()
        .args(["degeneracy", "-", "--format", "json"])
        .write_stdin(bytes)
        .output()
        .unwrap();
    assert!(from_pipe.status.success(), "{from_pipe:?}");
    assert_eq!(from_pipe.stdout, from_file.stdout);
}
