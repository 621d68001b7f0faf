#!/usr/bin/env bash
# The growth table of issue 29: `audit check` and `audit survey` over 1,000,
# 10,000 and 100,000 generated rig files (bench/gen_rigs.py), each size in
# one hyperfine run with its peers:
#   - the Python loop (bench/survey_python.py: tomllib + numpy, the same
#     numbers per rig), run with $PY (a venv with numpy);
#   - reading the files and nothing else: `find DIR -type f | xargs cat`.
# Then peak RSS of every command (/usr/bin/time -f %M, median of 3 runs), and
# the growth exponent of each command's median time and peak RSS (least
# squares slope of log(value) against log(files)).
#
#   PY=/path/to/venv/bin/python bench/fleet_growth.sh [OUT_DIR]
#   SIZES="300 1000" RUNS=3 bench/fleet_growth.sh /tmp/g    (a quick check)
#   RUNS_BIG=3: the runs at 100,000 files and more (the Python loop takes
#   about 40 s a run there); AUDIT=path: time that binary instead of
#   building the release one.
#
# Writes OUT_DIR/growth.md (the table, the machine's load before and after
# each size) next to hyperfine's JSON. The rig files are generated under
# OUT_DIR/rigs_N and deleted after their size is measured (100,000 files are
# about 400 MB of inodes). Run on an idle machine.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-/tmp/fleet-growth}
SIZES=${SIZES:-1000 10000 100000}
RUNS=${RUNS:-10}
RUNS_BIG=${RUNS_BIG:-$RUNS}
PY=${PY:-python3}
command -v hyperfine >/dev/null || { echo "hyperfine not found (apt-get install hyperfine)" >&2; exit 2; }
"$PY" -c "import numpy" 2>/dev/null || { echo "$PY has no numpy: set PY to a venv's python with numpy" >&2; exit 2; }
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
if [ -z "${AUDIT:-}" ]; then
  cargo build --release -q --bin audit
  AUDIT=$PWD/target/release/audit
fi
: > "$OUT/rss.txt"
: > "$OUT/load.txt"
for n in $SIZES; do
  dir="$OUT/rigs_$n"
  rm -rf "$dir"
  python3 bench/gen_rigs.py "$dir" "$n"
  cmds=(
    "$AUDIT check $dir"
    "$AUDIT survey $dir --format json"
    "$PY bench/survey_python.py $dir"
    "sh -c 'find $dir -type f | xargs cat >/dev/null'"
  )
  runs=$RUNS
  [ "$n" -ge 100000 ] && runs=$RUNS_BIG
  echo "$n before: $(uptime)" >> "$OUT/load.txt"
  # -i: `check` exits 1 when a rig fails the gate; the time is still the run's.
  hyperfine -N -i --warmup 1 --runs "$runs" --export-json "$OUT/time_$n.json" "${cmds[@]}" >/dev/null
  for i in "${!cmds[@]}"; do
    for _ in 1 2 3; do
      /usr/bin/time -f "%M" -o "$OUT/m" sh -c "${cmds[$i]} >/dev/null 2>&1" || true
      echo "$n $i $(tail -1 "$OUT/m")" >> "$OUT/rss.txt"
    done
  done
  echo "$n after: $(uptime)" >> "$OUT/load.txt"
  rm -rf "$dir"
done
python3 - "$OUT" <<'EOF' | tee "$OUT/growth.md"
import glob, json, math, statistics, sys
out = sys.argv[1]
names = ["audit check", "audit survey --format json", "Python loop (tomllib + numpy)", "find \\| xargs cat"]
rss = {}
for line in open(f"{out}/rss.txt"):
    n, i, kib = line.split()
    rss.setdefault((int(n), int(i)), []).append(int(kib))
times = {}
for f in glob.glob(f"{out}/time_*.json"):
    n = int(f.rsplit("_", 1)[1][:-5])
    times[n] = json.load(open(f))["results"]
sizes = sorted(times)


def slope(xs, ys):
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    mx, my = statistics.fmean(lx), statistics.fmean(ly)
    den = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / den if den else float("nan")


print("| files | command | time min / median / max | / Python | / find+cat | peak RSS (median of 3) |")
print("|---:|---|---|---:|---:|---:|")
for n in sizes:
    r = times[n]
    for i, name in enumerate(names):
        t = r[i]
        m = statistics.median(rss[(n, i)]) / 1024
        vs_py = r[2]["median"] / t["median"]
        vs_cat = t["median"] / r[3]["median"]
        span = f"{t['min'] * 1e3:.0f} / {t['median'] * 1e3:.0f} / {t['max'] * 1e3:.0f} ms"
        print(f"| {n:,} | {name} | {span} | {vs_py:.1f}x faster | {vs_cat:.2f}x | {m:.1f} MiB |")
print()
print("Growth exponent (slope of log value against log files, sizes " + ", ".join(f"{n:,}" for n in sizes) + "):")
print()
print("| command | time | peak RSS |")
print("|---|---:|---:|")
for i, name in enumerate(names):
    ts = [times[n][i]["median"] for n in sizes]
    ms = [statistics.median(rss[(n, i)]) for n in sizes]
    print(f"| {name} | {slope(sizes, ts):.3f} | {slope(sizes, ms):.3f} |")
print()
print("Load average:")
print()
for line in open(f"{out}/load.txt"):
    print(f"    {line.rstrip()}")
EOF
