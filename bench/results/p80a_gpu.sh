#!/bin/bash
# Stop 80 (issue 21), first run: the union grid of a converter's regions (render_scene.c grid_union, ed84b44; bricks shared a12ef72):
# DamagedHelmet at 1024 cells as vox2svo makes it (8 regions of 512) with the union and with each region under the
# BVH (render_bench --regions) in the same process, and as one model (--region 1024); every other bench scene and view against
# the kernel of fd65d1b (payload/gv/trace_p79.spv: none of them is regions, the same walk expected); then
# test_render_hits, test_passes and test_render_gpu on the GPU. Run with carry [".gl", "payload"]: payload/ holds
# render_bench.gz and T_*.gz (Release, a12ef72), gv/, REV, lib/, the five corpus .vox files and the two helmet .svo files.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p80a; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
for t in test_passes test_render_gpu test_render_hits; do gunzip -c payload/T_$t.gz > $T/$t; chmod +x $T/$t; done
LIM=${LIM:-400}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^helmet|^stats|^grid:"
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
K=payload/gv/trace_p79.spv@c1
R=${OUT:-/tmp}/p80a.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run helmet 70 $T/render_bench --shader-stats --grid-world --regions --sizes $SIZE --runs $RUNS --warmup $WU payload/helmet1024.svo
run helmetr 40 $T/render_bench --grid-world --sizes $SIZE --runs $RUNS --warmup $WU payload/helmet1024r.svo
run corpus 90 $T/render_bench --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 120 $T/render_bench --generate --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p80a
gpu_tests "hits frame|regions|deep float, depth" test_render_hits test_passes test_render_gpu
} 2>&1 | tee $R
