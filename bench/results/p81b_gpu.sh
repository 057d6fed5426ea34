#!/bin/bash
# Stop 81 (issue 21), second run: where a grid's root lies above level 1 (terrain4096: root at level 2, each coarse
# step a root load then a node load), the level-2 node last looked up kept across the loop (grid_walk.glsl
# GRID_NCACHE, on in this payload's binaries) against fa66441's kernel (payload/gv/trace_p81.spv, without it) in the
# same process; then test_render_gpu and test_passes on the GPU with it. Carry [".gl", "payload"] as p81a.
LIM=${LIM:-200}; source bench/results/gpu_payload_lib.sh; F="$F|^stats|^grid:"
payload_setup p81b test_render_gpu test_passes
R=${OUT:-/tmp}/p81b.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup --generate > /dev/null 2>&1
run terrain 150 $T/render_bench --generate --kernels payload/gv/trace_p81.spv@c1 --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p81b
gpu_tests "root|deep float, depth" test_render_gpu test_passes
} 2>&1 | tee $R
