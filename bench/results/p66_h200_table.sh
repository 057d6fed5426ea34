#!/bin/bash
# Issue 21 (stop 66): the bench table on the H200 with the session's merged main (glass seen directly, compact
# material ids, texture conversion, glass walks over uniform leaves: none in the trace kernels' loop), the corpus
# scenes and the generated terrains, ESVO in the same processes; as p61_h200_monu3.sh without eph_monu3.
# Run with carry [".gl", "payload"]: payload/ holds render_bench.gz (main build), REV, lib/ and the five .vox files.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p66; rm -rf $T; mkdir -p $T; gunzip -c payload/render_bench.gz > $T/rb; chmod +x $T/rb
LIM=${LIM:-280}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_"
echo "== main $(cat payload/REV) on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/rb --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 130 $T/rb --sizes $SIZE --runs $RUNS --warmup $WU payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox
run terrain 120 $T/rb --generate --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p66
