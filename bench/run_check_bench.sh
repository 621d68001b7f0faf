#!/bin/sh
# `audit check` and `audit survey` over 10,000 generated rig files (issue 11:
# each within 2 s). Run from the repository root after
# `cargo build --release --bin audit`. Prints wall-clock seconds per command,
# best of 3.
set -eu
AUDIT=${AUDIT:-target/release/audit}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 bench/gen_rigs.py "$dir/rigs" 10000
best() {
    b=""
    for _ in 1 2 3; do
        s=$(date +%s.%N)
        "$@" >/dev/null 2>&1 || true
        e=$(date +%s.%N)
        t=$(echo "$e - $s" | bc)
        if [ -z "$b" ] || [ "$(echo "$t < $b" | bc)" = 1 ]; then b=$t; fi
    done
    echo "$b"
}
echo "check:                 $(best "$AUDIT" check "$dir/rigs") s"
"$AUDIT" check "$dir/rigs" --write-baseline "$dir/baseline.json" >/dev/null 2>&1 || true
echo "check --baseline:      $(best "$AUDIT" check "$dir/rigs" --baseline "$dir/baseline.json") s"
echo "check --write-baseline: $(best "$AUDIT" check "$dir/rigs" --write-baseline "$dir/baseline.json") s"
echo "survey:                $(best "$AUDIT" survey "$dir/rigs") s"
