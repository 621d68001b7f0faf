#!/usr/bin/env bash
# `audit spread` and `audit check --fleet-tolerance` over generated fleets of
# 1,000 and 10,000 vehicles (bench/gen_fleet.py), each size in one hyperfine
# run with its peers:
#   - the Python peer (bench/fleet_python.py: PyYAML + scipy Rotation.mean,
#     the same mean and spread), run with $PY (a venv with numpy, scipy and
#     pyyaml);
#   - reading the files and nothing else: `find DIR -type f | xargs cat`.
# Before timing, the peer's mean and spread are checked equal to `audit
# spread`'s (quaternion and translation to 1e-9, stds to 1e-6), and `check`
# must name exactly the vehicles gen_fleet.py moved. Then peak RSS of every
# command (/usr/bin/time -f %M, median of 3 runs), and the growth exponent of
# each command's median time (log-log slope from the smallest to the largest
# size: 1 is linear).
#
#   PY=/path/to/venv/bin/python bench/fleet_bench.sh [OUT_DIR]
#   SIZES="100 300" RUNS=2 bench/fleet_bench.sh /tmp/f     (a quick check)
#   SIZES="1000 100000" bench/fleet_bench.sh                 (issue 29's sizes)
#
# A size of 100,000 vehicles or more is timed RUNS_BIG times (default 2, no
# warm-up) and its peak RSS taken once: the Python peer takes about a minute
# a run there.
#
# Writes OUT_DIR/fleet.md (min/median/max per command and size, peak RSS,
# the load before and after each size) beside hyperfine's JSON. The fleets
# are generated under OUT_DIR/fleet_N and deleted after their size. Run on an
# idle machine: the figures go in BENCHMARKS.md with the load.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-/tmp/fleet-bench}
SIZES=${SIZES:-1000 10000}
RUNS=${RUNS:-10}
RUNS_BIG=${RUNS_BIG:-2}
PY=${PY:-python3}
command -v hyperfine >/dev/null || { echo "hyperfine not found (apt-get install hyperfine)" >&2; exit 2; }
"$PY" -c "import numpy, scipy, yaml" 2>/dev/null ||
  { echo "$PY lacks numpy, scipy or pyyaml: set PY to a venv's python with them" >&2; exit 2; }
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
# AUDIT=path: time that binary instead of building the release one.
if [ -z "${AUDIT:-}" ]; then
  cargo build --release -q --bin audit
  AUDIT=$PWD/target/release/audit
fi
: > "$OUT/rss.txt"
: > "$OUT/load.txt"
for n in $SIZES; do
  dir="$OUT/fleet_$n"
  rm -rf "$dir"
  python3 bench/gen_fleet.py "$dir" "$n"
  # The same answer first: a faster wrong answer is no figure.
  "$AUDIT" spread "$dir" --from base_link --to velodyne_top --format json > "$OUT/spread_$n.json"
  "$PY" bench/fleet_python.py "$dir" > "$OUT/peer_$n.json"
  "$PY" bench/fleet_compare.py "$OUT/spread_$n.json" "$OUT/peer_$n.json"
  set +e
  "$AUDIT" check "$dir" --pair base_link:velodyne_top --fleet-tolerance 5,0.5 --format json > "$OUT/check_$n.json"
  code=$?
  set -e
  [ "$code" -eq 1 ] || { echo "check on $n vehicles: expected exit 1 (moved vehicles), found $code" >&2; exit 1; }
  "$PY" bench/fleet_compare.py --check "$OUT/check_$n.json" "$n"
  cmds=(
    "$AUDIT spread $dir --from base_link --to velodyne_top --format json"
    "$AUDIT check $dir --pair base_link:velodyne_top --fleet-tolerance 5,0.5"
    "$PY bench/fleet_python.py $dir"
    "sh -c 'find $dir -type f | xargs cat >/dev/null'"
  )
  runs=$RUNS warmup=1 rss_runs=3
  if [ "$n" -ge 100000 ]; then
    runs=$RUNS_BIG warmup=0 rss_runs=1
  fi
  echo "$n before: $(uptime)" >> "$OUT/load.txt"
  # -i: `check` exits 1 on the moved vehicles; the time is still the run's.
  hyperfine -N -i --warmup "$warmup" --runs "$runs" --export-json "$OUT/time_$n.json" "${cmds[@]}" >/dev/null
  for i in "${!cmds[@]}"; do
    for _ in $(seq "$rss_runs"); do
      /usr/bin/time -f "%M" -o "$OUT/m" sh -c "${cmds[$i]} >/dev/null 2>&1" || true
      echo "$n $i $(tail -1 "$OUT/m")" >> "$OUT/rss.txt"
    done
  done
  echo "$n after: $(uptime)" >> "$OUT/load.txt"
  rm -rf "$dir"
done
"$PY" bench/fleet_compare.py --table "$OUT" $SIZES > "$OUT/fleet.md"
cat "$OUT/fleet.md"
