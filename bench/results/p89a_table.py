# Stop 89 (issue 21): p89a's table: python3 bench/results/p89a_table.py bench/results/p89a_h100.txt (each experiment's rays/s over
# its baseline in the same process: @c2 / @c1, k_hold / k_main, --beam 8 and 16 / 0; the default row's G rays/s and VX / ES)
import re,collections,sys
rows=collections.OrderedDict()
for l in open(sys.argv[1]):
    f=l.split()
    if len(f)<18 or f[3] not in('overview','oblique','closeup') or f[4]!='1920x1080': continue
    lab=f[1]; m=re.search(r'\[kernel ([^\]]*)\]',l); k=m.group(1).replace('payload/gv/','') if m else 'default'
    if lab.startswith('beam') or lab.startswith('tbeam'): k='beam'+f[5]
    rows.setdefault((f[2].replace('.vox','')[:20],f[3]),{})[k]=(float(f[11]),float(f[15]),f[9],f[6])
print('| scene | view | hit | voxkit G rays/s (VX / ES) | one dispatch / two | GRID_HOLD / without | beam 8 / none | beam 16 / none | steps: none / beam 8 |')
print('| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |')
for (s,v),d in rows.items():
    def g(k,i=0): return d[k][i] if k in d else float('nan')
    r=lambda a,b: '%.3f'%(g(a)/g(b)) if a in d and b in d else '-'
    print("| %s | %s | %s | %.2f (%.2f) | %s | %s | %s | %s | %s / %s |" % (s,v,d['default'][3],g('default'),g('default',1), r('@c2','@c1'), r('k_hold.spv@c1','k_main.spv@c1'), r('beam8','beam0'), r('beam16','beam0'), d.get('beam0',('','','-'))[2], d.get('beam8',('','','-'))[2]))
