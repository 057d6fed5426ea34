#!/bin/bash
# Stop 77 (issue 21): the grid walk as adopted (the coarse walk on level-1 cells with the levels above looked up,
# the mirrored axes as 3 bits, the setup precise) against ESVO in the same processes, every view at 1920x1080 with
# the driver's shader statistics; then test_passes, test_render_hits and test_render_gpu on the GPU (grids on by
# default). Run with carry [".gl", "payload"]: payload/ holds render_bench.gz and T_*.gz (Release), REV, lib/ and
# the five corpus .vox files.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p77a; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
for t in test_passes test_render_gpu test_render_hits; do gunzip -c payload/T_$t.gz > $T/$t; chmod +x $T/$t; done
LIM=${LIM:-200}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^stats|^grid:"
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
R=${OUT:-/tmp}/p77a.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 80 $T/render_bench --shader-stats --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 80 $T/render_bench --shader-stats --generate --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p77a
for t in test_render_hits test_passes test_render_gpu; do
  s=$(date +%s); timeout ${TLIM:-120} $T/$t > $T/$t.log 2>&1; rc=$?
  echo "-- $t: exit $rc in $(( $(date +%s) - s )) s"
  grep -E "CHECK failed|FAIL|passed,|hits frame|deep float, depth|SKIP|mixed root" $T/$t.log | head -40
done
} 2>&1 | tee $R
