#!/usr/bin/env python3
"""Summarise bench/degeneracy.sh: a markdown table (min / median / max wall
time of each command, the numpy-over-audit ratio of medians, peak RSS) and an
SVG of time and peak memory against the number of points (log-log).

    python bench/summary.py DIR SIZE...
"""
import json, math, sys


def load(d, n):
    res = json.load(open(f"{d}/time_{n}.json"))["results"]
    return {r["command"].rsplit(" ", 1)[0]: r for r in res}


def rss(d):
    out = {}
    for line in open(f"{d}/rss.txt"):
        who, n, kib = line.split()
        out.setdefault((who, int(n)), []).append(int(kib))
    return out


def ms(r):
    return f"{r['min']*1e3:.1f} / {r['median']*1e3:.1f} / {r['max']*1e3:.1f}"


def svg(rows, path):
    """Two log-log panels: wall time (median, min-max bar) and peak RSS."""
    W, H, m = 360, 260, 50
    def panel(x0, title, series, ylab):
        ys = [v for s in series for (_, lo, mid, hi) in s[2] for v in (lo, hi)]
        xs = [n for (n, *_rest) in series[0][2]]
        lx0, lx1 = math.log10(min(xs)), math.log10(max(xs))
        ly0, ly1 = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))
        ly1 = max(ly1, ly0 + 1)
        X = lambda n: x0 + m + (math.log10(n) - lx0) / (lx1 - lx0 or 1) * (W - 1.5 * m)
        Y = lambda v: H - m + (-(math.log10(v) - ly0) / (ly1 - ly0)) * (H - 1.5 * m)
        g = [f'<text x="{x0 + W/2}" y="18" text-anchor="middle" font-size="13">{title}</text>']
        g.append(f'<rect x="{x0+m}" y="{m/2}" width="{W-1.5*m}" height="{H-1.5*m}" fill="none" stroke="#999"/>')
        for e in range(int(ly0), int(ly1) + 1):
            g.append(f'<text x="{x0+m-4}" y="{Y(10**e)+4}" text-anchor="end" font-size="10">1e{e}</text>')
            g.append(f'<line x1="{x0+m}" x2="{x0+W-m/2}" y1="{Y(10**e)}" y2="{Y(10**e)}" stroke="#eee"/>')
        for n in xs:
            g.append(f'<text x="{X(n)}" y="{H-m+14}" text-anchor="middle" font-size="10">{n:.0e}</text>')
        g.append(f'<text x="{x0+W/2}" y="{H-8}" text-anchor="middle" font-size="11">points</text>')
        g.append(f'<text x="{x0+12}" y="{H/2}" font-size="11" transform="rotate(-90 {x0+12} {H/2})" text-anchor="middle">{ylab}</text>')
        for name, colour, pts in series:
            g.append('<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>' % (colour, " ".join(f"{X(n):.1f},{Y(mid):.1f}" for n, _, mid, _ in pts)))
            for n, lo, mid, hi in pts:
                g.append(f'<line x1="{X(n):.1f}" x2="{X(n):.1f}" y1="{Y(lo):.1f}" y2="{Y(hi):.1f}" stroke="{colour}"/>')
                g.append(f'<circle cx="{X(n):.1f}" cy="{Y(mid):.1f}" r="3" fill="{colour}"/>')
        for k, (name, colour, _) in enumerate(series):
            g.append(f'<text x="{x0+m+8}" y="{m/2+14+13*k}" font-size="11" fill="{colour}">{name}</text>')
        return g
    t = [(r["n"], *r["audit_t"]) for r in rows]
    t1 = [(r["n"], *r["audit1_t"]) for r in rows]
    tn = [(r["n"], *r["numpy_t"]) for r in rows]
    ma = [(r["n"], *r["audit_m"]) for r in rows]
    mn = [(r["n"], *r["numpy_m"]) for r in rows]
    body = panel(0, "wall time (ms)", [("audit degeneracy", "#1f77b4", t), ("audit, 1 core", "#2ca02c", t1), ("numpy/scipy", "#d62728", tn)], "ms")
    body += panel(W, "peak RSS (MiB)", [("audit degeneracy", "#1f77b4", ma), ("numpy/scipy", "#d62728", mn)], "MiB")
    open(path, "w").write(f'<svg xmlns="http://www.w3.org/2000/svg" width="{2*W}" height="{H}" font-family="sans-serif">\n' + "\n".join(body) + "\n</svg>\n")


def main():
    d, sizes = sys.argv[1], [int(s) for s in sys.argv[2:]]
    mem = rss(d)
    rows = []
    print("| points | file | audit: min / median / max (ms) | audit, 1 core | numpy/scipy | numpy / audit (medians) | peak RSS audit (MiB) | peak RSS numpy (MiB) |")
    print("|---|---|---|---|---|---|---|---|")
    for n in sizes:
        r = load(d, n)
        a, a1, p = r["audit"], r["audit 1 core"], r["numpy"]
        ma = [k / 1024 for k in mem[("audit", n)]]
        mn = [k / 1024 for k in mem[("numpy", n)]]
        print(f"| {n:.0e} | {48*n/1e6:.1f} MB | {ms(a)} | {ms(a1)} | {ms(p)} | {p['median']/a['median']:.1f}x | {max(ma):.1f} | {max(mn):.0f} |")
        if "baseline" in r:
            b = r["baseline"]
            mb = [k / 1024 for k in mem.get(("baseline", n), [0])]
            print(f"| {n:.0e} | baseline binary | {ms(b)} | | | baseline / audit (medians) {b['median']/a['median']:.1f}x | {max(mb):.1f} | |")
        rows.append({"n": n,
                     "audit_t": [a["min"]*1e3, a["median"]*1e3, a["max"]*1e3],
                     "audit1_t": [a1["min"]*1e3, a1["median"]*1e3, a1["max"]*1e3],
                     "numpy_t": [p["min"]*1e3, p["median"]*1e3, p["max"]*1e3],
                     "audit_m": [min(ma), sorted(ma)[len(ma)//2], max(ma)],
                     "numpy_m": [min(mn), sorted(mn)[len(mn)//2], max(mn)]})
    json.dump(rows, open(f"{d}/summary.json", "w"), indent=1)
    svg(rows, f"{d}/degeneracy_growth.svg")
    print(f"\nplot: {d}/degeneracy_growth.svg")


if __name__ == "__main__":
    main()
