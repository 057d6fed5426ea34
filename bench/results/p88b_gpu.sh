#!/bin/bash
# Stop 88 (issue 21), second run: main's GPU tests on the NVIDIA machine at c8336de (p88a's test_render_gpu ran out
# of its 120 s): test_render_gpu (every walk against the CPU reference), test_render_hits (the 4096 terrain's hits
# frame under 1 s), test_passes. payload: T_test_render_gpu.gz, T_test_render_hits.gz, T_test_passes.gz (Release,
# c8336de), render_bench.gz, lib/. Carry [".gl", "payload"].
[ -n "$OUT" ] && exec > >(tee $OUT/p88b.log) 2>&1
LIM=${LIM:-560}; source bench/results/gpu_payload_lib.sh
payload_setup p88b test_render_gpu test_render_hits test_passes
echo "== $(cat payload/REV | head -1) on $(gpu_name), $(date -u +%T)"
TLIM=300 gpu_tests "hits frame|terrain" test_render_gpu
TLIM=100 gpu_tests "hits frame|terrain|4096" test_render_hits
TLIM=130 gpu_tests "" test_passes
