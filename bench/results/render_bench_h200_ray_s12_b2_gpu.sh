#!/bin/bash
# ray (issue 21, twelfth sitting), batch 2: the screen cull, the rectangle (the built-in kernel,
# c1) against the spans (@c2: per band of 8 rows the box's projection) against main's trace.comp
# (b74da51, k_main.spv, compiled apart, twice) in one process, with ESVO; then main's
# render_bench and the branch's alternated process by process. SIZE=WxH for lavapipe.
export LD_LIBRARY_PATH=bench/out/ray:bench/out/base/bin
L=bench/out/ray; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}
s0=$(date +%s)
echo "== ray $(cat $L/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo 'no nvidia-smi') size $SIZE $(date -u +%T)"
timeout ${WT:-5} $L/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
echo "== 1: five .vox scenes, four views: built-in (c1), k_main, c2, k_main $(date -u +%T)"
timeout ${T1:-78} $L/render_bench --sizes $SIZE --runs ${R1:-10} --warmup $WU --views overview,oblique,closeup,sky \
  --kernels $L/k_main.spv,@c2,$L/k_main.spv $L/eph_monu1.vox $L/ogt_test_multiple_model_scene.vox $L/eph_menger.vox \
  $L/ogt_doom.vox $L/eph_dragon.vox 2>&1 | grep -v '^shadow map'
echo "== 2: terrains 1024 and 4096 with ESVO: built-in (c1), k_main, c2, k_main $(date -u +%T)"
left=$(( ${T2:-122} - ($(date +%s) - s0) ))
[ $left -gt 5 ] && timeout $left $L/render_bench --generate --sizes $SIZE --runs ${R2:-10} --warmup $WU \
  --views overview,oblique,closeup,sky --kernels $L/k_main.spv,@c2,$L/k_main.spv 2>&1 | grep -v '^shadow map'
echo "== 3: processes alternated, main's render_bench (A) and the branch's (B), eph_monu1 $(date -u +%T)"
for round in 1 2 3; do
  for who in A B; do
    left=$(( ${TOTAL:-143} - ($(date +%s) - s0) ))
    [ $left -gt 4 ] || break 2
    bin=$B/render_bench; [ $who = B ] && bin=$L/render_bench
    echo "-- round $round $who"
    timeout $left $bin --no-esvo --sizes $SIZE --runs ${R3:-15} --warmup $WU --views overview,closeup,sky $L/eph_monu1.vox 2>&1 | grep -E '^eph'
  done
done
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
