#!/usr/bin/env python3
"""Compare two `audit run --format json` outputs (issue 26's before/after
check): every string, boolean, integer and null equal, and every float
within a relative tolerance (default 1e-9) of the other: relative to the
larger of the two, or in a list of numbers (eigenvalues, a vector) to the
list's largest magnitude.

  python3 bench/run_compare.py BEFORE.json AFTER.json [--rel 1e-9]
  python3 bench/run_compare.py BEFORE.jsonl AFTER.jsonl   (--jsonl: per scan)

Prints the number of floats compared, the largest relative difference and
where it is; exits 1 on a structural or non-float difference or a float
past the tolerance. Floats are compared as floats even where one side wrote
an integral value (serde writes 2.0 as 2.0, but be lenient).
"""

import argparse
import json
import sys


def num(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def walk(a, b, path, out, scale=None):
    if isinstance(a, dict) and isinstance(b, dict):
        if list(a) != list(b):
            out["bad"].append(f"{path}: keys {list(a)} vs {list(b)}")
            return
        for k in a:
            walk(a[k], b[k], f"{path}.{k}", out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out["bad"].append(f"{path}: {len(a)} vs {len(b)} items")
            return
        # A list of numbers (eigenvalues, a vector) is compared on its own
        # scale: its largest magnitude.
        sc = None
        if a and all(num(x) for x in a + b):
            sc = max(abs(x) for x in a + b)
        for i, (x, y) in enumerate(zip(a, b)):
            walk(x, y, f"{path}[{i}]", out, sc)
    elif isinstance(a, float) or isinstance(b, float):
        if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, (int, float)) or not isinstance(b, (int, float)):
            out["bad"].append(f"{path}: {a!r} vs {b!r}")
            return
        out["floats"] += 1
        if a == b:
            out["equal"] += 1
            return
        if abs(a - b) <= out["abs"]:
            return
        rel = abs(a - b) / (scale or max(abs(a), abs(b)))
        if rel > out["worst"][0]:
            out["worst"] = (rel, path, a, b)
    elif a != b or type(a) is not type(b):
        out["bad"].append(f"{path}: {a!r} vs {b!r}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--rel", type=float, default=1e-9)
    ap.add_argument("--abs", type=float, default=1e-12,
                    help="differences this small pass whatever the scale (rounding-level quantities such as "
                    "point_displacement_max_relative_change, about 1e-15)")
    a = ap.parse_args()
    def load(path):
        with open(path) as f:
            if path.endswith(".jsonl"):
                return [json.loads(line) for line in f if line.strip()]
            return json.load(f)

    x, y = load(a.before), load(a.after)
    out = {"abs": a.abs, "bad": [], "floats": 0, "equal": 0, "worst": (0.0, None, None, None)}
    walk(x, y, "$", out)
    rel, path, u, v = out["worst"]
    print(f"{out['floats']} floats, {out['equal']} bit-equal; largest relative difference {rel:.3e}"
          + (f" at {path} ({u!r} vs {v!r})" if path else ""))
    for m in out["bad"][:20]:
        print("DIFFERENT:", m)
    if out["bad"] or rel > a.rel:
        print(f"FAIL ({len(out['bad'])} non-float differences; tolerance {a.rel:g})")
        sys.exit(1)
    print(f"OK (tolerance {a.rel:g}; everything else identical)")


if __name__ == "__main__":
    main()
