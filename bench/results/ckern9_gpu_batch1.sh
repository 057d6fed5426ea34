#!/bin/bash
# ckern9 batch 1 (issue 18): the exploration binary (X: --variants, trace_compact.comp's
# CK9 constant: 1 the walk's stack as a ladder of selects (DEEP 0-1), 2 PUSH_BRICK in
# DEEP 1 too, 4 no tv_max test in DEEP 0, 8 the colour's lean forms (one 4-bit Morton
# code below the table, the delta decode's bytes at once), 0x100 starts from one push;
# 0x10-0x40 diagnostic stages of the colour,
# wrong colours on purpose: 1 the start table's entry, 2 after level 4, 3 after level 3,
# 4 the index without the decode), each timing trace.comp (main's, the GPU form) against
# the compact kernels in one process; then main's compact_bench (f807bf3).
# (Batch 0, ckern9_h200_batch0.txt, ran an earlier form of this script, X1 = monu1 and
# the helmet with 1,2,3,0x101,0x10,0x20,0x30,0x40, whose binary's SPIR-V was invalid:
# the NVIDIA compiler crashed; main's process ran.)
G=bench/out/ckern9; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; REPS=${REPS:-30}; END=${END:-97}
export LD_LIBRARY_PATH=$PWD/$G:$PWD/$B
T=/tmp/ck9; rm -rf $T; mkdir -p $T
gzip -dc $G/compact_bench.gz > $T/compact_bench && chmod +x $T/compact_bench
O=${OUTDIR:-$T}; mkdir -p $O
echo "== ckern9 batch 1, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
echo "=== warm-up t=$(t)"; timeout 3 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
run() { # who need_s max_s bin [args]
  who=$1 need=$2 max=$3 bin=$4; shift 4
  tob=$(( END - $(t) )); [ $tob -gt $max ] && tob=$max
  if [ $tob -lt $need ]; then echo "=== skip $who t=$(t)"; return; fi
  echo "=== $who t=$(t)"
  timeout $tob $bin --shader-stats --gpu $SIZE --reps $REPS "$@" > $O/k_${who}.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $O/k_${who}.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $O/k_${who}.txt | cut -d'|' -f2-8,10,14 | sed "s/^/$who |/"
  grep "^stats: trace compact \[spec [13]," $O/k_${who}.txt | sort -u | sed 's/ CS (subgroup 32)//; s/Register Count/R/; s/Binary Size/bin/; s/Shared Memory Size/shm/; s/Local Memory Size/lmem/; s/Stack Size/stk/' | cut -c1-170
}
run Xh 14 30 $T/compact_bench --closeups --variants 1,2,3,8,9,0xb,0x10,0x20,0x30,0x40 $G/helmet512.svo
run Xm 10 20 $T/compact_bench --closeups --variants 1,4,5,8,9,0x101 $G/eph_monu1.vox
run X2 15 25 $T/compact_bench --variants 1,3,8,9 $G/eph_menger.vox --terrain $TER
run main 12 20 $B/compact_bench $G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER
echo "=== end t=$(t)"
