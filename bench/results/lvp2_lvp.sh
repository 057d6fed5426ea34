#!/bin/bash
# lvp2 (issue 21, eighteenth sitting): voxkit against the bench's ESVO on lavapipe, rays per CPU second
# (render_bench --mrays --cpu-time: voxkit and ESVO in the same process, their ratio per process), main's binary
# (A, f807bf3) against the branch's (B), alternated process by process. Views overview, oblique, close-up;
# eph_monu1, eph_menger, ogt_doom, eph_dragon, and the terrains (--generate: terrain1024, DEEP 1; terrain4096,
# DEEP 2, the kernel this branch changes) in separate processes. Two CPU configurations as issue21_s17_lvp.sh:
#   host: lavapipe as it comes (the dev VM's AMD EPYC exposes AVX-512), avx2: GALLIUM_OVERRIDE_CPU_CAPS=avx.
# Phases in order (the log is complete up to where it was cut):
#   1: --generate at 480x270, ROUNDS rounds, each: host A B, avx2 A B
#   2: --generate at 1280x720, one round
#   3: the .vox scenes at 480x270, ROUNDS rounds
#   4: the .vox scenes at 1280x720, one round
#   5: LP_NUM_THREADS=2 (lavapipe's default on this VM), 1280x720, eph_monu1 and --generate, wall rates, A B host
#   6: the DEEP 2 ladder's cost: C (B's source with fbb131c's ladder size, S_MAX - 15 up: wrong for models of 17-21
#      levels, right for terrain4096's 12) against B, --generate at 480x270, ROUNDS rounds, host C B, avx2 C B
# WHO4: the binaries of phase 4 (default A B).
A=${A:-/tmp/lvp2_bin/render_bench_f807bf3}; B=${B:-/tmp/lvp2_bin/render_bench_1d24c21}; C=${C:-/tmp/lvp2_bin/render_bench_rows15}
WHO4=${WHO4:-A B}
ROUNDS=${ROUNDS:-3}; PHASES=${PHASES:-1 2 3 4 5}
V=/work/shared/corpus/vox; VOX="$V/eph_monu1.vox $V/eph_menger.vox $V/ogt_doom.vox $V/eph_dragon.vox"
OPT="--mrays --cpu-time --runs 5 --warmup 0.3 --views overview,oblique,closeup"
echo "== lavapipe lvp2 $(date -u +%F' '%T) A=$A B=$B C=$C rounds $ROUNDS phases $PHASES"
echo "== $(grep -m1 'model name' /proc/cpuinfo), $(nproc) CPUs; load $(cut -d' ' -f1-3 /proc/loadavg)"
one() { # phase round cfg who size threads args...
  local ph=$1 r=$2 cfg=$3 who=$4 size=$5 th=$6; shift 6
  local bin=$A; [ $who = B ] && bin=$B; [ $who = C ] && bin=$C
  local ov=; [ $cfg = avx2 ] && ov=avx
  echo "-- phase $ph round $r $cfg $who $size threads $th $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)"
  LP_NUM_THREADS=$th GALLIUM_OVERRIDE_CPU_CAPS=$ov timeout 1500 $bin $OPT --sizes $size "$@" 2>&1 | grep -v '^shadow map'
}
for ph in $PHASES; do
  case $ph in
  1) for r in $(seq 1 $ROUNDS); do for cfg in host avx2; do for w in A B; do one 1 $r $cfg $w 480x270 1 --generate; done; done; done ;;
  2) for cfg in host avx2; do for w in A B; do one 2 1 $cfg $w 1280x720 1 --generate; done; done ;;
  3) for r in $(seq 1 $ROUNDS); do for cfg in host avx2; do for w in A B; do one 3 $r $cfg $w 480x270 1 $VOX; done; done; done ;;
  4) for cfg in host avx2; do for w in $WHO4; do one 4 1 $cfg $w 1280x720 1 $VOX; done; done ;;
  5) for w in A B; do one 5 1 host $w 1280x720 2 $V/eph_monu1.vox; one 5 1 host $w 1280x720 2 --generate; done ;;
  6) for r in $(seq 1 $ROUNDS); do for cfg in host avx2; do for w in C B; do one 6 $r $cfg $w 480x270 1 --generate; done; done; done ;;
  esac
done
echo "== done $(date -u +%T)"
