#!/usr/bin/env python3
"""Generate N rig files for the `audit check` / `audit survey` benchmark.

Usage: gen_rigs.py OUT_DIR [N]   (default N = 10000)

Copies the shipped stand-alone TOML rigs (calibrations/*.toml) round-robin into OUT_DIR,
100 files per sub-directory, each with a unique id (`<id>-<k>`) and its
translation x shifted by k * 1e-6 m so that no two files are identical.
"""
import pathlib
import re
import sys

out = pathlib.Path(sys.argv[1])
n = int(sys.argv[2]) if len(sys.argv) > 2 else 10000
src = sorted(pathlib.Path(__file__).resolve().parent.parent.joinpath("calibrations").glob("*.toml"))
# Rigs that include another file (the ANYmal URDF) are left out: every
# generated file stands alone.
texts = [t for t in (p.read_text() for p in src) if not re.search(r"^file = ", t, re.M)]
for k in range(n):
    text = texts[k % len(texts)]
    text = re.sub(r'^id = "([^"]*)"', lambda m: f'id = "{m.group(1)}-{k:05d}"', text, count=1, flags=re.M)
    text = re.sub(
        r"^translation = \[\s*([-0-9.eE+]+)",
        lambda m: f"translation = [{float(m.group(1)) + k * 1e-6!r}",
        text,
        count=1,
        flags=re.M,
    )
    d = out / f"d{k // 100:03d}"
    d.mkdir(parents=True, exist_ok=True)
    (d / f"rig{k:05d}.toml").write_text(text)
print(f"{n} rig files in {out}")
