#!/usr/bin/env bash
# Issue 24's before/after table (BENCHMARKS.md, "Whole process before and
# after issue 24"): one command per benchmark section whose command exists in
# both binaries, each pair in ROUNDS hyperfine runs, the inputs generated here.
#
#   BEFORE=/path/to/old/audit AFTER=target/release/audit PY=/venv/bin/python ROUNDS=4 \
#     bench/before_after.sh [WORKDIR]
#
# BEFORE: a release build of the older commit (e.g. fd2fa2f in a worktree,
# with `cargo build --release --example read_xyz` there too); PY: a Python
# with numpy, mcap, rosbags and laspy[lazrs] (the generators' imports);
# the test-data folder as tools/testdata.py finds it.
set -euo pipefail
cd "$(dirname "$0")/.."
w=${1:-/tmp/audit-before-after}
mkdir -p "$w"
B=${BEFORE:?set BEFORE to the older audit binary}
A=${AFTER:-target/release/audit}
PY=${PY:-python3}
BX="$(dirname "$B")/examples/read_xyz"
cargo build --quiet --release --bin audit --example write_cloud --example read_xyz
AX=target/release/examples/read_xyz
td=$(python3 tools/testdata.py root)
# hyperfine's -i (below) would time a missing file's error: refuse first.
[ -d "$td/Gepetto__example-robot-data" ] || { echo "test data not found at $td: set EXTRINSIC_AUDIT_TEST_DATA (docs/test-data.md)" >&2; exit 2; }
[ -f "$w/chain.urdf" ] || python3 bench/gen_urdf_chain.py 100000 "$w/chain.urdf"
[ -d "$w/rigs" ] || python3 bench/gen_rigs.py "$w/rigs" 10000 > /dev/null
[ -f "$w/big.mcap" ] || "$PY" bench/make_big_bag.py "$w/big.mcap" 1024
[ -f "$w/c1e6.ply" ] || target/release/examples/write_cloud "$w/c1e6.ply" 1000000 ply-le
[ -f "$w/raw1e6.ply" ] || "$PY" bench/make_raw_million.py "$w/raw1e6.ply"
[ -f "$w/las/million.laz" ] || "$PY" bench/make_las_million.py "$w/las"
an="$td/Gepetto__example-robot-data/robots/anymal_c_simple_description/urdf/anymal.urdf --from base --to lidar"
pr2="$td/Gepetto__example-robot-data/robots/pr2_description/urdf/pr2.urdf --from base_footprint --to laser_tilt_link"
pr2x="$td/PR2__pr2_common/pr2_description/robots/pr2.urdf.xacro --from base_footprint --to laser_tilt_link"
# Each pair runs in ROUNDS hyperfine rounds (default 4), the order of its two
# commands swapped from one round to the next, so that neither binary always
# runs first, on a warmer cache or a cooler core; the table pools every run
# of a command over the rounds (the runs column counts them).
rounds=${ROUNDS:-4}
pair() {
    if [ $((r % 2)) -eq 0 ]; then
        printf '%s\n' -n "$1 (before)" "$B $2" -n "$1 (after)" "$A $2"
    else
        printf '%s\n' -n "$1 (after)" "$A $2" -n "$1 (before)" "$B $2"
    fi
}
bx() { # the LAZ read is an example program, not a subcommand
    if [ $((r % 2)) -eq 0 ]; then
        printf '%s\n' -n "LAZ 1e6 read_xyz (before)" "$BX $1" -n "LAZ 1e6 read_xyz (after)" "$AX $1"
    else
        printf '%s\n' -n "LAZ 1e6 read_xyz (after)" "$AX $1" -n "LAZ 1e6 read_xyz (before)" "$BX $1"
    fi
}
for r in $(seq 1 "$rounds"); do
    mapfile -t quick < <(pair anymal "$an"; pair pr2 "$pr2"; pair "survey calibrations/" "survey calibrations/";
        pair "check calibrations/" "check calibrations/"; pair "xacro PR2" "$pr2x"; pair "bag 1 GB --frames" "$w/big.mcap --frames";
        pair "degeneracy 1e6 PLY" "degeneracy $w/c1e6.ply")
    hyperfine -N -i --warmup 5 --runs 40 --export-json "$w/quick$r.json" "${quick[@]}" > /dev/null
    mapfile -t slow < <(pair "URDF 100k" "$w/chain.urdf --from l0 --to l99999"; pair "check 10k" "check $w/rigs";
        pair "survey 10k" "survey $w/rigs"; bx "$w/las/million.laz";
        pair "raw 1e6 normals" "degeneracy $w/raw1e6.ply --estimate-normals --voxel 0.1")
    hyperfine -N --warmup 2 --runs 15 --export-json "$w/slow$r.json" "${slow[@]}" > /dev/null
done
python3 - "$w" "$rounds" <<'PY'
import json, statistics, sys
w, rounds = sys.argv[1], int(sys.argv[2])
times, order = {}, []
for group in ("quick", "slow"):
    for r in range(1, rounds + 1):
        for x in json.load(open(f"{w}/{group}{r}.json"))["results"]:
            name, side = x["command"].rsplit(" (", 1)
            if name not in times:
                times[name] = {"before": [], "after": []}
                order.append(name)
            times[name][side.rstrip(")")] += x["times"]
print("| command | before min / median / max | after min / median / max | runs each | median after / before |")
print("|---|---|---|---:|---:|")
m = lambda x: "%.1f / %.1f / %.1f ms" % (min(x) * 1e3, statistics.median(x) * 1e3, max(x) * 1e3)
for name in order:
    b, a = times[name]["before"], times[name]["after"]
    print(f"| {name} | {m(b)} | {m(a)} | {len(a)} | {statistics.median(a) / statistics.median(b):.2f} |")
PY
