#!/usr/bin/env bash
# Growth of time and peak memory of loading a URDF with the number of links
# (an N-link chain, one element per line and the whole robot on one line).
#
#   bench/urdf_growth.sh [OUT_DIR] [N...]      (default N: 100 1000 10000 100000)
#
# Time: hyperfine (min / median / max); peak RSS: /usr/bin/time -f %M (KiB),
# 5 runs. The command loads the whole file and reports a one-edge chain
# (l0 -> l1), so the figure is the load, not the printing of a long chain.
# Then bench/urdf_growth_summary.py OUT_DIR writes the table and the SVG.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-/tmp/urdf-growth}
shift || true
SIZES=${*:-100 1000 10000 100000}
mkdir -p "$OUT"
cargo build --release -q
AUDIT=$PWD/target/release/audit
: > "$OUT/rss.txt"
for n in $SIZES; do
  for layout in lines one-line; do
    f="$OUT/chain_${n}_$layout.urdf"
    if [ "$layout" = one-line ]; then
      python3 bench/gen_urdf_chain.py "$n" "$f" --one-line
    else
      python3 bench/gen_urdf_chain.py "$n" "$f"
    fi
    runs=$(( n >= 100000 ? 10 : 30 ))
    hyperfine -N --warmup 2 --runs $runs --export-json "$OUT/time_${n}_$layout.json" \
      "$AUDIT $f --from l0 --to l1 --format json" >/dev/null
    for _ in 1 2 3 4 5; do
      /usr/bin/time -f "%M" -o "$OUT/m" "$AUDIT" "$f" --from l0 --to l1 --format json >/dev/null
      echo "$layout $n $(stat -c %s "$f") $(cat "$OUT/m")" >> "$OUT/rss.txt"
    done
  done
done
python3 bench/urdf_growth_summary.py "$OUT"
