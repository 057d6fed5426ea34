#!/bin/bash
# Stop 78 (issue 21), third run: GRID_EXACT (grid_walk.glsl: where every grid's root is at level k >= 2, k a
# constant; terrain4096) against the kernel before it (payload/gv/trace_p78b.spv: glslangValidator of 2f0a1d4's
# trace.comp, which reads the root's level from each model's depth) in the same processes on the generated
# terrains; the five corpus scenes as committed (every view against ESVO); the pass pipeline's G-buffer lists
# (passes_bench --gbuffer) with the grid walk and with every model on its octree walk (--octree), A B A B; then
# test_render_hits, test_passes and test_render_gpu on the GPU. Run with carry [".gl", "payload"]: payload/ holds
# render_bench.gz, passes_bench.gz and T_*.gz (Release), gv/, REV, lib/ and the five corpus .vox files.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p78c; rm -rf $T; mkdir -p $T
for b in render_bench passes_bench; do gunzip -c payload/$b.gz > $T/$b; chmod +x $T/$b; done
for t in test_passes test_render_gpu test_render_hits; do gunzip -c payload/T_$t.gz > $T/$t; chmod +x $T/$t; done
LIM=${LIM:-300}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^stats|^grid:|^\||^#|^##"
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
P="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox terrain:1024"
R=${OUT:-/tmp}/p78c.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run terrain 90 $T/render_bench --shader-stats --generate --kernels payload/gv/trace_p78b.spv@c1 --sizes $SIZE --runs $RUNS --warmup $WU
run corpus 60 $T/render_bench --sizes $SIZE --runs $RUNS --warmup $WU $V
for ab in A B A B; do
  o=; [ $ab = B ] && o=--octree
  run "passes-$ab" 40 $T/passes_bench --gbuffer $o --warmup 0.3 --size $SIZE --runs $RUNS $P
done
payload_end p78c
for t in test_render_hits test_passes test_render_gpu; do
  s=$(date +%s); timeout ${TLIM:-120} $T/$t > $T/$t.log 2>&1; rc=$?
  echo "-- $t: exit $rc in $(( $(date +%s) - s )) s"
  grep -E "CHECK failed|FAIL|passed,|hits frame|deep float, depth|SKIP|mixed root|root level 2 only" $T/$t.log | head -40
done
} 2>&1 | tee $R
