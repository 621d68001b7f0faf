#!/usr/bin/env bash
# Compare the detector with numpy/scipy on the same data (see compare_numpy.py).
# Creates bench/.venv (numpy + scipy from PyPI) on first use.
# Single-threaded BLAS so that both sides use one core.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -x bench/.venv/bin/python ]; then
  python3 -m venv bench/.venv
  bench/.venv/bin/pip install --quiet --upgrade pip
  bench/.venv/bin/pip install --quiet numpy scipy
fi
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1
cargo run --quiet --release --example bench_data -- bench/data "${1:-1000000}" > /dev/null
bench/.venv/bin/python bench/compare_numpy.py bench/data
