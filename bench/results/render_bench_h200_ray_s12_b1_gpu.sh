#!/bin/bash
# ray (issue 21, twelfth sitting), batch 1: pixels per invocation (PPI 1, 2, 4) and the screen
# cull (c1: the trace pass covers the scene box's pixel rectangle, a miss pass the rest), the
# branch's render_bench; its built-in kernel = @p1c1; k_main.spv = main's trace.comp (b74da51)
# compiled apart, in the same process (rows "[kernel ...]"), with ESVO. SIZE=WxH for lavapipe.
export LD_LIBRARY_PATH=bench/out/ray:bench/out/base/bin
L=bench/out/ray; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}
s0=$(date +%s)
echo "== ray $(cat $L/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo 'no nvidia-smi') size $SIZE $(date -u +%T)"
timeout ${WT:-5} $L/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
echo "== 1: five .vox scenes, four views: built-in (p1c1), k_main, p2c1, p4c1, p1c0 $(date -u +%T)"
timeout ${T1:-84} $L/render_bench --sizes $SIZE --runs ${R1:-10} --warmup $WU --views overview,oblique,closeup,sky \
  --kernels $L/k_main.spv,@p2c1,@p4c1,@p1c0 $L/eph_monu1.vox $L/eph_menger.vox $L/ogt_doom.vox \
  $L/ogt_test_multiple_model_scene.vox $L/eph_dragon.vox 2>&1 | grep -v '^shadow map'
echo "== 2: terrains 1024 and 4096 with ESVO: built-in (p1c1), k_main, p2c1 $(date -u +%T)"
left=$(( ${TOTAL:-140} - ($(date +%s) - s0) ))
[ $left -gt 5 ] && timeout $left $L/render_bench --generate --sizes $SIZE --runs ${R2:-10} --warmup $WU \
  --views overview,oblique,closeup,sky --kernels $L/k_main.spv,@p2c1 2>&1 | grep -v '^shadow map'
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
