#!/usr/bin/env bash
# xacro expansion benchmark (BENCHMARKS.md "xacro expansion"): the whole process
# on the largest xacro packages in the fixtures, paired in one hyperfine run with
# reading the same PR2 already expanded (Python xacro's URDF), its peer.
# Not a test: run by hand from the repository root. Needs hyperfine.
set -euo pipefail
work=${1:-/tmp/audit-xacro-bench}
mkdir -p "$work"
cargo build --release --bin audit
a=target/release/audit
x=tests/fixtures/xacro
hyperfine -N --warmup 5 --runs 40 --export-json "$work/hyperfine.json" \
    "$a $x/pr2_common/pr2_description/robots/pr2.urdf.xacro --from base_footprint --to laser_tilt_link" \
    "$a $x/expected/pr2.urdf --from base_footprint --to laser_tilt_link" \
    "$a $x/Universal_Robots_ROS2_Description/urdf/ur.urdf.xacro --arg ur_type=ur5e --arg name=ur --from base_link --to tool0" \
    "$a $x/own/lidar_rig/urdf/rig.urdf.xacro --from base_link --to velodyne"
python3 - "$work/hyperfine.json" <<'PY'
import json, sys
for r in json.load(open(sys.argv[1]))["results"]:
    print(f"{r['min']*1e3:.2f} / {r['median']*1e3:.2f} / {r['max']*1e3:.2f} ms  {r['command']}")
PY
