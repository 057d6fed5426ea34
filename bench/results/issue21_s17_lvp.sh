#!/bin/bash
# lvp1 (issue 21, seventeenth sitting): voxkit against the ESVO baseline on lavapipe, rays per CPU second
# (render_bench --cpu-time: voxkit and ESVO in the same process, their ratio per process). Views overview,
# oblique, close-up at 480x270 and 1280x720; eph_monu1, eph_menger, ogt_doom, eph_dragon, and the terrains
# (--generate) in a second process. Two CPU configurations alternated process by process:
#   host: lavapipe as it comes (the dev VM's AMD EPYC exposes AVX-512: LLVM 15 gets +avx512f,vl,bw,...)
#   avx2: GALLIUM_OVERRIDE_CPU_CAPS=avx (Mesa's switch: the AVX-512 features off, AVX2 kept), the code
#         an AVX2-only CPU gets
# ROUNDS rounds (default 3); LP_NUM_THREADS=${THREADS:-1}. BIN: the render_bench to run.
BIN=${BIN:-build/bin/render_bench}
ROUNDS=${ROUNDS:-3}
CFGS=${CFGS:-host avx2}
export LP_NUM_THREADS=${THREADS:-1}
V=/work/shared/corpus/vox
OPT="--mrays --cpu-time --sizes 480x270,1280x720 --runs 5 --warmup 0.3 --views overview,oblique,closeup"
echo "== lavapipe $(date -u +%F' '%T) BIN=$BIN ($(git rev-parse --short HEAD)) LP_NUM_THREADS=$LP_NUM_THREADS rounds $ROUNDS: $CFGS"
echo "== $(grep -m1 'model name' /proc/cpuinfo), $(nproc) CPUs; load $(cut -d' ' -f1-3 /proc/loadavg)"
for round in $(seq 1 $ROUNDS); do
  for what in vox gen; do
    for cfg in $CFGS; do
      ov=; [ $cfg = avx2 ] && ov=avx
      args="$V/eph_monu1.vox $V/eph_menger.vox $V/ogt_doom.vox $V/eph_dragon.vox"
      [ $what = gen ] && args=--generate
      echo "-- round $round $cfg $what $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)"
      GALLIUM_OVERRIDE_CPU_CAPS=$ov timeout 1200 $BIN $OPT $args 2>&1 | grep -v '^shadow map'
    done
  done
done
echo "== done $(date -u +%T)"
