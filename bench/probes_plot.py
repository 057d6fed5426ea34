#!/usr/bin/env python3
"""Plots bench/probes_error.sh output as an SVG (no dependencies). One panel
per scene: relative MSE of the indirect diffuse light (log) against render
time (log): the path tracer (1..256 spp), the light field (1..256 rays per
pixel, one line per bake) and probe GI (1, 4, 16 samples per pixel, one line
per bake); a last panel:
probe GI's error (16 jittered samples per pixel) against bake time. The dotted line is the 5% relative RMSE
goal (relMSE 0.0025).
Usage: probes_plot.py RESULTS.txt OUT.svg"""
import math
import sys

scenes = []  # (name, {'pt': [(t, e)], 'gi': {bake label: [(bake s, t, e)]}, 'lf': {bake label: [(t, e)]}})
for line in open(sys.argv[1]):
    if line.startswith('## '):
        scenes.append((line[3:].split(' (')[0].strip(), {'pt': [], 'gi': {}, 'lf': {}}))
        continue
    if not line.startswith('|') or not scenes or '---' in line or '| scene |' in line:
        continue
    f = [c.strip() for c in line.strip().strip('|').split('|')]
    method, probes, res, spp, bake, secs, rel = f[1], f[2], f[3], f[4], f[5], float(f[6]), float(f[8])
    d = scenes[-1][1]
    if method == 'pathtrace':
        d['pt'].append((secs, rel))
    elif method.startswith('gi'):
        d['gi'].setdefault(f'{probes} probes R{res} {spp}spp', []).append((float(bake), secs, rel))
    elif method.startswith('lightfield'):
        d['lf'].setdefault(f'{probes} probes R{res} {spp}spp', []).append((secs, rel))

n = len(scenes) + 1
PW, PH, M = 300, 260, 55
W, H = n * (PW + M + 15) + 10, PH + 2 * M + 40
svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="11">',
       f'<rect width="{W}" height="{H}" fill="white"/>']


def axes(x0, title, xlabel, xs, ys):
    lx0, lx1 = math.floor(math.log10(min(xs))), math.ceil(math.log10(max(xs)))
    ly0, ly1 = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))
    X = lambda v: x0 + M + (math.log10(v) - lx0) / max(lx1 - lx0, 1) * PW
    Y = lambda v: M + PH - (math.log10(v) - ly0) / max(ly1 - ly0, 1) * PH
    svg.append(f'<text x="{x0 + M + PW / 2}" y="{M - 12}" text-anchor="middle" font-size="13">{title}</text>')
    svg.append(f'<rect x="{x0 + M}" y="{M}" width="{PW}" height="{PH}" fill="none" stroke="#444"/>')
    for e in range(ly0, ly1 + 1):
        svg.append(f'<line x1="{x0 + M}" y1="{Y(10 ** e)}" x2="{x0 + M + PW}" y2="{Y(10 ** e)}" stroke="#ddd"/>')
        svg.append(f'<text x="{x0 + M - 5}" y="{Y(10 ** e) + 4}" text-anchor="end">1e{e}</text>')
    for e in range(lx0, lx1 + 1):
        svg.append(f'<line x1="{X(10 ** e)}" y1="{M}" x2="{X(10 ** e)}" y2="{M + PH}" stroke="#eee"/>')
        svg.append(f'<text x="{X(10 ** e)}" y="{M + PH + 15}" text-anchor="middle">1e{e}</text>')
    svg.append(f'<text x="{x0 + M + PW / 2}" y="{M + PH + 32}" text-anchor="middle">{xlabel}</text>')
    if 0.0025 >= 10 ** ly0:
        svg.append(f'<line x1="{x0 + M}" y1="{Y(0.0025)}" x2="{x0 + M + PW}" y2="{Y(0.0025)}" stroke="#000" '
                   f'stroke-dasharray="1 3"/>')
    svg.append(f'<text x="{x0 + 14}" y="{M + PH / 2}" transform="rotate(-90 {x0 + 14} {M + PH / 2})" '
               f'text-anchor="middle">relative MSE (indirect)</text>')
    return X, Y


def line(X, Y, pts, colour, width=1.8, dash=''):
    pts = [p for p in pts if p[0] > 0 and p[1] > 0]  # in sample-count order
    d = ' '.join(f'{X(a):.1f},{Y(b):.1f}' for a, b in pts)
    extra = f' stroke-dasharray="{dash}"' if dash else ''
    svg.append(f'<polyline points="{d}" fill="none" stroke="{colour}" stroke-width="{width}"{extra}/>')
    for a, b in pts:
        svg.append(f'<circle cx="{X(a):.1f}" cy="{Y(b):.1f}" r="2.2" fill="{colour}"/>')


FLOOR = 2e-5  # render times below the timer's resolution are drawn here
for i, (name, d) in enumerate(scenes):
    x0 = i * (PW + M + 15)
    xs = [max(t, FLOOR) for t, _ in d['pt']] + [max(t, FLOOR) for v in d['lf'].values() for t, _ in v] + \
         [max(t, FLOOR) for v in d['gi'].values() for _, t, _ in v]
    ys = [e for _, e in d['pt']] + [e for v in d['lf'].values() for _, e in v] + \
         [e for v in d['gi'].values() for _, _, e in v]
    X, Y = axes(x0, name, 'render seconds (GPU)', xs, [y for y in ys if y > 0])
    for k, pts in enumerate(d['lf'].values()):
        line(X, Y, [(max(t, FLOOR), e) for t, e in pts], '#2ca02c', 1.0, '4 2')
    line(X, Y, [(max(t, FLOOR), e) for t, e in d['pt']], '#1f77b4', 2.2)
    for pts in d['gi'].values():
        line(X, Y, [(max(t, FLOOR), e) for _, t, e in pts], '#d62728', 1.0)
        for _, t, e in pts:
            svg.append(f'<rect x="{X(max(t, FLOOR)) - 3:.1f}" y="{Y(e) - 3:.1f}" width="6" height="6" fill="#d62728"/>')

x0 = len(scenes) * (PW + M + 15)
colours = ['#d62728', '#9467bd', '#8c564b', '#e377c2']
# the bake-time panel uses each bake's best-sampled GI render (16 spp)
best = [(i, v[-1]) for i, (_, d) in enumerate(scenes) for v in d['gi'].values()]
bx = [b for _, (b, _, _) in best]
by = [e for _, (_, _, e) in best]
if bx:
    X, Y = axes(x0, 'probe GI against bake time', 'bake seconds (GPU machine)', bx, by)
    for i, (b, _, e) in best:
        svg.append(f'<circle cx="{X(b):.1f}" cy="{Y(e):.1f}" r="3.5" fill="{colours[i % len(colours)]}"/>')
    for i, (name, _) in enumerate(scenes):
        c = colours[i % len(colours)]
        svg.append(f'<rect x="{x0 + M + 8}" y="{M + 6 + 14 * i}" width="9" height="9" fill="{c}"/>')
        svg.append(f'<text x="{x0 + M + 21}" y="{M + 14 + 14 * i}">{name}</text>')
legend = [('#1f77b4', 'path tracing 1..256 spp'), ('#2ca02c', 'light field 1..256 rays/pixel (one line per bake)'),
          ('#d62728', 'probe GI 1, 4, 16 spp (one line per bake)'), ('#000', 'dotted: 5% relative RMSE')]
for i, (c, t) in enumerate(legend):
    svg.append(f'<rect x="{M + i * 260}" y="{H - 16}" width="10" height="10" fill="{c}"/>')
    svg.append(f'<text x="{M + i * 260 + 14}" y="{H - 7}">{t}</text>')
svg.append('</svg>')
open(sys.argv[2], 'w').write('\n'.join(svg) + '\n')
