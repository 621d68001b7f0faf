#!/usr/bin/env bash
# Rig report and survey, each paired with its Python peer in one hyperfine run.
#
#   PY=/path/to/venv/bin/python bench/rig_bench.sh [OUT_DIR]
#
# PY is a Python with numpy, pytransform3d and lxml
# (python3 -m venv /tmp/venv-bench && /tmp/venv-bench/bin/pip install numpy pytransform3d lxml).
# Writes OUT_DIR/rig_<robot>.json and OUT_DIR/survey.json (hyperfine --export-json)
# and prints min / median / max and the ratio of medians.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PY:-python3}
OUT=${1:-/tmp/rig-bench}
mkdir -p "$OUT"
cargo build --release -q
AUDIT=target/release/audit
# The real robots, read in place from the test-data folder (docs/test-data.md).
while read -r name file from to; do
  f=$(python3 tools/testdata.py path "$file")
  hyperfine -N --warmup 3 --runs 30 --export-json "$OUT/rig_$name.json" \
    "$AUDIT $f --from $from --to $to --format json" \
    "$PY bench/rig_pytransform3d.py $f $from $to" >/dev/null
done <<'ROBOTS'
anymal_c Gepetto__example-robot-data/robots/anymal_c_simple_description/urdf/anymal.urdf base lidar
pr2 Gepetto__example-robot-data/robots/pr2_description/urdf/pr2.urdf base_laser_link laser_tilt_link
unitree_h1 unitreerobotics__unitree_ros/robots/h1_description/urdf/h1.urdf pelvis mid360_link
ROBOTS
hyperfine -N --warmup 3 --runs 30 --export-json "$OUT/survey.json" \
  "$AUDIT survey calibrations --format json" \
  "$PY bench/survey_python.py calibrations" >/dev/null 2>&1
python3 - "$OUT" <<'PY'
import glob, json, sys
for f in sorted(glob.glob(f"{sys.argv[1]}/*.json")):
    r = json.load(open(f))["results"]
    ms = lambda x: f"{x['min']*1e3:.2f} / {x['median']*1e3:.2f} / {x['max']*1e3:.2f} ms"
    print(f"{f.rsplit('/',1)[1]:22} audit {ms(r[0])} | python {ms(r[1])} | ratio of medians {r[1]['median']/r[0]['median']:.1f}x")
PY
