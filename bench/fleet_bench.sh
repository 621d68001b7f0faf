#!/bin/sh
# `audit spread` and `audit check --fleet-tolerance` over generated fleets of
# 1,000 and 10,000 vehicles (bench/gen_fleet.py), `spread` paired with its
# Python peer (bench/fleet_python.py: PyYAML + scipy) in the same hyperfine
# run; time should grow linearly. Run from the repository root after
# `cargo build --release --bin audit`, on an idle machine (note `uptime`):
#
#   PY=/path/to/venv/bin/python bench/fleet_bench.sh [OUT_DIR]
#
# hyperfine prints min / median / max per command; OUT_DIR keeps the JSON.
set -eu
AUDIT=${AUDIT:-target/release/audit}
PY=${PY:-python3}
OUT=${1:-$(mktemp -d)}
mkdir -p "$OUT"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
uptime
for n in 1000 10000; do
    python3 bench/gen_fleet.py "$dir/f$n" "$n"
    hyperfine -N -i --warmup 1 --runs 10 --export-json "$OUT/fleet-$n.json" \
        "$AUDIT spread $dir/f$n --from base_link --to velodyne_top --format json" \
        "$AUDIT check $dir/f$n --pair base_link:velodyne_top --fleet-tolerance 5,0.5" \
        "$PY bench/fleet_python.py $dir/f$n"
done
uptime
