#!/bin/bash
# lean2 (issue 21), batch 3 (about 20 s): the branch's final build (B: trace.comp's colour and depth kernels lean for
# DEEP 0 and 1, one instance; the G-buffer kernels lean) with main's trace.comp (k/t_main.spv) in the same process on
# terrain1024 (DEEP 1: the new part) and, on the demo island (several instances), t_bvhd1 (the lean walk in the BVH
# kernels too, not in the branch); colour frames compared with the built-in kernel's; svo_render albedo A against B.
s0=$(date +%s); left() { echo $(( $1 * ${TS:-1} - ($(date +%s) - s0) )); }
T=/tmp/lean2; rm -rf $T; mkdir -p $T; tar xzf bins.tgz -C $T; for f in $T/*/*.gz; do gunzip -f $f; done; chmod +x $T/*/*
tar xzf k.tgz -C $T
SIZE=${SIZE:-1920x1080}; RUNS=${RUNS:-10}; WU=${WU:-0.1}; CHK=${CHK:-1920x1080}
echo "== lean2 batch 3 on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(nproc) CPUs $(date -u +%T); A $(cat A_COMMIT), B $(cat B_COMMIT)"
flt() { sed "s|$T/||g; s/\[shadow rays[^]]*\]  //; s/\[traced[^]]*\]  //; s/  *\[warps[^]]*\]//" | cut -c1-300; }
F='^scene|^eph|^terrain|^island|^stats: trace|^device'
l=$(left 3); timeout $l $T/B/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 1 --views overview island.vox > /dev/null 2>&1
echo "-- terrain1024, B with main's trace.comp $(date -u +%T)"
l=$(left 11); timeout $l $T/B/render_bench --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --shader-stats --kernels $T/k/t_main.spv@c1 terrain1024.svo 2>&1 | grep -E "$F" | flt
echo "-- island, B with main's trace.comp and t_bvhd1 $(date -u +%T)"
l=$(left 18); timeout $l $T/B/render_bench --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views closeup,oblique --shader-stats --kernels $T/k/t_main.spv@c1,$T/k/t_bvhd1.spv@c1 island.vox 2>&1 | grep -E "$F" | flt
echo "-- svo_render --mode albedo terrain1024, A against B $(date -u +%T)"
for x in A B; do l=$(left 21); [ $l -gt 1 ] && timeout $l $T/$x/svo_render terrain1024.svo $T/$x.pfm --size $CHK --mode albedo > /dev/null 2>&1; done
cmp $T/A.pfm $T/B.pfm && echo "   the same bytes"
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
