#!/usr/bin/env python3
# occ (issue 21, twentieth sitting): the A/B table of an occ batch log (processes "-- A1", "-- B1", ...):
# per view the primary rays/s (G) of each process, the B/A ratios of each round, voxkit / ESVO in B's processes.
#   python3 occ_s20_table.py occ_s20_b2.txt
import re, sys, statistics
cur = None; rows = {}; hits = {}
for l in open(sys.argv[1]):
    m = re.match(r'^-- ([AB]\d)', l)
    if m: cur = m.group(1); continue
    if cur is None or not re.match(r'^(eph|ogt)', l) or 'kernel ' in l: continue
    f = l.split()
    key = (f[0][:-4], f[1]); hits[key] = f[4]
    rows.setdefault(key, {})[cur] = (float(f[9]), float(f[10]))
procs = sorted({p for d in rows.values() for p in d}, key=lambda p: (p[1], p[0]))
print('| scene | view | hit | ' + ' | '.join(p for p in procs) + ' | B/A per round | VX/ES in B |')
print('| --- | --- | ---: | ' + ' | '.join('---:' for _ in procs) + ' | ---: | ---: |')
for key, d in rows.items():
    rat = [d['B%d' % r][0] / d['A%d' % r][0] for r in (1, 2, 3) if 'A%d' % r in d and 'B%d' % r in d]
    ves = [d[p][0] / d[p][1] for p in d if p[0] == 'B']
    print('| %s | %s | %s | %s | %s | %s |' % (key[0], key[1], hits[key], ' | '.join('%.2f' % d[p][0] if p in d else '-' for p in procs),
          ', '.join('%.3f' % r for r in rat), ', '.join('%.2f' % v for v in ves)))
