#!/usr/bin/env bash
# Whole-process benchmark of `audit degeneracy` on binary PLY files, paired in
# the same hyperfine run with the numpy/scipy peer (bench/degeneracy_numpy.py),
# plus peak memory (GNU time, %M = max RSS from wait4's rusage).
#
#   bench/degeneracy.sh [SIZES...]        default: 10000 100000 1000000 10000000
#
# Writes the clouds (examples/write_cloud.rs: the benchmark cloud, 48 bytes per
# point) to $BENCH_DIR (default /tmp/audit-bench), hyperfine JSON and a
# summary table (bench/summary.py) there. Needs hyperfine, GNU time and
# bench/.venv (numpy + scipy; bench/run_numpy.sh creates it). Single-threaded
# BLAS for the peer; `audit` uses the cores it has (`taskset -c 0` rows: one).
# BASELINE=/path/to/older/audit adds that binary to each run (before/after).
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${BENCH_DIR:-/tmp/audit-bench}
mkdir -p "$dir"
sizes=("$@")
[ ${#sizes[@]} -eq 0 ] && sizes=(10000 100000 1000000 10000000)
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1
cargo build --quiet --release --bin audit --example write_cloud
audit=target/release/audit
py=bench/.venv/bin/python
for n in "${sizes[@]}"; do
  f="$dir/c$n.ply"
  [ -f "$f" ] || target/release/examples/write_cloud "$f" "$n" ply-le
  runs=$(( n >= 10000000 ? 10 : 30 ))
  extra=()
  [ -n "${BASELINE:-}" ] && extra=(-n "baseline $n" "$BASELINE degeneracy $f")
  hyperfine -N --warmup 3 --runs "$runs" --export-json "$dir/time_$n.json" \
    "${extra[@]}" \
    -n "audit $n" "$audit degeneracy $f" \
    -n "audit 1 core $n" "taskset -c 0 $audit degeneracy $f" \
    -n "numpy $n" "$py bench/degeneracy_numpy.py $f" > /dev/null
  whos=(audit numpy)
  [ -n "${BASELINE:-}" ] && whos+=(baseline)
  for who in "${whos[@]}"; do
    for _ in 1 2 3; do
      case $who in
        audit) cmd=("$audit" degeneracy "$f") ;;
        baseline) cmd=("$BASELINE" degeneracy "$f") ;;
        *) cmd=("$py" bench/degeneracy_numpy.py "$f") ;;
      esac
      /usr/bin/time -f "%M" -o "$dir/rss.tmp" "${cmd[@]}" > /dev/null
      echo "$who $n $(cat "$dir/rss.tmp")" >> "$dir/rss.txt"
    done
  done
done
bench/.venv/bin/python bench/summary.py "$dir" "${sizes[@]}"
