#!/bin/bash
# Stop 88 (issue 21), first run: the headline table again with main's kernels (c8336de: grids on every device, the
# entry-axis rule of stop 87), and one per-step experiment beside it in the same processes: grid_walk.glsl
# GRID_LAZY2 (a brick cell's 2^3 block test loads the other word of its pair only where the cell's own word's half
# of the block is empty) against the same trace.comp compiled without it (render_bench --kernels
# payload/gv/k_main.spv@c1,payload/gv/k_lazy2.spv@c1: glslangValidator -V --target-env vulkan1.1 [-DGRID_LAZY2]
# render/shaders/trace.comp). Every bench scene and view with ESVO, two rounds; then test_render_gpu.
# payload: render_bench.gz (Release, c8336de), gv/, REV, lib/, the five corpus .vox files, T_test_render_gpu.gz.
# Carry [".gl", "payload"].
[ -n "$OUT" ] && exec > >(tee $OUT/p88a.log) 2>&1
LIM=${LIM:-420}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^grid:"
payload_setup p88a test_render_gpu
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
K=payload/gv/k_main.spv@c1,payload/gv/k_lazy2.spv@c1
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
for r in 1 2; do
  run corpus$r 90 $T/render_bench --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU $V
  run terrain$r 120 $T/render_bench --generate --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU
done
payload_end p88a
TLIM=120 gpu_tests "" test_render_gpu
