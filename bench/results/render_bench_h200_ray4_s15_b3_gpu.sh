#!/bin/bash
# ray4 (issue 21, fifteenth sitting), batch 3 (limit 90 s): the far-pointer kernels. Batch 2 had B's
# terrain4096 (FAR on) 1.5-3% slower in primary rays and 45% slower in primary + shadow rays than main's.
# B is now the hybrid (the push's child bits from one shift where FAR is off, tested in place with the
# child's bit where FAR is on: MASKS in trace_common.glsl). 1: A (main, bench/out/base/bin) and B
# alternated (A B A B), --generate (terrain1024 FAR off, terrain4096 FAR on), no ESVO, 3 views, --runs 10
# --warmup 0.1, with --shader-stats; B's processes also time k_shift (always one shift: batch 1-2's B)
# and k_mask (always in place) in the same process (@c1: the screen cull as built in). 2: the float64
# variant (--deep --variant precise, overview), A B, with --shader-stats.
export LD_LIBRARY_PATH=bench/out/base/bin
L=bench/out/ray4; A=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}; RUNS=${RUNS:-10}
s0=$(date +%s)
echo "== ray4 B $(cat $L/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo 'no nvidia-smi') size $SIZE $(date -u +%T)"
timeout ${WT:-4} $L/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
echo "== 1: terrains, A B A B, no ESVO; B with --kernels k_shift, k_mask $(date -u +%T)"
for round in 1 2; do
  for who in A B; do
    left=$(( ${T1:-72} - ($(date +%s) - s0) ))
    [ $left -gt 4 ] || break 2
    echo "-- round $round $who $(date -u +%T)"
    if [ $who = A ]; then
      timeout $left $A/render_bench --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views overview,oblique,closeup \
        $( [ $round = 1 ] && echo --shader-stats ) 2>&1 | grep -E '^terr|far pointer|^stats: trace'
    else
      timeout $left $L/render_bench --generate --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views overview,oblique,closeup \
        --kernels $L/k_shift.spv@c1,$L/k_mask.spv@c1 $( [ $round = 1 ] && echo --shader-stats ) 2>&1 | grep -E '^terr|far pointer|^stats: trace'
    fi
  done
done
echo "== 2: float64 variant (--deep --variant precise, overview), A B, shader statistics $(date -u +%T)"
for who in A B; do
  left=$(( ${TOTAL:-88} - ($(date +%s) - s0) ))
  [ $left -gt 2 ] || break
  echo "-- $who $(date -u +%T)"
  b=$A/render_bench; [ $who = B ] && b=$L/render_bench
  timeout $left $b --deep --variant precise --no-esvo --shader-stats --sizes $SIZE --runs $RUNS --warmup $WU --views overview 2>&1 | grep -E '^terr|^stats: trace'
done
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
