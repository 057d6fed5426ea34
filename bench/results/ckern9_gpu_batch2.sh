#!/bin/bash
# ckern9 batch 2 (issue 18): the branch's compact_bench (K: trace_compact.comp's DEEP 0 kernels
# without the test of tmin against the child's exit before a push; the stack's ladder only on
# CPU devices) against main's (bench/out/base/bin, f807bf3), alternating process by process
# (main, K, X, main, K), each timing trace.comp (main's, the GPU form) against the compact
# kernel in one process. X: the branch's binary with --variants (trace_compact.comp's CK9
# constant): 4 the tv_max test back (main's DEEP 0 form), 8 the colour through color_table
# (the group words loaded with the level-4 and level-3 slots), 0x88 also the two candidate
# block headers loaded with the brick.
G=bench/out/ckern9; B=bench/out/base/bin
SIZE=${SIZE:-1920x1080}; TER=${TER:-1024}; REPS=${REPS:-30}; END=${END:-97}
export LD_LIBRARY_PATH=$PWD/$G:$PWD/$B
T=/tmp/ck9; rm -rf $T; mkdir -p $T
gzip -dc $G/compact_bench.gz > $T/compact_bench && chmod +x $T/compact_bench
O=${OUTDIR:-$T}; mkdir -p $O
echo "== ckern9 batch 2, $(date -u)"; nproc; cat /proc/loadavg
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv,noheader 2>/dev/null
T0=$(date +%s); t() { echo $(( $(date +%s) - T0 )); }
echo "=== warm-up t=$(t)"; timeout 3 $B/compact_bench --gpu $SIZE --reps 60 $G/eph_menger.vox > /dev/null 2>&1
SC="$G/eph_monu1.vox $G/eph_menger.vox $G/helmet512.svo --terrain $TER"
run() { # who need_s max_s stats bin [args]
  who=$1 need=$2 max=$3 st=$4 bin=$5; shift 5
  tob=$(( END - $(t) )); [ $tob -gt $max ] && tob=$max
  if [ $tob -lt $need ]; then echo "=== skip $who t=$(t)"; return; fi
  echo "=== $who t=$(t)"
  timeout $tob $bin $st --gpu $SIZE --reps $REPS "$@" > $O/k_${who}.txt 2>&1
  echo "rc=$? t=$(t)"
  grep -v "^|\|^stats\|^device\|^$" $O/k_${who}.txt | sort | uniq -c | head -5
  grep "^| .* | \(overview\|close-up\)" $O/k_${who}.txt | cut -d'|' -f2-8,10,14 | sed "s/^/$who |/"
  grep "^stats: trace compact \[spec [13]," $O/k_${who}.txt | sort -u | sed 's/ CS (subgroup 32)//; s/Register Count/R/; s/Binary Size/bin/; s/Shared Memory Size/shm/; s/Local Memory Size=6871947/lmem=/; s/Stack Size/stk/' | cut -c1-170
}
run main1 12 18 "" $B/compact_bench $SC
run K1 12 18 --shader-stats $T/compact_bench $SC
run X 12 18 --shader-stats $T/compact_bench --closeups --variants 4,8,0x88 $SC
run main2 12 18 "" $B/compact_bench $SC
run K2 12 18 "" $T/compact_bench $SC
echo "=== end t=$(t)"
