#!/bin/bash
# Stop 79 (issue 21), second run: DamagedHelmet at 1024 cells as vox2svo makes it (helmet1024.svo: 8 regions of
# 512 cells, each a model under the BVH) and as one model (helmet1024r.svo: --region 1024, the single-instance
# kernel with the frame block's grid), each against ESVO in one process, with the shader statistics: what the
# regions cost the tracer. Run with carry [".gl", "payload"]: payload/ holds render_bench.gz (Release, 3285524),
# REV, lib/ and the two .svo files (made on the dev machine: vox2svo khronos_DamagedHelmet.glb OUT --res 1024
# [--region 1024]).
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p79b; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
LIM=${LIM:-200}; source bench/results/gpu_payload_lib.sh; F="$F|^helmet|^stats|^grid:"
R=${OUT:-/tmp}/p79b.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
for f in helmet1024 helmet1024r; do
  run $f 80 $T/render_bench --shader-stats --grid-world --sizes $SIZE --runs $RUNS --warmup $WU payload/$f.svo
done
payload_end p79b
} 2>&1 | tee $R
