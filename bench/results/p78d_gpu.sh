#!/bin/bash
# Stop 78 (issue 21), fourth run: a scene outside the bench's seven, DamagedHelmet voxelized at 1024 cells
# (vox2svo khronos_DamagedHelmet.glb helmet1024.svo --res 1024: its regions as models under the BVH, each with its
# grid) against ESVO (--grid-world: world units = cells, as the baseline needs) and against voxkit's octree walk (render_bench --octree) in one process, every view at
# 1920x1080 with the driver's shader statistics. Run with carry [".gl", "payload"]: payload/ holds render_bench.gz
# (Release, b732707), REV, lib/ and helmet1024.svo (12 MB, made on the dev machine by the command above).
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p78d; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
LIM=${LIM:-200}; source bench/results/gpu_payload_lib.sh; F="$F|^helmet|^stats|^grid:"
R=${OUT:-/tmp}/p78d.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run helmet 180 $T/render_bench --shader-stats --grid-world --octree --sizes $SIZE --runs $RUNS --warmup $WU payload/helmet1024.svo
payload_end p78d
} 2>&1 | tee $R
