#!/usr/bin/env bash
# Bag benchmark (issue 15): time `audit` reading /tf_static from a ~1 GB MCAP
# whose /tf_static is in the first chunk, and count the bytes it reads.
# Not a test: run by hand from the repository root.
#
#   bench/run_bag_bench.sh [SIZE_MB]   (default 1024)
#
# Needs python3 (a throwaway venv with rosbags and mcap is made under /tmp),
# hyperfine (apt-get install hyperfine) and, for the byte count, strace.
set -euo pipefail
size_mb=${1:-1024}
work=/tmp/audit-bag-bench
venv=/tmp/venv-audit-bag-bench
mkdir -p "$work"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install -q rosbags==0.11.9 mcap==1.6.0
fi
bag="$work/big_${size_mb}mb.mcap"
[ -f "$bag" ] || "$venv/bin/python" bench/make_big_bag.py "$bag" "$size_mb"
ls -l "$bag"
cargo build --release --bin audit
audit=target/release/audit
"$audit" "$bag" --frames
# The peer in the same run: the mcap library's seeking reader + rosbags' CDR
# decoder printing the same transforms (bench/bag_python.py).
hyperfine -N --warmup 3 --runs 30 --export-json "$work/hyperfine.json" \
    "$audit $bag --frames" \
    "$audit $bag --from base_link --to lidar --format json" \
    "$venv/bin/python bench/bag_python.py $bag"
python3 - "$work/hyperfine.json" <<'PY'
import json, sys
for r in json.load(open(sys.argv[1]))["results"]:
    print(f"{r['min']*1e3:.2f} / {r['median']*1e3:.2f} / {r['max']*1e3:.2f} ms  {r['command']}")
PY
if command -v strace >/dev/null; then
    # -y prints the path behind each descriptor: sum what was read from the bag.
    strace -f -y -e trace=read,pread64 -o "$work/strace.txt" "$audit" "$bag" --frames >/dev/null
    grep -F "<$bag>" "$work/strace.txt" |
        awk -F'= ' '{n += $NF; c++} END {printf "read from the bag: %d bytes in %d calls\n", n, c}'
fi
