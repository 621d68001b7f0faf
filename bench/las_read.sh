#!/usr/bin/env bash
# LAS/LAZ read benchmark (issue 16): 1e6 points read by extrinsic-audit
# (`examples/read_xyz.rs`, release) and by laspy (+lazrs) in one hyperfine run.
# Needs a venv with laspy, lazrs, numpy: VENV=/tmp/venv-las (default).
#   bench/las_read.sh [OUTDIR]   (default /tmp/audit-bench)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-/tmp/audit-bench}
venv=${VENV:-/tmp/venv-las}
[ -f "$out/million.laz" ] || "$venv/bin/python" bench/make_las_million.py "$out"
cargo build --release --example read_xyz
bin=target/release/examples/read_xyz
for f in million.las million.laz; do
    "$bin" "$out/$f"
    "$venv/bin/python" bench/las_read_laspy.py "$out/$f"
done
hyperfine -N --warmup 3 --runs 20 --export-json "$out/las_read.json" \
    "$bin $out/million.las" "$venv/bin/python bench/las_read_laspy.py $out/million.las" \
    "$bin $out/million.laz" "$venv/bin/python bench/las_read_laspy.py $out/million.laz"
