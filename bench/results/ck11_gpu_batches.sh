#!/bin/bash
# ck11's device scripts (issue 18), one file: BATCH=1, 2 or 3 runs what that batch ran (the payload folder held
# the binaries it names, gzipped, and helmet512.svo, eph_monu1.vox, eph_menger.vox; run.sh there, cwd the folder).
# X = the exploration compact_bench (bench/results/ck11_explore_batch1.patch: trace_compact.comp's CK11 constant
# through --variants; VX_CK11_TABMUL=8 start tables at 8 times the budget): 1 the residuals' two words loaded
# without a branch; 2 levels 4 and 3 from a side record per slot; 4 the index from the walk's path; 8 the decode
# from a record per block; diagnostics (wrong colours on purpose): 0x10 the colour a hash of the cell, 0x20 a hash
# of the index. M = main's compact_bench (1695247). K = the kept form with main's table floor (batch 2: the path in
# every DEEP < 2 scene, before records_on; batch 3: DEEP 1 only), KT = the branch (the 2^18 floor).
# Each kernel timed against trace.comp in its process (median of 5 rounds of 30 dispatches). Batches 1 and 2 put
# --shader-stats after --gpu, where compact_bench ignores it (no statistics in their logs); batch 3 before.
# SIZE, REPS, END, MUL: smaller runs for a check on lavapipe.
B=${BATCH:-3}
D=$PWD; T=/tmp/ck11; rm -rf $T; mkdir -p $T
for f in compact_bench compact_bench_main compact_bench_k compact_bench_kt; do
  [ -f $D/$f.gz ] && gzip -dc $D/$f.gz > $T/$f && chmod +x $T/$f
done
cp $D/helmet512.svo $D/eph_monu1.vox $D/eph_menger.vox $T/
cd $T
X=$T/compact_bench; M=$T/compact_bench_main; K=$T/compact_bench_k; KT=$T/compact_bench_kt
END=${END:-$(case $B in 1) echo 125;; 2) echo 135;; *) echo 105;; esac)}
echo "== ck11 batch $B, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
echo "=== warm-up t=$(t)"; timeout 4 $M --gpu ${SIZE:-1920x1080} --reps 60 eph_menger.vox > /dev/null 2>&1
SC="eph_monu1.vox eph_menger.vox helmet512.svo --terrain 1024"
run() { # who need_s max_s bin args...
  who=$1 need=$2 max=$(( $3 * ${MUL:-1} )) bin=$4; shift 4
  tob=$(( END - $(t) )); [ $tob -gt $max ] && tob=$max
  if [ $tob -lt $need ]; then echo "=== skip $who t=$(t)"; return; fi
  echo "=== $who t=$(t)"
  st=""; [ $B = 3 ] && [ "$1" = --shader-stats ] && { st=--shader-stats; shift; } # (before --gpu: compact_bench's rule)
  timeout $tob $bin $st --gpu ${SIZE:-1920x1080} --reps ${REPS:-30} "$@" > $T/k_${who}.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $T/k_${who}.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $T/k_${who}.txt | cut -d'|' -f2-$([ $B = 3 ] && echo 14 || echo 11,15) | sed "s/^/$who |/"
  grep "^stats: trace" $T/k_${who}.txt | sort -u | sed 's/ CS (subgroup 32)//; s/Register Count/R/; s/Binary Size/bin/; s/Shared Memory Size/shm/; s/Local Memory Size=6871947/lmem=/; s/Stack Size/stk/' | cut -c1-170
}
if [ $B = 1 ]; then
  run S 10 22 $X --shader-stats --closeups --variants 1,2,4,5,8,0xc,0xd,0x10,0x20,0x24 helmet512.svo
  VX_CK11_TABMUL=8 run T3 8 16 $X --closeups --variants 2,4,5,0xc,0xd,0x24 helmet512.svo
  run M1 9 16 $M $SC
  run A1 14 30 $X --variants 0xd,0x5,0x4 $SC
  run M2 9 16 $M $SC
  run S2 6 12 $X --closeups --variants 4,5,0xc,0xd helmet512.svo
elif [ $B = 2 ]; then
  run S 10 22 $X --shader-stats --closeups --variants 1,2,4,5,8,0xc,0xd,0x10,0x20,0x24 helmet512.svo
  VX_CK11_TABMUL=8 run T3 8 14 $X --closeups --variants 4,5,0xc,0xd,0x24 helmet512.svo
  run M1 9 16 $M $SC
  run K1 9 16 $K --shader-stats $SC
  run M2 9 16 $M $SC
  run K2 9 16 $K $SC
  run A1 12 25 $X --variants 0xd,0x5 $SC
else
  run M1 9 16 $M $SC
  run K1 9 16 $K --shader-stats $SC
  run T1 9 16 $KT --shader-stats $SC
  run M2 9 16 $M $SC
  run K2 9 16 $K $SC
  run T2 9 16 $KT $SC
fi
echo "=== end t=$(t)"
