#!/bin/bash
# Stop 78 (issue 21), sixth run, branch exact-t: the grid walk's exact entry t from q = (c0 - o) - o_lo made at the
# walk's setup (the loop then holds q and d, not o, o_lo and d; grid_walk.glsl grid_entry_tau:
# payload/gv/trace_exactq.spv) and without an exact t (payload/gv/trace_noexact.spv, p78e's upper bound) against the
# built-in kernel (b732707) in the same processes: DamagedHelmet at 1024 cells and the generated terrains; then the
# branch's test_render_gpu on the GPU (test_deep_float: the exact t against the CPU reference). Run with carry
# [".gl", "payload"].
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p78f; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
gunzip -c payload/T_test_render_gpu.gz > $T/test_render_gpu; chmod +x $T/test_render_gpu
LIM=${LIM:-150}; source bench/results/gpu_payload_lib.sh; F="$F|^helmet|^stats|^grid:"
K=payload/gv/trace_exactq.spv@c1,payload/gv/trace_noexact.spv@c1
R=${OUT:-/tmp}/p78f.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run helmet 50 $T/render_bench --shader-stats --grid-world --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU payload/helmet1024.svo
run terrain 80 $T/render_bench --shader-stats --generate --kernels $K --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p78f
s=$(date +%s); timeout ${TLIM:-120} $T/test_render_gpu > $T/t.log 2>&1; rc=$?
echo "-- test_render_gpu: exit $rc in $(( $(date +%s) - s )) s"
grep -E "CHECK failed|FAIL|passed,|deep float, depth|root level 2 only" $T/t.log | head -30
} 2>&1 | tee $R
