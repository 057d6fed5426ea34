#!/bin/bash
# lvp (issue 21, eleventh sitting), batch 2: branch lvp's render_bench (built-in kernel =
# ONE_SAMPLE + instance/model in the frame block + the BVH's items one per outer iteration;
# k_final.spv the same compiled apart) against main's kernel compiled apart (k_main.spv) in
# the same process, alternated; k_rbs.spv: the two-frame walk's slots in an array of their own
# (constant indices), for the DEEP 2 terrain. SIZE=WxH for a local lavapipe check.
export LD_LIBRARY_PATH=bench/out/lvp:bench/out/base/bin
L=bench/out/lvp; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; WU=${WU:-0.1}
s0=$(date +%s)
echo "== lvp $(cat $L/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo 'no nvidia-smi') size $SIZE $(date -u +%T)"
timeout ${WT:-6} $L/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 2 --views overview $L/eph_monu1.vox > /dev/null 2>&1
echo "== 1: the multi-instance scene (BVH), 30 runs, kernels alternated $(date -u +%T)"
timeout ${T1:-22} $L/render_bench --sizes $SIZE --runs ${R1:-30} --warmup $WU --views overview,oblique,closeup \
  --kernels $L/k_main.spv,$L/k_final.spv,$L/k_main.spv,$L/k_final.spv $L/ogt_test_multiple_model_scene.vox 2>&1 | grep -v '^shadow map'
echo "== 2: terrains 1024 and 4096, no ESVO (batch 1 has it), kernels alternated $(date -u +%T)"
timeout ${T2:-34} $L/render_bench --generate --no-esvo --sizes $SIZE --runs ${R2:-15} --warmup $WU \
  --kernels $L/k_main.spv,$L/k_rbs.spv,$L/k_main.spv,$L/k_rbs.spv 2>&1 | grep -v '^shadow map'
echo "== 3: four single-model scenes, shader statistics (main's kernel, the final one) $(date -u +%T)"
left=$(( ${TOTAL:-96} - ($(date +%s) - s0) ))
[ $left -gt 5 ] && timeout $left $L/render_bench --sizes $SIZE --runs ${R3:-10} --warmup $WU --shader-stats --views overview,closeup \
  --kernels $L/k_main.spv,$L/k_final.spv,$L/k_main.spv $L/eph_monu1.vox $L/ogt_doom.vox $L/eph_dragon.vox $L/eph_menger.vox 2>&1 \
  | grep -v '^shadow map' | grep -E -v '^stats: (frame|gbuffer|beam|dense|esvo-never)' 
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
