#!/usr/bin/env python3
"""Plots bench/mesh_bench.sh output as an SVG (no dependencies):
mean and max surface error (world units, log) and conversion seconds (log)
against --res (log2), one colour per model.
Usage: mesh_plot.py RESULTS.txt OUT.svg"""
import math
import sys

rows = {}
for line in open(sys.argv[1]):
    if line.startswith('#') or not line.strip():
        continue
    f = line.split()
    name, res, secs, mean, mx = f[0], int(f[1]), float(f[4]), float(f[8]), float(f[9])
    rows.setdefault(name, []).append((res, secs, mean, mx))

W, H, M = 900, 380, 60
colours = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd']
svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="11">',
       f'<rect width="{W}" height="{H}" fill="white"/>']


def panel(x0, title, ylabel, series, ylog=True):
    pw, ph = W / 2 - M - 20, H - 2 * M
    xs = [r for s in series for r, _ in s[1]]
    ys = [y for s in series for _, y in s[1] if y > 0 and not math.isnan(y)]
    if not xs or not ys:
        return
    lx0, lx1 = math.log2(min(xs)), math.log2(max(xs))
    ly0, ly1 = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))
    if ly1 == ly0:
        ly1 += 1
    X = lambda r: x0 + M + (math.log2(r) - lx0) / max(lx1 - lx0, 1) * pw
    Y = lambda v: M + ph - (math.log10(v) - ly0) / (ly1 - ly0) * ph
    svg.append(f'<text x="{x0 + M + pw / 2}" y="{M - 25}" text-anchor="middle" font-size="13">{title}</text>')
    svg.append(f'<rect x="{x0 + M}" y="{M}" width="{pw}" height="{ph}" fill="none" stroke="#444"/>')
    for e in range(ly0, ly1 + 1):
        y = Y(10 ** e)
        svg.append(f'<line x1="{x0 + M}" y1="{y}" x2="{x0 + M + pw}" y2="{y}" stroke="#ddd"/>')
        svg.append(f'<text x="{x0 + M - 5}" y="{y + 4}" text-anchor="end">1e{e}</text>')
    for r in sorted(set(xs)):
        svg.append(f'<text x="{X(r)}" y="{M + ph + 15}" text-anchor="middle">{r}</text>')
    svg.append(f'<text x="{x0 + M + pw / 2}" y="{M + ph + 32}" text-anchor="middle">--res</text>')
    svg.append(f'<text x="{x0 + 15}" y="{M + ph / 2}" transform="rotate(-90 {x0 + 15} {M + ph / 2})" '
               f'text-anchor="middle">{ylabel}</text>')
    for i, (label, pts, dash) in enumerate(series):
        pts = [(r, y) for r, y in pts if y > 0 and not math.isnan(y)]
        c = colours[(i // 2 if dash is not None else i) % len(colours)]
        d = ' '.join(f'{X(r):.1f},{Y(y):.1f}' for r, y in pts)
        extra = f' stroke-dasharray="{dash}"' if dash else ''
        svg.append(f'<polyline points="{d}" fill="none" stroke="{c}" stroke-width="1.8"{extra}/>')
        for r, y in pts:
            svg.append(f'<circle cx="{X(r):.1f}" cy="{Y(y):.1f}" r="2.5" fill="{c}"/>')


names = sorted(rows)
err_series, time_series = [], []
for n in names:
    pts = sorted(rows[n])
    err_series.append((n + ' mean', [(r, m) for r, _, m, _ in pts], ''))
    err_series.append((n + ' max', [(r, x) for r, _, _, x in pts], '4 3'))
    time_series.append((n, [(r, s) for r, s, _, _ in pts], None))
panel(0, 'surface error (solid: mean, dashed: max)', 'world units', err_series)
panel(W / 2, 'conversion time (read + voxelize + octree)', 'seconds', time_series)
for i, n in enumerate(names):
    svg.append(f'<rect x="{M + i * 220}" y="{H - 14}" width="10" height="10" fill="{colours[i % len(colours)]}"/>')
    svg.append(f'<text x="{M + i * 220 + 14}" y="{H - 5}">{n}</text>')
svg.append('</svg>')
open(sys.argv[2], 'w').write('\n'.join(svg) + '\n')
