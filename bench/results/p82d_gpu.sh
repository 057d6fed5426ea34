#!/bin/bash
# Stop 82 (issue 21), fourth run, for the next stop (not run at stop 82: no machine came, the device time ran out): where the shadow ray's time goes in a colour frame (eph_menger's
# overview, the one bench view under the 60% goal). Two timing variants of cd411da's trace.comp, not kernels (their
# images are wrong), each in the same process as the built-in kernel: gv/nosh.spv, no shadow ray and no depth-map
# lookup (vis 1); gv/smaponly.spv, the map's lookup but no walk (vis 1 where the map leaves a ray to walk); then the
# built-in kernel with the map off and on (--shadow-map off,0: the walk without the map). Then the map's texels
# interleaved (payload/render_bench_il.gz, built with bench/results/p82e_smap_texels.patch applied: m1, m2, top and
# occl of a texel in one 16-byte load) against cd411da's
# render_bench, alternating processes A B A B. Carry [".gl", "payload"].
LIM=${LIM:-260}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^grid:|^shadow map"
payload_setup p82d
V="payload/eph_menger.vox payload/eph_monu1.vox payload/eph_dragon.vox payload/ogt_test_multiple_model_scene.vox"
R=${OUT:-/tmp}/p82d.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run variants 60 $T/render_bench --no-esvo --views overview,closeup --kernels payload/gv/nosh.spv@c1,payload/gv/smaponly.spv@c1 --sizes $SIZE --runs $RUNS --warmup $WU $V
run maps 50 $T/render_bench --no-esvo --views overview,closeup --shadow-map off,0 --sizes $SIZE --runs $RUNS --warmup $WU $V
gunzip -c payload/render_bench_il.gz > $T/render_bench_il; chmod +x $T/render_bench_il
for k in 1 2; do
  run A$k 25 $T/render_bench --no-esvo --views overview,closeup --sizes $SIZE --runs $RUNS --warmup $WU $V
  run B$k 25 $T/render_bench_il --no-esvo --views overview,closeup --sizes $SIZE --runs $RUNS --warmup $WU $V
done
payload_end p82d
} 2>&1 | tee $R
