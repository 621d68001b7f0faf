#!/bin/sh
# `audit check` and `audit survey` over 10,000 generated rig files (issue 11:
# each within 2 s), the survey paired with its Python peer
# (bench/survey_python.py) in the same hyperfine run. Run from the repository
# root after `cargo build --release --bin audit`:
#
#   PY=/path/to/venv/bin/python bench/run_check_bench.sh [OUT_DIR]
#
# hyperfine prints min / median / max per command; OUT_DIR keeps the JSON.
set -eu
AUDIT=${AUDIT:-target/release/audit}
PY=${PY:-python3}
OUT=${1:-$(mktemp -d)}
mkdir -p "$OUT"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 bench/gen_rigs.py "$dir/rigs" 10000
"$AUDIT" check "$dir/rigs" --write-baseline "$dir/baseline.json" >/dev/null 2>&1 || true
hyperfine -N -i --warmup 1 --runs 10 --export-json "$OUT/check.json" \
    "$AUDIT check $dir/rigs" \
    "$AUDIT check $dir/rigs --baseline $dir/baseline.json" \
    "$AUDIT check $dir/rigs --write-baseline $dir/baseline.json"
hyperfine -N -i --warmup 1 --runs 10 --export-json "$OUT/survey.json" \
    "$AUDIT survey $dir/rigs --format json" \
    "$PY bench/survey_python.py $dir/rigs"
