#!/bin/bash
# ck11 batch 2 (issue 18; it printed "batch 1": the same script with K added): the helmet close-up's colour on the H200.
# X = the branch's exploration compact_bench (trace_compact.comp's CK11 constant through --variants; VX_CK11 for a
# whole process): 1 the residual's two words loaded without a branch; 2 the level-4 and level-3 steps from a side
# record per slot (cells before each octant; no prev rank, no bricks loop); 4 the index from the walk's path (the
# hit's level-3/level-4 ancestors from the stack and its brick from registers: the table entry, n4's word 0, n3's
# rank and record loaded independently); 8 the decode from a record per block (payload word, code, minimum,
# widths: one load before the residuals instead of three); diagnostics (wrong colours on purpose): 0x10 the
# colour a hash of the cell, 0x20 a hash of the index (no decode). VX_CK11_TABMUL=8: start tables at level 3.
# K = the branch's kept form (bit 4's path colour without switches: level-3 records of 8 bytes after the geometry,
# the level-4 term from the rank of the slot before n3). M = main's compact_bench (1695247). Each kernel timed
# against trace.comp in its process (median of 5 rounds of 30).
D=$PWD; T=/tmp/ck11; rm -rf $T; mkdir -p $T
for f in compact_bench compact_bench_main compact_bench_k; do gzip -dc $D/$f.gz > $T/$f && chmod +x $T/$f; done
cp $D/helmet512.svo $D/eph_monu1.vox $D/eph_menger.vox $T/
cd $T
X=$T/compact_bench; M=$T/compact_bench_main; K=$T/compact_bench_k
END=${END:-135}
echo "== ck11 batch 1, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
echo "=== warm-up t=$(t)"; timeout 4 $M --gpu ${SIZE:-1920x1080} --reps 60 eph_menger.vox > /dev/null 2>&1
SC="eph_monu1.vox eph_menger.vox helmet512.svo --terrain 1024"
run() { # who need_s max_s bin args...
  who=$1 need=$2 max=$(( $3 * ${MUL:-1} )) bin=$4; shift 4
  tob=$(( END - $(t) )); [ $tob -gt $max ] && tob=$max
  if [ $tob -lt $need ]; then echo "=== skip $who t=$(t)"; return; fi
  echo "=== $who t=$(t)"
  timeout $tob $bin --gpu ${SIZE:-1920x1080} --reps ${REPS:-30} "$@" > $T/k_${who}.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $T/k_${who}.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $T/k_${who}.txt | cut -d'|' -f2-11,15 | sed "s/^/$who |/"
  grep "^stats: trace" $T/k_${who}.txt | sort -u | sed 's/ CS (subgroup 32)//; s/Register Count/R/; s/Binary Size/bin/; s/Shared Memory Size/shm/; s/Local Memory Size=6871947/lmem=/; s/Stack Size/stk/' | cut -c1-170
}
run S 10 22 $X --shader-stats --closeups --variants 1,2,4,5,8,0xc,0xd,0x10,0x20,0x24 helmet512.svo
VX_CK11_TABMUL=8 run T3 8 14 $X --closeups --variants 4,5,0xc,0xd,0x24 helmet512.svo
run M1 9 16 $M $SC
run K1 9 16 $K --shader-stats $SC
run M2 9 16 $M $SC
run K2 9 16 $K $SC
run A1 12 25 $X --variants 0xd,0x5 $SC
echo "=== end t=$(t)"
