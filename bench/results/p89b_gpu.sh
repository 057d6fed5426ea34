#!/bin/bash
# Stop 89 (issue 21), second run: the headline table with main's kernels as committed (0daaaea: stop 88's octant
# extents where a root is 64 wide), every bench scene and view with ESVO, two rounds (one process per round for the
# corpus, one for the terrains). Table: python3 bench/results/p88_table.py bench/results/p89b_h100.txt.
# payload: render_bench.gz (Release, 0daaaea), REV, lib/, the five corpus .vox files. Carry [".gl", "payload"].
[ -n "$OUT" ] && exec > >(tee $OUT/p89b.log) 2>&1
LIM=${LIM:-330}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^grid:"
payload_setup p89b
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
echo "== $(cat payload/REV | tr '\n' ' ') on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
for r in 1 2; do
  run corpus$r 60 $T/render_bench --sizes $SIZE --runs $RUNS --warmup $WU $V
  run terrain$r 75 $T/render_bench --generate --sizes $SIZE --runs $RUNS --warmup $WU
done
payload_end p89b
