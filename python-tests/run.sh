#!/usr/bin/env bash
# The Python tests: one venv, target/py-venv, made from
# python-tests/requirements.txt (every version pinned) and made again only
# when that file changes; then every python-tests/test_*.py, against the
# `audit` binary $AUDIT_BIN (default: the newer of target/release/audit and
# target/debug/audit; build one first); then the Python package's wheel is
# built, installed in the venv and its pytest suite run (python/tests).
#
#   python-tests/run.sh            # from anywhere; extra arguments go to unittest
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/py-venv
stamp="$venv/.requirements.sha256"
# The stamp also names the checkout's path: a venv's scripts (pip, maturin)
# start with the absolute path of its python, so a moved checkout needs a new
# venv (a moved worktree once stopped CI at target/py-venv/bin/pip).
want="$(sha256sum python-tests/requirements.txt | cut -d' ' -f1) $PWD"
if [ ! -x "$venv/bin/python" ] || [ "$(cat "$stamp" 2> /dev/null)" != "$want" ]; then
    rm -rf "$venv"
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet --disable-pip-version-check -r python-tests/requirements.txt
    echo "$want" > "$stamp"
fi
"$venv/bin/python" -m unittest discover -s python-tests -t python-tests "$@"

# The Python package (python/, issue 32): its abi3 wheel built by maturin
# (release, as a user's `pip install ./python` builds it) into a folder of
# its own, installed in the venv with its `audit` console script, then its
# pytest suite. PYTHON_PACKAGE=0 skips it.
if [ "${PYTHON_PACKAGE:-1}" != 0 ]; then
    start=$SECONDS
    wheels=target/py-wheel
    rm -rf "$wheels"
    nice -n "${PYTHON_PACKAGE_NICE:-0}" "$venv/bin/maturin" build --release --quiet \
        -m python/Cargo.toml -i "$venv/bin/python" -o "$wheels"
    "$venv/bin/pip" install --quiet --disable-pip-version-check --no-deps --force-reinstall \
        "$wheels"/extrinsic_audit-*.whl
    built=$((SECONDS - start))
    # From python/tests, not python/: there the source folder
    # python/extrinsic_audit (no native module in a clean checkout) would
    # shadow the installed wheel, which is what is under test.
    (cd python/tests && "../../$venv/bin/python" -m pytest -q -p no:cacheprovider --rootdir=. .)
    echo "python package: wheel built and installed in ${built} s, step $((SECONDS - start)) s"
fi
