#!/bin/bash
# ray6 (issue 21, seventeenth sitting), batch 1 (limit 100 s). Main's render_bench (bench/out/base/bin, 46eb6d3)
# with trace kernel variants built from the branch's source (--kernels, one process, the same scene and rays):
# 1: the terrains (--generate --no-esvo) with --shader-stats: the file form (VX_GPU_NODE_FORM=file, the rate to
#    reach) and the GPU form (default) with variants of the deep models' kernel in the GPU form without the turn:
#    k_gf (plain: the fifteenth sitting's 96 registers?), k_gfz (the rebase slots' indices through an opaque 0),
#    k_gfp (the stack array padded to 64 entries), k_gfzp (both), k_gfp2 (padded to 128), k_gf1 (GPU form + one
#    call site for primary and shadow rays); two rounds F G F G where time allows (round 2: built-in kernels only).
# 2: eph_menger, eph_monu1, ogt_doom, eph_dragon with ESVO: k_merge (the push's valid test and the child's exit
#    test in one compare, DEEP 0 kernels).
# (the k_*.spv: bench/results/issue21_s17_variants.sh; bench/out/ray6 held them and the four .vox files)
export LD_LIBRARY_PATH=bench/out/base/bin
L=bench/out/ray6; A=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}; RUNS=${RUNS:-10}; V=${V:-overview,oblique,closeup}
s0=$(date +%s); left() { echo $(( $1 - ($(date +%s) - s0) )); }
echo "== ray6 batch 1 on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1) $(date -u +%T)"
timeout 4 $A/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
K1=$L/k_gf.spv@c1,$L/k_gfz.spv@c1,$L/k_gfp.spv@c1,$L/k_gfzp.spv@c1,$L/k_gfp2.spv@c1,$L/k_gf1.spv@c1
for round in 1 2; do
  for who in F G; do
    l=$(left 66); [ $l -gt 6 ] || break 2
    echo "-- 1: terrains round $round $who $(date -u +%T)"
    if [ $who = F ]; then
      VX_GPU_NODE_FORM=file timeout $l $A/render_bench --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views $V \
        $( [ $round = 1 ] && echo --shader-stats ) 2>&1 | grep -E '^terr|^stats: trace \[spec 0|^stats: trace \[spec 3'
    else
      timeout $l $A/render_bench --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views $V \
        $( [ $round = 1 ] && echo --kernels $K1 --shader-stats ) 2>&1 | grep -E '^terr|^stats: trace \[spec 0|^stats: trace \[spec 3' | cut -c1-420
    fi
  done
done
echo "-- 2: eph_menger, eph_monu1, ogt_doom, eph_dragon with ESVO, k_merge $(date -u +%T)"
l=$(left 97); [ $l -gt 6 ] && timeout $l $A/render_bench --sizes $SIZE --runs $RUNS --warmup $WU --views $V \
  --kernels $L/k_merge.spv@c1 --shader-stats $L/eph_menger.vox $L/eph_monu1.vox $L/ogt_doom.vox $L/eph_dragon.vox 2>&1 \
  | grep -E '^eph|^ogt|^stats: trace \[spec 0|^stats: trace \[spec 3' | cut -c1-420
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
