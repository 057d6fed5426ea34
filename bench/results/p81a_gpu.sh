#!/bin/bash
# Stop 81 (issue 21), first run: trace.comp's depth mode writes a vec2 (depth, coverage) a pixel instead of a vec4
# (vx_render_frame widens it on the host): 8 bytes a pixel, as the ESVO baseline's uvec2 (depth, steps). Every bench
# scene and view, the helmet's regions included, against the kernel of cae0ca3 (payload/gv/trace_p80.spv: vec4
# pixels, the same walk) in the same processes; then test_render_hits, test_passes and test_render_gpu on the GPU.
# Run with carry [".gl", "payload"]: payload/ holds render_bench.gz and T_*.gz (Release, this stop's tree), gv/, REV,
# lib/, the five corpus .vox files and the helmet's .svo file.
LIM=${LIM:-330}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^helmet|^stats|^grid:"
payload_setup p81a test_passes test_render_gpu test_render_hits
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
K=payload/gv/trace_p80.spv@c1
R=${OUT:-/tmp}/p81a.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 100 $T/render_bench --shader-stats --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 120 $T/render_bench --generate --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU
run helmet 60 $T/render_bench --grid-world --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU payload/helmet1024.svo
payload_end p81a
gpu_tests "hits frame|regions|deep float, depth|depth pixels" test_render_hits test_passes test_render_gpu
} 2>&1 | tee $R
