#!/bin/bash
# Stop 84 (issue 21): the union grid of turned instances (render_scene.c prepare_union_turned; measured and dropped:
# bench/results/p84_union_turned.patch, applied to a084213, builds U) on the 104-instance
# scene (ogt_test_multiple_model_scene: 41 models of 8^3 turned about z, at cell offsets within bricks). U (this
# stop's build, payload/render_bench_u.gz) with --regions: the union and the same instances each walked under the
# BVH (main's walk) and ESVO in one process; A (main, payload/render_bench_il.gz) beside it, alternating U A U A;
# then the GPU tests of the union (test_render_gpu: test_grid_union, test_grid_union_turned, test_many_instances,
# test_corpus). Carry [".gl", "payload"].
LIM=${LIM:-200}; source bench/results/gpu_payload_lib.sh; F="$F|^ogt_|^grid:|^shadow map"
payload_setup p84b test_render_gpu
R=${OUT:-/tmp}/p84b.txt
{
echo "== U $(cat payload/REV_U) / A $(cat payload/REV) on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
for b in u il; do gunzip -c payload/render_bench_$b.gz > $T/rb_$b; chmod +x $T/rb_$b; done
timeout 6 $T/rb_u --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
S=payload/ogt_test_multiple_model_scene.vox
for k in 1 2; do
  run U$k 20 $T/rb_u --regions --sizes $SIZE --runs $RUNS --warmup $WU $S
  run A$k 20 $T/rb_il --sizes $SIZE --runs $RUNS --warmup $WU $S
done
run Uc 12 $T/rb_u --no-esvo --views closeup --sizes $SIZE --runs $RUNS --warmup $WU --shader-stats $S
VX_TEST_ONLY=test_grid_union,test_grid_union_turned,test_many_instances,test_corpus TLIM=${TLIM:-120} \
  gpu_tests "union grid|turned|multiple" test_render_gpu
payload_end p84b
} 2>&1 | tee $R
