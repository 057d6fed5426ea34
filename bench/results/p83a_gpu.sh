#!/bin/bash
# Stop 83 (issue 21), first run: stop 82's prepared p82d (never ran) plus what adopting its patch needs. Where the
# shadow ray's time goes in a colour frame (eph_menger's overview, the one bench view under the 60% goal): two timing
# variants of 442a119's trace.comp, not kernels (their images are wrong), in the same process as the built-in kernel:
# gv/nosh.spv, no shadow ray and no depth-map lookup (vis 1); gv/smaponly.spv, the map's lookup but no walk. Then the
# map's texels interleaved (payload/render_bench_il.gz, built with bench/results/p82e_smap_texels.patch applied: m1,
# m2, top and occl of a texel in one 16-byte load) against 442a119's render_bench, alternating processes A B A B;
# the patched build's map off and on (--shadow-map off,0: the map must change no pixel), the patched build on every
# bench scene (the headline table if adopted), and test_render_smap built with the patch on the GPU.
# Carry [".gl", "payload"].
LIM=${LIM:-540}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^grid:|^shadow map"
payload_setup p83a test_render_smap
V="payload/eph_menger.vox payload/eph_monu1.vox payload/eph_dragon.vox payload/ogt_test_multiple_model_scene.vox"
A="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
R=${OUT:-/tmp}/p83a.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
gunzip -c payload/render_bench_il.gz > $T/render_bench_il; chmod +x $T/render_bench_il
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
for k in 1 2; do
  run A$k 25 $T/render_bench --no-esvo --views overview,closeup --sizes $SIZE --runs $RUNS --warmup $WU $V
  run B$k 25 $T/render_bench_il --no-esvo --views overview,closeup --sizes $SIZE --runs $RUNS --warmup $WU $V
done
run variants 60 $T/render_bench --no-esvo --views overview,closeup --kernels payload/gv/nosh.spv@c1,payload/gv/smaponly.spv@c1 --sizes $SIZE --runs $RUNS --warmup $WU $V
run mapsB 50 $T/render_bench_il --no-esvo --views overview,closeup --shadow-map off,0 --sizes $SIZE --runs $RUNS --warmup $WU $V
run corpusB 60 $T/render_bench_il --sizes $SIZE --runs $RUNS --warmup $WU $A
run terrainB 90 $T/render_bench_il --generate --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p83a
TLIM=100 gpu_tests "" test_render_smap
} 2>&1 | tee $R
