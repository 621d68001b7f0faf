#!/usr/bin/env bash
# Regenerate the pictures the READMEs show (docs/img/*.png): the frame tree
# of a real robot (the Clearpath Husky's kinematics, tests/fixtures/urdf;
# SOURCES.md there gives source and licence) with its base_link -> velodyne
# chain, and the survey plot of calibrations/, each drawn by audit as SVG and
# photographed with headless Chromium (`apt-get install -y chromium` where
# missing).
#
#   tools/screenshots.sh            # from the repository root or anywhere
set -euo pipefail
cd "$(dirname "$0")/.."
browser=$(command -v chromium || command -v chromium-browser || command -v google-chrome || true)
if [ -z "$browser" ]; then
    echo "tools/screenshots.sh: no Chromium found (apt-get install -y chromium)" >&2
    exit 2
fi
cargo build --quiet
audit=target/debug/audit
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$audit" tests/fixtures/urdf/husky_kinematics.urdf --frames --from base_link --to velodyne \
    --format svg > "$tmp/frames-husky.svg"
"$audit" survey calibrations/ --plot "$tmp/survey.svg" > /dev/null 2>&1

# Photograph an SVG at its own size (the width and height of its <svg>).
shoot() {
    local svg=$1 png=$2 w h
    w=$(grep -o -m1 '<svg[^>]* width="[0-9.]*"' "$svg" | sed 's/.* width="\([0-9.]*\)"/\1/')
    h=$(grep -o -m1 '<svg[^>]* height="[0-9.]*"' "$svg" | sed 's/.* height="\([0-9.]*\)"/\1/')
    "$browser" --headless --no-sandbox --disable-gpu --hide-scrollbars \
        --window-size="${w%.*},${h%.*}" --screenshot="$png" "file://$svg" > /dev/null 2>&1
    echo "$png (${w%.*}x${h%.*})"
}
mkdir -p docs/img
shoot "$tmp/frames-husky.svg" "$PWD/docs/img/frames-husky.png"
shoot "$tmp/survey.svg" "$PWD/docs/img/survey-plot.png"
