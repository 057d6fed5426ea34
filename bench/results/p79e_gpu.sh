#!/bin/bash
# Stop 79 (issue 21), fifth run: the grid walk with the empty 2^3 block skip as committed (36b14cf), against it
# the working tree's trace.comp, whose loop falls through from a brick's entry to its first cell step only where
# a root may lie above level 1 (GRID_TOP >= 2; grid_walk.glsl), in the same processes
# (render_bench --kernels payload/gv/trace_fall2.spv@c1: glslangValidator -V --target-env vulkan1.1
# of render/shaders/trace.comp), every bench scene and view with ESVO, DamagedHelmet at 1024 cells as 8 regions and
# as one model; then test_render_hits, test_passes and test_render_gpu on the GPU. Run with carry [".gl", "payload"]: payload/ holds render_bench.gz
# (Release, 36b14cf) and T_*.gz (Release, the working tree), gv/, REV, lib/, the five corpus .vox files and the two helmet .svo files (p79b).
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p79e; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
for t in test_passes test_render_gpu test_render_hits; do gunzip -c payload/T_$t.gz > $T/$t; chmod +x $T/$t; done
LIM=${LIM:-420}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^helmet|^grid:"
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
K=payload/gv/trace_fall2.spv@c1
R=${OUT:-/tmp}/p79e.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 100 $T/render_bench --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 150 $T/render_bench --generate --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU
run helmet 100 $T/render_bench --grid-world --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU payload/helmet1024.svo payload/helmet1024r.svo
payload_end p79e
for t in test_render_hits test_passes test_render_gpu; do
  s=$(date +%s); timeout ${TLIM:-120} $T/$t > $T/$t.log 2>&1; rc=$?
  echo "-- $t: exit $rc in $(( $(date +%s) - s )) s"
  grep -E "CHECK failed|FAIL|passed,|hits frame|deep float, depth|SKIP|mixed root|root level 2 only" $T/$t.log | head -40
done
} 2>&1 | tee $R
