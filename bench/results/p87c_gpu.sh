#!/bin/bash
# Stop 87 (issue 21): the hit's entry axis never one the ray runs along (grid_walk.glsl, trace_common.glsl,
# trace_compact.comp; after the loop). On NVIDIA: test_render_gpu (test_axis_rays_on_edges now checks normals on
# both walks) and test_sky, then render_bench A (payload/render_bench.gz, main before this stop) and B (141e182)
# alternating, A B A B, the five corpus scenes at 1920x1080, ESVO beside. payload: render_bench.gz,
# render_bench_b.gz, T_test_render_gpu.gz, T_test_sky.gz, the corpus .vox copies, lib/. Carry [".gl", "payload"].
[ -n "$OUT" ] && exec > >(tee $OUT/p87c.log) 2>&1
LIM=${LIM:-560}; source bench/results/gpu_payload_lib.sh
payload_setup p87c test_render_gpu test_sky
gunzip -c payload/render_bench_b.gz > $T/render_bench_b; chmod +x $T/render_bench_b
echo "== stop 87 entry axis on $(gpu_name), $(date -u +%T)"
[ -n "$NOTEST" ] || TLIM=200 gpu_tests "axis .*normal|top face|side face" test_render_gpu test_sky
F="$F|\.vox  "
clock_start
S="payload/eph_monu1.vox payload/eph_menger.vox payload/eph_dragon.vox payload/ogt_doom.vox payload/ogt_test_multiple_model_scene.vox"
timeout 3 nvidia-smi -q -d CLOCK >/dev/null 2>&1; sleep 2
for r in 1 2; do
  run A$r 90 $T/render_bench --runs 15 --warmup 0.5 --sizes $SIZE $S
  run B$r 90 $T/render_bench_b --runs 15 --warmup 0.5 --sizes $SIZE $S
done
payload_end p87c
