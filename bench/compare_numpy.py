#!/usr/bin/env python3
"""numpy/scipy doing the detector's work on the same data as the Rust code.

Reads DIR/points.f64 (N x 6 little-endian doubles, written by
`cargo run --release --example bench_data -- DIR`) and DIR/rust.json (Rust's H,
M, eigenvalues and min/median/max times), then:
  - assembles H = sum a a^T with a = [p x n; n] and M = sum J^T J (from N, sum p,
    sum p p^T, the same moments the Rust code uses) with vectorised numpy;
  - solves scipy.linalg.eigh(H, M);
checks that both agree with Rust, and prints the times and the ratios.
"""
import json, sys, time
import numpy as np
import scipy.linalg

def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])

def assemble(P, N):
    A = np.hstack([np.cross(P, N), N])          # N x 6
    H = A.T @ A
    s = P.sum(axis=0)
    S = P.T @ P
    M = np.zeros((6, 6))
    M[:3, :3] = np.trace(S) * np.eye(3) - S
    M[:3, 3:] = skew(s)
    M[3:, :3] = -skew(s)
    M[3:, 3:] = len(P) * np.eye(3)
    return H, M

def spread_time(f, reps):
    """Min, median and max wall time of `reps` calls."""
    ts = []
    for _ in range(reps):
        t = time.perf_counter()
        f()
        ts.append(time.perf_counter() - t)
    return [float(np.min(ts)), float(np.median(ts)), float(np.max(ts))]

def main():
    d = sys.argv[1] if len(sys.argv) > 1 else "bench/data"
    rust = json.load(open(d + "/rust.json"))
    X = np.fromfile(d + "/points.f64", dtype="<f8").reshape(-1, 6)
    P, N = np.ascontiguousarray(X[:, :3]), np.ascontiguousarray(X[:, 3:])
    H, M = assemble(P, N)
    Hr, Mr = np.array(rust["h"]), np.array(rust["m"])
    rel_h = np.abs(H - Hr).max() / np.abs(Hr).max()
    rel_m = np.abs(M - Mr).max() / np.abs(Mr).max()
    w = scipy.linalg.eigh(H, M, eigvals_only=True)
    rel_w = np.abs(w - np.array(rust["eigenvalues"])).max()
    t_asm = spread_time(lambda: assemble(P, N), 10)
    t_eig = [t / 1000 for t in spread_time(lambda: [scipy.linalg.eigh(Hr, Mr) for _ in range(1000)], 10)]
    ms = lambda t: " / ".join(f"{x * 1e3:.3g}" for x in t)
    out = {
        "n": len(P),
        "numpy_assemble_s": t_asm,
        "scipy_eigh_s": t_eig,
        "rust_assemble_s": rust["assemble_s"],
        "rust_gen_eigen_s": rust["gen_eigen_s"],
        "assemble_ratio_numpy_over_rust_medians": t_asm[1] / rust["assemble_s"][1],
        "eigen_ratio_scipy_over_rust_medians": t_eig[1] / rust["gen_eigen_s"][1],
        "min_median_max_ms": {
            "numpy_assemble": ms(t_asm), "rust_assemble": ms(rust["assemble_s"]),
            "scipy_eigh": ms(t_eig), "rust_gen_eigen": ms(rust["gen_eigen_s"]),
        },
        "agreement": {"H_rel": rel_h, "M_rel": rel_m, "eigenvalues_abs": rel_w},
        "numpy": np.__version__, "scipy": scipy.__version__,
    }
    print(json.dumps(out, indent=2))
    ok = rel_h < 1e-10 and rel_m < 1e-10 and rel_w < 1e-9
    sys.exit(0 if ok else 1)

if __name__ == "__main__":
    main()
