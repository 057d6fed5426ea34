#!/bin/bash
# Stop 76 (issue 21): voxkit's tracer with the grid walk (render/grid.h, render/shaders/grid_walk.glsl: the
# models' grids built at upload, trace.comp walks them) against its octree walk (render_bench --octree: the
# same kernel with GRID 0, rows "[kernel octree walk]") and the ESVO baseline in the same processes, every view
# at 1920x1080, with the driver's shader statistics. "px differ from the first row" on the octree rows counts
# the pixels whose hits differ between the two walks.
# Run with carry [".gl", "payload"]: payload/ holds render_bench.gz (Release), REV, lib/ and the five corpus
# .vox files.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p76; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
LIM=${LIM:-330}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^stats|^grid:|^brick-variant"
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
R=${OUT:-/tmp}/p76_grid.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 170 $T/render_bench --octree ${BRICK:+--brick} --shader-stats --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 140 $T/render_bench --octree ${BRICK:+--brick} --generate --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p76
} 2>&1 | tee $R
