#!/bin/bash
# Issue 21 (stop 61): voxkit against ESVO on 65 public MagicaVoxel scenes that are not in the corpus (ephtracy/voxel-model
# @8044f9e, jpaver/opengametools @dcabf82, vengi-voxel/vengi @ee98c87, AstrorEnales/blender_magicavoxel @4ce62b5;
# payload/more/REPO_FILE.vox), one process, the H200 warmed first. Run with carry [".gl", "payload"].
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p61b; rm -rf $T; mkdir -p $T; gunzip -c payload/render_bench.gz > $T/rb; chmod +x $T/rb
LIM=${LIM:-420}; source bench/results/gpu_payload_lib.sh; F="$F|^[a-z]*_"
echo "== main $(cat payload/REV) on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/rb --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run more 400 $T/rb --sizes $SIZE --runs ${RUNS2:-10} --warmup ${WU2:-0.2} payload/more/*.vox
payload_end p61b
