#!/bin/bash
# ray4 (issue 21, fifteenth sitting), batch 2 (limit 100 s): the descriptors' GPU form on the terrains and
# the float64 variant. 1: main's render_bench (A, bench/out/base/bin, 8ab2eb2) and the branch's (B)
# alternated process by process (A B A B), --generate (terrain1024, terrain4096) without ESVO, 3 views,
# 1920x1080, --runs 10 --warmup 0.1; 2: the float64 variant (--deep --variant precise: terrain1024 in a
# 2^20 model), A B A B, close-up and oblique; 3: shader statistics of A and B (the multi-instance scene's
# kernels: batch 1 had its overview 5% slower; the float64 kernels); 4: B's kernel variants in one process.
export LD_LIBRARY_PATH=bench/out/base/bin
L=bench/out/ray4; A=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}; RUNS=${RUNS:-10}
s0=$(date +%s)
echo "== ray4 B $(cat $L/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo 'no nvidia-smi') size $SIZE $(date -u +%T)"
timeout ${WT:-4} $L/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
bin_of() { case $1 in A) echo $A/render_bench;; B) echo $L/render_bench;; esac; }
echo "== 1: terrains, processes alternated A B A B, no ESVO $(date -u +%T)"
for round in 1 2; do
  for who in A B; do
    left=$(( ${T1:-56} - ($(date +%s) - s0) ))
    [ $left -gt 4 ] || break 2
    echo "-- round $round $who $(date -u +%T)"
    timeout $left $(bin_of $who) --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views overview,oblique,closeup 2>&1 | grep -E '^terr|far pointer'
  done
done
echo "== 2: float64 variant (--deep --variant precise), A B A B $(date -u +%T)"
for round in 1 2; do
  for who in A B; do
    left=$(( ${T2:-82} - ($(date +%s) - s0) ))
    [ $left -gt 3 ] || break 2
    echo "-- round $round $who $(date -u +%T)"
    timeout $left $(bin_of $who) --deep --variant precise --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views oblique,closeup 2>&1 | grep -E '^terr'
  done
done
echo "== 3: shader statistics, A and B (the multi-instance scene, float; the deep terrain, precise) $(date -u +%T)"
for who in A B; do
  left=$(( ${TOTAL:-92} - ($(date +%s) - s0) ))
  [ $left -gt 1 ] || break
  echo "-- $who"
  timeout $left $(bin_of $who) --no-esvo --shader-stats --sizes 64x64 --runs 1 --warmup 0 --views overview \
    $L/ogt_test_multiple_model_scene.vox 2>&1 | grep '^stats: trace'
  left=$(( ${TOTAL:-92} - ($(date +%s) - s0) ))
  [ $left -gt 1 ] || break
  timeout $left $(bin_of $who) --deep --variant precise --no-esvo --shader-stats --sizes 64x64 --runs 1 --warmup 0 --views closeup 2>&1 | grep '^stats: trace'
done
echo "== 4: B, the multi-instance scene and eph_monu1: built-in, k_mask (main's masks on the GPU form), k_self (the branch's trace.comp compiled apart) $(date -u +%T)"
left=$(( ${TOTAL2:-99} - ($(date +%s) - s0) ))
[ $left -gt 2 ] && timeout $left $L/render_bench --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views overview,closeup \
  --kernels $L/k_mask.spv,$L/k_self.spv $L/ogt_test_multiple_model_scene.vox $L/eph_monu1.vox 2>&1 | grep -E '^(eph|ogt)'
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
