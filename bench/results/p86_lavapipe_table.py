# Stop 86 (issue 21): per view, voxkit / ESVO of the grid walk and of the octree walk (timestamps / per CPU second)
# from a `render_bench --grid --octree --cpu-time` log: python3 bench/results/p86_lavapipe_table.py LOG
import sys,collections
rows=collections.defaultdict(list)
for l in open(sys.argv[1]):
    if '640x360' not in l or l.startswith('shadow'): continue
    f=l.split()
    kind='oct' if 'octree walk' in l else 'grid'
    rows[(f[0],f[1],kind)].append((float(f[13]),float(f[21])))
keys=[]
for k in rows:
    if (k[0],k[1]) not in keys: keys.append((k[0],k[1]))
ok={'grid':[0,0],'oct':[0,0]}
for s,v in keys:
    g=rows[(s,v,'grid')]; o=rows[(s,v,'oct')]
    fmt=lambda xs:' '.join('%.2f/%.2f'%x for x in xs)
    print('%-22s %-9s grid %-22s octree %-22s'%(s[:22],v,fmt(g),fmt(o)))
    import statistics
    for kind,xs in (('grid',g),('oct',o)):
        if xs:
            ok[kind][0]+= min(x[1] for x in xs)>=1.0
            ok[kind][1]+=1
print('views with every round >= 1.0 per CPU s:',ok)
