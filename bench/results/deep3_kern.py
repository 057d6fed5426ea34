#!/usr/bin/env python3
"""deep3 (issue 21, twenty-fourth sitting): the --kernels rows of a batch log as a table.
   python3 deep3_kern.py LOG
Rows "HH:MM:SS.s K<x> scene view size ..." (K<x>: one render_bench process with --kernels) give per view and kernel
the G primary rays/s and G primary + shadow pixels/s in each process, their ratio to the same process's built-in
row, and the pixels that differ from the built-in kernel (hits frame, colour frame). The A/B rows: ray8_ab.py."""
import re, sys, statistics as st
from collections import defaultdict
rows = defaultdict(dict)  # (scene, view) -> {(proc, kernel): (rays, pix, steps, diff)}
procs, kerns = [], []
for line in open(sys.argv[1]):
    f = line.split()
    if len(f) < 20 or not re.match(r'\d\d:\d\d:\d\d', f[0]) or not re.fullmatch(r'K[a-z]', f[1]): continue
    if f[3] not in ('overview', 'oblique', 'closeup', 'sky'): continue
    m = re.search(r'\[kernel ([^\]@]*?)(\.spv)?@', line)
    k = m.group(1) if m else 'built-in'
    d = re.search(r'\[(\d+) px differ from the first row, (\d+) in colour\]', line)
    p = f[1]
    procs += [p] if p not in procs else []
    kerns += [k] if k not in kerns else []
    rows[(f[2], f[3])][(p, k)] = (float(f[11]), float(f[17]), f[9], f'{d.group(1)} / {d.group(2)}' if d else '-')
print('| scene | view | kernel | steps | ' + ' | '.join(f'{p} G rays/s (/ built-in)' for p in procs) +
      ' | rays / built-in (median) | prim+shadow / built-in (median) | px differ (hits / colour) |')
print('| --- | --- | --- | ---: | ' + ' | '.join('---:' for p in procs) + ' | ---: | ---: | ---: |')
for (sc, v), r in rows.items():
    for k in kerns:
        have = [p for p in procs if (p, k) in r and (p, 'built-in') in r]
        if not have: continue
        cells, ra, rp = [], [], []
        for p in procs:
            if p not in have: cells.append('-'); continue
            x, b = r[(p, k)], r[(p, 'built-in')]
            ra.append(x[0] / b[0] if b[0] else float('nan')); rp.append(x[1] / b[1] if b[1] else float('nan'))
            cells.append(f'{x[0]:.2f} ({ra[-1]:.3f})')
        diff = next((r[(p, k)][3] for p in have if r[(p, k)][3] != '-'), '-')
        print(f'| {sc} | {v} | {k} | {r[(have[0], k)][2]} | ' + ' | '.join(cells) +
              f' | {st.median(ra):.3f} | {st.median(rp):.3f} | {diff} |')
