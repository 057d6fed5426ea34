#!/bin/bash
# Stop 74 (issue 21): on one H200, (1) the occupancy pyramid prototype (render_bench --mip, bench/mipgrid.h: a
# pointerless, stackless octree walk; variants: probe 0/1/2) beside voxkit and ESVO in the same processes, every
# view at 1920x1080, with the driver's shader statistics; (2) stop 73's pending NVIDIA checks
# (p73b_h200_metal_lf.sh: the light field sort before and after its fix, test_metal_gi and friends).
# Run with carry [".gl", "payload"]: payload/ holds render_bench.gz (build/, Release), the test binaries and
# lfdiff_{old,new}.gz of p73b, REV, lib/ and the five corpus .vox files.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p74; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
LIM=${LIM:-330}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^stats|^mip-variant"
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
R=${OUT:-/tmp}/p74_mip.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 170 $T/render_bench --mip --shader-stats --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 130 $T/render_bench --mip --generate --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p74
} 2>&1 | tee $R
[ -n "$NO_P73B" ] || bash bench/results/p73b_h200_metal_lf.sh
