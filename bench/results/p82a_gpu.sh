#!/bin/bash
# Stop 82 (issue 21), first run: where a colour frame's time goes (primary plus shadow rays, the 60% goal), for the
# views under it. Three timing variants of trace.comp (not kernels to adopt: their images are wrong), each in the same
# process as the built-in kernel and payload/gv/base.spv (the same source compiled by hand: the control):
# gv/norec.spv, a grid hit's record (its octree descent for the colour) skipped; gv/nosh.spv, no shadow ray and no
# depth-map lookup (vis 1); gv/st2.spv, the colour mode's pixel stored as a vec2 (half the bytes).
# Carry [".gl", "payload"].
LIM=${LIM:-330}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^grid:"
payload_setup p82a
V="payload/eph_menger.vox payload/eph_monu1.vox payload/eph_dragon.vox"
K=payload/gv/base.spv@c1,payload/gv/norec.spv@c1,payload/gv/nosh.spv@c1,payload/gv/st2.spv@c1
R=${OUT:-/tmp}/p82a.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 120 $T/render_bench --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 150 $T/render_bench --generate --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p82a
} 2>&1 | tee $R
