#!/bin/bash
# lvp1 (issue 21, seventeenth sitting): main's render_bench (A, 46eb6d3) and the branch's (B) alternated process
# by process on lavapipe, each process with the ESVO baseline, rays per CPU second (--cpu-time), in the two CPU
# configurations of issue21_s17_lvp.sh (host: the dev VM's AVX-512; avx2: GALLIUM_OVERRIDE_CPU_CAPS=avx).
# WHAT: vox (eph_monu1, eph_menger, ogt_doom, eph_dragon) or gen (--generate: terrain1024, terrain4096).
# ROUNDS rounds; SIZES (default 480x270); stops starting processes after DEADLINE (epoch seconds).
A=${A:-/tmp/lvp1_bin/render_bench_46eb6d3}; B=${B:-/tmp/lvp1_bin/render_bench_e7c2140}
WHAT=${WHAT:-vox}; ROUNDS=${ROUNDS:-2}; SIZES=${SIZES:-480x270}; DEADLINE=${DEADLINE:-9999999999}
export LP_NUM_THREADS=${THREADS:-1}
V=/work/shared/corpus/vox
OPT="--mrays --cpu-time --sizes $SIZES --runs 5 --warmup 0.3 --views overview,oblique,closeup"
args="$V/eph_monu1.vox $V/eph_menger.vox $V/ogt_doom.vox $V/eph_dragon.vox"; [ $WHAT = gen ] && args=--generate
echo "== lavapipe A B $WHAT $(date -u +%F' '%T) A=$A B=$B LP_NUM_THREADS=$LP_NUM_THREADS sizes $SIZES rounds $ROUNDS"
for round in $(seq 1 $ROUNDS); do
  for cfg in host avx2; do
    for who in A B; do
      [ $(date +%s) -lt $DEADLINE ] || { echo "== deadline $(date -u +%T)"; exit 0; }
      bin=$A; [ $who = B ] && bin=$B
      ov=; [ $cfg = avx2 ] && ov=avx
      echo "-- round $round $cfg $who $WHAT $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)"
      GALLIUM_OVERRIDE_CPU_CAPS=$ov timeout 1500 $bin $OPT $args 2>&1 | grep -v '^shadow map'
    done
  done
done
echo "== done $(date -u +%T)"
