#!/usr/bin/env python3
"""lvp2 (issue 21, eighteenth sitting): the lavapipe tables from the raw log of lvp2_lvp.sh.
Per (threads, config, binary, scene, view, size): medians over the processes of McpuVX and McpuES (M primary rays
per CPU s, render_bench --cpu-time) and of the per-process ratio cVX/ES with its minimum; with two threads the
wall rates MrayVX / MrayES. Usage: lvp2_table.py LOG..."""
import re, sys, statistics as st
from collections import defaultdict

rows = defaultdict(list)  # (threads, cfg, who, scene, view, size) -> [(vx, es, ratio, hit, wall_vx, wall_es)]
rows6 = defaultdict(list)  # phase 6's B: (cfg, scene, view) -> same
for path in sys.argv[1:]:
    key = None
    for line in open(path):
        m = re.match(r'-- phase (\d+) round \d+ (host|avx2) (A|B|C) (\S+) threads (\d+)', line)
        if m:
            key = (int(m.group(5)), m.group(2), m.group(3))
            ph6 = m.group(1) == '6'
            continue
        t = line.split()
        if key is None or len(t) < 23 or t[1] not in ('overview', 'oblique', 'closeup') or 'x' not in t[2]:
            continue
        try:
            vals = (float(t[19]), float(t[20]), float(t[21]), t[4], float(t[9]), float(t[10]))
        except ValueError:
            continue
        if ph6 and key[2] == 'B':
            rows6[(key[1], t[0], t[1])].append(vals)  # phase 6's B: against C only
        else:
            rows[key + (t[0].replace('.vox', ''), t[1], t[2])].append(vals)

med = lambda v: st.median(v) if v else float('nan')
scenes = ['eph_monu1', 'eph_menger', 'ogt_doom', 'eph_dragon', 'terrain1024', 'terrain4096']
views = ['overview', 'oblique', 'closeup']

def get(th, cfg, who, sc, vw, sz):
    r = rows.get((th, cfg, who, sc, vw, sz), [])
    return dict(vx=med([x[0] for x in r]), es=med([x[1] for x in r]), ratio=med([x[2] for x in r]),
                rmin=min([x[2] for x in r]) if r else float('nan'), n=len(r), hit=r[0][3] if r else '-',
                wvx=med([x[4] for x in r]), wes=med([x[5] for x in r]))

for sz in ('480x270', '1280x720'):
    print(f'\n## LP_NUM_THREADS=1, {sz}: M primary rays per CPU s (medians), B / A, voxkit / ESVO (median of the '
          'per-process ratios [min]) of A and of B (n: processes)')
    print('| scene | view | hit | host A | host B | **B / A** | VX/ES A | **VX/ES B** [min] (n) | avx2 A | avx2 B | '
          '**B / A** | VX/ES A | **VX/ES B** [min] (n) |')
    print('| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |')
    for sc in scenes:
        for vw in views:
            cells, hit = [], '-'
            for cfg in ('host', 'avx2'):
                a, b = get(1, cfg, 'A', sc, vw, sz), get(1, cfg, 'B', sc, vw, sz)
                hit = a['hit'] if a['n'] else (b['hit'] if b['n'] else hit)
                ba = f"**{b['vx'] / a['vx']:.2f}**" if a['n'] and b['n'] else '-'
                cells += [f"{a['vx']:.2f}" if a['n'] else '-', f"{b['vx']:.2f}" if b['n'] else '-', ba,
                          f"{a['ratio']:.2f}" if a['n'] else '-',
                          f"**{b['ratio']:.2f}** [{b['rmin']:.2f}] ({b['n']})" if b['n'] else '-']
            if all(c == '-' for c in cells[:1] + cells[1:2] + cells[5:7]):
                continue
            print(f'| {sc} | {vw} | {hit} | ' + ' | '.join(cells) + ' |')

two = [k for k in rows if k[0] == 2]
if two:
    print('\n## LP_NUM_THREADS=2, host: wall M primary rays/s (dispatch timestamps), voxkit A / B, ESVO in B\'s process')
    print('| scene | view | size | hit | VX A | VX B | B / A | ESVO | VX B / ESVO |')
    print('| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |')
    for sc in scenes:
        for vw in views:
            for sz in ('480x270', '1280x720'):
                a, b = get(2, 'host', 'A', sc, vw, sz), get(2, 'host', 'B', sc, vw, sz)
                if not a['n'] and not b['n']:
                    continue
                print(f"| {sc} | {vw} | {sz} | {b['hit']} | {a['wvx']:.1f} | {b['wvx']:.1f} | {b['wvx'] / a['wvx']:.2f} | "
                      f"{b['wes']:.1f} | {b['wvx'] / b['wes']:.2f} |")

if any(k[2] == 'C' for k in rows):
    print('\n## The DEEP 2 ladder\'s size, 480x270, LP_NUM_THREADS=1: C (S_MAX - 15 up, fbb131c\'s) against B (S_MAX - 20 up), '
          'M primary rays per CPU s, medians (B\'s processes of phase 6 only)')
    print('| scene | view | host C | host B | **B / C** | avx2 C | avx2 B | **B / C** |')
    print('| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |')
    for sc in ('terrain1024', 'terrain4096'):
        for vw in views:
            cells = []
            for cfg in ('host', 'avx2'):
                c, b = rows.get((1, cfg, 'C', sc, vw, '480x270'), []), rows6.get((cfg, sc, vw), [])
                cv, bv = med([x[0] for x in c]), med([x[0] for x in b])
                cells += [f'{cv:.2f} ({len(c)})', f'{bv:.2f} ({len(b)})', f'**{bv / cv:.2f}**' if c and b else '-']
            print(f'| {sc} | {vw} | ' + ' | '.join(cells) + ' |')
