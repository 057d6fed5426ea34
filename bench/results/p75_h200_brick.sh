#!/bin/bash
# Stop 75 (issue 21): on one GPU, the two-level grid prototype (render_bench --brick, bench/brickgrid.h: a
# hierarchical DDA over 8^3-cell bricks with distance skips; the last argument of each row: the variant) beside voxkit and ESVO in the
# same processes, every view at 1920x1080, with the driver's shader statistics (variants: FCOORD 0/1; ROOT9=1
# also the terrains with the root grid at most 512 wide).
# Run with carry [".gl", "payload"]: payload/ holds render_bench.gz (build/, Release), REV, lib/ and the five
# corpus .vox files.
if command -v nvidia-smi >/dev/null; then for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; fi
export LD_LIBRARY_PATH=$PWD/payload/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
T=/tmp/p75; rm -rf $T; mkdir -p $T
gunzip -c payload/render_bench.gz > $T/render_bench; chmod +x $T/render_bench
LIM=${LIM:-330}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^stats|^brick-variant"
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
R=${OUT:-/tmp}/p75_brick.txt
{
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
run corpus 170 $T/render_bench --brick --shader-stats --sizes $SIZE --runs $RUNS --warmup $WU $V
run terrain 130 $T/render_bench --brick --generate --sizes $SIZE --runs $RUNS --warmup $WU
# the root at most 512 wide (2^9): terrain4096's grid with root level 1 (512 MiB of root) instead of 2
[ -n "$ROOT9" ] && run terrain-root9 130 $T/render_bench --brick --brick-root 9 --generate --sizes $SIZE --runs $RUNS --warmup $WU
payload_end p75
} 2>&1 | tee $R
