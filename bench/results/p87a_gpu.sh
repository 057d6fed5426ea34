#!/bin/bash
# Stop 87 (issue 21): an edited model's grid made again in one submission (render_scene.c regrid: the grid's words
# from the update's staging buffer and its table word in one command buffer; the drop's table word in the update's
# own submission) against stop 86's three staged uploads, on NVIDIA (device-local grid buffer). test_render_edit, then
# view_bench --stroke with the grids off and on, A (stop 86's binary, payload/view_bench_a.gz) and B (this stop's)
# alternating, two rounds. payload: T_test_render_edit.gz, view_bench.gz, view_bench_a.gz, eph_dragon.svo,
# eph_monu1.svo, lib/. Carry [".gl", "payload"].
[ -n "$OUT" ] && exec > >(tee $OUT/p87a.log) 2>&1
LIM=${LIM:-300}; source bench/results/gpu_payload_lib.sh
payload_setup p87a test_render_edit
for v in view_bench view_bench_a; do gunzip -c payload/$v.gz > $T/$v; chmod +x $T/$v; done
echo "== stop 87 regrid in one submission on $(gpu_name), $(date -u +%T)"
TLIM=120 gpu_tests "grids|strokes|tie" test_render_edit
for round in 1 2; do
  for f in payload/eph_dragon.svo payload/eph_monu1.svo terrain256; do
    for g in off on; do
      for v in view_bench_a view_bench; do
        echo "-- round $round $v --stroke $f 30 4 $g"
        timeout 100 $T/$v --stroke $f 30 4 $g 2>&1 | grep -v "^$" | grep -iE 'update|median|stroke|frame|grid' | head -8
      done
    done
  done
done
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
