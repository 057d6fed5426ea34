#!/bin/bash
# Stop 78 (issue 21): the grid walk's loop variants (grid_walk.glsl's bench macro GV, compiled with
# glslangValidator -DGV=N into payload/gv/trace_gvN.spv) against the built-in walk and ESVO in the same processes
# (render_bench --kernels, the screen cull on), every view at 1920x1080 with the driver's shader statistics
# (registers); GV bits: 1 no P (the level-1 cell is f >> 3), 2 cells from the plane times (no ad, fr), 4 one loop
# tail, 8 the root's entry cached (roots at level 2: terrain4096), 16 the loop not precise, 32 the mirrored axes
# read from bflip. Then test_render_hits, test_passes and test_render_gpu built with GV=19 on the GPU.
# Run with carry [".gl", "payload"]: payload/ holds render_bench.gz and T_*.gz (Release), gv/, REV, lib/ and the
# five corpus .vox files.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p78; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
for t in test_passes test_render_gpu test_render_hits; do gunzip -c payload/T_$t.gz > $T/$t; chmod +x $T/$t; done
LIM=${LIM:-330}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^stats|^grid:"
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
kl() { local k=; for v in "$@"; do k="$k${k:+,}payload/gv/trace_gv$v.spv@c1"; done; echo $k; }
R=${OUT:-/tmp}/p78.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 220 $T/render_bench --shader-stats --kernels $(kl ${KC:-1 2 3 4 16 19 35 51}) --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 110 $T/render_bench --shader-stats --generate --kernels $(kl ${KT:-1 3 8 11 19 27 43 59}) --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p78
for t in test_render_hits test_passes test_render_gpu; do
  s=$(date +%s); timeout ${TLIM:-120} $T/$t > $T/$t.log 2>&1; rc=$?
  echo "-- $t: exit $rc in $(( $(date +%s) - s )) s"
  grep -E "CHECK failed|FAIL|passed,|hits frame|deep float, depth|SKIP|mixed root" $T/$t.log | head -40
done
} 2>&1 | tee $R
