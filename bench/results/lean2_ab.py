# lean2 (issue 21): A/B tables from a batch log: python3 lean2_ab.py lean2_b2.txt (render_bench: medians of the
# A and B processes, per-round ratios; passes_bench: every process, the ratio of the faster of each)
import sys,re,statistics as st
rb={}; pb={}; cur=None; scene=None; view=None
for line in open(sys.argv[1]):
    m=re.match(r'-- (render_bench|passes_bench) ([ABC])(\d)',line)
    if m: cur=(m.group(1),m.group(2)); continue
    if line.startswith('-- '): cur=None; continue
    if not cur: continue
    if cur[0]=='render_bench':
        f=line.split()
        if len(f)>15 and f[2].count('x')==1 and f[0]!='scene' and 'kernel' not in line:
            rb.setdefault((f[0],f[1]),{}).setdefault(cur[1],[]).append((float(f[9]),float(f[15]),f[4]))
    else:
        m=re.match(r'## (\S+), (\S+) \(([\d.]+)%',line)
        if m: scene,view,hit=m.group(1),m.group(2),m.group(3); continue
        m=re.match(r'\| (single shader|gbuffer,direct|gbuffer) [^|]*\| ([\d.]+) \|',line)
        if m: pb.setdefault((scene,view,hit,m.group(1)),{}).setdefault(cur[1],[]).append(float(m.group(2)))
print('| scene | view | hit | primary A / B G rays/s | B/A | primary+shadow A / B G pix/s | B/A | per round B/A | sh/prim A, B |')
print('| --- | --- | ---: | ---: | ---: | ---: | ---: | --- | --- |')
for (s,v),d in rb.items():
    if 'A' not in d or 'B' not in d: continue
    pa=st.median([x[0] for x in d['A']]); pbb=st.median([x[0] for x in d['B']])
    sa=st.median([x[1] for x in d['A']]); sb=st.median([x[1] for x in d['B']])
    rounds=', '.join('%.3f'%(b[1]/a[1]) for a,b in zip(d['A'],d['B']))
    print('| %s | %s | %s | %.2f / %.2f | %.3f | %.2f / %.2f | %.3f | %s | %.2f, %.2f |'%(s,v,d['A'][0][2],pa,pbb,pbb/pa,sa,sb,sb/sa,rounds,sa/pa,sb/pbb))
print()
print('| scene | view (hit) | row | A ms | B ms | B/A | C ms | C/A |')
print('| --- | --- | --- | --- | --- | ---: | --- | ---: |')
for (s,v,h,r),d in pb.items():
    a=d.get('A',[]); b=d.get('B',[]); c=d.get('C',[])
    if not a or not b: continue
    print('| %s | %s (%s%%) | %s | %s | %s | %.3f | %s | %s |'%(s,v,h,r,', '.join('%.3f'%x for x in a),', '.join('%.3f'%x for x in b),min(b)/min(a),', '.join('%.3f'%x for x in c),'%.3f'%(min(c)/min(a)) if c else '-'))
