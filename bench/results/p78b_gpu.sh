#!/bin/bash
# Stop 78 (issue 21), second run: trace.comp with one instance reads its model's grid address and cells' box from
# the frame block (TRACE_GRID_UBO: no load before the walk's first, no conversion of the box) against 8e06230's
# kernel (payload/gv/trace_8e06230.spv, glslangValidator of that commit's trace.comp, which loads both per ray) and
# the same with 4 divisions a ray instead of 10 (payload/gv/trace_fastdiv.spv: grid_walk.glsl's GW_FASTDIV) in the
# same processes (render_bench --kernels, the screen cull on), every view at 1920x1080 with the driver's shader
# statistics; then test_render_hits, test_passes and test_render_gpu (built with the frame block's grid) on the
# GPU. Run with carry [".gl", "payload"]: payload/ holds render_bench.gz and T_*.gz (Release), gv/, REV, lib/ and
# the five corpus .vox files.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p78b; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
for t in test_passes test_render_gpu test_render_hits; do gunzip -c payload/T_$t.gz > $T/$t; chmod +x $T/$t; done
LIM=${LIM:-200}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^stats|^grid:"
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
K=payload/gv/trace_8e06230.spv@c1,payload/gv/trace_fastdiv.spv@c1
R=${OUT:-/tmp}/p78b.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 120 $T/render_bench --shader-stats --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 80 $T/render_bench --shader-stats --generate --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p78b
for t in test_render_hits test_passes test_render_gpu; do
  s=$(date +%s); timeout ${TLIM:-120} $T/$t > $T/$t.log 2>&1; rc=$?
  echo "-- $t: exit $rc in $(( $(date +%s) - s )) s"
  grep -E "CHECK failed|FAIL|passed,|hits frame|deep float, depth|SKIP|mixed root" $T/$t.log | head -40
done
} 2>&1 | tee $R
