#!/bin/bash
# Stop 88 (issue 21), fourth run: p88c's octant extents cost 4-7% a step on the corpus's close-ups (eph_menger's
# at the same steps). Three forms of grid_walk.glsl's GRID_SKIP distance, as variants of trace.comp timed in the
# same processes by this change's render_bench (its grids carry the extents; render_bench --kernels
# payload/gv/k_octN.spv@c1: glslangValidator -V --target-env vulkan1.1 -DOCTV=N of the experiment's
# render/shaders/trace.comp): 0 the distance alone (main's walk: the extents not read), 1 the extent from a shift
# held across the loop (p88c's), 2 the shift made from negm in the skip. --shader-stats: registers of each.
# payload: render_bench_b.gz, gv/, REV, lib/, the corpus .vox copies. Carry [".gl", "payload"].
[ -n "$OUT" ] && exec > >(tee $OUT/p88d.log) 2>&1
LIM=${LIM:-300}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^grid:|regist|stats"
payload_setup p88d
gunzip -c payload/render_bench_b.gz > $T/render_bench_b; chmod +x $T/render_bench_b
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
K=payload/gv/k_oct0.spv@c1,payload/gv/k_oct1.spv@c1,payload/gv/k_oct2.spv@c1
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench_b --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus1 100 $T/render_bench_b --shader-stats --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU $V
run corpus2 100 $T/render_bench_b --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 90 $T/render_bench_b --generate --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p88d
