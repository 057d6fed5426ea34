#!/bin/bash
# lean5's device scripts (issue 18), one file: BATCH=1 or 2 runs what that batch's run.sh ran (the payload folder held
# compact_bench.gz, compact_bench_main.gz, helmet512.svo and eph_monu1.vox; cwd the folder). M = main's compact_bench
# (0acd33a); X = the exploration build (0acd33a with lean5_explore.patch; batch 1's build had bits 1-2 only, the same
# code for LV 1-3), VX_LEAN5 = trace_compact.comp's spec constant LV:
#   1 PUSH_BRICK in DEEP 1 (lean4's X1); 2 the hit cell's ray (oa, d, L, the start-inside flag) on the stack in DEEP 0-1
#   (not in registers across the walk); 8 SENT (desc 0 marks a node not loaded) in every DEEP 0-1 kernel;
#   diagnostics, wrong colours on purpose: 16 the colour a hash of the hit cell, 32 a hash of the attribute index.
# Batch 1: M1 X3 X2 M2 X3 (X3 on the DEEP 1 scenes: its DEEP 0 kernels are X2's), X1's statistics; round 1 with
#   --shader-stats. Batch 2: M1, P = LV 9 (PUSH_BRICK and SENT: the depth kernels' walk in the albedo kernels),
#   D17 / D16 (the colour a hash of the cell, with and without PUSH_BRICK), M2, D33 (PUSH_BRICK, a hash of the index).
# SIZE, REPS, END, TER, SLOW (the limits times SLOW): smaller runs on lavapipe.
B=${BATCH:-2}
D=$PWD; T=/tmp/${NAME:-lean5}; rm -rf $T; mkdir -p $T
for f in $D/*.gz; do gzip -dc $f > $T/$(basename $f .gz); done; chmod +x $T/*
cp $D/helmet512.svo $D/eph_monu1.vox $T/; cd $T
END=${END:-$([ $B = 1 ] && echo 62 || echo 55)}
echo "== lean5 payload $B, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
md5sum $T/compact_bench $T/compact_bench_main
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
G="--gpu ${SIZE:-1920x1080} --reps ${REPS:-30}"; DEEP1="helmet512.svo --terrain ${TER:-1024}"; ALL="eph_monu1.vox $DEEP1"
run() { # who need_s max_s bin args...
  who=$1 need=$2 max=$(( $3 * ${SLOW:-1} )) bin=$4; shift 4
  tob=$(( END - $(t) )); [ $tob -gt $max ] && tob=$max
  if [ $tob -lt $need ]; then echo "=== skip $who t=$(t)"; return 1; fi
  echo "=== $who t=$(t) ${VX_LEAN5:+VX_LEAN5=$VX_LEAN5}"
  timeout $tob $bin "$@" > $T/k_$who.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $T/k_$who.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $T/k_$who.txt | cut -d"|" -f2-10,14 | sed "s/^/$who |/"
  grep "^stats: trace" $T/k_$who.txt | grep -v misses | sort -u | sed 's/ CS (subgroup 32)//; s/Register Count/R/; s/Binary Size/bin/; s/Shared Memory Size/shm/; s/Local Memory Size=6871947/lmem=/; s/Stack Size/stk/' | cut -c1-150
  return 0
}
M=$T/compact_bench_main; X=$T/compact_bench
if [ $B = 1 ]; then
  run M1 8 16 $M --shader-stats $G $ALL
  VX_LEAN5=3 run X3.1 6 14 $X --shader-stats $G $DEEP1
  VX_LEAN5=2 run X2.1 8 16 $X --shader-stats $G $ALL
  run M2 7 10 $M $G $ALL
  VX_LEAN5=3 run X3.2 5 7 $X $G $DEEP1
  # X1's kernels' statistics only (lean4 timed it today), a small frame
  VX_LEAN5=1 run X1s 4 6 $X --shader-stats --gpu 64x36 --reps 1 helmet512.svo
  VX_LEAN5=2 run X2.2 7 10 $X $G $ALL
else
  run M1 8 16 $M --shader-stats $G $ALL
  VX_LEAN5=9 run P1 8 17 $X --shader-stats $G $ALL
  VX_LEAN5=17 run D17 5 9 $X --shader-stats $G helmet512.svo
  VX_LEAN5=16 run D16 5 9 $X --shader-stats $G helmet512.svo
  run M2 5 8 $M $G $DEEP1
  VX_LEAN5=33 run D33 5 8 $X --shader-stats $G helmet512.svo
fi
echo "=== end t=$(t)"
