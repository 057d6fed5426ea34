#!/bin/bash
# lvp1 (issue 21, seventeenth sitting): the branch's render_bench with the ESVO baseline given the same stack
# form as trace.comp's on CPU devices (--esvo-kernel: bench/results/issue21_s17_esvo_selects.comp, exact to
# depth 12), rays per CPU second, in the two CPU configurations of issue21_s17_lvp.sh (host, avx2) alternated
# process by process; vox scenes, then --generate. SIZES (default 480x270), ROUNDS (default 1), DEADLINE.
B=${B:-/tmp/lvp1_bin/render_bench_esvok}; K=${K:-/tmp/lvp1_bin/esvo_sel.spv}
ROUNDS=${ROUNDS:-1}; SIZES=${SIZES:-480x270}; DEADLINE=${DEADLINE:-9999999999}
export LP_NUM_THREADS=${THREADS:-1}
V=/work/shared/corpus/vox
OPT="--mrays --cpu-time --sizes $SIZES --runs 5 --warmup 0.3 --views overview,oblique,closeup --esvo-kernel $K"
echo "== lavapipe ESVO-selects $(date -u +%F' '%T) B=$B K=$K LP_NUM_THREADS=$LP_NUM_THREADS sizes $SIZES rounds $ROUNDS"
for round in $(seq 1 $ROUNDS); do
  for what in vox gen; do
    for cfg in host avx2; do
      [ $(date +%s) -lt $DEADLINE ] || { echo "== deadline $(date -u +%T)"; exit 0; }
      ov=; [ $cfg = avx2 ] && ov=avx
      args="$V/eph_monu1.vox $V/eph_menger.vox $V/ogt_doom.vox $V/eph_dragon.vox"; [ $what = gen ] && args=--generate
      echo "-- round $round $cfg $what $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)"
      GALLIUM_OVERRIDE_CPU_CAPS=$ov timeout 1500 $B $OPT $args 2>&1 | grep -v '^shadow map'
    done
  done
done
echo "== done $(date -u +%T)"
