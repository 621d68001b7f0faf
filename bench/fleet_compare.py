#!/usr/bin/env python3
"""bench/fleet_bench.sh's checks and table.

    fleet_compare.py SPREAD.json PEER.json     `audit spread` against the peer
    fleet_compare.py --check CHECK.json N      the moved vehicles, no other
    fleet_compare.py --table OUT N...          OUT/fleet.md from hyperfine's JSON
"""
import json
import math
import statistics
import sys

NAMES = ["audit spread", "audit check --fleet-tolerance", "Python peer (PyYAML + scipy)",
         "find \\| xargs cat"]


def same(a, b, tol, what):
    if any(abs(x - y) > tol for x, y in zip(a, b)) or len(a) != len(b):
        sys.exit(f"{what}: audit {a} against the peer {b} (tolerance {tol})")


def compare(spread_path, peer_path):
    s, p = json.load(open(spread_path)), json.load(open(peer_path))
    if s["count"] != p["count"]:
        sys.exit(f"count: audit {s['count']}, peer {p['count']}")
    q, qp = s["mean"]["quaternion_xyzw"], p["mean_quaternion_xyzw"]
    if q[3] * qp[3] < 0:
        qp = [-x for x in qp]
    same(q, qp, 1e-9, "mean quaternion")
    same(s["mean"]["translation_m"], p["mean_translation_m"], 1e-9, "mean translation")
    # The peer takes mean.inv() * R, the deviation in the to-frame axes.
    same(s["spread"]["rotation_to_deg"]["std"], p["rotation_std_deg"], 1e-6, "rotation std")
    same(s["spread"]["translation_from_mm"]["std"], p["translation_std_mm"], 1e-6, "translation std")


def check(check_path, n):
    findings = json.load(open(check_path))["findings"]
    got = sorted(f["file"].split("/")[-2] for f in findings if f["code"] == "fleet-deviation")
    # Sorted as text as `got` is: past 99,999 the names outgrow five digits
    # (v100000 sorts before v10100).
    want = sorted(f"v{i:05d}" for i in range(100, n + 1, 100))
    if got != want:
        sys.exit(f"check: fleet-deviation on {got[:5]}... ({len(got)}), expected every 100th vehicle ({len(want)})")


def table(out, sizes):
    rss = {}
    for line in open(f"{out}/rss.txt"):
        n, i, kb = line.split()
        rss.setdefault((int(n), int(i)), []).append(int(kb))
    print("| vehicles | command | time [min median max] (s) | peak RSS (MiB, median of 3; 1 run from 100,000) |")
    print("|---|---|---|---|")
    medians = {}
    for n in sizes:
        results = json.load(open(f"{out}/time_{n}.json"))["results"]
        for i, r in enumerate(results):
            t = r["times"]
            medians[(n, i)] = statistics.median(t)
            m = statistics.median(rss.get((n, i), [0])) / 1024
            print(f"| {n:,} | {NAMES[i]} | [{min(t):.3f} {statistics.median(t):.3f} {max(t):.3f}] | {m:.1f} |")
    if len(sizes) > 1:
        a, b = sizes[0], sizes[-1]
        print()
        for i, name in enumerate(NAMES):
            k = math.log(medians[(b, i)] / medians[(a, i)]) / math.log(b / a)
            print(f"- {name}: time grows as N^{k:.2f} from {a:,} to {b:,}")
    print()
    print("Load:")
    for line in open(f"{out}/load.txt"):
        print(f"- {line.strip()}")


def main():
    if sys.argv[1] == "--check":
        check(sys.argv[2], int(sys.argv[3]))
    elif sys.argv[1] == "--table":
        table(sys.argv[2], [int(x) for x in sys.argv[3:]])
    else:
        compare(sys.argv[1], sys.argv[2])


if __name__ == "__main__":
    main()
