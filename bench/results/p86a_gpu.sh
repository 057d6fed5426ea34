#!/bin/bash
# Stop 86 (issue 21): an edited model's grid made again (render_scene.c regrid) on NVIDIA, where the grid buffer is
# device-local (uploads staged, the buffer's growth a GPU copy; lavapipe's buffers are mapped): test_render_edit
# (its grid variant against the octree walk), then view_bench --stroke with the grids off and on (a stroke's update
# with and without the rebuild). payload: T_test_render_edit.gz, view_bench.gz, eph_dragon.svo, eph_monu1.svo (vox2svo
# of the corpus files), lib/. Carry [".gl", "payload"].
[ -n "$OUT" ] && exec > >(tee $OUT/p86a.log) 2>&1
LIM=${LIM:-300}; source bench/results/gpu_payload_lib.sh
payload_setup p86a test_render_edit
gunzip -c payload/view_bench.gz > $T/view_bench; chmod +x $T/view_bench
echo "== stop 86 regrid on $(gpu_name), $(date -u +%T)"
TLIM=200 gpu_tests "grids|strokes|tie" test_render_edit
for f in payload/eph_dragon.svo payload/eph_monu1.svo terrain256; do
  for g in off on; do
    echo "-- view_bench --stroke $f 30 4 $g"
    timeout 120 $T/view_bench --stroke $f 30 4 $g 2>&1 | grep -v "^$"
  done
done
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
