#!/bin/bash
# ray2 (issue 21, thirteenth sitting), batch 3 (limit 100 s): main's render_bench (A, bench/out/base/bin,
# b16046b), the branch's second commit (C: tiles + the BVH node words from the box test's load) and its
# third (B: the BVH stack holds a far child's words and entry t) alternated process by process, three
# rounds, on the multi-instance scene (with ESVO); exactness of B; A and B once on single-instance views;
# shader statistics. SIZE=WxH for lavapipe.
export LD_LIBRARY_PATH=bench/out/ray2:bench/out/base/bin
L=bench/out/ray2; A=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}
s0=$(date +%s)
echo "== ray2 B $(cat $L/REV) C $(cat $L/REV_c2) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo 'no nvidia-smi') size $SIZE $(date -u +%T)"
timeout ${WT:-4} $L/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
bin_of() { case $1 in A) echo $A/render_bench;; B) echo $L/render_bench;; C) echo $L/render_bench_c2;; esac; }
echo "== 1: processes alternated A C B, the multi-instance scene with ESVO $(date -u +%T)"
for round in 1 2 3; do
  for who in A C B; do
    left=$(( ${T1:-62} - ($(date +%s) - s0) ))
    [ $left -gt 4 ] || break 2
    echo "-- round $round $who"
    timeout $left $(bin_of $who) --sizes $SIZE --runs ${R1:-15} --warmup $WU --views overview,oblique,closeup \
      $L/ogt_test_multiple_model_scene.vox 2>&1 | grep -E '^ogt'
  done
done
echo "== 1b: exactness in one process: B built-in against B with no cull (@c0: the walk from the root) and main's trace.comp (k_main.spv, b16046b) $(date -u +%T)"
left=$(( ${T1B:-68} - ($(date +%s) - s0) ))
[ $left -gt 3 ] && timeout $left $L/render_bench --no-esvo --sizes $SIZE --runs 3 --warmup 0 --views overview,oblique,closeup \
  --kernels @c0,$L/k_main.spv@c0 $L/ogt_test_multiple_model_scene.vox 2>&1 | grep -E '^ogt'
echo "== 2: single-instance views, A then B $(date -u +%T)"
for who in A B; do
  left=$(( ${T2:-90} - ($(date +%s) - s0) ))
  [ $left -gt 4 ] || break
  echo "-- $who"
  timeout $left $(bin_of $who) --no-esvo --sizes $SIZE --runs ${R2:-10} --warmup $WU --views oblique,closeup \
    $L/eph_monu1.vox $L/eph_dragon.vox 2>&1 | grep -E '^(eph|ogt)'
done
echo "== 3: shader statistics, B (the multi-instance scene, depth and colour) $(date -u +%T)"
left=$(( ${TOTAL:-97} - ($(date +%s) - s0) ))
[ $left -gt 3 ] && timeout $left $L/render_bench --no-esvo --shader-stats --sizes 64x64 --runs 1 --warmup 0 --views overview \
  $L/ogt_test_multiple_model_scene.vox 2>&1 | grep '^stats: trace \[spec [03],1,1,0,0'
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
