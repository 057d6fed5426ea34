#!/bin/bash
# Stop 78 (issue 21), fifth run: what holding the model-space ray across the grid walk's loop costs in the DEEP
# kernels (models deeper than VX_RENDER_EXACT_DEPTH take their hit's t from entry_tau(o, o_lo, d, ...) after the
# loop, so o, o_lo and d stay live): payload/gv/trace_noexact.spv is b8e660d's trace.comp with grid_walk.glsl's
# line `if (DEEP >= 1 && (m.flags & 2u) != 0u) th = max(entry_tau(...), te);` removed (glslangValidator of that
# tree; its t is the walk's, not exact: an upper bound on what forming the ray again after the loop could gain),
# against the built-in kernel in the same processes (render_bench --kernels, the screen cull on), with the driver's
# shader statistics: DamagedHelmet at 1024 cells (8 regions of depth 9: DEEP 1, BVH) and the generated terrains
# (terrain1024 DEEP 1, terrain4096 DEEP 2, one instance). Run with carry [".gl", "payload"]: payload/ holds
# render_bench.gz (Release, b732707), gv/trace_noexact.spv, REV, lib/, eph_monu1.vox and helmet1024.svo.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p78e; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
LIM=${LIM:-200}; source bench/results/gpu_payload_lib.sh; F="$F|^helmet|^stats|^grid:"
K=payload/gv/trace_noexact.spv@c1
R=${OUT:-/tmp}/p78e.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run helmet 70 $T/render_bench --shader-stats --grid-world --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU payload/helmet1024.svo
run terrain 90 $T/render_bench --shader-stats --generate --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p78e
} 2>&1 | tee $R
