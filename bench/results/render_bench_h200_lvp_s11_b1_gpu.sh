#!/bin/bash
# lvp (issue 21, eleventh sitting): the per-ray fixed cost. Branch lvp's render_bench
# (built-in kernel = ONE_SAMPLE + instance/model in the frame block) against main's
# kernel compiled apart (k_main.spv) in the same process, ONE_SAMPLE alone (k_one.spv),
# the new kernel compiled apart (k_new.spv), the BVH's items one per outer iteration (k_flat.spv); then main's binary against ours process
# by process (ABAB); then the terrains. SIZE=WxH for a local lavapipe check.
export LD_LIBRARY_PATH=bench/out/lvp:bench/out/base/bin
L=bench/out/lvp; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; RUNS=${RUNS:-10}; WU=${WU:-0.1}
T=/tmp/lvp_gpu; rm -rf $T; mkdir -p $T
V="$L/eph_monu1.vox $L/ogt_test_multiple_model_scene.vox $L/ogt_doom.vox $L/eph_dragon.vox $L/eph_menger.vox"
echo "== lvp $(cat $L/REV) on $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo 'no nvidia-smi') size $SIZE $(date -u +%T)"
s0=$(date +%s)
# warm-up: the GPU to its clocks
timeout ${WT:-12} $L/render_bench --no-esvo --sizes $SIZE --runs 200 --warmup 3 --views overview $L/eph_monu1.vox > /dev/null 2>&1
echo "== 1: in-process, five .vox scenes, four views (built-in = new; k_main = main's kernel) $(date -u +%T)"
timeout ${T1:-70} $L/render_bench --sizes $SIZE --runs $RUNS --warmup $WU --cpu-time --views overview,oblique,closeup,sky \
  --kernels $L/k_main.spv,$L/k_one.spv,$L/k_new.spv,$L/k_flat.spv,$L/k_main.spv $V 2>&1 | grep -v '^shadow map'
echo "== 2: processes ABAB, main's binary (A) and lvp's (B), depth rays, no ESVO $(date -u +%T)"
for r in 1 2; do
  for k in A B; do
    bin=$B/render_bench; [ $k = B ] && bin=$L/render_bench
    timeout ${T2:-8} $bin --no-esvo --sizes $SIZE --runs $RUNS --warmup $WU --views overview,closeup \
      $L/eph_monu1.vox $L/ogt_doom.vox 2>&1 | grep -E '^(eph|ogt)' | awk -v k=$k -v r=$r '{print k, r, $1, $2, $10}' | tee -a $T/abab.txt
  done
done
for sc in eph_monu1.vox ogt_doom.vox; do for v in overview closeup; do
  ma=$(awk -v s=$sc -v v=$v '$1=="A" && $3==s && $4==v {print $5}' $T/abab.txt | sort -g | awk '{a[NR]=$1} END {if (NR) print a[int((NR+1)/2)]}')
  mb=$(awk -v s=$sc -v v=$v '$1=="B" && $3==s && $4==v {print $5}' $T/abab.txt | sort -g | awk '{a[NR]=$1} END {if (NR) print a[int((NR+1)/2)]}')
  [ -n "$ma" ] && [ -n "$mb" ] && echo "median $sc $v: main $ma lvp $mb rays/s (G; M on lavapipe) lvp/main $(awk -v a=$ma -v b=$mb 'BEGIN {printf "%.3f", b / a}')"
done; done
echo "== 3: terrains 1024 and 4096 (built-in, k_main, k_new) $(date -u +%T)"
left=$(( ${TOTAL:-146} - ($(date +%s) - s0) ))
[ $left -gt 5 ] && timeout $left $L/render_bench --generate --sizes $SIZE --runs $RUNS --warmup $WU \
  --kernels $L/k_main.spv,$L/k_new.spv 2>&1 | grep -v '^shadow map'
echo "== done $(date -u +%T), $(( $(date +%s) - s0 )) s"
