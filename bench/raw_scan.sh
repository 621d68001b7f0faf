#!/usr/bin/env bash
# Issue 16 benchmark: about 1e6 raw points (bench/make_raw_million.py: the real
# Velodyne scan tiled 15 times) read from binary PCD, voxel grid 0.1 m, normals
# estimated and H/M assembled, every family solved: `audit degeneracy
# --estimate-normals --voxel 0.1` against the numpy/scipy peer
# bench/raw_scan_numpy.py in one hyperfine run (target: 2 s).
#
#   bench/raw_scan.sh          (needs hyperfine and a venv with numpy + scipy:
#                               PY=/path/to/python, default bench/.venv/bin/python)
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${BENCH_DIR:-/tmp/audit-bench}
mkdir -p "$dir"
py=${PY:-bench/.venv/bin/python}
f="$dir/raw_million.pcd"
[ -f "$f" ] || "$py" bench/make_raw_million.py "$f"
cargo build --quiet --release --bin audit
hyperfine -N --warmup 1 --runs ${RUNS:-10} --export-json "$dir/raw_scan.json" \
  -n "audit raw 1e6" "target/release/audit degeneracy $f --estimate-normals --voxel 0.1" \
  -n "audit raw 1e6, 1 core" "taskset -c 0 target/release/audit degeneracy $f --estimate-normals --voxel 0.1" \
  -n "numpy raw 1e6" "$py bench/raw_scan_numpy.py $f"
"$py" - "$dir/raw_scan.json" <<'PY'
import json, sys
for r in json.load(open(sys.argv[1]))["results"]:
    t = sorted(r["times"])
    print(f'{r["command"]}: min {t[0]*1e3:.0f} / median {t[len(t)//2]*1e3:.0f} / max {t[-1]*1e3:.0f} ms')
PY
