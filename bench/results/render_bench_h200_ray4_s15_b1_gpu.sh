#!/bin/bash
# ray4 (issue 21, fifteenth sitting), batch 1 (limit 100 s): the descriptors' GPU form (the low byte the
# inner mask, one shift per push). 1: main's render_bench (A, bench/out/base/bin, 8ab2eb2) and the branch's
# (B) alternated process by process (A B A B) with ESVO, 5 .vox scenes, 3 views, 1920x1080, --runs 10
# --warmup 0.1; 2: shader statistics of B. SIZE=WxH and TOTAL for a lavapipe check.
export LD_LIBRARY_PATH=bench/out/base/bin
L=bench/out/ray4; A=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}; RUNS=${RUNS:-10}
s0=$(date +%s)
echo "== ray4 B $(cat $L/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo 'no nvidia-smi') size $SIZE $(date -u +%T)"
timeout ${WT:-4} $L/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
bin_of() { case $1 in A) echo $A/render_bench;; B) echo $L/render_bench;; esac; }
SC="$L/eph_monu1.vox $L/eph_menger.vox $L/ogt_doom.vox $L/eph_dragon.vox $L/ogt_test_multiple_model_scene.vox"
echo "== 1: processes alternated A B A B, with ESVO $(date -u +%T)"
for round in 1 2; do
  for who in A B; do
    left=$(( ${T1:-92} - ($(date +%s) - s0) ))
    [ $left -gt 4 ] || break 2
    echo "-- round $round $who $(date -u +%T)"
    timeout $left $(bin_of $who) --sizes $SIZE --runs $RUNS --warmup $WU --views overview,oblique,closeup $SC 2>&1 | grep -E '^(eph|ogt)|far pointer'
  done
done
echo "== 2: shader statistics, B (eph_monu1) $(date -u +%T)"
left=$(( ${TOTAL:-98} - ($(date +%s) - s0) ))
[ $left -gt 1 ] && timeout $left $L/render_bench --shader-stats --sizes 64x64 --runs 1 --warmup 0 --views closeup \
  $L/eph_monu1.vox 2>&1 | grep '^stats:'
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
