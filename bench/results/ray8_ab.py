#!/usr/bin/env python3
"""ray8 (issue 21, twenty-third sitting): tables from a batch log (ray8_b1.txt, ray8_b2.txt).
   python3 ray8_ab.py LOG
Rows "HH:MM:SS.ss X<round> scene view size ..." of render_bench (X = A main, B/C a branch binary) give per view
the median G rays/s of each binary over its processes, B/A per round, ESVO's median and voxkit / ESVO; rows
without a binary label (the table) are printed as they are with the share of pixels hit."""
import re, sys, statistics as st
from collections import defaultdict
rate = defaultdict(list)  # (x, scene, view) -> [(round, vx, es, sh)]
table = []
for line in open(sys.argv[1]):
    f = line.split()
    if len(f) < 20 or not re.match(r'\d\d:\d\d:\d\d', f[0]): continue
    lab = None
    if re.fullmatch(r'[A-Z]\d', f[1]): lab, f = f[1], f[:1] + f[2:]
    if f[2] not in ('overview', 'oblique', 'closeup', 'sky'): continue
    sc, view, hit = f[1], f[2], f[5]
    vx, es = float(f[10]), (float(f[11]) if f[11] != '-' else None)
    sh = float(f[16]) if f[16] != '-' else None
    if lab: rate[(lab[0], sc, view)].append((int(lab[1]), vx, es, sh, hit))
    else: table.append((f[0], sc, view, hit, f[8], f[9], vx, es, f[15], sh, f[18], f[19]))
if table:
    print('| time | scene | view | hit | steps VX / ES | VX G rays/s | ESVO G rays/s | VX / ES | depth= | prim+shadow G px/s | MiB VX / ES |')
    print('| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |')
    for t, sc, v, hit, sv, se, vx, es, dep, sh, mv, me in table:
        print(f'| {t[:8]} | {sc} | {v} | {hit} | {sv} / {se} | {vx:.2f} | {es if es is None else f"{es:.2f}"} | '
              f'{"-" if not es or not vx else f"{vx / es:.2f}"} | {dep} | {sh} | {mv} / {me} |')
xs = sorted({k[0] for k in rate})
views = sorted({(k[1], k[2]) for k in rate}, key=lambda k: (k[0], ['overview', 'oblique', 'closeup', 'sky'].index(k[1])))
for x in xs[1:]:
    print(f'\n| scene | view | hit | A G rays/s (n) | {x} (n) | {x} / A | {x}/A per round | ESVO | A / ESVO | {x} / ESVO | A, {x} prim+shadow G px/s |')
    print('| --- | --- | ---: | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: |')
    for sc, v in views:
        a, b = rate.get(('A', sc, v), []), rate.get((x, sc, v), [])
        if not a or not b: continue
        ma, mb = st.median(r[1] for r in a), st.median(r[1] for r in b)
        es = st.median([r[2] for r in a + b if r[2]] or [float('nan')])
        if not ma: continue
        ra = {r[0]: r[1] for r in a}
        per = ', '.join(f'{r[1] / ra[r[0]]:.3f}' for r in b if r[0] in ra)
        sha = st.median([r[3] for r in a if r[3]] or [0]); shb = st.median([r[3] for r in b if r[3]] or [0])
        print(f'| {sc} | {v} | {a[0][4]} | {ma:.2f} ({len(a)}) | {mb:.2f} ({len(b)}) | {mb / ma:.3f} | {per} | {es:.2f} | '
              f'{ma / es:.2f} | {mb / es:.2f} | {sha:.2f}, {shb:.2f} |')
