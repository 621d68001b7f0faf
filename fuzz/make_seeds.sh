#!/usr/bin/env bash
# Build a seed corpus for every fuzz target from real files.
#   fuzz/make_seeds.sh OUT_DIR SRC_DIR...
# Each seed is `selector byte + file` (the targets read the first byte as the
# path/format selector; see fuzz_targets/*.rs), except `points` (raw bytes).
# Files above 64 KiB are skipped (libFuzzer -max_len). The committed
# fuzz/seeds/ was made with: fuzz/make_seeds.sh fuzz/seeds tests/fixtures calibrations
set -euo pipefail
out=$1; shift
maxsize=65536
put() { # target selector file
    local t=$1 sel=$2 f=$3 name
    name=$(echo "$f" | tr '/ ' '__' | sed 's/^[._]*//')
    mkdir -p "$out/$t"
    { printf "\\x$(printf %02x "$sel")"; cat "$f"; } > "$out/$t/$name.s$sel"
}
for src in "$@"; do
    find "$src" -type f -size -${maxsize}c | sort | while read -r f; do
        lower=$(echo "$f" | tr 'A-Z' 'a-z')
        head=$(head -c 4096 "$f" | tr -d '\0' || true)
        case "$lower" in
            *.urdf|*.xacro) put urdf 0 "$f" ;;
            *.launch.py|*.py) put launch 3 "$f" ;;
            *.launch.yaml|*.launch.yml) put launch 2 "$f" ;;
            *.launch|*.launch.xml) put launch 0 "$f" ;;
            *.xml) if grep -q '<robot' <<<"$head"; then put urdf 1 "$f"; else put launch 7 "$f"; fi ;;
            *.toml) put rig_toml 0 "$f" ;;
            *.json) put json 0 "$f"; put json 3 "$f"
                if grep -q "source_frame" <<<"$head"; then put json 5 "$f"; fi
                if grep -q "sensor_name" <<<"$head"; then put json 6 "$f"; fi ;;
            *.feather) put json 7 "$f" ;;
            *.csv|*.ply|*.pcd|*.las|*.laz) mkdir -p "$out/points"; cp "$f" "$out/points/$(echo "$f" | tr '/ ' '__' | sed 's/^[._]*//')" ;;
            *.yaml|*.yml|*.txt)
                if grep -q 'child_frame_id\|transforms:' <<<"$head"; then put tf_static 0 "$f"; fi
                if grep -q 'static_transform_publisher' <<<"$head"; then put launch 4 "$f"; fi
                put yaml 0 "$f" ;;
        esac
    done
done
# Hand-made seeds for shapes the real files lack.
mkdir -p "$out/tf_static" "$out/points"
printf '\x00transforms:\n- header:\n    stamp:\n      sec: 0\n      nanosec: 0\n    frame_id: base_link\n  child_frame_id: lidar\n  transform:\n    translation:\n      x: 0.1\n      y: 0.0\n      z: 0.2\n    rotation:\n      x: 0.0\n      y: 0.0\n      z: 0.0\n      w: 1.0\n---\n' > "$out/tf_static/hand-ros2-echo"
printf '\x00transforms: \n  - \n    header: \n      seq: 0\n      stamp: \n        secs: 0\n        nsecs: 0\n      frame_id: "imu"\n    child_frame_id: "velodyne"\n    transform: \n      translation: \n        x: 0.1\n        y: 0.2\n        z: 0.3\n      rotation: \n        x: 0.0\n        y: 0.0\n        z: 0.7071068\n        w: 0.7071068\n---\n' > "$out/tf_static/hand-ros1-echo"
printf 'x,y,z,nx,ny,nz\n1,2,3,0,0,1\n4,5,6,1,0,0\n7,8,9,0,1,0\n' > "$out/points/hand.csv"
printf 'VERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\nTYPE F F F F F F\nCOUNT 1 1 1 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3 0 0 1\n4 5 6 1 0 0\n' > "$out/points/hand.pcd"
