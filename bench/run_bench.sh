#!/usr/bin/env bash
# `audit run` against its Python peer (issue 26): scans/s and points/s on
# generated runs of 32k- and 128k-point scans, paired in one hyperfine run,
# and peak RSS at two run lengths (flat memory). Not a test: run by hand from
# the repository root on a quiet machine, and record `uptime` with the figures.
#
#   bench/run_bench.sh            (~10 GB of generated bags under /tmp, removed at the end)
#
# Venv (exact): python3.11 -m venv /tmp/venv26 && /tmp/venv26/bin/pip install
#   rosbags==0.11.9 mcap==1.6.0 numpy==2.4.6 scipy==1.17.1 lz4==4.4.5
#   zstandard==0.25.0 open3d-cpu==0.20.0   (Open3D needs libusb-1.0-0 from apt)
set -euo pipefail
py=${PY:-/tmp/venv26/bin/python}
work=$(mktemp -d /tmp/audit-run-bench.XXXXXX)
trap 'rm -rf "$work"' EXIT
cargo build --release --bin audit
audit=target/release/audit
uptime
for beams in 32 128; do
    bag="$work/run$beams.mcap"
    "$py" bench/make_run_bag.py "$bag" --beams "$beams" --scans 60
    hyperfine -N --warmup 1 --runs 5 --export-json "$work/hf$beams.json" \
        "$audit run $bag --estimate-normals --voxel 0.1 --format json" \
        "$py bench/run_peer.py $bag --voxel 0.1 --quiet"
    cp "$work/hf$beams.json" "bench/run_hyperfine_$beams.json"
done
# Flat memory: peak RSS for 200 and 800 scans of 128k points (1.2 and 4.8 GiB).
for n in 200 800; do
    bag="$work/long$n.mcap"
    "$py" bench/make_run_bag.py "$bag" --beams 128 --scans "$n"
    /usr/bin/time -v "$audit" run "$bag" --estimate-normals --voxel 0.1 --format json \
        2>&1 >/dev/null | grep -E "Maximum resident|Elapsed"
    rm -f "$bag"
done
uptime
