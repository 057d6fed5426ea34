#!/bin/bash
# ray3 (issue 21, fourteenth sitting), batch 3 (limit 90 s): the branch's final binary. 1: main's render_bench
# (A, bench/out/base/bin, 0b39e32) and the branch's (B) alternated process by process with ESVO, two
# rounds (4 .vox scenes, 3 views); 2: the terrains and the multi-instance scene, B's built-in kernel against
# itself with the starts off (@c1p0) and main's trace.comp compiled apart (k_main), twice, one process;
# 3: shader statistics. SIZE=WxH for lavapipe.
export LD_LIBRARY_PATH=bench/out/base/bin
L=bench/out/ray3; A=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}
s0=$(date +%s)
echo "== ray3 B $(cat $L/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo 'no nvidia-smi') size $SIZE $(date -u +%T)"
timeout ${WT:-4} $L/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
bin_of() { case $1 in A) echo $A/render_bench;; B) echo $L/render_bench;; esac; }
SC="$L/eph_monu1.vox $L/eph_dragon.vox $L/ogt_doom.vox $L/eph_menger.vox"
echo "== 1: processes alternated A B, with ESVO $(date -u +%T)"
for round in 1 2; do
  for who in A B; do
    left=$(( ${T1:-58} - ($(date +%s) - s0) ))
    [ $left -gt 4 ] || break 2
    echo "-- round $round $who"
    timeout $left $(bin_of $who) --sizes $SIZE --runs ${R1:-6} --warmup $WU --views overview,oblique,closeup $SC 2>&1 | grep -E '^(eph|ogt)'
  done
done
echo "== 2: terrains, B built-in, starts off (@c1p0), k_main, twice, one process (no ESVO) $(date -u +%T)"
left=$(( ${T2:-84} - ($(date +%s) - s0) ))
[ $left -gt 3 ] && timeout $left $L/render_bench --generate --no-esvo --sizes $SIZE --runs ${R2:-6} --warmup $WU --views closeup,oblique \
  --kernels @c1p0,$L/k_main.spv@c1,@c1,@c1p0,$L/k_main.spv@c1 2>&1 | grep -E '^terr'
echo "== 3: shader statistics, B (eph_monu1) $(date -u +%T)"
left=$(( ${TOTAL:-88} - ($(date +%s) - s0) ))
[ $left -gt 1 ] && timeout $left $L/render_bench --no-esvo --shader-stats --sizes 64x64 --runs 1 --warmup 0 --views closeup \
  $L/eph_monu1.vox 2>&1 | grep '^stats: trace \[spec [03],1,0,0,0'
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
