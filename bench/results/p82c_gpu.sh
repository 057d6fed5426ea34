#!/bin/bash
# Stop 82 (issue 21), third run: the headline table with this stop's kernel (a grid hit's record from its brick's
# record word) on every bench scene and the helmet's regions, then test_render_gpu on the GPU with its albedo check
# (each walk's albedo frame against the CPU reference's within half a step of 1/255) and test_passes.
# Carry [".gl", "payload"].
LIM=${LIM:-300}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^helmet|^grid:"
payload_setup p82c test_render_gpu test_passes
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
R=${OUT:-/tmp}/p82c.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 60 $T/render_bench --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 90 $T/render_bench --generate --sizes $SIZE --runs $RUNS --warmup $WU
run helmet 30 $T/render_bench --grid-world --sizes $SIZE --runs $RUNS --warmup $WU payload/helmet1024.svo
payload_end p82c
TLIM=110 gpu_tests "albedo|regions" test_render_gpu
} 2>&1 | tee $R
