#!/usr/bin/env bash
# The URDF reader against the parser under it (issue 29): `audit` loading an
# N-link chain (default 100,000; bench/gen_urdf_chain.py, one element per
# line) and reporting one edge (so the figure is the load), paired in one
# hyperfine run with
#   - examples/xml_events_peer.rs: quick-xml's events over the same file, every
#     attribute split and unescaped, nothing else (the floor for a reader on
#     quick-xml);
#   - `xmllint --stream --noout` (libxml2's streaming reader; Debian package
#     libxml2-utils).
# Then peak RSS of each (/usr/bin/time -f %M, 5 runs, median) and the
# reader's RSS beyond the file's size per link, as in bench/urdf_growth.sh.
#
#   bench/urdf_speed.sh [OUT_DIR]          (N=... RUNS=... to change)
#
# Writes OUT_DIR/summary.md (the table) next to hyperfine's JSON; the load
# average before and after is in the summary. Run on an idle machine.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-/tmp/urdf-speed}
N=${N:-100000}
RUNS=${RUNS:-20}
command -v hyperfine >/dev/null || { echo "hyperfine not found (apt-get install hyperfine)" >&2; exit 2; }
command -v xmllint >/dev/null || { echo "xmllint not found (apt-get install libxml2-utils)" >&2; exit 2; }
mkdir -p "$OUT"
cargo build --release -q --bin audit --example xml_events_peer
AUDIT=$PWD/target/release/audit
PEER=$PWD/target/release/examples/xml_events_peer
f="$OUT/chain_$N.urdf"
python3 bench/gen_urdf_chain.py "$N" "$f"
cmds=(
  "$AUDIT $f --from l0 --to l1 --format json"
  "$PEER $f"
  "xmllint --stream --noout $f"
)
load_before=$(uptime)
hyperfine -N --warmup 2 --runs "$RUNS" --export-json "$OUT/time.json" "${cmds[@]}" >/dev/null
: > "$OUT/rss.txt"
for i in "${!cmds[@]}"; do
  for _ in 1 2 3 4 5; do
    # shellcheck disable=SC2086 # the command is split into its words on purpose
    /usr/bin/time -f "%M" -o "$OUT/m" ${cmds[$i]} >/dev/null
    echo "$i $(cat "$OUT/m")" >> "$OUT/rss.txt"
  done
done
load_after=$(uptime)
python3 - "$OUT" "$N" "$(stat -c %s "$f")" "$load_before" "$load_after" <<'EOF' | tee "$OUT/summary.md"
import json, statistics, sys
out, n, size, before, after = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4], sys.argv[5]
res = json.load(open(f"{out}/time.json"))["results"]
rss = {}
for line in open(f"{out}/rss.txt"):
    i, kib = line.split()
    rss.setdefault(int(i), []).append(int(kib))
names = ["audit (load, one edge)", "quick-xml events + attributes", "xmllint --stream"]
base = res[0]["median"]
print(f"{n:,}-link chain, {size / 1e6:.2f} MB; load before: {before.strip()}; after: {after.strip()}")
print()
print("| command | time min / median / max | audit / it | peak RSS (median of 5) |")
print("|---|---|---:|---:|")
for i, r in enumerate(res):
    m = statistics.median(rss[i])
    t = f"{r['min'] * 1e3:.1f} / {r['median'] * 1e3:.1f} / {r['max'] * 1e3:.1f} ms"
    print(f"| {names[i]} | {t} | {base / r['median']:.2f}x | {m / 1024:.1f} MiB |")
m = statistics.median(rss[0])
print()
print(f"audit's RSS beyond the file: {(m * 1024 - size) / n:,.0f} B per link")
EOF
