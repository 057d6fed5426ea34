#!/bin/bash
# ray2 (issue 21, thirteenth sitting), batch 1: the BVH walk's start per screen tile (vx__frame_tiles,
# trace.comp's primary rays in scenes of several instances) and the rectangle of a box that crosses the
# eye's plane cut at the plane z = zc. main's render_bench (A, bench/out/base/bin, b16046b) and the
# branch's (B) alternated process by process, three rounds; then the other .vox scenes once each way;
# shader statistics. SIZE=WxH for lavapipe.
export LD_LIBRARY_PATH=bench/out/ray2:bench/out/base/bin
L=bench/out/ray2; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}
s0=$(date +%s)
echo "== ray2 $(cat $L/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo 'no nvidia-smi') size $SIZE $(date -u +%T)"
timeout ${WT:-5} $L/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
echo "== 1: processes alternated, A main, B branch: the multi-instance scene (with ESVO), eph_monu1, eph_menger $(date -u +%T)"
for round in 1 2 3; do
  for who in A B; do
    left=$(( ${T1:-92} - ($(date +%s) - s0) ))
    [ $left -gt 4 ] || break 2
    bin=$B/render_bench; [ $who = B ] && bin=$L/render_bench
    echo "-- round $round $who"
    timeout $left $bin --sizes $SIZE --runs ${R1:-15} --warmup $WU --views overview,oblique,closeup,sky \
      $L/ogt_test_multiple_model_scene.vox 2>&1 | grep -E '^ogt'
    left=$(( ${T1:-92} - ($(date +%s) - s0) ))
    [ $left -gt 4 ] || break 2
    timeout $left $bin --no-esvo --sizes $SIZE --runs ${R1:-15} --warmup $WU --views overview,closeup \
      $L/eph_monu1.vox $L/eph_menger.vox 2>&1 | grep -E '^eph'
  done
done
echo "== 1b: exactness in one process: B built-in (tiles) against B with no cull (@c0: the walk from the root) $(date -u +%T)"
left=$(( ${T1B:-110} - ($(date +%s) - s0) ))
[ $left -gt 4 ] && timeout $left $L/render_bench --no-esvo --sizes $SIZE --runs 3 --warmup 0 --views overview,oblique,closeup,sky \
  --kernels @c0 $L/ogt_test_multiple_model_scene.vox 2>&1 | grep -E '^ogt'
echo "== 2: eph_dragon, ogt_doom, obliques and close-ups, A then B then A then B $(date -u +%T)"
for who in A B A B; do
  left=$(( ${T2:-136} - ($(date +%s) - s0) ))
  [ $left -gt 4 ] || break
  bin=$B/render_bench; [ $who = B ] && bin=$L/render_bench
  echo "-- $who"
  timeout $left $bin --no-esvo --sizes $SIZE --runs ${R2:-10} --warmup $WU --views oblique,closeup \
    $L/eph_dragon.vox $L/ogt_doom.vox 2>&1 | grep -E '^(eph|ogt)'
done
echo "== 3: shader statistics, A then B (the multi-instance scene) $(date -u +%T)"
for who in A B; do
  left=$(( ${TOTAL:-146} - ($(date +%s) - s0) ))
  [ $left -gt 3 ] || break
  bin=$B/render_bench; [ $who = B ] && bin=$L/render_bench
  echo "-- $who"
  timeout $left $bin --no-esvo --shader-stats --sizes 64x64 --runs 1 --warmup 0 --views overview $L/ogt_test_multiple_model_scene.vox 2>&1 | grep '^stats: trace'
done
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
