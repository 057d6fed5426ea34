#!/bin/bash
# Stop 79 (issue 21), third run: the grid walk's fine level leaving an empty block of a brick in one step
# (grid_walk.glsl GRID_SUB: 2 the cell's 2^3 block, 4 its 4^3 block, 6 the 2^3 block then the 4^3 one; the
# same cells and planes as the cell by cell walk, 0 pixels apart on lavapipe) against the kernel as committed in
# the same processes (render_bench --kernels payload/gv/trace_subN.spv@c1: glslangValidator -V --target-env
# vulkan1.1 -DGRID_SUB=N of render/shaders/trace.comp), every bench scene and view with ESVO, and DamagedHelmet at
# 1024 cells as 8 regions and as one model. Run with carry [".gl", "payload"]: payload/ holds render_bench.gz
# (Release, 3285524), gv/, REV, lib/, the five corpus .vox files and the two helmet .svo files (p79b).
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p79c; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
LIM=${LIM:-420}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^helmet|^grid:"
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
K=payload/gv/trace_sub2.spv@c1,payload/gv/trace_sub4.spv@c1,payload/gv/trace_sub6.spv@c1
R=${OUT:-/tmp}/p79c.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 100 $T/render_bench --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 150 $T/render_bench --generate --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU
run helmet 100 $T/render_bench --grid-world --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU payload/helmet1024.svo payload/helmet1024r.svo
payload_end p79c
} 2>&1 | tee $R
