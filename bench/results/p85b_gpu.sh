#!/bin/bash
# Stop 85 (issue 21): the grid over its cells' box's cube (B, payload/render_bench_b.gz) against main (A,
# payload/render_bench_il.gz, cca6620's code), one process each, alternating A B A B on the corpus's bench scenes,
# then A B on the generated terrains and on five scenes outside the corpus (payload/more: vengi's cubictest and
# test-transform, tentacle2, chr_man, monu0), ESVO in every process. Carry [".gl", "payload"].
[ -n "$OUT" ] && exec > >(tee $OUT/p85b.log) 2>&1
LIM=${LIM:-400}; source bench/results/gpu_payload_lib.sh; F="$F|^eph_|^ogt_|^[a-z]*_|^grid:"
payload_setup p85b
gunzip -c payload/render_bench_il.gz > $T/A; gunzip -c payload/render_bench_b.gz > $T/B; chmod +x $T/A $T/B
V="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
M="payload/more/vengi_data_tests_cubictest.vox payload/more/vengi_data_tests_test-transform.vox
   payload/more/blender_magicavoxel_examples_tentacle2.vox payload/more/eph_character_chr_man.vox payload/more/eph_monument_monu0.vox"
echo "== A il / B stop 85 on $(gpu_name), $(date -u +%T)"
clock_start
timeout 10 $T/A --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
for r in 1 2; do
  run A$r 40 $T/A --sizes $SIZE --runs $RUNS --warmup $WU $V
  run B$r 40 $T/B --sizes $SIZE --runs $RUNS --warmup $WU $V
done
run tA 45 $T/A --generate --sizes $SIZE --runs $RUNS --warmup $WU
run tB 45 $T/B --generate --sizes $SIZE --runs $RUNS --warmup $WU
run mA 30 $T/A --sizes $SIZE --runs $RUNS --warmup $WU $M
run mB 30 $T/B --sizes $SIZE --runs $RUNS --warmup $WU $M
payload_end p85b
