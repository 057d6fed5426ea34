#!/bin/bash
# lvp (issue 21, eleventh sitting), batch 3: the final table. Branch lvp's render_bench (built-in
# kernel = ONE_SAMPLE + instance/model in the frame block + the BVH's items one per outer
# iteration; k_final.spv the same compiled apart) against main's kernel compiled apart
# (k_main.spv) in the same process, alternated, with ESVO; the .vox scenes' four views, then the
# terrains' three. SIZE=WxH for a local lavapipe check.
export LD_LIBRARY_PATH=bench/out/lvp:bench/out/base/bin
L=bench/out/lvp
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}
s0=$(date +%s)
echo "== lvp $(cat $L/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo 'no nvidia-smi') size $SIZE $(date -u +%T)"
timeout ${WT:-5} $L/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
echo "== 1: five .vox scenes, four views $(date -u +%T)"
timeout ${T1:-56} $L/render_bench --sizes $SIZE --runs ${R1:-12} --warmup $WU --views overview,oblique,closeup,sky \
  --kernels $L/k_main.spv,$L/k_final.spv,$L/k_main.spv $L/eph_monu1.vox $L/ogt_test_multiple_model_scene.vox \
  $L/ogt_doom.vox $L/eph_dragon.vox $L/eph_menger.vox 2>&1 | grep -v '^shadow map'
echo "== 2: terrains 1024 and 4096 with ESVO $(date -u +%T)"
left=$(( ${TOTAL:-96} - ($(date +%s) - s0) ))
[ $left -gt 5 ] && timeout $left $L/render_bench --generate --sizes $SIZE --runs ${R2:-15} --warmup $WU \
  --kernels $L/k_main.spv,$L/k_final.spv,$L/k_main.spv 2>&1 | grep -v '^shadow map'
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
