#!/usr/bin/env bash
# Build the seed corpus of every fuzz target from real files:
#   fuzz/make_seeds.sh [OUT_DIR [SRC...]]
# OUT_DIR defaults to fuzz/corpus-seeds (gitignored: seeds are never
# committed). SRC are directories or files; by default the project's own
# fixtures (tests/fixtures, calibrations) and every third-party file of the
# test-data folder (docs/test-data.md: $EXTRINSIC_AUDIT_TEST_DATA, else
# shared/test-data beside the checkout), read in place, each checked
# against its sha256 by tools/testdata.py; where the folder is absent, that
# is said and the project's fixtures alone are used.
# Each seed is `selector byte + file` (the targets read the first byte as the
# path/format selector; see fuzz_targets/*.rs), except `points` (raw bytes),
# made in OUT_DIR, never beside the source. Files above 64 KiB are skipped
# (libFuzzer -max_len).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(dirname "$here")
out=${1:-$here/corpus-seeds}
[ $# -gt 0 ] && shift
maxsize=65536
mkdir -p "$out"
out=$(cd "$out" && pwd)

files=()
if [ $# -gt 0 ]; then
    while IFS= read -r f; do files+=("$(realpath "$f")"); done < <(find "$@" -type f | sort)
    cd "$repo"
else
    cd "$repo"
    while IFS= read -r f; do files+=("$f"); done < <(find tests/fixtures calibrations -type f -not -path '*/.venv/*' | sort)
    td=$(python3 tools/testdata.py root)
    mapfile -t names < <(python3 tools/testdata.py list)
    if real=$(python3 tools/testdata.py path "${names[@]}"); then
        mapfile -t -O "${#files[@]}" files <<<"$real"
    else
        echo "make_seeds: no test data in $td (docs/test-data.md): seeds from the project's fixtures only" >&2
    fi
fi

# A seed's name: the source path below the checkout or the test-data folder, slashes as _.
seed_name() {
    local f=${1#"${td:-}/"}
    f=${f#"$repo/"}
    echo "$f" | tr '/ ' '__' | sed 's/^[._]*//'
}
put() { # target selector file
    local t=$1 sel=$2 f=$3
    mkdir -p "$out/$t"
    { printf "\\x$(printf %02x "$sel")"; cat "$f"; } > "$out/$t/$(seed_name "$f").s$sel"
}
n=0
for f in "${files[@]}"; do
    [ "$(stat -c %s "$f")" -lt "$maxsize" ] || continue
    lower=$(echo "$f" | tr 'A-Z' 'a-z')
    head=$(head -c 4096 "$f" | tr -d '\0' || true)
    n=$((n + 1))
    case "$lower" in
        *.urdf|*.xacro) put urdf 0 "$f" ;;
        *.launch.py|*.py) put launch 3 "$f"; put pyexpr 0 "$f" ;;
        *.launch.yaml|*.launch.yml) put launch 2 "$f" ;;
        *.launch|*.launch.xml) put launch 0 "$f" ;;
        *.xml) if grep -q '<robot' <<<"$head"; then put urdf 1 "$f"; else put launch 7 "$f"; fi ;;
        *.toml) put rig_toml 0 "$f" ;;
        *.json) put json 0 "$f"; put json 3 "$f"
            if grep -q "source_frame" <<<"$head"; then put json 5 "$f"; fi
            if grep -q "sensor_name" <<<"$head"; then put json 6 "$f"; fi ;;
        *.feather) put json 7 "$f" ;;
        *.csv|*.ply|*.pcd|*.las|*.laz) mkdir -p "$out/points"; cp "$f" "$out/points/$(seed_name "$f")" ;;
        *.bash|*.sh) put launch 4 "$f" ;;
        *.yaml|*.yml|*.txt)
            if grep -q 'child_frame_id\|transforms:' <<<"$head"; then put tf_static 0 "$f"; fi
            if grep -q 'static_transform_publisher' <<<"$head"; then put launch 4 "$f"; fi
            put yaml 0 "$f" ;;
        *) n=$((n - 1)) ;;
    esac
done
# Hand-made seeds for shapes the real files lack.
mkdir -p "$out/tf_static" "$out/points"
printf '\x00transforms:\n- header:\n    stamp:\n      sec: 0\n      nanosec: 0\n    frame_id: base_link\n  child_frame_id: lidar\n  transform:\n    translation:\n      x: 0.1\n      y: 0.0\n      z: 0.2\n    rotation:\n      x: 0.0\n      y: 0.0\n      z: 0.0\n      w: 1.0\n---\n' > "$out/tf_static/hand-ros2-echo"
printf '\x00transforms: \n  - \n    header: \n      seq: 0\n      stamp: \n        secs: 0\n        nsecs: 0\n      frame_id: "imu"\n    child_frame_id: "velodyne"\n    transform: \n      translation: \n        x: 0.1\n        y: 0.2\n        z: 0.3\n      rotation: \n        x: 0.0\n        y: 0.0\n        z: 0.7071068\n        w: 0.7071068\n---\n' > "$out/tf_static/hand-ros1-echo"
printf 'x,y,z,nx,ny,nz\n1,2,3,0,0,1\n4,5,6,1,0,0\n7,8,9,0,1,0\n' > "$out/points/hand.csv"
printf 'VERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\nTYPE F F F F F F\nCOUNT 1 1 1 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3 0 0 1\n4 5 6 1 0 0\n' > "$out/points/hand.pcd"
echo "make_seeds: $n source files -> $(find "$out" -type f | wc -l) seeds in $out" >&2
