#!/bin/bash
# Stop 84 (issue 21): p83b_gpu.sh (not run at stop 83) plus the shader statistics of main's kernels (the colour kernel with the record words and the map's one load).
# p83b: the depth map's four
# texel words in one 16-byte load alone (main at 5731c2e: payload/render_bench_il.gz) against 442a119
# (payload/render_bench.gz), alternating processes A IL A IL, the colour frames (primary plus shadow) of the corpus
# scenes' overviews and close-ups, no ESVO (p83a measured the change only together with the pair layout); then
# terrain4096's overview three times a build (its colour frame was 0.48 of primary in p83a, 0.69 in p82c with the
# same kernel). Carry [".gl", "payload"].
LIM=${LIM:-290}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^grid:|^shadow map"
payload_setup p84a
V="payload/eph_menger.vox payload/eph_monu1.vox payload/eph_dragon.vox payload/ogt_test_multiple_model_scene.vox"
R=${OUT:-/tmp}/p84a.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
gunzip -c payload/render_bench_il.gz > $T/render_bench_il; chmod +x $T/render_bench_il
timeout 6 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
for k in 1 2; do
  run A$k 16 $T/render_bench --no-esvo --views overview,closeup --sizes $SIZE --runs $RUNS --warmup $WU $V
  run IL$k 16 $T/render_bench_il --no-esvo --views overview,closeup --sizes $SIZE --runs $RUNS --warmup $WU $V
done
for k in 1 2 3; do
  run tA$k 30 $T/render_bench --no-esvo --generate --views overview --sizes $SIZE --runs $RUNS --warmup $WU
  run tIL$k 30 $T/render_bench_il --no-esvo --generate --views overview --sizes $SIZE --runs $RUNS --warmup $WU
done
run S 25 $T/render_bench_il --shader-stats --no-esvo --views closeup --sizes $SIZE --runs 1 --warmup 0 payload/eph_monu1.vox
payload_end p84a
} 2>&1 | tee $R
