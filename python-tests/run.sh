#!/usr/bin/env bash
# The Python tests: one venv, target/py-venv, made from
# python-tests/requirements.txt (every version pinned) and made again only
# when that file changes; then every python-tests/test_*.py, against the
# `audit` binary $AUDIT_BIN (default: the newer of target/release/audit and
# target/debug/audit; build one first).
#
#   python-tests/run.sh            # from anywhere; extra arguments go to unittest
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/py-venv
stamp="$venv/.requirements.sha256"
want=$(sha256sum python-tests/requirements.txt | cut -d' ' -f1)
if [ ! -x "$venv/bin/python" ] || [ "$(cat "$stamp" 2> /dev/null)" != "$want" ]; then
    rm -rf "$venv"
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet --disable-pip-version-check -r python-tests/requirements.txt
    echo "$want" > "$stamp"
fi
exec "$venv/bin/python" -m unittest discover -s python-tests -t python-tests "$@"
