#!/bin/bash
# Issue 21 (stop 85): main's grid walk against ESVO on 67 public MagicaVoxel scenes that are not in the corpus (stop 61's
# 64 and eph_monu3, vengi's teardown and vox-to-kv6-broken; ephtracy/voxel-model, jpaver/opengametools,
# vengi-voxel/vengi data/tests, AstrorEnales/blender_magicavoxel examples, as fetched on 2026-12-07; payload/more/
# REPO_PATH.vox with the corpus's files left out), two processes (render_bench takes at most 64 files), the GPU warmed
# first. Run with carry [".gl", "payload"]. The device call that ran it ran p85b_gpu.sh first (one machine start for
# both, in 600 s): p85b with LIM 240, then this survey within the rest.
[ -z "$P85_ALONE" ] && LIM=240 bash bench/results/p85b_gpu.sh
[ -n "$OUT" ] && exec > >(tee $OUT/p85a.log) 2>&1  # the whole log comes back in $OUT
LIM=${LIM:-340}; source bench/results/gpu_payload_lib.sh; F="$F|^[a-z]*_|^grid:"
payload_setup p85a
echo "== main $(cat payload/REV) on $(gpu_name), $(nproc) CPUs, $(date -u +%T)"
clock_start
timeout 10 $T/render_bench --no-esvo --sizes $SIZE --runs 300 --warmup 2 --views closeup payload/eph_monu1.vox > /dev/null 2>&1
set -- payload/more/*.vox; n=$#; h=$(( (n + 1) / 2 ))
run more1 165 $T/render_bench --sizes $SIZE --runs ${RUNS2:-10} --warmup ${WU2:-0.2} "${@:1:$h}"
run more2 165 $T/render_bench --sizes $SIZE --runs ${RUNS2:-10} --warmup ${WU2:-0.2} "${@:$((h + 1))}"
payload_end p85a
