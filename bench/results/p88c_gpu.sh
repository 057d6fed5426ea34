#!/bin/bash
# Stop 88 (issue 21), third run: an empty entry's extent toward the ray's octant (render/grid.c fill_octants,
# grid_walk.glsl GRID_SKIP: a ray leaves the empty cube from its entry toward its octant, not only the Chebyshev
# cube around it). render_bench A (payload/render_bench.gz, main c8336de) and B (render_bench_b.gz, this change)
# alternating, A B A B, every bench scene and view with ESVO; then this change's test_render_gpu, test_render_hits
# and test_passes on the GPU. payload: render_bench.gz, render_bench_b.gz, T_*.gz, REV, lib/, the corpus .vox
# copies. Carry [".gl", "payload"].
[ -n "$OUT" ] && exec > >(tee $OUT/p88c.log) 2>&1
LIM=${LIM:-330}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^grid:"
payload_setup p88c test_render_gpu test_render_hits test_passes
gunzip -c payload/render_bench_b.gz > $T/render_bench_b; chmod +x $T/render_bench_b
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
for r in 1 2; do
  run A$r 40 $T/render_bench --sizes $SIZE --runs $RUNS --warmup $WU $V
  run B$r 40 $T/render_bench_b --sizes $SIZE --runs $RUNS --warmup $WU $V
done
run At 45 $T/render_bench --generate --sizes $SIZE --runs $RUNS --warmup $WU
run Bt 45 $T/render_bench_b --generate --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p88c
[ -n "$NOTEST" ] || { TLIM=200 gpu_tests "" test_render_gpu; TLIM=40 gpu_tests "4096" test_render_hits; TLIM=60 gpu_tests "" test_passes; }
