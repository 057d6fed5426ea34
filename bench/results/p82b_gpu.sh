#!/bin/bash
# Stop 82 (issue 21), second run: a grid hit's record from its brick's record word (render/grid.h
# vx__grid_brick_record: the descent takes the last 3 levels, not all), this tree's render_bench, against
# payload/gv/base.spv (trace.comp before the change, compiled by hand: the descent from the root; the same host
# and grids, whose record words it does not read) and three timing variants of that kernel, not kernels to adopt
# (their images are wrong): gv/norec.spv, no record at all (the bound); gv/nosh.spv, no shadow ray and no depth-map
# lookup (vis 1); gv/st2.spv, the colour mode's pixel stored as a vec2. Then the GPU tests.
# Carry [".gl", "payload"].
LIM=${LIM:-420}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^helmet|^grid:"
payload_setup p82b test_render_gpu test_passes test_render_hits
V="payload/eph_menger.vox payload/eph_monu1.vox payload/eph_dragon.vox payload/ogt_test_multiple_model_scene.vox"
K=payload/gv/base.spv@c1,payload/gv/norec.spv@c1,payload/gv/nosh.spv@c1,payload/gv/st2.spv@c1
R=${OUT:-/tmp}/p82b.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 120 $T/render_bench --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 130 $T/render_bench --generate --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU
run helmet 40 $T/render_bench --grid-world --kernels payload/gv/base.spv@c1 --sizes $SIZE --runs $RUNS --warmup $WU payload/helmet1024.svo
payload_end p82b
TLIM=100 gpu_tests "regions|union" test_render_hits test_passes test_render_gpu
} 2>&1 | tee $R
