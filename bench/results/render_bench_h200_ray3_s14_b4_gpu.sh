#!/bin/bash
# ray3 (issue 21, fourteenth sitting), batch 4 (limit 60 s): does a subgroup-wide start (subgroupAll) make
# the per-tile starts at the rays' box entries pay? 1: one process, B's built-in kernel (starts where the
# eye is inside the model box), @c1p2 (also the tiles whose rays enter the box), @c1p0 (none) and main's
# trace.comp (k_main), twice, 4 .vox scenes, 3 views; 2: the terrains likewise (close-up, oblique);
# 3: main's render_bench (A) and B on the close-ups, one process each. SIZE=WxH for lavapipe.
export LD_LIBRARY_PATH=bench/out/base/bin
L=bench/out/ray3; A=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}
s0=$(date +%s)
echo "== ray3 B $(cat $L/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo 'no nvidia-smi') size $SIZE $(date -u +%T)"
timeout ${WT:-4} $L/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
SC="$L/eph_monu1.vox $L/eph_dragon.vox $L/ogt_doom.vox $L/eph_menger.vox"
echo "== 1: one process: B built-in, @c1p2, @c1p0, k_main, twice $(date -u +%T)"
left=$(( ${T1:-32} - ($(date +%s) - s0) ))
[ $left -gt 3 ] && timeout $left $L/render_bench --no-esvo --sizes $SIZE --runs ${R1:-6} --warmup $WU --views overview,oblique,closeup \
  --kernels @c1p2,@c1p0,$L/k_main.spv@c1,@c1,@c1p2,@c1p0,$L/k_main.spv@c1 $SC 2>&1 | grep -E '^(eph|ogt)'
echo "== 2: terrains likewise, one process $(date -u +%T)"
left=$(( ${T2:-48} - ($(date +%s) - s0) ))
[ $left -gt 3 ] && timeout $left $L/render_bench --generate --no-esvo --sizes $SIZE --runs ${R1:-6} --warmup $WU --views closeup,oblique \
  --kernels @c1p2,@c1p0,$L/k_main.spv@c1,@c1,@c1p2 2>&1 | grep -E '^terr'
echo "== 3: A then B, close-ups, with ESVO $(date -u +%T)"
for who in A B; do
  left=$(( ${TOTAL:-58} - ($(date +%s) - s0) ))
  [ $left -gt 3 ] || break
  bin=$A/render_bench; [ $who = B ] && bin=$L/render_bench
  echo "-- $who"
  timeout $left $bin --sizes $SIZE --runs ${R1:-6} --warmup $WU --views closeup $SC 2>&1 | grep -E '^(eph|ogt)'
done
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
