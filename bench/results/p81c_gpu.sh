#!/bin/bash
# Stop 81 (issue 21), third run: where an overview's time goes, for the next stop. Two timing variants of fa66441's
# trace.comp (not kernels to adopt: their images are wrong), each in the same process as the built-in kernel:
# payload/gv/trace_nomiss.spv, the screen cull's miss pass returns at once (what the miss pass costs);
# payload/gv/trace_nostore.spv, the depth mode's pixel store skipped (what the stores cost; the walk kept by a store
# under a condition that never holds). eph_monu1, eph_dragon and the 104-instance scene, overview and close-up.
# Carry [".gl", "payload"].
LIM=${LIM:-150}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^grid:"
payload_setup p81c
V="payload/eph_monu1.vox payload/eph_dragon.vox payload/ogt_test_multiple_model_scene.vox"
R=${OUT:-/tmp}/p81c.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 120 $T/render_bench --views overview,closeup --kernels payload/gv/trace_nomiss.spv@c1,payload/gv/trace_nostore.spv@c1 --sizes $SIZE --runs $RUNS --warmup $WU $V
payload_end p81c
} 2>&1 | tee $R
