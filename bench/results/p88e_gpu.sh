#!/bin/bash
# Stop 88 (issue 21), fifth run: the octant extents as committed (GRID's bit 6, GRID_OCT, where some grid's root is
# at least 64 entries a side: render_scene.c grid_bits; the corpus's scenes keep main's kernel), every bench scene
# and view with ESVO, one round; then test_render_gpu (its root-level-2 and deep scenes walk with GRID_OCT).
# payload: render_bench_b.gz, T_test_render_gpu.gz, REV, lib/, the corpus .vox copies. Carry [".gl", "payload"].
[ -n "$OUT" ] && exec > >(tee $OUT/p88e.log) 2>&1
LIM=${LIM:-110}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^grid:"
payload_setup p88e test_render_gpu
gunzip -c payload/render_bench_b.gz > $T/render_bench_b; chmod +x $T/render_bench_b
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
run corpus 40 $T/render_bench_b --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 60 $T/render_bench_b --generate --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p88e
TLIM=190 gpu_tests "" test_render_gpu
