#!/usr/bin/env bash
# xacro expansion benchmark (BENCHMARKS.md "xacro expansion"): the whole process
# on the largest xacro packages of the test data (docs/test-data.md), paired in one hyperfine run with
# reading the same PR2 already expanded (Python xacro's URDF), its peer.
# Not a test: run by hand from the repository root. Needs hyperfine.
set -euo pipefail
work=${1:-/tmp/audit-xacro-bench}
mkdir -p "$work"
cargo build --release --bin audit
a=target/release/audit
x=tests/fixtures/xacro
td=$(python3 tools/testdata.py root)
# Every file of the two packages and of the rig's, checked against its sha256.
python3 tools/testdata.py path $(python3 tools/testdata.py list PR2__pr2_common) \
    $(python3 tools/testdata.py list UniversalRobots__Universal_Robots_ROS2_Description) \
    $(python3 tools/testdata.py list ToyotaResearchInstitute__velodyne_simulator) \
    $(python3 tools/testdata.py list IntelRealSense__realsense-ros) >/dev/null
pkgs="--package-path $td/ToyotaResearchInstitute__velodyne_simulator --package-path $td/IntelRealSense__realsense-ros"
hyperfine -N --warmup 5 --runs 40 --export-json "$work/hyperfine.json" \
    "$a $td/PR2__pr2_common/pr2_description/robots/pr2.urdf.xacro --from base_footprint --to laser_tilt_link" \
    "$a $x/expected/pr2.urdf --from base_footprint --to laser_tilt_link" \
    "$a $td/UniversalRobots__Universal_Robots_ROS2_Description/urdf/ur.urdf.xacro --arg ur_type=ur5e --arg name=ur --from base_link --to tool0" \
    "$a $x/own/lidar_rig/urdf/rig.urdf.xacro $pkgs --from base_link --to velodyne"
python3 - "$work/hyperfine.json" <<'PY'
import json, sys
for r in json.load(open(sys.argv[1]))["results"]:
    print(f"{r['min']*1e3:.2f} / {r['median']*1e3:.2f} / {r['max']*1e3:.2f} ms  {r['command']}")
PY
