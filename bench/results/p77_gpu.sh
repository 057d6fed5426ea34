#!/bin/bash
# Stop 77 (issue 21), run at 4b566bb (the variants and render_bench --grid-variant were folded into the walk or
# dropped after it): the grid walk's bench variants against its default in the same processes (render_bench
# --grid-variant: 8 FLAT, roots above level 1 walked on level-1 cells with the levels above looked up; 16 NOFR,
# the position at t without fr; 32 PACKFLIP, the mirrored axes as 3 bits), every view at 1920x1080 with the driver's
# shader statistics; then the render tests on the GPU with grids on by default (test_passes: the pass kernels'
# grid walk; test_render_gpu, test_render_hits). Run with carry [".gl", "payload"]: payload/ holds render_bench.gz
# and T_*.gz (Release), REV, lib/ and the five corpus .vox files.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p77; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
for t in test_passes test_render_gpu test_render_hits; do gunzip -c payload/T_$t.gz > $T/$t; chmod +x $T/$t; done
LIM=${LIM:-300}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^stats|^grid:"
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
R=${OUT:-/tmp}/p77.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 150 $T/render_bench --grid-variant 16 --grid-variant 32 --grid-variant 48 --shader-stats --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 120 $T/render_bench --grid-variant 8 --grid-variant 24 --grid-variant 56 --shader-stats --generate --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p77
for t in test_render_hits test_passes test_render_gpu; do
  s=$(date +%s); timeout ${TLIM:-150} $T/$t > $T/$t.log 2>&1; rc=$?
  echo "-- $t: exit $rc in $(( $(date +%s) - s )) s"
  grep -E "CHECK failed|FAIL|passed,|hits frame|deep float, depth|SKIP|grids\]" $T/$t.log | head -60
done
} 2>&1 | tee $R
