#!/bin/bash
# Stop 89 (issue 21), second run, written and NOT RUN: the session's device time was spent by starts that found no
# machine. Two experiments against the same trace.comp without them, in one process per scene set, with the kernels'
# shader statistics (render_bench --kernels payload/gv/k_main.spv@c1,payload/gv/k_regs.spv@c1,payload/gv/k_fine2.spv@c1
# --shader-stats; glslangValidator -V --target-env vulkan1.1 [-DGRID_REGS | -DGRID_FINE2] render/shaders/trace.comp
# with bench/results/p89b_variants.patch applied to b24baa8's grid_walk.glsl; main has neither):
# - GRID_REGS: a walk's position from t as (t - bias) / invd, so that fr and ad need not live across the loop (on
#   lavapipe 0 pixels apart on the .vox scenes, 1 pixel on three of the terrains' views);
# - GRID_FINE2: where every root is at level 1, a brick's cell step that stays in its brick takes the next cell
#   step in the same iteration (two an iteration; on lavapipe 0 pixels apart).
# With ROUNDS="1 2" (TREGS=1: the terrains too), main's headline table first (b24baa8: 0daaaea's kernels), every bench
# scene and view with ESVO, one process per round for the corpus and one for the terrains; table: python3
# bench/results/p88_table.py LOG.
# payload: render_bench.gz (Release, b24baa8), gv/, REV, lib/, the five corpus .vox files. Carry [".gl", "payload"].
[ -n "$OUT" ] && exec > >(tee $OUT/p89b.log) 2>&1
LIM=${LIM:-130}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^grid:"
payload_setup p89b
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
gpu_warmup payload/eph_monu1.vox
for r in ${ROUNDS:-}; do
  run corpus$r 60 $T/render_bench --sizes $SIZE --runs $RUNS --warmup $WU $V
  run terrain$r 75 $T/render_bench --generate --sizes $SIZE --runs $RUNS --warmup $WU
done
K=payload/gv/k_main.spv@c1,payload/gv/k_regs.spv@c1,payload/gv/k_fine2.spv@c1
run regs 95 $T/render_bench --kernels $K --shader-stats --sizes $SIZE --runs $RUNS --warmup $WU $V
[ -n "$TREGS" ] && run tregs 75 $T/render_bench --generate --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p89b
