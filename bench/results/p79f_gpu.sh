#!/bin/bash
# Stop 79 (issue 21), sixth run: the table as committed at 5abb647 (the grid walk leaving empty 2^3 blocks of a
# brick in one step; where a root may lie above level 1, a brick's entry falling through to its first cell step),
# every bench scene and view against ESVO with the driver's shader statistics, and DamagedHelmet at 1024 cells as
# vox2svo makes it (8 regions) and as one model (--region 1024). Run with carry [".gl", "payload"]: payload/ holds
# render_bench.gz (Release, 5abb647), REV, lib/, the five corpus .vox files and the two helmet .svo files (p79b).
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p79f; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
LIM=${LIM:-300}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^helmet|^stats|^grid:"
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
R=${OUT:-/tmp}/p79f.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 60 $T/render_bench --shader-stats --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 90 $T/render_bench --shader-stats --generate --sizes $SIZE --runs $RUNS --warmup $WU
run helmet 60 $T/render_bench --shader-stats --grid-world --sizes $SIZE --runs $RUNS --warmup $WU payload/helmet1024.svo payload/helmet1024r.svo
payload_end p79f
} 2>&1 | tee $R
