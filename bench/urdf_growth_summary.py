#!/usr/bin/env python3
"""Summarise bench/urdf_growth.sh: a markdown table (min / median / max wall
time, median peak RSS, RSS beyond the file's size per link) and an SVG of time
and memory against the number of links (log-log), both layouts.

    python3 bench/urdf_growth_summary.py DIR   (writes DIR/urdf_growth.svg)
"""
import glob
import json
import math
import statistics
import sys

d = sys.argv[1]
rss = {}
size = {}
for line in open(f"{d}/rss.txt"):
    layout, n, nbytes, kib = line.split()
    rss.setdefault((layout, int(n)), []).append(int(kib))
    size[(layout, int(n))] = int(nbytes)

rows = []
for f in sorted(glob.glob(f"{d}/time_*.json")):
    _, n, layout = f.rsplit("/", 1)[1][:-5].split("_", 2)
    r = json.load(open(f))["results"][0]
    key = (layout, int(n))
    m = statistics.median(rss[key])
    rows.append((layout, int(n), r["min"], r["median"], r["max"], m, size[key]))
rows.sort(key=lambda x: (x[0], x[1]))

print("| layout | links | file | time min / median / max | peak RSS (median of 5) | RSS beyond the file, per link |")
print("|---|---:|---:|---|---:|---:|")
for layout, n, lo, med, hi, m, nb in rows:
    per = (m * 1024 - nb) / n
    print(f"| {layout} | {n:,} | {nb/1e6:.2f} MB | {lo*1e3:.1f} / {med*1e3:.1f} / {hi*1e3:.1f} ms | {m/1024:.1f} MiB | {per:,.0f} B |")

W, H, M = 360, 260, 55


def panel(x0, title, ylab, series, ymin, ymax):
    out = [f'<text x="{x0+W/2}" y="18" text-anchor="middle" font-size="13">{title}</text>']
    lx = lambda n: x0 + M + (math.log10(n) - 2) / 3 * (W - M - 15)
    ly = lambda v: H - 35 - (math.log10(v) - math.log10(ymin)) / (math.log10(ymax) - math.log10(ymin)) * (H - 70)
    out.append(f'<rect x="{x0+M}" y="35" width="{W-M-15}" height="{H-70}" fill="none" stroke="#999"/>')
    for n in [100, 1000, 10000, 100000]:
        out.append(f'<text x="{lx(n)}" y="{H-18}" text-anchor="middle" font-size="11">{n:,}</text>')
    e = math.floor(math.log10(ymin))
    while 10 ** e <= ymax:
        if 10 ** e >= ymin:
            out.append(f'<text x="{x0+M-5}" y="{ly(10**e)+4}" text-anchor="end" font-size="11">{10**e:g}</text>')
            out.append(f'<line x1="{x0+M}" x2="{x0+W-15}" y1="{ly(10**e)}" y2="{ly(10**e)}" stroke="#eee"/>')
        e += 1
    out.append(f'<text x="{x0+12}" y="{H/2}" transform="rotate(-90 {x0+12} {H/2})" text-anchor="middle" font-size="11">{ylab}</text>')
    out.append(f'<text x="{x0+W/2}" y="{H-3}" text-anchor="middle" font-size="11">links</text>')
    for (name, colour), pts in series.items():
        path = " ".join(f"{'M' if i == 0 else 'L'}{lx(n):.1f},{ly(v):.1f}" for i, (n, v) in enumerate(pts))
        out.append(f'<path d="{path}" fill="none" stroke="{colour}" stroke-width="2"/>')
        for n, v in pts:
            out.append(f'<circle cx="{lx(n):.1f}" cy="{ly(v):.1f}" r="3" fill="{colour}"/>')
    return out


colours = {"lines": "#1f77b4", "one-line": "#d62728"}
t = {(l, colours[l]): [(n, med * 1e3) for (ll, n, _, med, _, _, _) in rows if ll == l] for l in colours}
m = {(l, colours[l]): [(n, mm / 1024) for (ll, n, _, _, _, mm, _) in rows if ll == l] for l in colours}
body = panel(0, "load time (median)", "ms", t, 0.5, 1e4) + panel(W, "peak RSS (median)", "MiB", m, 1, 1e3)
body += [f'<text x="{W*2-150}" y="{50+16*i}" font-size="11" fill="{c}">{l}</text>' for i, (l, c) in enumerate(colours.items())]
open(f"{d}/urdf_growth.svg", "w").write(
    f'<svg xmlns="http://www.w3.org/2000/svg" width="{2*W}" height="{H}" font-family="sans-serif">\n'
    + "\n".join(body) + "\n</svg>\n")
print(f"\nplot: {d}/urdf_growth.svg")
