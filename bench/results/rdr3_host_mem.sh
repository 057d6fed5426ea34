#!/bin/sh
# issue 18, branch rdr3: svo_bake's host peak, --load whole against --load models (dev VM, lavapipe).
# usage: rdr3_host_mem.sh BIN (build-gpu/bin of the branch) DIR (helmet_r64.svo, terrain.svo made by:
#   vox2svo khronos_DamagedHelmet.glb helmet_r64.svo --res 1024 --region 64; svo_build_bench -o terrain.svo)
B=$1; D=$2
for f in helmet_r64 terrain; do
  for l in whole models; do
    echo "== $f --load $l"
    /usr/bin/time -v "$B/svo_bake" "$D/$f.svo" "$D/${f}_$l.probes" --grid 2,2,2 --res 16 --spp 1 -q -v --load $l 2>&1 |
      grep -E 'host:|load:|baked|Maximum resident|Elapsed'
  done
  cmp "$D/${f}_whole.probes" "$D/${f}_models.probes" && echo "$f: same bytes"
done
