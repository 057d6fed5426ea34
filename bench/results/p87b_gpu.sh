#!/bin/bash
# Stop 87 (issue 21): the union grid of turned instances on CPU devices only (stop 84's patch); on NVIDIA the
# scenes keep the BVH, so test_render_gpu (test_grid_union, test_grid_union_turned: a GPU builds no union of
# turned instances and runs the same views under the BVH) checks that and the shader's union branch compiles there.
# payload: T_test_render_gpu.gz, lib/. Carry [".gl", "payload"].
[ -n "$OUT" ] && exec > >(tee $OUT/p87b.log) 2>&1
LIM=${LIM:-300}; source bench/results/gpu_payload_lib.sh
payload_setup p87b test_render_gpu
echo "== stop 87 turned union (CPU only) on $(gpu_name), $(date -u +%T)"
TLIM=280 gpu_tests "union|turned" test_render_gpu
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
