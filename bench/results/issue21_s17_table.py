#!/usr/bin/env python3
"""lvp1 (issue 21, seventeenth sitting): the lavapipe tables from the raw logs of issue21_s17_lvp*.sh.
Rows per (config, binary, scene, view, size): medians over the processes of McpuVX, McpuES and the per-process
ratio cVX/ES (render_bench --cpu-time). Usage: issue21_s17_table.py LOG... (headers '-- round R CFG [A|B] ...')."""
import re, sys, statistics as st
from collections import defaultdict

rows = defaultdict(list)  # (cfg, who, kind, scene, view, size) -> [(vx, es, ratio, hit)]
for path in sys.argv[1:]:
    cfg = who = None
    # issue21_s17_lvp.sh: main (A); _ab: A and B (e7c2140); _esvosel: B (3552fa6, B's kernel) against the ESVO
    # given the same stack form; _final_gen: F (fbb131c) against the bench's ESVO (plain) and that ESVO (sel)
    kind = 'sel' if 'esvosel' in path else 'es'
    for line in open(path):
        m = re.match(r'-- round \d+ (host|avx2) (?:(A|B|plain|sel) )?(?:vox|gen)', line)
        if m:
            cfg, w = m.group(1), m.group(2)
            if w in ('plain', 'sel'):
                who, kind = 'F', ('sel' if w == 'sel' else 'es')
            else:
                who = w or ('B' if kind == 'sel' else 'A')
                if who == 'B' and 'final_vox' in path:
                    who = 'F'  # _final_vox: A against fbb131c, one round at a quiet moment
            continue
        t = line.split()
        if cfg is None or len(t) < 23 or t[1] not in ('overview', 'oblique', 'closeup') or 'x' not in t[2]:
            continue
        try:
            vx, es, ratio = float(t[19]), float(t[20]), float(t[21])
        except ValueError:
            continue
        rows[(cfg, who, kind, t[0].replace('.vox', ''), t[1], t[2])].append((vx, es, ratio, t[4]))

def med(v):
    return st.median(v) if v else float('nan')

scenes = ['eph_monu1', 'eph_menger', 'ogt_doom', 'eph_dragon', 'terrain1024', 'terrain4096']
views = ['overview', 'oblique', 'closeup']

def get(cfg, who, kind, sc, vw, sz):
    r = rows.get((cfg, who, kind, sc, vw, sz), [])
    return (med([x[0] for x in r]), med([x[1] for x in r]), med([x[2] for x in r]), len(r), r[0][3] if r else '-',
            min([x[2] for x in r]) if r else float('nan'))

print('## main (A) against ESVO: McpuVX / McpuES (medians), VX/ES median of the per-process ratios [min] (n processes)')
for cfg in ('host', 'avx2'):
    print(f'\n### {cfg}')
    print('| scene | view | hit | 480x270 VX / ES | VX/ES [min] (n) | 1280x720 VX / ES | VX/ES [min] (n) |')
    print('| --- | --- | ---: | ---: | ---: | ---: | ---: |')
    for sc in scenes:
        for vw in views:
            a = get(cfg, 'A', 'es', sc, vw, '480x270'); b = get(cfg, 'A', 'es', sc, vw, '1280x720')
            if not a[3] and not b[3]: continue
            print(f'| {sc} | {vw} | {a[4]} | {a[0]:.2f} / {a[1]:.2f} | **{a[2]:.2f}** [{a[5]:.2f}] ({a[3]}) | '
                  f'{b[0]:.2f} / {b[1]:.2f} | **{b[2]:.2f}** [{b[5]:.2f}] ({b[3]}) |')

print('\n## the branch (B: e7c2140 on the .vox scenes, F: fbb131c on the terrains) against main (A), 480x270: '
      'McpuVX medians, B / A; VX/ES of B\'s processes; VX/ES against the ESVO given the same stack form (sel)')
print('| scene | view | host A | host B | **B / A** | F / A | VX/ES B | VX/ES-sel B | avx2 A | avx2 B | **B / A** | F / A | VX/ES B | VX/ES-sel B |')
print('| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |')
for sc in scenes:
    for vw in views:
        cells = []
        for cfg in ('host', 'avx2'):
            bw = 'F' if sc.startswith('terrain') else 'B'
            a = get(cfg, 'A', 'es', sc, vw, '480x270'); b = get(cfg, bw, 'es', sc, vw, '480x270')
            s = get(cfg, bw, 'sel', sc, vw, '480x270')
            fa = get(cfg, 'F', 'es', sc, vw, '480x270')
            fcell = f'{fa[0] / a[0]:.2f}' if (fa[3] and a[3] and bw == 'B') else '-'
            cells += [f'{a[0]:.2f}', f'{b[0]:.2f}', f'**{b[0] / a[0]:.2f}**' if a[3] and b[3] else '-', fcell,
                      f'{b[2]:.2f}' if b[3] else '-', f'{s[2]:.2f}' if s[3] else '-']
        print(f'| {sc} | {vw} | ' + ' | '.join(cells) + ' |')
