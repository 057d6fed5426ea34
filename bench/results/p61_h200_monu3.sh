#!/bin/bash
# Issue 21 (stop 61): the bench table on the H200 with eph_monu3 (ephtracy/voxel-model @8044f9e vox/monument/monu3.vox,
# not in the corpus) beside the corpus scenes and the generated terrains; ESVO in the same processes.
# The loader from .gl (the device README's recipe); the binary's libz, libzstd, libdeflate in payload/lib.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
# Run with carry [".gl", "payload"]: payload/ holds render_bench.gz (main build), lib/ and the six .vox files.
T=/tmp/p61; rm -rf $T; mkdir -p $T; gunzip -c payload/render_bench.gz > $T/rb; chmod +x $T/rb
LIM=${LIM:-280}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_"
echo "== main $(cat payload/REV) on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/rb --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 120 $T/rb --sizes $SIZE --runs $RUNS --warmup $WU payload/eph_monu3.vox payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox
run terrain 110 $T/rb --generate --sizes $SIZE --runs $RUNS --warmup $WU
run monu3_720 30 $T/rb --sizes 1280x720 --runs $RUNS --warmup $WU payload/eph_monu3.vox
payload_end p61
