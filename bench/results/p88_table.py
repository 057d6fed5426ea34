# Stop 88 (issue 21): the headline table from a p88a log (render_bench's built-in rows, two rounds):
# python3 bench/results/p88_table.py bench/results/p88a_h100.txt. Per view: hit, steps VX / ES, G rays/s of both
# (mean of the rounds), voxkit / ESVO of each round, primary + shadow over primary (GpixSh / GrayVX), GPU MiB.
import sys, collections
rows = collections.OrderedDict()
for l in open(sys.argv[1]):
    f = l.split()
    if len(f) < 20 or 'kernel' in l or f[3] not in ('overview', 'oblique', 'closeup') or f[4] != '1920x1080':
        continue
    rows.setdefault((f[2], f[3]), []).append(f)
n13 = 0
print('| scene | view | hit | steps VX / ES | G rays/s VX / ES | VX / ES (rounds) | Sh / prim | GPU MiB VX / ES |')
print('| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |')
for (s, v), fs in rows.items():
    vx = [float(f[11]) for f in fs]; es = [float(f[12]) for f in fs]
    r = [a / b for a, b in zip(vx, es)]
    sh = sum(float(f[17]) / float(f[11]) for f in fs) / len(fs)
    ok = min(r) >= 1.3
    n13 += ok
    rr = ', '.join(('**%.2f**' if ok else '%.3f' if round(x, 2) == 1.30 else '%.2f') % x for x in r)
    print('| %s | %s | %s | %s / %s | %.2f / %.2f | %s | %.2f | %s / %s |' % (
        s.replace('.vox', ''), v, fs[0][6], fs[0][9], fs[0][10], sum(vx) / len(vx), sum(es) / len(es), rr, sh,
        fs[0][19], fs[0][20]))
print('\nviews at 1.3x or more in every round: %d of %d' % (n13, len(rows)))
