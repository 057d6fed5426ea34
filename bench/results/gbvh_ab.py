#!/usr/bin/env python3
"""gbvh (issue 21): the A/B table of a gbvh payload's log (passes_bench --gbuffer rows, processes A1 B1 A2 B2 ...):
per scene, view and row, A's and B's per-process times (the row's frame ms; for the separate passes also the
gbuffer pass's own ms), their medians, B/A of the medians and B/A per round.  python3 gbvh_ab.py LOG"""
import re, sys, statistics as st
rows = {}  # (scene, view, row) -> {'A': {round: ms}, 'B': ...}
hit = {}
cur = {}
compact = set()
for line in open(sys.argv[1]):
    m = re.match(r'\S+ ([AB])(\d) (.*)', line.rstrip('\n'))
    if not m:
        continue
    x, r, rest = m.group(1), int(m.group(2)), m.group(3)
    h = re.match(r'## (\S+), camera (\d) \(([\d.]+)% of pixels hit\)', rest)
    if h:
        cur[x] = (h.group(1), int(h.group(2)))
        hit[cur[x]] = h.group(3)
        continue
    c = re.match(r'\| (single shader[^|]*?|gbuffer[^|]*?) \| ([\d.]+) \| ([^|]*)\|', rest)
    if not c or x not in cur:
        continue
    name, ms, per = c.group(1).strip(), float(c.group(2)), c.group(3)
    if 'trace_compact' in name:  # a --layout compact process: its rows apart
        compact.add((x, r))
    sc, v = cur[x]
    key = (sc + (' (compact)' if (x, r) in compact else ''), v)
    hit[key] = hit[cur[x]]
    keys = [name]
    vals = [ms]
    g = re.search(r'(?:^|, )gbuffer ([\d.]+)', per)
    if 'separate' in name and g:
        keys.append('gbuffer pass alone')
        vals.append(float(g.group(1)))
    for k, val in zip(keys, vals):
        rows.setdefault(key + (k,), {'A': {}, 'B': {}})[x][r] = val
def names(sc):  # render_bench's views: three cameras overview, oblique, close-up; two oblique, close-up
    n = 1 + max(v for (s2, v) in hit if s2 == sc)
    return ['overview', 'oblique', 'close-up'][3 - n:]
print('| scene | view (hit) | row | A ms (per process) | B ms (per process) | A med | B med | B/A | B/A per round |')
print('| --- | --- | --- | --- | --- | ---: | ---: | ---: | --- |')
for (sc, v, k), d in rows.items():
    a, b = d['A'], d['B']
    if not a or not b:
        continue
    am, bm = st.median(a.values()), st.median(b.values())
    per = ', '.join('%.3f' % (b[r] / a[r]) for r in sorted(a) if r in b and a[r] > 0)
    print('| %s | %s (%s%%) | %s | %s | %s | %.4f | %.4f | %s | %s |' % (
        sc, names(sc)[v],
        hit.get((sc, v), '?'), k, ', '.join('%g' % a[r] for r in sorted(a)), ', '.join('%g' % b[r] for r in sorted(b)),
        am, bm, '%.3f' % (bm / am) if am > 0 else '-', per))
