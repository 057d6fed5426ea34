#!/bin/bash
# Stop 89 (issue 21), first run: three experiments beside main's kernel in the same processes, every bench scene
# and view with ESVO, one round (ROUNDS="1 2": two); the default rows time stop 88's committed octant extents (what
# p88e_gpu.sh was written for); then test_render_gpu. The experiments' code: bench/results/p89_experiments.patch
# (applies to 0daaaea; the payload's binaries were built with it).
# - the screen cull in one dispatch (render_bench --kernels @c2: trace.comp CULL_PASS 2, the misses' workgroups as
#   rows after the rectangle's) against main's two dispatches (@c1, the default row and again last);
# - GRID_HOLD (grid_walk.glsl: a brick's cell steps keep the two words of the cell's 8x4x2 cells in registers and
#   load them again only where the step leaves them) against the same trace.comp without it (payload/gv/k_main.spv,
#   k_hold.spv: glslangValidator -V --target-env vulkan1.1 [-DGRID_HOLD] render/shaders/trace.comp);
# - the beam pass (beam.comp, the block's tube over the octree) before the grid walk, which starts at the block's
#   distance (render_bench --beam 0,8,16; main turns the beam off where grids are walked).
# payload: render_bench.gz, T_test_render_gpu.gz, gv/, REV, lib/, the five corpus .vox files. Carry [".gl", "payload"].
[ -n "$OUT" ] && exec > >(tee $OUT/p89a.log) 2>&1
LIM=${LIM:-380}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^grid:"
payload_setup p89a test_render_gpu
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
K=@c2,payload/gv/k_main.spv@c1,payload/gv/k_hold.spv@c1,@c1
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
gpu_warmup payload/eph_monu1.vox
for r in ${ROUNDS:-1}; do
  run corpus$r 75 $T/render_bench --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU $V
  run terrain$r 75 $T/render_bench --generate --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU
  run beam$r 50 $T/render_bench --beam 0,8,16 --sizes $SIZE --runs $RUNS --warmup $WU $V
  run tbeam$r 50 $T/render_bench --generate --beam 0,8,16 --sizes $SIZE --runs $RUNS --warmup $WU
done
payload_end p89a
[ -z "$NOTEST" ] && TLIM=190 gpu_tests "" test_render_gpu
